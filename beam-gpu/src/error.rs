//! The errors of beam-gpu: [`GpuError`].

use beam_bvh::gpu::GpuBvhError;
use beam_render::BackendError;
use beam_scene::SceneError;
use std::path::PathBuf;

/// An error of the GPU: no adapter or device, a shader that does not validate or translate, an
/// error the device reports (validation, out of memory), a batch beyond one dispatch or binding, or
/// an error of the scene or backend a pass works with.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// `WGPU_BACKEND` names a backend wgpu does not know (wgpu drops it and then finds no adapter).
    #[error(
        "no GPU adapter: WGPU_BACKEND={value:?} names unknown backend {:?} (expected a comma-separated list of \
         vulkan, metal, dx12, gl, webgpu)",
        unknown.join(",")
    )]
    UnknownBackend {
        /// The value of `WGPU_BACKEND`.
        value: String,
        /// The names in it wgpu does not know.
        unknown: Vec<String>,
    },
    /// No adapter was found.
    #[error(
        "no GPU adapter ({source}); on Linux without a GPU install Mesa's software Vulkan driver: apt-get install \
         mesa-vulkan-drivers"
    )]
    NoAdapter {
        /// What wgpu said.
        source: wgpu::RequestAdapterError,
    },
    /// The adapter would not open a device.
    #[error("{adapter} ({backend:?}): cannot open a device: {source}")]
    OpenDevice {
        /// The adapter's name.
        adapter: String,
        /// Its backend.
        backend: wgpu::Backend,
        /// What wgpu said.
        source: wgpu::RequestDeviceError,
    },
    /// The device reported an error (validation, out of memory, internal) during a pass run through
    /// [`checked`](crate::buffers::checked).
    #[error("{device}: {source}")]
    Device {
        /// The device, `name (backend)` ([`Gpu::describe`](crate::Gpu::describe)).
        device: String,
        /// What the device said.
        source: wgpu::Error,
    },
    /// Waiting for the device failed.
    #[error("GPU wait failed: {0}")]
    Wait(#[source] wgpu::PollError),
    /// Reading a mapped buffer back failed.
    #[error("GPU readback failed: {0:?}")]
    Readback(#[source] wgpu::MapRangeError),
    /// No shader of that name ([`SHADERS`](crate::shaders::SHADERS)).
    #[error("no shader named `{name}`")]
    NoShader {
        /// The name asked for.
        name: String,
    },
    /// A shader that naga does not parse or validate.
    #[error("{name}.wgsl: {message}")]
    Shader {
        /// The shader's name.
        name: String,
        /// naga's diagnostic, with the source lines it points at.
        message: String,
    },
    /// A WGSL file whose `// #import` line names a file that is not in
    /// [`LIBRARY`](crate::shaders::LIBRARY).
    #[error("{file}: imports `{import}`, which is not a shader library file")]
    UnknownImport {
        /// The importing file (`raytrace.wgsl`, `lib/trace.wgsl`).
        file: String,
        /// The name it imports.
        import: String,
    },
    /// WGSL files whose `// #import` lines import each other in a cycle.
    #[error("shader import cycle: {}", cycle.join(" → "))]
    ImportCycle {
        /// The files of the cycle, from its first file back to it.
        cycle: Vec<String>,
    },
    /// A shader that naga does not translate to a language of [`emit`](crate::shaders::emit).
    #[error("{name}: {language}: {source}")]
    Translate {
        /// The shader's name.
        name: String,
        /// The language (`SPIR-V`, `GLSL`, `MSL`, `HLSL`).
        language: &'static str,
        /// What naga's writer said.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A language name [`Language::parse`](crate::shaders::Language::parse) does not know.
    #[error("unknown shader language `{name}` (spv, glsl, msl, hlsl)")]
    UnknownLanguage {
        /// The name given.
        name: String,
    },
    /// The folder translated shaders go to could not be created.
    #[error("{}: {source}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A scene's BVH whose traversal needs a deeper stack than the shaders have.
    #[error(transparent)]
    Bvh(#[from] GpuBvhError),
    /// Writing an output file failed.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// More cases than one dispatch of the nonlinear check takes.
    #[error("{cases} cases exceed one dispatch")]
    TooManyCases {
        /// Cases asked for.
        cases: usize,
    },
    /// A ray whose traversal overflowed the shader's stack (which [`GpuBvhError`] rules out).
    #[error("ray {ray}: the GPU traversal stack overflowed")]
    StackOverflow {
        /// The ray's index in its batch.
        ray: usize,
    },
    /// A beam's texture larger than an atlas page.
    #[error("a beam of {size}² texels does not fit a {page}² atlas page")]
    BeamTooLarge {
        /// The beam's texels per side.
        size: u32,
        /// The page's texels per side.
        page: u32,
    },
    /// A scene whose BVH (its nodes or its triangles) is larger than one storage binding holds: the
    /// traversal reads the whole tree from one binding.
    #[error("the scene's BVH {what} take {bytes} bytes, more than one GPU storage binding holds ({max})")]
    SceneTooLarge {
        /// `nodes` or `triangles`.
        what: &'static str,
        /// Their bytes.
        bytes: u64,
        /// The device's largest binding.
        max: u64,
    },
    /// A shadow-beam query of a light the batch does not have.
    #[error("a shadow-beam query names light {light}, but the batch has {lights} lights")]
    NoSuchLight {
        /// The light named.
        light: u32,
        /// The lights of the batch.
        lights: usize,
    },
    /// A scene with more mirror and glass triangles than one texture of the device holds (the
    /// Whitted rays' specular bounces read them from one).
    #[error("the scene has {triangles} mirror and glass triangles, more than one GPU texture holds ({max})")]
    TooManySpecular {
        /// Its mirror and glass triangles.
        triangles: usize,
        /// The most one texture holds.
        max: usize,
    },
    /// A beam that meets more scene triangles than one storage binding holds.
    #[error("a beam meets {triangles} scene triangles, more than one GPU binding holds ({max})")]
    TooManyTriangles {
        /// The triangles it meets.
        triangles: usize,
        /// The most one binding holds.
        max: usize,
    },
    /// The GPU gather asked for with Gaussian volumes other than exact ones.
    #[error("the GPU gather integrates the Gaussian volumes exactly (--volume exact)")]
    InexactVolumes,
    /// More point emitters than the GPU gather takes.
    #[error(
        "the GPU gather takes at most {max} point emitters (point lights, and area lights' strata), not {emitters}"
    )]
    TooManyEmitters {
        /// The scene's point emitters.
        emitters: usize,
        /// The most the gather takes.
        max: usize,
    },
    /// A broken invariant of the atlas packing (a beam left unplaced or unrendered): a bug.
    #[error("{0}")]
    Internal(&'static str),
    /// The work a pass was given failed (the shading of points it hands back to the caller).
    #[error(transparent)]
    Backend(#[from] BackendError),
}

/// A GPU error as the backend traits' error; a [`GpuError::Backend`] is unwrapped, not boxed again.
impl From<GpuError> for BackendError {
    fn from(e: GpuError) -> Self {
        match e {
            GpuError::Backend(b) => b,
            e => BackendError::new("gpu", e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The messages are the ones these errors had as strings.
    #[test]
    fn messages_are_unchanged() {
        let e = crate::shaders::Language::parse("wgsl").unwrap_err();
        assert_eq!(e.to_string(), "unknown shader language `wgsl` (spv, glsl, msl, hlsl)");
        let e = crate::shaders::validate("nope").unwrap_err();
        assert!(matches!(&e, GpuError::NoShader { name } if name == "nope"), "{e:?}");
        assert_eq!(e.to_string(), "no shader named `nope`");
        let cases = [
            (GpuError::StackOverflow { ray: 7 }, "ray 7: the GPU traversal stack overflowed"),
            (
                GpuError::SceneTooLarge { what: "triangles", bytes: 96_000, max: 65_536 },
                "the scene's BVH triangles take 96000 bytes, more than one GPU storage binding holds (65536)",
            ),
            (
                GpuError::TooManySpecular { triangles: 3_000_000, max: 2_097_152 },
                "the scene has 3000000 mirror and glass triangles, more than one GPU texture holds (2097152)",
            ),
            (
                GpuError::BeamTooLarge { size: 5000, page: 4096 },
                "a beam of 5000² texels does not fit a 4096² atlas page",
            ),
            (
                GpuError::TooManyEmitters { emitters: 70, max: 64 },
                "the GPU gather takes at most 64 point emitters (point lights, and area lights' strata), not 70",
            ),
            (
                GpuError::UnknownBackend { value: "vulkan,foo".into(), unknown: vec!["foo".into()] },
                "no GPU adapter: WGPU_BACKEND=\"vulkan,foo\" names unknown backend \"foo\" (expected a comma-separated \
                 list of vulkan, metal, dx12, gl, webgpu)",
            ),
        ];
        for (e, message) in cases {
            assert_eq!(e.to_string(), message);
        }
    }

    /// A GPU error becomes a backend error of the GPU, but one that came from the work a pass was
    /// given stays what it was.
    #[test]
    fn backend_errors_are_not_wrapped_twice() {
        let e = BackendError::from(GpuError::StackOverflow { ray: 1 });
        assert_eq!((e.backend, e.to_string().as_str()), ("gpu", "ray 1: the GPU traversal stack overflowed"));
        let e = BackendError::from(GpuError::Backend(BackendError::new("cpu", "shading failed")));
        assert_eq!((e.backend, e.to_string().as_str()), ("cpu", "shading failed"));
    }
}
