//! What the eye's view, the tree's levels and the composite hand each other on the GPU: the
//! points kept for shading ([`KeptPoints`]), the composite records made of mirror and glass points
//! ([`CompositeRecord`], [`EyeRecords`]), and what those records read under coarse S-mesh faces
//! ([`LocateTable`], [`CoarseBindings`]). Data only, below the passes that make and read them
//! (`eye`, `level`, `composite`).

use super::lookups::LookupBeams;
use crate::buffers::{buffer_entry, output, read_all, storage, view_entry};
use crate::interface::{LEVEL_CURVED, LEVEL_PLAIN};
use crate::scratch::{Scratch, scratch};
use crate::shade::{PointShader, ShadeInput};
use crate::{Gpu, GpuError};
use beam_render::nonlinear::SMesh;
use beam_scene::scene::Scene;
use bytemuck::{Pod, Zeroable};

/// One composited texel of a level (on a specular face with child beams) for the composite pass.
///
/// WGSL twin: `Record` in `shaders/composite.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CompositeRecord {
    /// Where its face's reflection beam is looked up: the point its ray hit, or under a coarse
    /// S-mesh face the point of the face at [`Composite::reflected_at`](beam_render::nonlinear::Composite).
    pub p: [f32; 3],
    /// Its index in the level's radiance.
    pub texel: u32,
    /// Unit direction of the ray.
    pub d: [f32; 3],
    /// Its S-mesh face, as an index into the dispatch's faces (those its records reference).
    pub face: u32,
    /// Its face's reflection beam in the level below, as an index into the dispatch's regions.
    pub reflected: u32,
    /// Its face's refraction beam, likewise; [`NONE`](crate::interface::NONE) for none.
    pub refracted: u32,
    /// Padding.
    pub pad: [u32; 2],
    /// Where its face's refraction beam is looked up (as `p`, at `Composite::refracted_at`).
    pub refracted_p: [f32; 3],
    /// Padding.
    pub pad2: u32,
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
const _: () = assert!(size_of::<CompositeRecord>() == 64 && size_of::<RecordCounts>() == 32);

/// The shading inputs one dispatch of the eye's view (or of a kept level) kept on the GPU: one
/// frame's, until its composite shades them.
pub struct KeptPoints {
    /// [`ShadeInput`]s, `count` of them.
    pub inputs: Scratch,
    /// The pixel of each.
    pub targets: Scratch,
    /// How many.
    pub count: u32,
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
    /// The S mesh's candidates and corners.
    pub(super) locate: &'a LocateTable,
    /// The child level's beams.
    pub(super) child_level: &'a LookupBeams,
    /// The scene's mirror and glass triangles.
    pub(super) specular: (&'a wgpu::Buffer, &'a wgpu::TextureView),
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

    /// No candidates: every hit's face [`NONE`](crate::interface::NONE).
    pub(super) fn none(gpu: &Gpu) -> Self {
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
/// Per scene triangle of `scene`: [`LEVEL_PLAIN`] where the shading pass shades it, `|`
/// [`LEVEL_CURVED`] where its normals are interpolated (the eye's and the levels' passes).
pub(super) fn triangle_kinds(scene: &Scene) -> Vec<u32> {
    (0..scene.triangles.len() as u32)
        .map(|p| {
            let plain = if PointShader::shades(scene, p) { LEVEL_PLAIN } else { 0 };
            plain | if scene.smooth_normals.contains_key(&p) { LEVEL_CURVED } else { 0 }
        })
        .collect()
}
