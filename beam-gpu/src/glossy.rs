//! The gather of the glossy light volumes (002) on the GPU (`shaders/glossy_gather.wgsl`): the
//! beams, their cones and the cone hierarchy built on the CPU ([`LightVolumes`]) are uploaded, and
//! one invocation per receiver point walks the hierarchy, with second-order shadow rays through the
//! GPU BVH. CPU twin: [`LightVolumes::gather`].

use crate::Gpu;
use crate::buffers::{checked, compute_pipeline, dispatch, output, read_back, storage, uniform};
use crate::raytrace::RayTracer;
use beam_bvh::gpu::GpuBvh;
use beam_cpu::glossy::{BoundingCone, Gathered, GlossyOptions, LightVolumes};
use beam_cpu::render::shading_eps;
use beam_cpu::scene::Scene;
use beam_math::glam::Vec3;
use beam_math::glossy::VolumeMethod;
use bytemuck::{Pod, Zeroable};

/// A light beam.
///
/// Keep in sync with the WGSL twin `LightBeam` in `shaders/glossy_gather.wgsl`.
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
/// Keep in sync with the WGSL twin `Cone` in `shaders/glossy_gather.wgsl`.
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
/// Keep in sync with the WGSL twin `ConeNode` in `shaders/glossy_gather.wgsl`.
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
    /// Padding.
    pub pad: [u32; 3],
}

/// A receiver point.
///
/// Keep in sync with the WGSL twin `GatherPoint` in `shaders/glossy_gather.wgsl`.
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

/// What a receiver point gathered.
///
/// Keep in sync with the WGSL twin `Gathered` in `shaders/glossy_gather.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuGathered {
    /// Irradiance of the scattered beams.
    pub irradiance: [f32; 3],
    /// Bit `l`: a shadow beam of light `l` covers the point.
    pub shadowed: u32,
    /// Beams evaluated.
    pub tested: u32,
    /// Padding.
    pub pad: [u32; 3],
}

/// Uniforms of the gather.
///
/// Keep in sync with the WGSL twin `GatherParams` in `shaders/glossy_gather.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GatherParams {
    /// Receiver points.
    pub points: u32,
    /// Nodes of the hierarchy.
    pub nodes: u32,
    /// Bit 0: second-order shadows.
    pub flags: u32,
    /// Offset of shadow-ray ends off the scatterer.
    pub eps: f32,
}

const _: () = assert!(
    size_of::<GpuLightBeam>() == 112
        && size_of::<GpuCone>() == 32
        && size_of::<GpuConeNode>() == 48
        && size_of::<GatherPoint>() == 32
        && size_of::<GpuGathered>() == 32
        && size_of::<GatherParams>() == 16
);

/// Point emitters (point lights, and area lights' strata) the GPU's shadow mask holds: as many as
/// the CPU makes at most when it can ([`beam_cpu::glossy::MAX_EMITTERS`]).
pub const MAX_LIGHTS: usize = 32;

const _: () = assert!(MAX_LIGHTS == beam_cpu::glossy::MAX_EMITTERS);

/// Points per dispatch.
const CHUNK: usize = 1 << 20;

fn cone(c: &BoundingCone) -> GpuCone {
    GpuCone { apex: c.apex.to_array(), cos: c.cos, axis: c.axis.to_array(), pad: 0 }
}

/// The gather pass for one scene: its BVH uploaded for the second-order shadow rays.
pub struct GpuGather {
    pipeline: wgpu::ComputePipeline,
    tracer: RayTracer,
    eps: f32,
}

impl GpuGather {
    /// Compile the pass and upload `scene`'s BVH.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self, String> {
        Ok(Self {
            pipeline: compute_pipeline(gpu, "glossy_gather", "gather")?,
            tracer: RayTracer::new(gpu, &GpuBvh::new(&scene.bvh, &scene.triangles))?,
            eps: shading_eps(scene),
        })
    }

    /// The gather of `volumes` at `points` (point, unit normal), as [`beam_cpu::glossy::gather_on_cpu`]
    /// with `options` (exact Gaussian volumes, through the hierarchy; second-order shadows when set).
    pub fn gather(
        &self,
        gpu: &Gpu,
        volumes: &LightVolumes,
        points: &[(Vec3, Vec3)],
        options: &GlossyOptions,
    ) -> Result<Vec<Gathered>, String> {
        if options.method != VolumeMethod::Exact {
            return Err("the GPU gather integrates the Gaussian volumes exactly (--volume exact)".into());
        }
        if volumes.lights.len() > MAX_LIGHTS {
            return Err(format!(
                "the GPU gather takes at most {MAX_LIGHTS} point emitters (point lights, and area lights' strata), \
                 not {}",
                volumes.lights.len()
            ));
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
        let nodes: Vec<GpuConeNode> = volumes
            .tree
            .nodes
            .iter()
            .map(|n| {
                let c = cone(&n.cone);
                GpuConeNode {
                    apex: c.apex,
                    cos: c.cos,
                    axis: c.axis,
                    right_or_first: n.right_or_first,
                    count: n.count,
                    pad: [0; 3],
                }
            })
            .collect();
        checked(gpu, || {
            let beam_buffer = storage(gpu, "light beams", &beams, wgpu::BufferUsages::empty());
            let cone_buffer = storage(gpu, "beam cones", &cones, wgpu::BufferUsages::empty());
            let node_buffer = storage(gpu, "cone tree", &nodes, wgpu::BufferUsages::empty());
            let mut out = Vec::with_capacity(points.len());
            for chunk in points.chunks(CHUNK) {
                let input: Vec<GatherPoint> = chunk
                    .iter()
                    .map(|&(p, n)| GatherPoint { p: (p + n * self.eps).to_array(), pad0: 0, n: n.to_array(), pad1: 0 })
                    .collect();
                let params = GatherParams {
                    points: chunk.len() as u32,
                    nodes: nodes.len() as u32,
                    flags: u32::from(options.second_order),
                    eps: self.eps,
                };
                let params = uniform(gpu, "gather params", bytemuck::bytes_of(&params));
                let point_buffer = storage(gpu, "receivers", &input, wgpu::BufferUsages::empty());
                let size = (chunk.len() * size_of::<GpuGathered>()) as u64;
                let result = output(gpu, "gathered", size);
                let (bvh_nodes, triangles) = self.tracer.buffers();
                let buffers =
                    [bvh_nodes, triangles, &params, &beam_buffer, &cone_buffer, &node_buffer, &point_buffer, &result];
                let encoder = dispatch(gpu, &self.pipeline, &buffers, chunk.len().div_ceil(64) as u32);
                let raw: Vec<GpuGathered> = bytemuck::pod_collect_to_vec(&read_back(gpu, encoder, &result, size)?);
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
