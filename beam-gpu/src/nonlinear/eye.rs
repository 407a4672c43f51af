//! The eye's view of a frame on the GPU (`shaders/eye.wgsl`, 000 §7.3): every pixel's primary ray
//! made and traced there. The diffuse, glossy and emissive hits of the crop become shading inputs
//! that stay on the GPU ([`KeptPoints`], shaded and written to the eye's level by the composite);
//! only the mirror and glass hits, from which the host builds the beam tree, are read back. CPU
//! twin: [`Camera::pixel_ray`] and the nearest hit of each ray.

use super::composite::GpuComposite;
use super::lookups::LookupBeams;
use super::records::{CoarseBindings, EyeRecords, KeptPoints, LocateTable, RecordOutputs, triangle_kinds};
use super::whitted::GpuWhitted;
use crate::buffers::{buffer_entry, compute_pipeline, encode_pass, output, read_all, storage, uniform};
use crate::interface::NONE;
use crate::raytrace::RayTracer;
use crate::scratch::{Scratch, scratch};
use crate::shade::ShadeInput;
use crate::{Gpu, GpuError};
use beam_render::nonlinear::SMesh;
use beam_scene::region::PixelRect;
use beam_scene::scene::{Camera, Scene};
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

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
    /// `eye_records`: the scene's diagonal, where a texel's ray leaves the scene (beam-render's
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

const _: () = assert!(size_of::<EyeParams>() == 96 && size_of::<EyeHit>() == 16 && size_of::<EyeCounts>() == 16);

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

/// What the eye's view returns ([`GpuEye::run`]): one frame's.
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

/// The eye's view passes (the frame's first stage), compiled with the renderer for one scene, for
/// its life; they keep nothing of a frame: [`GpuEye::run`] returns what it kept ([`EyeOut`]).
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
                buffer_entry(16, locate.candidates()),
                buffer_entry(17, locate.corners()),
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

/// The mirror and glass hits of a frame's eye view kept on the GPU (per frame, in the frame's
/// kept value), until the composite makes their records.
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
