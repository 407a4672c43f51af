//! The WGSL shaders, their validation by naga, and their translation for engines that take them
//! into their own pipelines (`beam shaders --emit spv|glsl|msl|hlsl`).

use crate::GpuError;
use std::path::Path;

/// Code shared by the shaders (`shaders/shared/*.wgsl`), prepended to each.
pub(crate) const SHARED: &[(&str, &str)] = &[
    ("shared/bvh.wgsl", include_str!("../shaders/shared/bvh.wgsl")),
    ("shared/nonlinear.wgsl", include_str!("../shaders/shared/nonlinear.wgsl")),
];

/// The shaders: name and source (without the shared code).
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

/// Library code that some shaders include (`shaders/lib/*.wgsl`): name, source, the shaders that
/// include it.
pub(crate) const LIBRARY: &[(&str, &str, &[&str])] = &[
    ("lib/trace.wgsl", include_str!("../shaders/lib/trace.wgsl"), &["raytrace", "glossy_gather", "eye", "whitted"]),
    ("lib/atlas.wgsl", include_str!("../shaders/lib/atlas.wgsl"), &["beam_atlas", "beam_cull", "beam_texels"]),
    ("lib/record.wgsl", include_str!("../shaders/lib/record.wgsl"), &["composite", "eye", "level_points"]),
    (
        "lib/lookup.wgsl",
        include_str!("../shaders/lib/lookup.wgsl"),
        &["nonlinear_check", "lookups", "eye", "level_points"],
    ),
    ("lib/reproject.wgsl", include_str!("../shaders/lib/reproject.wgsl"), &["lookups", "eye", "level_points"]),
    ("lib/specular.wgsl", include_str!("../shaders/lib/specular.wgsl"), &["eye", "whitted", "level_points"]),
    ("lib/coarse.wgsl", include_str!("../shaders/lib/coarse.wgsl"), &["eye", "level_points"]),
    ("lib/fit.wgsl", include_str!("../shaders/lib/fit.wgsl"), &["level_points"]),
    ("lib/quad.wgsl", include_str!("../shaders/lib/quad.wgsl"), &["shadow_beam", "eye_beam"]),
    ("lib/eye_pieces.wgsl", include_str!("../shaders/lib/eye_pieces.wgsl"), &["eye_beam"]),
    (
        "lib/region.wgsl",
        include_str!("../shaders/lib/region.wgsl"),
        &["beam_atlas", "beam_texels", "level_points", "lookups", "eye"],
    ),
];

/// The full source of shader `name`: the constants it shares with Rust ([`crate::interface::wgsl`]),
/// the shared code, the library code it includes, then the shader.
#[must_use]
pub fn source(name: &str) -> Option<String> {
    let (_, body) = SHADERS.iter().find(|(n, _)| *n == name)?;
    let included = LIBRARY.iter().filter(|(_, _, users)| users.contains(&name)).map(|(_, s, _)| *s);
    let mut out = crate::interface::wgsl();
    out.push_str(&SHARED.iter().map(|(_, s)| *s).chain(included).collect::<Vec<_>>().join("\n"));
    out.push('\n');
    out.push_str(body);
    Some(out)
}

/// Parse and validate shader `name` with naga.
pub fn validate(name: &str) -> Result<(naga::Module, naga::valid::ModuleInfo), GpuError> {
    let src = source(name).ok_or_else(|| GpuError::NoShader { name: name.to_string() })?;
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
