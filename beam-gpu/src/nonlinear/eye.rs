//! The eye's view of a frame on the GPU (`shaders/eye.wgsl`, 000 §7.3): every pixel's primary ray
//! made and traced there. The diffuse, glossy and emissive hits of the crop become shading inputs
//! that stay on the GPU ([`KeptPoints`], shaded and written to the eye's level by the composite);
//! only the mirror and glass hits, from which the host builds the beam tree, are read back. CPU
//! twin: [`Camera::pixel_ray`] and the nearest hit of each ray.

use super::atlas::GpuBeams;
use super::composite::{CompositeRecord, GpuComposite};
use super::level::triangle_kinds;
use super::lookups::LookupBeams;
use super::whitted::GpuWhitted;
use crate::buffers::{
    buffer_entry, checked, compute_pipeline, encode_pass, output, read_all, storage, uniform, view_entry,
};
use crate::interface::NONE;
use crate::raytrace::RayTracer;
use crate::scratch::{Scratch, scratch};
use crate::shade::ShadeInput;
use crate::texels;
use crate::{Gpu, GpuError};
use beam_bvh::Hit;
use beam_math::glam::Vec3;
use beam_math::{Ray, Triangle};
use beam_render::BackendError;
use beam_render::nonlinear::{CoarseByRays, EyeFaces, EyeView, SMesh, ShadePoint, TexelRadiance, eye_by_rays};
use beam_render::options::{RenderOptions, Shading};
use beam_scene::region::PixelRect;
use beam_scene::scene::{Camera, Scene};
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;
use std::sync::PoisonError;
use std::time::Instant;

/// The camera's frame and one dispatch's pixels.
///
/// WGSL twin: `EyeParams` in `shaders/eye.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct EyeParams {
    /// Eye position.
    pub position: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Unit view direction (of the camera's frame, `Camera::frame`).
    pub forward: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Unit right vector.
    pub right: [f32; 3],
    /// First pixel of the dispatch (row-major).
    pub first: u32,
    /// Unit up vector.
    pub up: [f32; 3],
    /// Pixels of the dispatch.
    pub count: u32,
    /// Half width of the image plane at distance 1.
    pub half_width: f32,
    /// Half height of the image plane at distance 1.
    pub half_height: f32,
    /// `eye_records`: the scene's diagonal, where a texel's ray leaves the scene (beam-cpu's
    /// `reproject`).
    pub far: f32,
    /// Padding.
    pub pad: u32,
    /// The crop, `[x0, y0, x1, y1]`: only its diffuse, glossy and emissive hits are kept.
    pub crop: [u32; 4],
}

/// A mirror or glass hit of the eye's view, read back for the host.
///
/// WGSL twin: `EyeHit` in `shaders/eye.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct EyeHit {
    /// The pixel (row-major).
    pub pixel: u32,
    /// The scene triangle hit.
    pub prim: u32,
    /// The ray parameter of the hit (the ray from the eye through the pixel's centre on the image
    /// plane at distance 1).
    pub t: f32,
    /// The S-mesh face its point maps to: its triangle's own, or the candidate it lies nearest
    /// under a coarse face ([`LocateTable`]; [`SMesh::locate`]'s choice); [`NONE`] for none (a hit
    /// handed back).
    pub face: u32,
}

/// What one dispatch appended.
///
/// WGSL twin: `EyeCounts` in `shaders/eye.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct EyeCounts {
    /// Shading inputs kept.
    pub kept: u32,
    /// Hits appended for the host.
    pub others: u32,
    /// 1 + the largest pixel whose traversal overflowed its stack, 0 for none.
    pub overflow: u32,
    /// Mirror and glass hits kept.
    pub specular: u32,
}

/// What one dispatch of `eye_records` (or `level_records`) appended.
///
/// WGSL twin: `RecordCounts` in `shaders/eye.wgsl` and `shaders/level_points.wgsl` (layouts
/// compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RecordCounts {
    /// Composite records appended.
    pub records: u32,
    /// Points appended for the Whitted rays (no child beam).
    pub rest: u32,
    /// Of those, points under a coarse S-mesh face whose child beams do not hold their scattered
    /// rays (`eye_records`).
    pub uncovered: u32,
    /// Of those, points under a coarse S-mesh face on triangles with interpolated normals
    /// (`eye_records`: every one; `level_records`: the uncovered ones, as the host counts the
    /// others, and where the GPU summed the level's fits, the ones without child beams at their
    /// face, fine or coarse, which the host does not see).
    pub curved: u32,
    /// Records made under coarse S-mesh faces.
    pub coarse: u32,
    /// Padding.
    pub pad: [u32; 3],
}

const _: () = assert!(
    size_of::<EyeParams>() == 96
        && size_of::<EyeHit>() == 16
        && size_of::<EyeCounts>() == 16
        && size_of::<RecordCounts>() == 32
);

/// The shading inputs one dispatch of the eye's view kept on the GPU.
pub struct KeptPoints {
    /// [`ShadeInput`]s, `count` of them.
    pub inputs: Scratch,
    /// The pixel of each.
    pub targets: Scratch,
    /// How many.
    pub count: u32,
}

/// The mirror and glass hits of one dispatch of the eye's view kept on the GPU.
pub struct KeptSpecular {
    /// [`EyeHit`]s, `count` of them.
    pub hits: Scratch,
    /// How many.
    pub count: u32,
}

/// The S-mesh faces the eye's view maps its mirror and glass hits to on the GPU ([`GpuEye::run`]).
pub struct EyeFaceMap<'a> {
    /// Per scene triangle, its S-mesh face where it is the face itself, else [`NONE`].
    pub face_of: &'a wgpu::Buffer,
    /// The candidates that locate the hits under coarse faces (none: the host locates them).
    pub locate: Option<&'a LocateTable>,
    /// Faces of the S mesh.
    pub faces: usize,
}

/// An S mesh's candidates and corners on the GPU, for `eye.wgsl`'s `nearest_face`: the choice
/// of [`SMesh::locate`] for the points of the mirror and glass hits handed to the host, so that
/// the host does not make it (the mirror teapot's eye view hands back 182 K points a frame under
/// its 850 coarse faces, about five candidates each).
pub struct LocateTable {
    /// Per scene triangle `p`, at `2p` and `2p + 1`, the range in this buffer of its candidates.
    candidates: wgpu::Buffer,
    /// Per face, its three vertices (`[f32; 4]`, w unused).
    corners: wgpu::Buffer,
}

/// What the composite records of points under coarse S-mesh faces read (`lib/coarse.wgsl`): the
/// S mesh's candidates and corners, the child level's beams, the scene's mirror and glass
/// triangles, and the scene's diagonal (where a texel's ray leaves the scene).
pub struct CoarseBindings<'a> {
    /// Per scene triangle, its kind ([`LEVEL_CURVED`](crate::interface::LEVEL_CURVED) counts
    /// the points on curved triangles that go to the rays).
    pub(super) kinds: &'a wgpu::Buffer,
    locate: &'a LocateTable,
    child_level: &'a LookupBeams,
    specular: (&'a wgpu::Buffer, &'a wgpu::TextureView),
    /// The scene's diagonal.
    pub far: f32,
}

impl CoarseBindings<'_> {
    /// Their entries from binding `first` on, in `lib/coarse.wgsl`'s order: `candidates`,
    /// `corners`, `child_beams`, `texel_t`, `slots`, `specular_prims`.
    pub(super) fn entries(&self, first: u32) -> [wgpu::BindGroupEntry<'_>; 6] {
        [
            buffer_entry(first, &self.locate.candidates),
            buffer_entry(first + 1, &self.locate.corners),
            buffer_entry(first + 2, &self.child_level.beams),
            buffer_entry(first + 3, &self.child_level.depths),
            buffer_entry(first + 4, self.specular.0),
            view_entry(first + 5, self.specular.1),
        ]
    }
}

impl LocateTable {
    /// The candidates of `scene`'s triangles among the faces of `smesh`, and its faces' corners,
    /// uploaded (on a fine S mesh, a triangle's lone candidate is its own face: the levels'
    /// fits locate their texels by it, [`super::FitTable`]).
    pub fn new(gpu: &Gpu, scene: &Scene, smesh: &SMesh) -> Self {
        let triangles = scene.triangles.len() as u32;
        let mut table = Vec::with_capacity(2 * triangles as usize);
        let mut lists = Vec::new();
        for p in 0..triangles {
            let start = 2 * triangles + lists.len() as u32;
            lists.extend_from_slice(smesh.candidates(p));
            table.extend([start, 2 * triangles + lists.len() as u32]);
        }
        table.extend(lists);
        let corners: Vec<[f32; 4]> = smesh.faces.iter().flat_map(|f| f.v.map(|v| v.extend(0.0).to_array())).collect();
        Self::upload(gpu, &table, &corners)
    }

    /// Per scene triangle `p`, at `2p` and `2p + 1`, the range in this buffer of its candidates.
    pub(super) fn candidates(&self) -> &wgpu::Buffer {
        &self.candidates
    }

    /// Per face, its three vertices.
    pub(super) fn corners(&self) -> &wgpu::Buffer {
        &self.corners
    }

    /// No candidates: every hit's face [`NONE`].
    fn none(gpu: &Gpu) -> Self {
        Self::upload(gpu, &[], &[])
    }

    /// `table` and `corners` uploaded; an empty one as the smallest one with no candidate (a
    /// binding is never empty).
    fn upload(gpu: &Gpu, table: &[u32], corners: &[[f32; 4]]) -> Self {
        let none = wgpu::BufferUsages::empty();
        let table = if table.is_empty() { &[0, 0][..] } else { table };
        let corners = if corners.is_empty() { &[[0.0; 4]; 3][..] } else { corners };
        Self {
            candidates: storage(gpu, "S-mesh candidates of the triangles", table, none),
            corners: storage(gpu, "S-mesh corners", corners, none),
        }
    }
}

/// The composite records `eye_records` made of one dispatch's kept mirror and glass hits (or
/// `level_records` of one dispatch's texels handed to the host).
pub struct EyeRecords {
    /// [`CompositeRecord`]s (faces and child beams indexed in the whole S mesh and level).
    pub records: Scratch,
    /// How many.
    pub count: u32,
    /// Points for the Whitted rays, with their pixels.
    pub rest: KeptPoints,
    /// Under coarse faces: the records made, and of the points for the Whitted rays those no
    /// child beam held and those on curved triangles ([`RecordCounts`]'s `coarse`, `uncovered`,
    /// `curved`).
    pub coarse: [u32; 3],
}

/// What the eye's view returns ([`GpuEye::run`]).
pub struct EyeOut {
    /// Per dispatch, the kept diffuse, glossy and emissive points of the crop.
    pub kept: Vec<KeptPoints>,
    /// Per dispatch, the kept mirror and glass hits.
    pub specular: Vec<KeptSpecular>,
    /// The hits for the host, in pixel order.
    pub others: Vec<EyeHit>,
    /// Per S-mesh face, the kept hits that see it: of the frame, of the crop.
    pub seen: Vec<[u32; 2]>,
}

/// The eye's view pass.
pub struct GpuEye {
    pipeline: wgpu::ComputePipeline,
    records: wgpu::ComputePipeline,
    /// Per scene triangle: [`LEVEL_PLAIN`] where the shading pass shades it, `|` [`LEVEL_CURVED`]
    /// where its normals are interpolated.
    kinds: wgpu::Buffer,
    /// Per scene triangle: [`NONE`] (no S-mesh face on the GPU: every mirror and glass hit for
    /// the host).
    no_faces: wgpu::Buffer,
    /// No candidates (no hit located).
    no_locate: LocateTable,
    /// No beams to look up.
    no_beams: LookupBeams,
}

impl GpuEye {
    /// Compile the passes and upload the kinds of `scene`'s triangles.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let kinds = triangle_kinds(scene);
        let no_faces = vec![NONE; scene.triangles.len()];
        Ok(Self {
            pipeline: compute_pipeline(gpu, "eye", "eye_view")?,
            records: compute_pipeline(gpu, "eye", "eye_records")?,
            kinds: storage(gpu, "triangle kinds", &kinds, wgpu::BufferUsages::empty()),
            no_faces: storage(gpu, "no S-mesh faces", &no_faces, wgpu::BufferUsages::empty()),
            no_locate: LocateTable::none(gpu),
            no_beams: LookupBeams::upload(gpu, &[])?.ok_or(GpuError::Internal("no beams past a binding"))?,
        })
    }

    /// The camera's frame and `count` items from pixel `first` on.
    fn params(camera: &Camera, crop: PixelRect, (first, count): (usize, usize)) -> EyeParams {
        let frame = camera.frame();
        EyeParams {
            position: camera.position.to_array(),
            width: camera.width,
            forward: frame.forward.to_array(),
            height: camera.height,
            right: frame.right.to_array(),
            first: first as u32,
            up: frame.up.to_array(),
            count: count as u32,
            half_width: frame.half_width,
            half_height: frame.half_height,
            far: 0.0,
            pad: 0,
            crop: [crop.x0, crop.y0, crop.x1, crop.y1],
        }
    }

    /// The eye's view of `camera` in dispatches of as many pixels as a composite dispatch takes
    /// texels: per dispatch, the diffuse, glossy and emissive hits of `crop` kept as shading inputs,
    /// the mirror and glass hits of the frame on triangles that `faces` maps to S-mesh faces kept
    /// (and counted per face), and the other mirror and glass hits of the frame, in pixel order.
    pub fn run(
        &self,
        gpu: &Gpu,
        tracer: &RayTracer,
        camera: &Camera,
        crop: PixelRect,
        faces: Option<EyeFaceMap<'_>>,
    ) -> Result<EyeOut, GpuError> {
        let pixels = camera.width as usize * camera.height as usize;
        let chunk = GpuComposite::records_per_dispatch(gpu);
        let (nodes, triangles) = tracer.buffers();
        let (face_of, locate, face_count) = faces.map_or((&self.no_faces, None, 0), |f| (f.face_of, f.locate, f.faces));
        let locate = locate.unwrap_or(&self.no_locate);
        // Zeroed by wgpu.
        let seen = output(gpu, "faces seen", (face_count * 8) as u64);
        let mut dispatched = Vec::new();
        let mut encoders = Vec::new();
        for first in (0..pixels).step_by(chunk) {
            let count = chunk.min(pixels - first);
            let params = Self::params(camera, crop, (first, count));
            let size = |bytes: usize| (count * bytes) as u64;
            let inputs = scratch(gpu, "eye points", size(size_of::<ShadeInput>()));
            let targets = scratch(gpu, "eye targets", size(4));
            let others = scratch(gpu, "eye hits", size(size_of::<EyeHit>()));
            let specular = scratch(gpu, "eye mirror and glass hits", size(size_of::<EyeHit>()));
            // Zeroed by wgpu.
            let counts = output(gpu, "eye counts", size_of::<EyeCounts>() as u64);
            let params = uniform(gpu, "eye params", bytemuck::bytes_of(&params));
            let entries = [
                buffer_entry(0, nodes),
                buffer_entry(1, triangles),
                buffer_entry(2, &params),
                buffer_entry(3, &self.kinds),
                buffer_entry(4, &inputs),
                buffer_entry(5, &targets),
                buffer_entry(6, &others),
                buffer_entry(7, &counts),
                buffer_entry(8, face_of),
                buffer_entry(9, &seen),
                buffer_entry(10, &specular),
                buffer_entry(16, &locate.candidates),
                buffer_entry(17, &locate.corners),
            ];
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            encode_pass(gpu, &mut encoder, &self.pipeline, count as u32, &entries);
            encoders.push(encoder.finish());
            dispatched.push((inputs, targets, others, specular, counts));
        }
        // One submission with the counts' copy: a second would wait for the first where it is made
        // (lavapipe), uncounted as a wait on the device.
        let counts = dispatched.iter().map(|(.., counts)| (counts, size_of::<EyeCounts>() as u64));
        let counts = counts.chain(std::iter::once((&seen, (face_count * 8) as u64)));
        let words: Vec<u32> = read_all(gpu, encoders, counts)?;
        let (all_counts, seen) = words.split_at(dispatched.len() * 4);
        let all_counts: Vec<EyeCounts> = bytemuck::pod_collect_to_vec(all_counts);
        if let Some(c) = all_counts.iter().find(|c| c.overflow > 0) {
            return Err(GpuError::StackOverflow { ray: c.overflow as usize - 1 });
        }
        let hit_bytes = |n: u32| u64::from(n) * size_of::<EyeHit>() as u64;
        let sources = dispatched.iter().zip(&all_counts).map(|((.., o, _, _), c)| (&**o, hit_bytes(c.others)));
        let mut others: Vec<EyeHit> = read_all(gpu, Vec::new(), sources)?;
        // Appended in any order: put back in pixel order.
        others.par_sort_unstable_by_key(|h| h.pixel);
        let (mut kept, mut specular) = (Vec::new(), Vec::new());
        for ((inputs, targets, _, hits, _), c) in dispatched.into_iter().zip(&all_counts) {
            kept.push(KeptPoints { inputs, targets, count: c.kept });
            specular.push(KeptSpecular { hits, count: c.specular });
        }
        Ok(EyeOut { kept, specular, others, seen: bytemuck::pod_collect_to_vec(seen) })
    }

    /// `locate` where given, else the stand-in with no candidate.
    pub(super) fn locate_or_none<'a>(&'a self, locate: Option<&'a LocateTable>) -> &'a LocateTable {
        locate.unwrap_or(&self.no_locate)
    }

    /// What a composite under coarse faces reads ([`CoarseBindings`]): `locate` and the child
    /// level `child_level` where given (stand-ins with no candidate and no beam otherwise), the
    /// mirror and glass triangles of `specular`, the diagonal `far`.
    pub fn coarse<'a>(
        &'a self,
        locate: Option<&'a LocateTable>,
        child_level: Option<&'a LookupBeams>,
        specular: &'a GpuWhitted,
        far: f32,
    ) -> CoarseBindings<'a> {
        CoarseBindings {
            kinds: &self.kinds,
            locate: locate.unwrap_or(&self.no_locate),
            child_level: child_level.unwrap_or(&self.no_beams),
            specular: specular.specular_prims(),
            far,
        }
    }

    /// The composite records of the hits inside the crop that the eye's view `kept`, per dispatch,
    /// and the points of faces without child beams (or whose child beams do not hold a point's
    /// scattered rays, under a coarse face) for the Whitted rays: `children` per S-mesh face, its
    /// reflection and refraction beams in the tree's first level ([`NONE`] for none), which a
    /// point under a coarse face looks up for its own scattered rays (`coarse`, its child level
    /// the tree's first).
    pub fn records(
        &self,
        gpu: &Gpu,
        kept: &KeptEyeHits,
        children: &wgpu::Buffer,
        coarse: &CoarseBindings<'_>,
    ) -> Result<Vec<EyeRecords>, GpuError> {
        let (camera, crop) = &kept.view;
        let far = coarse.far;
        let mut encoders = Vec::new();
        let mut outs = Vec::new();
        for list in &kept.lists {
            let count = list.count as usize;
            let params = EyeParams { far, ..Self::params(camera, *crop, (0, count)) };
            let params = uniform(gpu, "eye params", bytemuck::bytes_of(&params));
            let out = RecordOutputs::new(gpu, count);
            let entries = [
                buffer_entry(2, &params),
                buffer_entry(3, &self.kinds),
                buffer_entry(8, &kept.face_of),
                buffer_entry(10, &list.hits),
                buffer_entry(11, children),
                buffer_entry(12, &out.records),
                buffer_entry(13, &out.inputs),
                buffer_entry(14, &out.targets),
                buffer_entry(15, &out.counts),
            ];
            let entries: Vec<_> = entries.into_iter().chain(coarse.entries(16)).collect();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            encode_pass(gpu, &mut encoder, &self.records, count as u32, &entries);
            encoders.push(encoder.finish());
            outs.push(out);
        }
        RecordOutputs::read(gpu, encoders, outs)
    }
}

/// The outputs of one dispatch that makes the composite records of `count` points (`eye_records`,
/// `level_records`): the records, the points for the Whitted rays and their targets, the counts.
pub(super) struct RecordOutputs {
    pub records: Scratch,
    pub inputs: Scratch,
    pub targets: Scratch,
    /// [`RecordCounts`], zeroed by wgpu.
    pub counts: wgpu::Buffer,
}

impl RecordOutputs {
    /// Room for `count` points' records or Whitted points.
    pub(super) fn new(gpu: &Gpu, count: usize) -> Self {
        Self {
            records: scratch(gpu, "records", (count * size_of::<CompositeRecord>()) as u64),
            inputs: scratch(gpu, "points past the tree", (count * size_of::<ShadeInput>()) as u64),
            targets: scratch(gpu, "targets past the tree", count as u64 * 4),
            counts: output(gpu, "record counts", size_of::<RecordCounts>() as u64),
        }
    }

    /// Submit `encoders` (which fill `outs`) and read their counts back: the records made.
    pub(super) fn read(
        gpu: &Gpu,
        encoders: Vec<wgpu::CommandBuffer>,
        outs: Vec<Self>,
    ) -> Result<Vec<EyeRecords>, GpuError> {
        let sources = outs.iter().map(|o| (&o.counts, size_of::<RecordCounts>() as u64));
        let counts: Vec<RecordCounts> = read_all(gpu, encoders, sources)?;
        Ok(outs
            .into_iter()
            .zip(counts)
            .map(|(o, c)| EyeRecords {
                records: o.records,
                count: c.records,
                rest: KeptPoints { inputs: o.inputs, targets: o.targets, count: c.rest },
                coarse: [c.coarse, c.uncovered, c.curved],
            })
            .collect())
    }
}

/// The mirror and glass hits of a frame's eye view kept on the GPU, until the composite makes
/// their records.
pub struct KeptEyeHits {
    /// Per dispatch of the eye's view.
    pub lists: Vec<KeptSpecular>,
    /// Per scene triangle, its S-mesh face where it is the face itself, else [`NONE`].
    pub face_of: wgpu::Buffer,
    /// The candidates that located the hits under coarse faces, and locate the levels' texels.
    pub locate: LocateTable,
    /// The frame's camera and crop.
    pub view: (Camera, PixelRect),
}

impl GpuBeams<'_> {
    /// The eye's view on the GPU with `faces` (where given, its mirror and glass hits on them kept),
    /// or `None` where the composite will not shade the frame (shading not exact, the eye's level
    /// past one texture).
    fn eye_on_gpu(
        &self,
        camera: &Camera,
        options: &RenderOptions,
        faces: Option<EyeFaceMap<'_>>,
    ) -> Result<Option<EyeOut>, GpuError> {
        let pixels = camera.width as usize * camera.height as usize;
        if options.shading != Shading::Exact || !texels::fits(self.gpu, pixels) {
            return Ok(None);
        }
        let start = Instant::now();
        let out = checked(self.gpu, || self.eye.run(self.gpu, &self.tracer, camera, options.region(), faces));
        self.add_times(|t| t.ray_seconds += start.elapsed().as_secs_f64());
        Ok(Some(out?))
    }

    /// `hits` (the tracer's triangle and t) as `(pixel, ray, hit)` with the barycentric weights of
    /// each hit point. Written in place by an indexed collect where every hit names a triangle of
    /// the scene (a filtered collect gathers lists and copies them once more).
    fn eye_hits(scene: &Scene, camera: &Camera, hits: &[EyeHit]) -> Vec<(usize, Ray, Hit)> {
        let frame = camera.frame();
        let hit = |h: &EyeHit, tri: &Triangle| {
            let ray = camera.pixel_ray(&frame, h.pixel as usize);
            let w = tri.barycentric(ray.at(h.t)).unwrap_or_default();
            (h.pixel as usize, ray, Hit { prim: h.prim, t: h.t, u: w.y, v: w.z })
        };
        let on = |h: &EyeHit| scene.triangles.get(h.prim as usize);
        if hits.par_iter().all(|h| on(h).is_some()) {
            let mut out = Vec::with_capacity(hits.len());
            hits.par_iter().map(|h| hit(h, &scene.triangles[h.prim as usize])).collect_into_vec(&mut out);
            return out;
        }
        hits.par_iter().filter_map(|h| Some(hit(h, on(h)?))).collect()
    }
}

impl EyeView for GpuBeams<'_> {
    /// On the GPU ([`GpuEye`]) where the composite will shade the frame (exact shading, the eye's
    /// level within one texture): the diffuse, glossy and emissive pixels of the region are kept
    /// there. Otherwise by the compute ray tracer, keeping none.
    fn eye_view(
        &self,
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Result<Vec<(usize, Ray, Hit)>, BackendError> {
        let Some(out) = self.eye_on_gpu(camera, options, None)? else {
            return eye_by_rays(self, scene, camera);
        };
        *self.kept.lock().unwrap_or_else(PoisonError::into_inner) = Some(out.kept);
        Ok(Self::eye_hits(scene, camera, &out.others))
    }

    /// Keeps the mirror and glass hits on S-mesh faces too, fine or coarse, each at its face
    /// (under a coarse one, the candidate its point lies nearest), unless
    /// [`GpuBeams::reading_levels_back`], where the composite takes the whole S mesh in one
    /// binding.
    fn eye_faces(
        &self,
        scene: &Scene,
        smesh: &SMesh,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Result<EyeFaces, BackendError> {
        if !self.keep_levels || !GpuComposite::faces_fit(self.gpu, smesh.faces.len()) {
            return Ok(EyeFaces::handed_back(self.eye_view(scene, camera, options)?, smesh));
        }
        let face_of = fine_faces(self.gpu, scene, smesh);
        let locate = LocateTable::new(self.gpu, scene, smesh);
        let faces = EyeFaceMap { face_of: &face_of, locate: Some(&locate), faces: smesh.faces.len() };
        let Some(out) = self.eye_on_gpu(camera, options, Some(faces))? else {
            return Ok(EyeFaces::handed_back(eye_by_rays(self, scene, camera)?, smesh));
        };
        *self.kept.lock().unwrap_or_else(PoisonError::into_inner) = Some(out.kept);
        let kept = out.specular.iter().map(|l| u64::from(l.count)).sum();
        *self.kept_eye_hits.lock().unwrap_or_else(PoisonError::into_inner) =
            Some(KeptEyeHits { lists: out.specular, face_of, locate, view: (*camera, options.region()) });
        Ok(EyeFaces { hits: Self::eye_hits(scene, camera, &out.others), seen: out.seen, kept })
    }

    /// The kept hits read back.
    fn take_kept_eye_hits(&self, scene: &Scene) -> Result<Vec<(usize, Ray, Hit)>, BackendError> {
        let Some(kept) = self.kept_eye_hits.lock().unwrap_or_else(PoisonError::into_inner).take() else {
            return Ok(Vec::new());
        };
        let sources = kept.lists.iter().map(|l| (&*l.hits, u64::from(l.count) * size_of::<EyeHit>() as u64));
        let mut hits: Vec<EyeHit> = checked(self.gpu, || read_all(self.gpu, Vec::new(), sources))?;
        hits.par_sort_unstable_by_key(|h| h.pixel);
        Ok(Self::eye_hits(scene, &kept.view.0, &hits))
    }

    fn take_coarse_by_rays(&self) -> CoarseByRays {
        std::mem::take(&mut *self.coarse_by_rays.lock().unwrap_or_else(PoisonError::into_inner))
    }

    /// The kept points read back; the shader's seed of each is its pixel.
    fn take_kept_eye(&self) -> Result<Vec<TexelRadiance>, BackendError> {
        let Some(kept) = self.kept.lock().unwrap_or_else(PoisonError::into_inner).take() else {
            return Ok(Vec::new());
        };
        let sources = kept.iter().map(|k| (&*k.inputs, u64::from(k.count) * size_of::<ShadeInput>() as u64));
        let inputs: Vec<ShadeInput> = checked(self.gpu, || read_all(self.gpu, Vec::new(), sources))?;
        Ok(inputs
            .par_iter()
            .map(|s| TexelRadiance {
                texel: s.seed,
                point: ShadePoint {
                    prim: s.prim,
                    p: Vec3::from_array(s.p),
                    d: Vec3::from_array(s.d),
                    seed: u64::from(s.seed),
                },
                composite: None,
            })
            .collect())
    }
}

/// Per scene triangle of `scene`, its face where it is a fine S-mesh face of its own, else
/// [`NONE`], uploaded.
pub(super) fn fine_faces(gpu: &Gpu, scene: &Scene, smesh: &SMesh) -> wgpu::Buffer {
    let face_of: Vec<u32> = (0..scene.triangles.len() as u32)
        .map(|p| match smesh.candidates(p) {
            &[f] if !smesh.is_coarse(f as usize) => f,
            _ => NONE,
        })
        .collect();
    storage(gpu, "S-mesh faces of the triangles", &face_of, wgpu::BufferUsages::empty())
}
