//! The WGSL shaders, their validation by naga, and their translation for engines that take them
//! into their own pipelines (`beam shaders --emit spv|glsl|msl|hlsl`). Each shader names the
//! library files it uses ([`LIBRARY`]: `shaders/lib/*.wgsl`, `shaders/shared/*.wgsl`) on lines of
//! its own such as `// #import lib/trace.wgsl`, and a library file the files it uses in turn;
//! [`source`] follows them transitively, each file once, after the files it imports (a cycle is an
//! error).

use crate::GpuError;
use std::path::Path;

mod imports;

/// The shaders: name and source (without the library files it imports).
pub const SHADERS: &[(&str, &str)] = &[
    ("raytrace", include_str!("../shaders/raytrace.wgsl")),
    ("beam_atlas", include_str!("../shaders/beam_atlas.wgsl")),
    ("beam_cull", include_str!("../shaders/beam_cull.wgsl")),
    ("beam_texels", include_str!("../shaders/beam_texels.wgsl")),
    ("nonlinear_check", include_str!("../shaders/nonlinear_check.wgsl")),
    ("composite", include_str!("../shaders/composite.wgsl")),
    ("eye", include_str!("../shaders/eye.wgsl")),
    ("whitted", include_str!("../shaders/whitted.wgsl")),
    ("glossy_gather", include_str!("../shaders/glossy_gather.wgsl")),
    ("level_points", include_str!("../shaders/level_points.wgsl")),
    ("lookups", include_str!("../shaders/lookups.wgsl")),
    ("shadow_beam", include_str!("../shaders/shadow_beam.wgsl")),
    ("eye_beam", include_str!("../shaders/eye_beam.wgsl")),
];

/// Shaders that use 64-bit atomics (wgpu's `SHADER_INT64_ATOMIC_MIN_MAX`): emitted for MSL 2.4 and
/// HLSL shader model 6.6, and not for GLSL, which naga writes without 64-bit integers.
pub const INT64_ATOMICS: &[&str] = &["beam_texels"];

/// The library files the shaders import (`shaders/shared/*.wgsl`, `shaders/lib/*.wgsl`): the name
/// an import line gives (relative to `shaders/`) and the source.
pub const LIBRARY: &[(&str, &str)] = &[
    ("shared/bvh.wgsl", include_str!("../shaders/shared/bvh.wgsl")),
    ("shared/nonlinear.wgsl", include_str!("../shaders/shared/nonlinear.wgsl")),
    ("lib/trace.wgsl", include_str!("../shaders/lib/trace.wgsl")),
    ("lib/atlas.wgsl", include_str!("../shaders/lib/atlas.wgsl")),
    ("lib/record.wgsl", include_str!("../shaders/lib/record.wgsl")),
    ("lib/shade_input.wgsl", include_str!("../shaders/lib/shade_input.wgsl")),
    ("lib/lookup.wgsl", include_str!("../shaders/lib/lookup.wgsl")),
    ("lib/reproject.wgsl", include_str!("../shaders/lib/reproject.wgsl")),
    ("lib/specular.wgsl", include_str!("../shaders/lib/specular.wgsl")),
    ("lib/coarse.wgsl", include_str!("../shaders/lib/coarse.wgsl")),
    ("lib/fit.wgsl", include_str!("../shaders/lib/fit.wgsl")),
    ("lib/quad.wgsl", include_str!("../shaders/lib/quad.wgsl")),
    ("lib/eye_pieces.wgsl", include_str!("../shaders/lib/eye_pieces.wgsl")),
    ("lib/region.wgsl", include_str!("../shaders/lib/region.wgsl")),
];

/// The files shader `name` is made of, `(file, source)`: the library files its imports bring in,
/// transitively, each once and after the files it imports, then the shader (`name.wgsl`) last.
pub(crate) fn files(name: &str) -> Result<Vec<(String, &'static str)>, GpuError> {
    let (_, body) =
        SHADERS.iter().find(|(n, _)| *n == name).ok_or_else(|| GpuError::NoShader { name: name.to_string() })?;
    let file = format!("{name}.wgsl");
    imports::resolve(&file, body, |import| LIBRARY.iter().find(|(n, _)| *n == import).map(|(_, text)| *text))
}

/// The full source of shader `name`, or `None` for no shader of that name: the constants it shares
/// with Rust ([`crate::interface::wgsl`]), then the library files its imports bring in
/// (`files`), then the shader.
///
/// # Panics
///
/// If the embedded files' imports name a file not in [`LIBRARY`] or form a cycle (a test rules
/// both out).
#[must_use]
pub fn source(name: &str) -> Option<String> {
    match try_source(name) {
        Ok(source) => Some(source),
        Err(GpuError::NoShader { .. }) => None,
        Err(e) => panic!("{e}"),
    }
}

/// [`source`], with a broken import an error.
fn try_source(name: &str) -> Result<String, GpuError> {
    let mut out = crate::interface::wgsl();
    for (file, text) in files(name)? {
        out.push_str("\n// ---- ");
        out.push_str(&file);
        out.push('\n');
        out.push_str(text);
        if !text.ends_with('\n') {
            out.push('\n');
        }
    }
    Ok(out)
}

/// Parse and validate shader `name` with naga.
pub fn validate(name: &str) -> Result<(naga::Module, naga::valid::ModuleInfo), GpuError> {
    let src = try_source(name)?;
    let invalid = |message| GpuError::Shader { name: name.to_string(), message };
    let module = naga::front::wgsl::parse_str(&src).map_err(|e| invalid(e.emit_to_string(&src)))?;
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .map_err(|e| invalid(e.emit_to_string(&src)))?;
    Ok((module, info))
}

/// A target language of [`emit`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Language {
    /// SPIR-V binary (`.spv`).
    Spirv,
    /// GLSL 4.50 (`.<entry>.<comp|vert|frag>.glsl`), one file per entry point.
    Glsl,
    /// Metal Shading Language (`.metal`).
    Msl,
    /// HLSL shader model 5.1 (`.hlsl`).
    Hlsl,
}

impl Language {
    /// From `spv`, `glsl`, `msl` or `hlsl`.
    pub fn parse(s: &str) -> Result<Self, GpuError> {
        match s {
            "spv" => Ok(Self::Spirv),
            "glsl" => Ok(Self::Glsl),
            "msl" => Ok(Self::Msl),
            "hlsl" => Ok(Self::Hlsl),
            _ => Err(GpuError::UnknownLanguage { name: s.to_string() }),
        }
    }
}

/// Translate every shader to `lang` into directory `out` (created), each file written atomically;
/// returns the files written. GLSL leaves out [`INT64_ATOMICS`] (their pipelines' rasterized twins
/// stand in for them).
pub fn emit(lang: Language, out: &Path) -> Result<Vec<std::path::PathBuf>, GpuError> {
    std::fs::create_dir_all(out).map_err(|source| GpuError::Folder { path: out.to_path_buf(), source })?;
    let mut written = Vec::new();
    for (name, _) in SHADERS {
        let int64 = INT64_ATOMICS.contains(name);
        if int64 && lang == Language::Glsl {
            continue;
        }
        let (module, info) = validate(name)?;
        let failed = |language, source| GpuError::Translate { name: name.to_string(), language, source };
        let files: Vec<(String, Vec<u8>)> = match lang {
            Language::Spirv => {
                let words = naga::back::spv::write_vec(&module, &info, &naga::back::spv::Options::default(), None)
                    .map_err(|e| failed("SPIR-V", e.into()))?;
                vec![(format!("{name}.spv"), words.iter().flat_map(|w| w.to_le_bytes()).collect())]
            }
            Language::Glsl => {
                let mut files = Vec::new();
                for ep in &module.entry_points {
                    let mut text = String::new();
                    let options = naga::back::glsl::Options {
                        version: naga::back::glsl::Version::Desktop(450),
                        ..Default::default()
                    };
                    let pipeline = naga::back::glsl::PipelineOptions {
                        shader_stage: ep.stage,
                        entry_point: ep.name.clone(),
                        multiview: None,
                    };
                    naga::back::glsl::Writer::new(
                        &mut text,
                        &module,
                        &info,
                        &options,
                        &pipeline,
                        naga::proc::BoundsCheckPolicies::default(),
                    )
                    .and_then(|mut w| w.write().map(|_| ()))
                    .map_err(|e| failed("GLSL", e.into()))?;
                    let stage = match ep.stage {
                        naga::ShaderStage::Vertex => "vert",
                        naga::ShaderStage::Fragment => "frag",
                        _ => "comp",
                    };
                    files.push((format!("{name}.{}.{stage}.glsl", ep.name), text.into_bytes()));
                }
                files
            }
            Language::Msl => {
                let (text, _) = naga::back::msl::write_string(
                    &module,
                    &info,
                    // MSL 2.0 for instance ids in vertex functions (every Metal GPU since 2017), 2.4
                    // for 64-bit atomics.
                    &naga::back::msl::Options {
                        lang_version: if int64 { (2, 4) } else { (2, 0) },
                        ..Default::default()
                    },
                    &naga::back::msl::PipelineOptions::default(),
                )
                .map_err(|e| failed("MSL", e.into()))?;
                vec![(format!("{name}.metal"), text.into_bytes())]
            }
            Language::Hlsl => {
                let mut text = String::new();
                let shader_model =
                    if int64 { naga::back::hlsl::ShaderModel::V6_6 } else { naga::back::hlsl::ShaderModel::V5_1 };
                let options = naga::back::hlsl::Options { shader_model, ..Default::default() };
                naga::back::hlsl::Writer::new(&mut text, &options, &Default::default())
                    .write(&module, &info, None)
                    .map_err(|e| failed("HLSL", e.into()))?;
                vec![(format!("{name}.hlsl"), text.into_bytes())]
            }
        };
        for (file, bytes) in files {
            // Through beam-cpu's writer: hidden, unique temporaries that a signal removes.
            let path = out.join(file);
            beam_scene::io::write_atomic(&path, &bytes)?;
            written.push(path);
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shader_validates() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let on_disk = std::fs::read_dir(&dir)
            .unwrap()
            .filter(|e| e.as_ref().is_ok_and(|e| e.path().extension().is_some_and(|x| x == "wgsl")));
        let n = on_disk.count();
        assert!(n > 0, "no shaders found in {}", dir.display());
        assert_eq!(n, SHADERS.len(), "every shaders/*.wgsl must be listed in SHADERS");
        for (name, _) in SHADERS {
            validate(name).unwrap_or_else(|e| panic!("{e}"));
        }
    }

    /// Every `shaders/lib/*.wgsl` and `shaders/shared/*.wgsl` is in [`LIBRARY`] and imported by some
    /// shader, and a shader's source holds each of its files once.
    #[test]
    fn every_library_file_is_listed_and_imported_once() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let mut on_disk = Vec::new();
        for dir in ["lib", "shared"] {
            for entry in std::fs::read_dir(root.join(dir)).unwrap() {
                let name = entry.unwrap().file_name().into_string().unwrap();
                if name.ends_with(".wgsl") {
                    on_disk.push(format!("{dir}/{name}"));
                }
            }
        }
        on_disk.sort();
        let mut listed: Vec<_> = LIBRARY.iter().map(|(n, _)| (*n).to_string()).collect();
        listed.sort();
        assert_eq!(on_disk, listed, "LIBRARY must list every shaders/lib and shaders/shared file");
        let mut used = std::collections::BTreeSet::new();
        for (name, _) in SHADERS {
            let files = files(name).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(files.last().map(|(f, _)| f.as_str()), Some(format!("{name}.wgsl").as_str()));
            let source = source(name).unwrap();
            for (file, _) in &files {
                assert_eq!(source.matches(&format!("// ---- {file}\n")).count(), 1, "{name}: {file}");
                used.insert(file.clone());
            }
        }
        for (file, _) in LIBRARY {
            assert!(used.contains(*file), "{file} is imported by no shader");
        }
        assert_eq!(source("nope"), None);
    }

    /// Each WGSL struct is defined in one file (a file that needs it imports that one).
    #[test]
    fn no_struct_is_defined_twice() {
        let mut defined: std::collections::HashMap<&str, &str> = std::collections::HashMap::new();
        let mut twice = Vec::new();
        let shaders = SHADERS.iter().map(|(n, s)| (*n, *s));
        for (file, text) in LIBRARY.iter().copied().chain(shaders) {
            for line in text.lines() {
                let Some(rest) = line.trim_start().strip_prefix("struct ") else { continue };
                let name = rest.split(|c: char| !(c.is_alphanumeric() || c == '_')).next().unwrap_or(rest);
                if let Some(first) = defined.insert(name, file) {
                    twice.push(format!("struct {name}: {first} and {file}"));
                }
            }
        }
        assert!(defined.contains_key("RecordCounts") && defined.contains_key("ShadeInput"));
        assert!(twice.is_empty(), "structs defined twice:\n{}", twice.join("\n"));
    }

    #[test]
    fn every_language_translates() {
        let dir = std::env::temp_dir().join(format!("beam-shaders-{}", std::process::id()));
        for lang in [Language::Spirv, Language::Glsl, Language::Msl, Language::Hlsl] {
            let files = emit(lang, &dir).unwrap_or_else(|e| panic!("{lang:?}: {e}"));
            assert!(!files.is_empty() && files.iter().all(|f| f.metadata().is_ok_and(|m| m.len() > 0)), "{lang:?}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
