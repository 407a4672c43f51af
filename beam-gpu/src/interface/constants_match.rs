//! The generated constants in every shader: each declared once with [`CONSTANTS`]' type and value
//! (bit for bit, as naga reads it), the compute entry points' workgroup size and the traversal
//! stack taken from them, and no shader source declaring its own copy or spelling a value the
//! table replaced.

use super::parsed::Modules;
use super::{CONSTANTS, TRAVERSAL_STACK, Value, WORKGROUP_SIZE};
use crate::shaders::{LIBRARY, SHADERS};
use naga::{Expression, Literal, Scalar, TypeInner};

/// The value of module constant `name`, if declared exactly once.
fn declared(module: &naga::Module, name: &str) -> Result<Value, String> {
    let found: Vec<_> = module.constants.iter().filter(|(_, c)| c.name.as_deref() == Some(name)).collect();
    let [(_, c)] = found[..] else {
        return Err(format!("{name} declared {} times", found.len()));
    };
    match (&module.types[c.ty].inner, &module.global_expressions[c.init]) {
        (TypeInner::Scalar(Scalar::U32), Expression::Literal(Literal::U32(v))) => Ok(Value::U32(*v)),
        (TypeInner::Scalar(Scalar::F32), Expression::Literal(Literal::F32(v))) => Ok(Value::F32(*v)),
        (ty, init) => Err(format!("{name}: {ty:?} = {init:?}")),
    }
}

fn same(a: Value, b: Value) -> bool {
    match (a, b) {
        (Value::U32(a), Value::U32(b)) => a == b,
        (Value::F32(a), Value::F32(b)) => a.to_bits() == b.to_bits(),
        _ => false,
    }
}

#[test]
fn every_shader_has_every_constant_with_its_rust_value() {
    let mut modules = Modules::default();
    let mut errors = Vec::new();
    for (shader, _) in SHADERS {
        let module = modules.get(shader);
        for &(name, value) in CONSTANTS {
            match declared(module, name) {
                Ok(v) if same(v, value) => {}
                Ok(v) => errors.push(format!("{shader}.wgsl: {name} is {v:?}, Rust {value:?}")),
                Err(e) => errors.push(format!("{shader}.wgsl: {e}")),
            }
        }
        for ep in module.entry_points.iter().filter(|ep| ep.stage == naga::ShaderStage::Compute) {
            if ep.workgroup_size != [WORKGROUP_SIZE, 1, 1] {
                errors.push(format!("{shader}.wgsl {}: workgroup size {:?}", ep.name, ep.workgroup_size));
            }
        }
    }
    assert!(errors.is_empty(), "constants differ:\n{}", errors.join("\n"));
}

#[test]
fn the_traversal_stack_has_traversal_stack_entries() {
    let mut modules = Modules::default();
    for shader in ["raytrace", "glossy_gather"] {
        let module = modules.get(shader);
        let trace = module.functions.iter().find(|(_, f)| f.name.as_deref() == Some("trace_ray")).map(|(_, f)| f);
        let stack = trace.and_then(|f| f.local_variables.iter().find(|(_, v)| v.name.as_deref() == Some("stack")));
        let size = stack.map(|(_, v)| &module.types[v.ty].inner);
        let Some(TypeInner::Array { size: naga::ArraySize::Constant(n), .. }) = size else {
            panic!("{shader}.wgsl: no trace_ray stack array ({size:?})");
        };
        assert_eq!(n.get(), TRAVERSAL_STACK, "{shader}.wgsl");
    }
}

#[test]
fn no_shader_source_copies_a_constant() {
    let sources = LIBRARY.iter().chain(SHADERS).copied();
    let mut errors = Vec::new();
    for (file, text) in sources {
        for (name, _) in CONSTANTS {
            if text.contains(&format!("const {name}:")) || text.contains(&format!("const {name} ")) {
                errors.push(format!("{file}: declares {name}"));
            }
        }
        // Spellings of values the table took over.
        for spelling in ["0xffffffff", "@workgroup_size(64", "* 64u", "array<u32, 64>"] {
            if text.contains(spelling) {
                errors.push(format!("{file}: spells `{spelling}`"));
            }
        }
    }
    assert!(errors.is_empty(), "shader sources repeat the table:\n{}", errors.join("\n"));
}
