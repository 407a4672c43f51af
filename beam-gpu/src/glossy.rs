//! The gather of the glossy light volumes (002) on the GPU (`shaders/glossy_gather.wgsl`): the
//! beams, their cones and the cone hierarchy built on the CPU ([`LightVolumes`]) are uploaded, and
//! one invocation per receiver point walks the hierarchy, with second-order shadow rays through the
//! GPU BVH, in passes of bounded work ([`PASS_BUDGET`]). CPU twin: [`LightVolumes::gather`].

use crate::buffers::{checked, compute_pipeline, dispatch, max_binding, output, read_back, storage, uniform};
use crate::interface::{SECOND_ORDER_SHADOWS, WORKGROUP_SIZE};
use crate::raytrace::RayTracer;
use crate::{Gpu, GpuError};
use beam_bvh::gpu::GpuBvh;
use beam_math::glam::Vec3;
use beam_math::glossy::VolumeMethod;
use beam_render::glossy::{BoundingCone, ConeNode, Gathered, GlossyOptions, LightVolumes};
use beam_render::tolerance::shading_eps;
use beam_scene::scene::Scene;
use bytemuck::{Pod, Zeroable};

/// A light beam.
///
/// WGSL twin: `LightBeam` in `shaders/glossy_gather.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLightBeam {
    /// First scatterer vertex.
    pub o0: [f32; 3],
    /// `Φs / I = Ω`.
    pub flux: f32,
    /// Second vertex.
    pub o1: [f32; 3],
    /// Micro-facet standard deviation (radians).
    pub sigma: f32,
    /// Third vertex.
    pub o2: [f32; 3],
    /// Index of its emitter (point light, or area light's stratum).
    pub light: u32,
    /// Unit direction at the first vertex.
    pub d0: [f32; 3],
    /// 1 for a negative shadow beam.
    pub shadow: u32,
    /// At the second vertex.
    pub d1: [f32; 3],
    /// Padding.
    pub pad0: u32,
    /// At the third vertex.
    pub d2: [f32; 3],
    /// Padding.
    pub pad1: u32,
    /// Light intensity times tint and Fresnel weight.
    pub power: [f32; 3],
    /// Padding.
    pub pad2: u32,
}

/// A bounding cone.
///
/// WGSL twin: `Cone` in `shaders/glossy_gather.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuCone {
    /// Apex.
    pub apex: [f32; 3],
    /// Cosine of the half-angle (−1: every point).
    pub cos: f32,
    /// Unit axis.
    pub axis: [f32; 3],
    /// Padding.
    pub pad: u32,
}

/// A node of the cone hierarchy.
///
/// WGSL twin: `ConeNode` in `shaders/glossy_gather.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuConeNode {
    /// Its cone's apex.
    pub apex: [f32; 3],
    /// Cosine of its half-angle.
    pub cos: f32,
    /// Its axis.
    pub axis: [f32; 3],
    /// Inner node: second child; leaf: first beam.
    pub right_or_first: u32,
    /// Beams of a leaf, 0 for an inner node.
    pub count: u32,
    /// The node after its subtree in depth-first order (the node count after the last): where the
    /// walk goes on when it skips or finishes the node.
    pub skip: u32,
    /// Padding.
    pub pad: [u32; 2],
}

/// A receiver point.
///
/// WGSL twin: `GatherPoint` in `shaders/glossy_gather.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GatherPoint {
    /// The point (offset off its surface).
    pub p: [f32; 3],
    /// Padding.
    pub pad0: u32,
    /// Its unit normal.
    pub n: [f32; 3],
    /// Padding.
    pub pad1: u32,
}

/// What a receiver point gathered, and (between the passes of [`GpuGather::gather`]) where its walk
/// of the hierarchy goes on.
///
/// WGSL twin: `Gathered` in `shaders/glossy_gather.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuGathered {
    /// Irradiance of the scattered beams.
    pub irradiance: [f32; 3],
    /// Bit `l`: a shadow beam of light `l` covers the point.
    pub shadowed: u32,
    /// Beams evaluated.
    pub tested: u32,
    /// The node the walk goes on at (done from the node count on).
    pub next: u32,
    /// Beams of leaf `next` already added.
    pub in_leaf: u32,
    /// Padding.
    pub pad: u32,
}

/// Uniforms of the gather.
///
/// WGSL twin: `GatherParams` in `shaders/glossy_gather.wgsl` (layouts compared in [`crate::interface`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GatherParams {
    /// Receiver points.
    pub points: u32,
    /// Nodes of the hierarchy.
    pub nodes: u32,
    /// [`SECOND_ORDER_SHADOWS`] or 0.
    pub flags: u32,
    /// Offset of shadow-ray ends off the scatterer.
    pub eps: f32,
    /// Loop iterations an invocation runs per pass at most (besides finishing one beam).
    pub budget: u32,
    /// Padding.
    pub pad: [u32; 3],
}

const _: () = assert!(
    size_of::<GpuLightBeam>() == 112
        && size_of::<GpuCone>() == 32
        && size_of::<GpuConeNode>() == 48
        && size_of::<GatherPoint>() == 32
        && size_of::<GpuGathered>() == 32
        && size_of::<GatherParams>() == 32
);

/// Point emitters (point lights, and area lights' strata) the GPU's shadow mask holds: as many as
/// the CPU makes at most when it can ([`crate::interface::MAX_LIGHTS`]).
pub const MAX_LIGHTS: usize = crate::interface::MAX_LIGHTS as usize;

/// Points per dispatch.
const CHUNK: usize = 1 << 20;

/// Loop iterations (cone-tree steps, beams, BVH steps and triangle tests of shadow rays, Owen's T
/// panels) an invocation runs in one pass of the gather before it leaves the rest of its walk to
/// the next. Mesa's software Vulkan (llvmpipe, lavapipe) stops every loop of a group of invocations
/// for good once all its loops together have run 65,535 iterations (`LP_MAX_TGSI_LOOP_ITERATIONS`,
/// counted per SIMD iteration, whichever lanes are active): the walks of the group then end early,
/// each cut short by what the others in the batch did. On `mirror-glass-coarse` (16 emitters) a
/// budget of 2,048 still lost a shadow ray, 512 did not; 256 leaves room even were the count shared
/// by a whole workgroup of 64 (64 × 256 = 16,384, plus one beam's work each). On other devices the
/// passes keep dispatches short.
pub const PASS_BUDGET: u32 = 256;

/// For each node of a hierarchy in depth-first order (first child next, `right_or_first` the
/// second), the node after its subtree.
fn skips(nodes: &[ConeNode]) -> Vec<u32> {
    let mut skip = vec![0u32; nodes.len()];
    for k in (0..nodes.len()).rev() {
        let node = &nodes[k];
        skip[k] = if node.count > 0 { k as u32 + 1 } else { skip[node.right_or_first as usize] };
    }
    skip
}

/// A subtree of the cone hierarchy: its nodes (depth-first, contiguous) and its beams (contiguous:
/// [`beam_render::glossy::ConeTree::build`] reorders the beams so that each leaf's are).
struct Part {
    nodes: std::ops::Range<usize>,
    beams: std::ops::Range<usize>,
}

/// Subtrees that together hold every beam once, each with at most `max_beams` beams (or a single
/// leaf): the root where it fits, else its children's parts.
fn parts(nodes: &[ConeNode], skip: &[u32], max_beams: usize) -> Vec<Part> {
    // Each subtree's beams: a leaf's own; an inner node's from its first child's first to its
    // second child's last.
    let mut range = vec![0..0; nodes.len()];
    for k in (0..nodes.len()).rev() {
        let n = &nodes[k];
        let first = n.right_or_first as usize;
        range[k] = if n.count > 0 { first..first + n.count as usize } else { range[k + 1].start..range[first].end };
    }
    let mut out = Vec::new();
    let mut stack = if nodes.is_empty() { Vec::new() } else { vec![0usize] };
    while let Some(k) = stack.pop() {
        if nodes[k].count > 0 || range[k].len() <= max_beams {
            out.push(Part { nodes: k..skip[k] as usize, beams: range[k].clone() });
        } else {
            stack.push(nodes[k].right_or_first as usize);
            stack.push(k + 1);
        }
    }
    out
}

fn cone(c: &BoundingCone) -> GpuCone {
    GpuCone { apex: c.apex.to_array(), cos: c.cos, axis: c.axis.to_array(), pad: 0 }
}

/// The gather pass for one scene: its BVH uploaded for the second-order shadow rays.
pub struct GpuGather {
    pipeline: wgpu::ComputePipeline,
    tracer: RayTracer,
    eps: f32,
    /// Most beams of one part of the hierarchy (`None`: as many as one storage binding holds).
    part_beams: Option<usize>,
}

impl GpuGather {
    /// Compile the pass and upload `scene`'s BVH.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, GpuError> {
        Ok(Self {
            pipeline: compute_pipeline(gpu, "glossy_gather", "gather")?,
            tracer: RayTracer::new(gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)?)?,
            eps: shading_eps(scene),
            part_beams: None,
        })
    }

    /// This gather with at most `beams` beams a part (tests split small hierarchies so).
    #[must_use]
    pub fn with_part_beams(mut self, beams: usize) -> Self {
        self.part_beams = Some(beams.max(1));
        self
    }

    /// The gather of `volumes` at `points` (point, unit normal), as beam-cpu's `gather_on_cpu`
    /// with `options` (exact Gaussian volumes, through the hierarchy; second-order shadows when set).
    pub fn gather(
        &self,
        gpu: &Gpu,
        volumes: &LightVolumes,
        points: &[(Vec3, Vec3)],
        options: &GlossyOptions,
    ) -> Result<Vec<Gathered>, GpuError> {
        if options.method != VolumeMethod::Exact {
            return Err(GpuError::InexactVolumes);
        }
        if volumes.lights.len() > MAX_LIGHTS {
            return Err(GpuError::TooManyEmitters { emitters: volumes.lights.len(), max: MAX_LIGHTS });
        }
        let beams: Vec<GpuLightBeam> = volumes
            .beams
            .iter()
            .map(|b| {
                let [o0, o1, o2] = b.beam.origins.map(|v| v.to_array());
                let [d0, d1, d2] = b.beam.dirs.map(|v| v.to_array());
                GpuLightBeam {
                    o0,
                    flux: b.beam.flux,
                    o1,
                    sigma: b.sigma,
                    o2,
                    light: b.light,
                    d0,
                    shadow: u32::from(b.shadow),
                    d1,
                    pad0: 0,
                    d2,
                    pad1: 0,
                    power: b.power.to_array(),
                    pad2: 0,
                }
            })
            .collect();
        let cones: Vec<GpuCone> = volumes.tree.cones.iter().map(cone).collect();
        let skip = skips(&volumes.tree.nodes);
        let nodes: Vec<GpuConeNode> = volumes
            .tree
            .nodes
            .iter()
            .zip(&skip)
            .map(|(n, &skip)| {
                let c = cone(&n.cone);
                GpuConeNode {
                    apex: c.apex,
                    cos: c.cos,
                    axis: c.axis,
                    right_or_first: n.right_or_first,
                    count: n.count,
                    skip,
                    pad: [0; 2],
                }
            })
            .collect();
        // The hierarchy in parts whose beams each fit one storage binding (a teapot's mirror sends
        // more than 128 MB of beams): the gather is a sum over beams, so the parts' sums add up.
        let fits = (max_binding(gpu) / size_of::<GpuLightBeam>() as u64).max(1) as usize;
        let max_beams = self.part_beams.map_or(fits, |b| b.min(fits));
        let mut out: Vec<Gathered> = vec![Gathered::default(); points.len()];
        for part in parts(&volumes.tree.nodes, &skip, max_beams) {
            let part_nodes: Vec<GpuConeNode> = nodes[part.nodes.clone()]
                .iter()
                .map(|n| {
                    let shift = if n.count > 0 { part.beams.start } else { part.nodes.start } as u32;
                    GpuConeNode {
                        right_or_first: n.right_or_first - shift,
                        skip: n.skip - part.nodes.start as u32,
                        ..*n
                    }
                })
                .collect();
            let gathered = self.gather_part(
                gpu,
                (&beams[part.beams.clone()], &cones[part.beams.clone()], &part_nodes),
                points,
                options,
            )?;
            for (o, g) in out.iter_mut().zip(gathered) {
                o.irradiance += g.irradiance;
                o.shadowed += g.shadowed;
                o.tested += g.tested;
            }
        }
        Ok(out)
    }

    /// The gather over one part of the hierarchy: its beams, their cones and its nodes (indices
    /// local to the part).
    fn gather_part(
        &self,
        gpu: &Gpu,
        (beams, cones, nodes): (&[GpuLightBeam], &[GpuCone], &[GpuConeNode]),
        points: &[(Vec3, Vec3)],
        options: &GlossyOptions,
    ) -> Result<Vec<Gathered>, GpuError> {
        checked(gpu, || {
            let beam_buffer = storage(gpu, "light beams", beams, wgpu::BufferUsages::empty());
            let cone_buffer = storage(gpu, "beam cones", cones, wgpu::BufferUsages::empty());
            let node_buffer = storage(gpu, "cone tree", nodes, wgpu::BufferUsages::empty());
            let mut out = Vec::with_capacity(points.len());
            for chunk in points.chunks(CHUNK) {
                let input: Vec<GatherPoint> = chunk
                    .iter()
                    .map(|&(p, n)| GatherPoint { p: (p + n * self.eps).to_array(), pad0: 0, n: n.to_array(), pad1: 0 })
                    .collect();
                let params = GatherParams {
                    points: chunk.len() as u32,
                    nodes: nodes.len() as u32,
                    flags: if options.second_order { SECOND_ORDER_SHADOWS } else { 0 },
                    eps: self.eps,
                    budget: PASS_BUDGET,
                    pad: [0; 3],
                };
                let params = uniform(gpu, "gather params", bytemuck::bytes_of(&params));
                let point_buffer = storage(gpu, "receivers", &input, wgpu::BufferUsages::empty());
                let size = (chunk.len() * size_of::<GpuGathered>()) as u64;
                // Zeroed by wgpu: every walk starts at the root.
                let result = output(gpu, "gathered", size);
                let unfinished = output(gpu, "unfinished walks", 4);
                let (bvh_nodes, triangles) = self.tracer.buffers();
                let buffers = [
                    bvh_nodes,
                    triangles,
                    &params,
                    &beam_buffer,
                    &cone_buffer,
                    &node_buffer,
                    &point_buffer,
                    &result,
                    &unfinished,
                ];
                // Passes until no walk is left unfinished (each moves every unfinished walk on by at
                // least one node or beam).
                loop {
                    gpu.queue.write_buffer(&unfinished, 0, &[0; 4]);
                    let encoder =
                        dispatch(gpu, &self.pipeline, &buffers, chunk.len().div_ceil(WORKGROUP_SIZE as usize) as u32);
                    let left: Vec<u32> = read_back(gpu, encoder, &unfinished, 4)?;
                    if left.first().is_none_or(|&n| n == 0) {
                        break;
                    }
                }
                let encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
                let raw: Vec<GpuGathered> = read_back(gpu, encoder, &result, size)?;
                out.extend(raw.iter().map(|g| Gathered {
                    irradiance: Vec3::from(g.irradiance),
                    shadowed: u64::from(g.shadowed),
                    tested: g.tested,
                }));
            }
            Ok(out)
        })
    }
}
