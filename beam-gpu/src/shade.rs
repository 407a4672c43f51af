//! Shading on the GPU (`shaders/raytrace.wgsl`, entry point `shade`): diffuse, glossy and emissive
//! points, point lights by one shadow ray each and area lights by stratified shadow rays (the
//! `Shading::Exact` estimator of beam-cpu's `shade_point`'s `Method::Ray`, its jitter from a
//! hash of the point's seed), all traced through the GPU BVH, plus the caustic irradiance maps of
//! the nonlinear renderer, in passes of bounded work ([`PASS_BUDGET`]). CPU twin: [`twin::shade_twin`];
//! on point-lit scenes it equals `shade_point`.

use crate::buffers::{
    buffer_entry, checked, compute_pass, compute_pipeline, max_binding, output, read_back, storage, uniform, view_entry,
};
use crate::checks::ShadeChecks;
use crate::interface::{
    LIGHT_POINT, LIGHT_QUAD, LIGHT_TRIANGLE, SURFACE_EMISSIVE, SURFACE_REFLECTING, SURFACE_UNSHADED, WORKGROUP_SIZE,
};
use crate::raytrace::RayTracer;
use crate::scratch::{Scratch, scratch};
use crate::{Gpu, GpuError};
use beam_math::glam::Vec3;
use beam_render::irradiance_map::IrradianceMap;
use beam_render::nonlinear::ShadePoint;
use beam_render::tolerance::shading_eps;
use beam_scene::scene::{Light, Material, Scene};
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

pub mod twin;

/// A point to shade.
///
/// WGSL twin: `ShadeInput` in `shaders/raytrace.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ShadeInput {
    /// The point.
    pub p: [f32; 3],
    /// Its scene triangle.
    pub prim: u32,
    /// Unit direction of the arriving ray.
    pub d: [f32; 3],
    /// Seed of its shadow-ray jitter.
    pub seed: u32,
}

impl ShadeInput {
    /// Point `s` for the shader (its seed folded to 32 bits, [`seed32`]).
    #[must_use]
    pub fn new(s: &ShadePoint) -> Self {
        Self { p: s.p.to_array(), prim: s.prim, d: s.d.to_array(), seed: seed32(s.seed) }
    }
}

/// What shading needs of a scene triangle.
///
/// WGSL twin: `PrimShading` in `shaders/raytrace.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PrimShading {
    /// Unit geometric normal.
    pub normal: [f32; 3],
    /// [`SURFACE_REFLECTING`] (diffuse or glossy, `color` the albedo), [`SURFACE_EMISSIVE`]
    /// (`color` the radiance) or [`SURFACE_UNSHADED`].
    pub kind: u32,
    /// Albedo or radiance.
    pub color: [f32; 3],
    /// The front grid of its plane in the caustic irradiance maps (the back one next), −1 for none.
    pub plane: i32,
}

/// A light.
///
/// WGSL twin: `Light` in `shaders/raytrace.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// Point: position; quad: corner; triangle: first vertex.
    pub a: [f32; 3],
    /// [`LIGHT_POINT`], [`LIGHT_QUAD`] or [`LIGHT_TRIANGLE`].
    pub kind: u32,
    /// Quad: first edge; triangle: `v1 − v0`.
    pub b: [f32; 3],
    /// Area (0 for a point light).
    pub area: f32,
    /// Quad: second edge; triangle: `v2 − v0`.
    pub c: [f32; 3],
    /// Padding.
    pub pad: u32,
    /// Intensity (point) or radiance (area lights).
    pub power: [f32; 3],
    /// Padding.
    pub pad2: u32,
}

impl GpuLight {
    /// `light` for the shader.
    #[must_use]
    pub fn new(light: &Light) -> Self {
        let (a, kind, b, c) = match *light {
            Light::Point { position, .. } => (position, LIGHT_POINT, Vec3::ZERO, Vec3::ZERO),
            Light::Quad { corner, edge_u, edge_v, .. } => (corner, LIGHT_QUAD, edge_u, edge_v),
            Light::Triangle { v, .. } => (v[0], LIGHT_TRIANGLE, v[1] - v[0], v[2] - v[0]),
        };
        Self {
            a: a.to_array(),
            kind,
            b: b.to_array(),
            area: light.area(),
            c: c.to_array(),
            pad: 0,
            power: light.power().to_array(),
            pad2: 0,
        }
    }
}

/// One plane of the caustic irradiance maps.
///
/// WGSL twin: `CausticPlane` in `shaders/raytrace.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CausticPlane {
    /// Texel-centre origin.
    pub origin: [f32; 3],
    /// Its first texel in the flux texture (texel `i` at `(i mod width, i / width)` of it).
    pub offset: u32,
    /// First axis, scaled to texels.
    pub axis_u: [f32; 3],
    /// Texels along it.
    pub width: u32,
    /// Second axis, scaled to texels.
    pub axis_v: [f32; 3],
    /// Texels along it.
    pub height: u32,
}

/// Uniforms of the shading pass.
///
/// WGSL twin: `ShadeParams` in `shaders/raytrace.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ShadeParams {
    /// Offset of shadow-ray origins off the surface.
    pub eps: f32,
    /// `1 / texel²` of the irradiance maps.
    pub inv_texel_area: f32,
    /// Point lights.
    pub lights: u32,
    /// Points to shade.
    pub points: u32,
    /// Shadow rays per area light.
    pub spp: u32,
    /// Loop iterations an invocation may run in one pass ([`PASS_BUDGET`]).
    pub budget: u32,
    /// Padding.
    pub pad: [u32; 2],
}

/// A point's shading between passes (zero before the first).
///
/// WGSL twin: `ShadeState` in `shaders/raytrace.wgsl` (layouts compared in [`crate::interface`]),
/// kept after a 16-byte header (`ShadeStates`: the count of points a pass left unfinished, and
/// padding).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ShadeState {
    /// Irradiance of the lights before `light`.
    pub e: [f32; 3],
    /// Area light `light`'s sum over its samples before `sample`.
    pub integral: f32,
    /// The light the point goes on at; [`SHADED`](crate::interface::SHADED) once shaded.
    pub light: u32,
    /// The next sample of area light `light`.
    pub sample: u32,
    /// Padding.
    pub pad: [u32; 2],
}

/// Loop iterations (shadow rays, their BVH steps and triangle tests) one invocation of the shading
/// runs in a pass before it leaves the rest to the next. Mesa's software Vulkan (llvmpipe,
/// lavapipe) ends every loop of a SIMD group of 8 invocations for good once all the loops of that
/// group together have run 65,535 iterations (`LP_MAX_TGSI_LOOP_ITERATIONS`): a point's `spp`
/// shadow rays per area light pass that from about 1,800 rays on the Cornell box and 330 on Šibenik
/// (its points then come out wrong, silently). A pass runs at most this plus one ray's traversal
/// per invocation (at most 569 iterations for a group on the shared scenes, see `lib/trace.wgsl`):
/// even were the 8 lanes' iterations added up, 8 × (2,048 + 569) = 20,936 stays under the cap. On
/// other devices the passes cost little: a submission encodes as many as the last shading needed and
/// reads back 4 bytes per pass once, after them.
pub const PASS_BUDGET: u32 = 2048;

/// The most shading passes one submission encodes before it reads back how many points are left.
const MAX_PASSES_AT_ONCE: u32 = 16;

const _: () = assert!(
    size_of::<ShadeInput>() == 32
        && size_of::<PrimShading>() == 32
        && size_of::<GpuLight>() == 64
        && size_of::<CausticPlane>() == 48
        && size_of::<ShadeParams>() == 32
        && size_of::<ShadeState>() == 32
);

/// Bytes before the first [`ShadeState`] in the state buffer (the unfinished count and padding).
pub(crate) const STATE_HEADER: u64 = 16;

/// The shading pass for one scene: its lights uploaded, its triangles' normals and materials kept.
pub struct PointShader {
    pipeline: wgpu::ComputePipeline,
    prims: Vec<PrimShading>,
    /// [`Self::prepare`] without caustics, made once: it depends on the scene alone.
    plain: ShadeScene,
    /// The last [`Self::prepare`] with caustics, under the maps' [`IrradianceMap::content_id`] and
    /// texel size: the frames of a scene share one made-once map, uploaded once (1.2 M texels on
    /// the wavy lake, 4 ms of host time a frame when uploaded every frame).
    caustic: Option<((u64, u32), ShadeScene)>,
    lights: wgpu::Buffer,
    light_count: u32,
    eps: f32,
    /// Passes the last shading took (of shadings checked together, the most demanding): how many
    /// the next one encodes in its first submission.
    passes: AtomicU32,
}

impl PointShader {
    /// The pass for `scene`.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let lights: Vec<GpuLight> = scene.lights.iter().map(GpuLight::new).collect();
        let prims: Vec<PrimShading> = (0..scene.triangles.len() as u32)
            .map(|i| {
                let (kind, color) = match scene.material(i) {
                    Material::Emissive { radiance } => (SURFACE_EMISSIVE, radiance),
                    Material::Diffuse { albedo } | Material::Glossy { albedo, .. } => (SURFACE_REFLECTING, albedo),
                    _ => (SURFACE_UNSHADED, Vec3::ZERO),
                };
                PrimShading { normal: scene.normal(i).to_array(), kind, color: color.to_array(), plane: -1 }
            })
            .collect();
        Ok(Self {
            pipeline: compute_pipeline(gpu, "raytrace", "shade")?,
            plain: upload_shading(gpu, prims.clone(), None),
            caustic: None,
            prims,
            lights: storage(gpu, "lights", &lights, wgpu::BufferUsages::empty()),
            light_count: lights.len() as u32,
            eps: shading_eps(scene),
            passes: AtomicU32::new(1),
        })
    }

    /// True when the pass shades points of triangle `prim` (diffuse, glossy, emissive).
    #[must_use]
    pub fn shades(scene: &Scene, prim: u32) -> bool {
        matches!(scene.material(prim), Material::Diffuse { .. } | Material::Glossy { .. } | Material::Emissive { .. })
    }

    /// The triangles' shading and the irradiance maps of `caustics` on the GPU, for
    /// [`shade_into`](Self::shade_into): uploaded once for maps of the same
    /// [`IrradianceMap::content_id`] (and texel size), again after the maps change.
    #[must_use]
    pub fn prepare(&mut self, gpu: &Gpu, caustics: Option<&IrradianceMap>) -> ShadeScene {
        let Some(map) = caustics else { return self.plain.clone() };
        let key = (map.content_id(), map.texel.to_bits());
        match &self.caustic {
            Some((k, scene)) if *k == key => scene.clone(),
            _ => self.caustic.insert((key, upload_shading(gpu, self.prims.clone(), caustics))).1.clone(),
        }
    }

    /// The radiance of `points` (all of triangles the pass [`shades`](Self::shades)), shadow rays
    /// through `tracer`'s BVH (`spp` per area light), with the irradiance of `caustics`.
    pub fn shade(
        &mut self,
        gpu: &Gpu,
        tracer: &RayTracer,
        caustics: Option<&IrradianceMap>,
        spp: u32,
        points: &[ShadePoint],
    ) -> Result<Vec<Vec3>, GpuError> {
        if points.is_empty() {
            return Ok(Vec::new());
        }
        let prepared = self.prepare(gpu, caustics);
        let mut out = Vec::with_capacity(points.len());
        for batch in points.chunks(Self::max_points(gpu)) {
            checked(gpu, || {
                let (encoder, shaded) = self.shade_into(gpu, tracer, &prepared, spp, batch, 0)?;
                let size = (batch.len() * 16) as u64;
                let radiance: Vec<[f32; 4]> = read_back(gpu, encoder, &shaded, size)?;
                out.extend(radiance.iter().map(|r| Vec3::new(r[0], r[1], r[2])));
                Ok(())
            })?;
        }
        Ok(out)
    }

    /// Points one [`shade_into`](Self::shade_into) takes on `gpu`: their inputs (32 bytes each) and
    /// their state (32 bytes each after a 16-byte header) within one storage binding.
    #[must_use]
    pub fn max_points(gpu: &Gpu) -> usize {
        ((max_binding(gpu).saturating_sub(STATE_HEADER) / size_of::<ShadeState>() as u64) as usize).max(1)
    }

    /// The radiance of `points` (at most [`max_points`](Self::max_points), with `extra` at most as
    /// many again) shaded, in passes of bounded work ([`PASS_BUDGET`]) submitted and waited for, in a
    /// buffer (`vec4` each) with room for `extra` more after them; and an encoder for the caller's
    /// next work.
    pub fn shade_into(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        scene: &ShadeScene,
        spp: u32,
        points: &[ShadePoint],
        extra: usize,
    ) -> Result<(wgpu::CommandEncoder, Scratch), GpuError> {
        let inputs: Vec<ShadeInput> = points.par_iter().map(ShadeInput::new).collect();
        let input = storage(gpu, "shade points", &inputs, wgpu::BufferUsages::empty());
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        let shaded = self.shade_inputs(gpu, tracer, scene, spp, (&input, points.len(), extra), None, &mut encoder)?;
        Ok((encoder, shaded.radiance))
    }

    /// [`shade_into`](Self::shade_into) of the first `count` [`ShadeInput`]s of `input`, a buffer
    /// already on the GPU, with room for `extra` more after them. The radiance (and the room after
    /// it) is zeroed, and the passes shade it, in `encoder` after the caller's work there (such as
    /// copies into `input`). With `checks` that do not wait (given by [`Self::shade_checked`]), the
    /// passes are not waited for, nor submitted: the caller submits `encoder` (holding the returned
    /// [`Shaded`] until then) before any other work reads the radiance or adds to it, and the
    /// radiance is whole once `shade_checked` says so. Otherwise they are submitted with what
    /// `encoder` held and waited for, leaving it empty (but for the clearing where there are no
    /// points, which the caller submits all the same).
    pub fn shade_inputs(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        scene: &ShadeScene,
        spp: u32,
        (input, count, extra): (&wgpu::Buffer, usize, usize),
        mut checks: Option<&mut ShadeChecks>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Shaded, GpuError> {
        let params = ShadeParams {
            eps: self.eps,
            inv_texel_area: scene.inv_texel_area,
            lights: self.light_count,
            points: count as u32,
            spp: spp.max(1),
            budget: PASS_BUDGET,
            pad: [0; 2],
        };
        let uniform = uniform(gpu, "shade params", bytemuck::bytes_of(&params));
        // Scratch buffers (a frame's shadings made and freed 240 MB of them on the glass lens),
        // zeroed: the radiance and the room after it (the Whitted rays add to it), and the state,
        // where every point starts at its first light.
        let out = scratch(gpu, "radiance", ((count + extra) * 16) as u64);
        let new_encoder = || gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        encoder.clear_buffer(&out, 0, None);
        if count == 0 {
            // Cleared before the caller adds to it.
            return Ok(Shaded { radiance: out, _state: None });
        }
        let state = scratch(gpu, "shade state", STATE_HEADER + (count * size_of::<ShadeState>()) as u64);
        encoder.clear_buffer(&state, 0, None);
        let (nodes, triangles) = tracer.buffers();
        let flux = scene.flux.create_view(&Default::default());
        let mut entries: Vec<wgpu::BindGroupEntry<'_>> = [
            (0, nodes),
            (1, triangles),
            (4, &uniform),
            (5, input),
            (6, &scene.prims),
            (7, &self.lights),
            (8, &scene.planes),
            (10, &out),
            (11, &state),
        ]
        .into_iter()
        .map(|(binding, b)| buffer_entry(binding, b))
        .collect();
        entries.push(view_entry(9, &flux));
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shade"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        // Passes until no point is left unfinished (each moves every unfinished point on by at least
        // one light or shadow ray). A submission encodes as many passes as the last shading needed,
        // so that a frame's shadings mostly wait once each: a pass after a point is shaded leaves it
        // as it is (it only reads its state), so the radiance is the same however many are encoded.
        // Each pass counts the points it leaves unfinished afresh, copied out after it.
        let last = self.passes.load(Ordering::Relaxed);
        let passes = last.clamp(1, MAX_PASSES_AT_ONCE);
        let left_after = output(gpu, "shade passes", 4 * u64::from(MAX_PASSES_AT_ONCE));
        // Unchecked where the frame checks its shadings at its end, unless the last one needed
        // more passes than one submission encodes.
        if let Some(checks) = checks.as_deref_mut().filter(|c| !c.wait() && last <= MAX_PASSES_AT_ONCE) {
            self.encode_passes(encoder, &bind, (&state, &left_after), count, passes);
            checks.add(left_after, passes);
            return Ok(Shaded { radiance: out, _state: Some(state) });
        }
        let mut first = Some(std::mem::replace(encoder, new_encoder()));
        let mut total = 0;
        loop {
            let mut encoder = first.take().unwrap_or_else(new_encoder);
            self.encode_passes(&mut encoder, &bind, (&state, &left_after), count, passes);
            let left: Vec<u32> = read_back(gpu, encoder, &left_after, 4 * u64::from(passes))?;
            match left.iter().position(|&n| n == 0).or(left.is_empty().then_some(0)) {
                Some(k) => {
                    total += k as u32 + 1;
                    break;
                }
                None => total += passes,
            }
        }
        self.passes.store(total, Ordering::Relaxed);
        if let Some(checks) = checks {
            checks.waited(total);
        }
        Ok(Shaded { radiance: out, _state: None })
    }

    /// Add to `encoder` `passes` shading passes over `count` points bound by `bind`, each followed
    /// by the copy of the count of points it left unfinished (the first word of `state`) to its
    /// word of `left`.
    fn encode_passes(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind: &wgpu::BindGroup,
        (state, left): (&wgpu::Buffer, &wgpu::Buffer),
        count: usize,
        passes: u32,
    ) {
        for k in 0..passes {
            encoder.clear_buffer(state, 0, Some(4));
            compute_pass(encoder, &self.pipeline, bind, count.div_ceil(WORKGROUP_SIZE as usize) as u32);
            encoder.copy_buffer_to_buffer(state, 0, left, 4 * u64::from(k), 4);
        }
    }

    /// `shade(checks)`, each of whose shadings is given `checks`: submitted unchecked, their counts
    /// read back in one wait at the end. Where one was left unfinished (its radiance incomplete),
    /// `shade` again with shadings that wait for their own counts. The next shadings encode as
    /// many passes as the most demanding of these needed.
    pub fn shade_checked<T>(
        &self,
        gpu: &Gpu,
        mut shade: impl FnMut(&mut ShadeChecks) -> Result<T, GpuError>,
    ) -> Result<T, GpuError> {
        let mut checks = ShadeChecks::unchecked();
        let out = shade(&mut checks)?;
        if self.verify(gpu, &mut checks)? {
            return Ok(out);
        }
        let mut checks = ShadeChecks::waiting();
        let out = shade(&mut checks)?;
        self.verify(gpu, &mut checks)?;
        Ok(out)
    }

    /// Whether every shading given `checks` finished its points (the counts of those submitted
    /// unchecked read back in one wait); the next shadings encode as many passes as the most
    /// demanding of them needed.
    fn verify(&self, gpu: &Gpu, checks: &mut ShadeChecks) -> Result<bool, GpuError> {
        let needed = checks.needed(gpu)?;
        if let Some(passes) = needed {
            self.passes.store(passes, Ordering::Relaxed);
        }
        Ok(needed.is_some())
    }
}

/// A shading's radiance ([`PointShader::shade_inputs`]), and the state its passes use: held
/// until the encoder they were added to is submitted (a scratch buffer handed back before then
/// could be another shading's state in the same submission).
pub struct Shaded {
    /// The radiance, a `vec4` per point and per room after them.
    pub radiance: Scratch,
    /// The points' state, while their passes wait to be submitted.
    _state: Option<Scratch>,
}

/// `prims` (the scene's triangles' shading, [`PointShader`]'s) and the irradiance maps of `caustics`
/// on the GPU ([`PointShader::prepare`]).
fn upload_shading(gpu: &Gpu, mut prims: Vec<PrimShading>, caustics: Option<&IrradianceMap>) -> ShadeScene {
    let mut planes = Vec::new();
    let mut flux: Vec<[f32; 4]> = Vec::new();
    if let Some(map) = caustics {
        // Which plane each triangle's points read: the front grid of it (the back one next).
        for (i, p) in prims.iter_mut().enumerate() {
            p.plane = map.plane_of(i as u32).map_or(-1, |k| 2 * k as i32);
        }
        for (origin, axes, size, texels) in map.grids() {
            // A side that received nothing has no texels: a grid of none, read as zero.
            let size = if texels.is_empty() { [0, 0] } else { size };
            planes.push(CausticPlane {
                origin: origin.to_array(),
                offset: flux.len() as u32,
                axis_u: axes[0].to_array(),
                width: size[0],
                axis_v: axes[1].to_array(),
                height: size[1],
            });
            flux.extend(texels.iter().map(|f| [f.x, f.y, f.z, 0.0]));
        }
    }
    let texel = caustics.map_or(1.0, |m| m.texel);
    ShadeScene {
        prims: storage(gpu, "prim shading", &prims, wgpu::BufferUsages::empty()),
        planes: storage(gpu, "caustic planes", &planes, wgpu::BufferUsages::empty()),
        flux: crate::texels::upload(gpu, "caustic flux", &flux, wgpu::TextureFormat::Rgba32Uint),
        inv_texel_area: 1.0 / (texel * texel),
    }
}

/// A scene's triangles' shading and caustic irradiance maps on the GPU ([`PointShader::prepare`]);
/// equal where they are the same upload.
#[derive(Clone, PartialEq)]
pub struct ShadeScene {
    prims: wgpu::Buffer,
    planes: wgpu::Buffer,
    /// The maps' flux texels (rgb as `f32` bits), [`crate::texels`]: no binding bounds their number.
    flux: wgpu::Texture,
    inv_texel_area: f32,
}

/// The 32-bit seed the shader gets for a point's 64-bit seed.
#[must_use]
pub fn seed32(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}
