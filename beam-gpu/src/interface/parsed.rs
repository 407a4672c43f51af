//! The shaders as naga parses them, once per test, and the sizes of naga's types.

use crate::shaders::validate;
use std::collections::HashMap;

/// Parsed and validated shaders by name.
#[derive(Default)]
pub(super) struct Modules(HashMap<&'static str, naga::Module>);

impl Modules {
    /// Shader `name`'s module (panics when it does not validate).
    pub(super) fn get(&mut self, name: &'static str) -> &naga::Module {
        self.0.entry(name).or_insert_with(|| validate(name).unwrap_or_else(|e| panic!("{e}")).0)
    }
}

/// Bytes of a value of type `ty` in WGSL (a runtime-sized array: one element's stride).
pub(super) fn member_size(module: &naga::Module, ty: naga::Handle<naga::Type>) -> usize {
    match module.types[ty].inner {
        naga::TypeInner::Array { size: naga::ArraySize::Dynamic, stride, .. } => stride as usize,
        ref inner => inner.size(module.to_ctx()) as usize,
    }
}
