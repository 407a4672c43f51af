//! The final composite of 000 §7.3 on the GPU (`shaders/composite.wgsl`): the radiance flow of a
//! beam tree, deepest level first, with every level's radiance kept on the GPU (half floats, as an
//! RGBA16F atlas) and only the eye's pixels read back. Diffuse, glossy and emissive points are
//! shaded by [`PointShader`] straight into the buffer the composite pass reads; mirror and glass
//! points without child beams (past the last level) come from the caller. CPU twin:
//! beam-cpu's `composite_levels`.

use crate::buffers::{compute_pipeline, dispatch, max_binding, output, read_back, storage, uniform};
use crate::interface::WORKGROUP_SIZE;
use crate::raytrace::RayTracer;
use crate::shade::PointShader;
use crate::{Gpu, GpuError};
use beam_math::glam::Vec3;
use beam_scene::BackendError;
use beam_scene::irradiance_map::IrradianceMap;
use beam_scene::nonlinear::{LevelRadiance, SMesh, ShadePoint};
use beam_scene::scene::{Material, Scene};
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

/// An S-mesh face for the composite.
///
/// WGSL twin: `Face` in `shaders/composite.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuFace {
    /// Vertices (w unused).
    pub v: [[f32; 4]; 3],
    /// Unit vertex normals on the side of the geometric normal (w unused).
    pub n: [[f32; 4]; 3],
    /// The scene triangle's unit geometric normal (w unused).
    pub normal: [f32; 4],
    /// rgb: a mirror's tint; w: a glass's index of refraction, 0 for a mirror.
    pub material: [f32; 4],
}

/// One texel of a level for the composite pass.
///
/// WGSL twin: `Record` in `shaders/composite.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CompositeRecord {
    /// Where its face's reflection beam is looked up: the point its ray hit, or under a coarse
    /// S-mesh face the point of the face at [`Composite::reflected_at`](beam_scene::nonlinear::Composite).
    pub p: [f32; 3],
    /// Its index in the level's radiance.
    pub texel: u32,
    /// Unit direction of the ray.
    pub d: [f32; 3],
    /// Index of its shaded radiance, [`NONE`] when composited.
    pub src: u32,
    /// Its S-mesh face.
    pub face: u32,
    /// Its face's reflection beam in the level below.
    pub reflected: u32,
    /// Its face's refraction beam, [`NONE`] for none.
    pub refracted: u32,
    /// Padding.
    pub pad: u32,
    /// Where its face's refraction beam is looked up (as `p`, at `Composite::refracted_at`).
    pub refracted_p: [f32; 3],
    /// Padding.
    pub pad2: u32,
}

/// Uniforms of the composite pass.
///
/// WGSL twin: `CompositeParams` in `shaders/composite.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CompositeParams {
    /// Records of the dispatch.
    pub records: u32,
    /// Padding.
    pub pad: [u32; 3],
}

const _: () =
    assert!(size_of::<GpuFace>() == 128 && size_of::<CompositeRecord>() == 64 && size_of::<CompositeParams>() == 16);

/// "None" in [`CompositeRecord`] ([`crate::interface::NONE`]).
pub use crate::interface::NONE;

/// Bytes of a texel of a level's radiance (rgb as half floats, and padding).
const TEXEL_BYTES: u64 = 8;

/// Shades a batch of the points the [`PointShader`] does not (mirrors and glass past the tree).
pub type ShadeRest<'a> = dyn Fn(&[ShadePoint]) -> Result<Vec<Vec3>, BackendError> + 'a;

/// The composite pass.
pub struct GpuComposite {
    pipeline: wgpu::ComputePipeline,
}

impl GpuComposite {
    /// Compile the pass.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        Ok(Self { pipeline: compute_pipeline(gpu, "composite", "composite")? })
    }

    /// True when every level's radiance fits one storage binding of the device.
    #[must_use]
    pub fn fits(gpu: &Gpu, levels: &[LevelRadiance]) -> bool {
        let limit = max_binding(gpu);
        levels.iter().all(|l| l.len as u64 * TEXEL_BYTES <= limit)
    }

    /// The radiance flow of `levels` (`levels[0]` the eye's view) on the GPU: the eye's pixels.
    /// Points the [`PointShader`] shades are shaded on the GPU (`spp` shadow rays per area light,
    /// the irradiance of `caustics`), the others by `rest`. Call inside [`crate::buffers::checked`].
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        shader: &PointShader,
        (scene, smesh): (&Scene, &SMesh),
        caustics: Option<&IrradianceMap>,
        spp: u32,
        levels: &[LevelRadiance],
        rest: &ShadeRest<'_>,
    ) -> Result<Vec<Vec3>, GpuError> {
        let faces = storage(gpu, "faces", &gpu_faces(scene, smesh), wgpu::BufferUsages::empty());
        let prepared = shader.prepare(gpu, caustics);
        // Records, shade inputs and outputs of one dispatch within a binding.
        let chunk = ((max_binding(gpu) / 64) as usize).clamp(1, 1 << 20);
        let empty = || storage::<[u32; 2]>(gpu, "empty", &[], wgpu::BufferUsages::empty());
        let (mut below, mut below_regions) = (empty(), empty());
        let mut len = 0;
        for level in levels.iter().rev() {
            len = level.len as u64 * TEXEL_BYTES;
            let radiance = output(gpu, "level radiance", len);
            for texels in level.texels.chunks(chunk) {
                // Points not composited: on the GPU where the point shader shades them, else by `rest`.
                let kinds: Vec<Option<bool>> = texels
                    .par_iter()
                    .map(|t| t.composite.is_none().then(|| PointShader::shades(scene, t.point.prim)))
                    .collect();
                let (mut direct, mut other) = (Vec::new(), Vec::new());
                // Per texel: composited, or where its shaded radiance lies (direct or other).
                let sources: Vec<Option<(bool, usize)>> = texels
                    .iter()
                    .zip(&kinds)
                    .map(|(t, kind)| {
                        let on_gpu = (*kind)?;
                        let list = if on_gpu { &mut direct } else { &mut other };
                        list.push(t.point);
                        Some((on_gpu, list.len() - 1))
                    })
                    .collect();
                let other_radiance: Vec<[f32; 4]> = rest(&other)?.iter().map(|c| c.extend(0.0).to_array()).collect();
                let (encoder, shaded) = shader.shade_into(gpu, tracer, &prepared, spp, &direct, other.len())?;
                gpu.queue.write_buffer(&shaded, (direct.len() * 16) as u64, bytemuck::cast_slice(&other_radiance));
                let records: Vec<CompositeRecord> = texels
                    .par_iter()
                    .zip(&sources)
                    .map(|(t, source)| {
                        let c = t.composite;
                        // The shader looks the children up at `p`'s and `refracted_p`'s barycentric
                        // coordinates on the face: under a coarse S-mesh face, the points of the
                        // face where the CPU looks the reflection and the refraction up.
                        let (p, refracted_p) = match c {
                            Some(c) if smesh.is_coarse(c.face as usize) => {
                                let f = &smesh.faces[c.face as usize];
                                let at = |w: Vec3| w.x * f.v[0] + w.y * f.v[1] + w.z * f.v[2];
                                (at(c.reflected_at), at(c.refracted_at))
                            }
                            _ => (t.point.p, t.point.p),
                        };
                        CompositeRecord {
                            p: p.to_array(),
                            texel: t.texel,
                            d: t.point.d.to_array(),
                            src: source.map_or(NONE, |(on_gpu, i)| (if on_gpu { i } else { direct.len() + i }) as u32),
                            face: c.map_or(NONE, |c| c.face),
                            reflected: c.map_or(NONE, |c| c.reflected),
                            refracted: c.and_then(|c| c.refracted).unwrap_or(NONE),
                            pad: 0,
                            refracted_p: refracted_p.to_array(),
                            pad2: 0,
                        }
                    })
                    .collect();
                let params = CompositeParams { records: records.len() as u32, pad: [0; 3] };
                let params = uniform(gpu, "composite params", bytemuck::bytes_of(&params));
                let records_buffer = storage(gpu, "records", &records, wgpu::BufferUsages::empty());
                let buffers = [&params, &records_buffer, &faces, &shaded, &below, &below_regions, &radiance];
                let composite =
                    dispatch(gpu, &self.pipeline, &buffers, records.len().div_ceil(WORKGROUP_SIZE as usize) as u32);
                gpu.queue.submit([encoder.finish(), composite.finish()]);
            }
            let regions: Vec<[u32; 2]> = level.regions.iter().map(|&(first, size)| [first, size]).collect();
            below_regions = storage(gpu, "regions", &regions, wgpu::BufferUsages::empty());
            below = radiance;
        }
        let encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let halves: Vec<[u16; 4]> = read_back(gpu, encoder, &below, len)?;
        Ok(halves
            .par_iter()
            .map(|h| Vec3::from_array([h[0], h[1], h[2]].map(|x| half::f16::from_bits(x).to_f32())))
            .collect())
    }
}

/// The faces of `smesh` for the shader.
fn gpu_faces(scene: &Scene, smesh: &SMesh) -> Vec<GpuFace> {
    smesh
        .faces
        .iter()
        .map(|f| GpuFace {
            v: f.v.map(|v| v.extend(0.0).to_array()),
            n: f.n.map(|n| n.extend(0.0).to_array()),
            normal: f.normal.extend(0.0).to_array(),
            material: match scene.material(f.prim) {
                Material::Mirror { tint, .. } => tint.extend(0.0).to_array(),
                Material::Glass { ior } => [1.0, 1.0, 1.0, ior],
                _ => [0.0; 4],
            },
        })
        .collect()
}
