//! GPU properties (beam-gpu on whatever adapter wgpu finds: Mesa lavapipe in CI): the WGSL
//! nonlinear-beam functions against beam-math, the compute ray tracer against the CPU's BVH, the
//! atlas pipeline's beam textures and the nonlinear images against the CPU renderer's. Each skips,
//! saying why, only when no adapter exists at all, and fails instead under `BEAM_REQUIRE_GPU=1`.

use crate::generate;
use crate::property::{Backend, Config, Outcome, Property};
use beam_bvh::gpu::GpuBvh;
use beam_cpu::nonlinear::CpuBeams;
use beam_gpu::checks::ShadeChecks;
use beam_gpu::nonlinear::{GpuBeams, NonlinearCheck};
use beam_gpu::raytrace::RayTracer;
use beam_math::glam::Vec3;
use beam_math::nonlinear::BoundingCase;
use beam_math::{Ray, Triangle};
use beam_render::nonlinear::{Beam, BeamJob, BeamRasterizer, Degree, Exclude, SMesh};
use beam_render::nonlinear::{CAUSTIC_STRATA, NonlinearOptions, render_nonlinear_with};
use beam_render::options::RenderOptions;
use beam_scene::scene;
use rand::Rng;

mod beams;
mod bindings;
mod coarse;
mod cull;
mod device;
mod eye;
mod eye_beam;
mod gbuffer;
mod glossy;
mod level;
mod lookup;
mod pixels;
mod readback;
mod surfaces;
mod twin;
mod whitted;

pub(crate) use device::adapter;

use beams::{kind, level_one_beams, random_beams};
use bindings::gpu_images_fit_narrow_bindings;
use coarse::{gpu_coarse_smesh_equals_cpu, gpu_eye_locates_as_cpu};
use cull::gpu_cone_culling_equals_host;
use eye::gpu_eye_view_equals_cpu;
use eye_beam::gpu_eye_beam_coverage_equals_cpu;
use gbuffer::gpu_gbuffer_irradiance_equals_cpu;
use glossy::{gpu_glossy_gather_area_lights_equal_cpu, gpu_glossy_gather_equals_cpu};
use level::{
    gpu_kept_level_equals_host_texels, gpu_kept_level_images_equal_read_back, gpu_summed_fits_equal_host_fits,
};
use lookup::gpu_lookup_projections_equal_cpu;
use pixels::PixelDifference;
use readback::gpu_readbacks_reuse_buffers;
use surfaces::gpu_textured_surfaces_equal_cpu;
use twin::TwinShading;
use whitted::gpu_whitted_equals_cpu;

const GPU: &[Backend] = &[Backend::Gpu];

/// The GPU properties.
#[must_use]
pub fn properties() -> Vec<Property> {
    vec![
        Property {
            name: "gpu_bounding_triangles_match_math",
            cites: "000 Algs. 3-4, eq. 5",
            backends: GPU,
            body: gpu_bounding_triangles_match_math,
        },
        Property {
            name: "gpu_texel_rays_match_math",
            cites: "000 eq. 1, §6.3",
            backends: GPU,
            body: gpu_texel_rays_match_math,
        },
        Property {
            name: "gpu_lookup_projections_equal_cpu",
            cites: "000 §5, §7.1",
            backends: GPU,
            body: gpu_lookup_projections_equal_cpu,
        },
        Property {
            name: "gpu_ray_hits_equal_cpu_hits",
            cites: "BVH traversal",
            backends: GPU,
            body: gpu_ray_hits_equal_cpu_hits,
        },
        Property { name: "gpu_eye_view_equals_cpu", cites: "000 §7.3", backends: GPU, body: gpu_eye_view_equals_cpu },
        Property {
            name: "gpu_beam_texels_equal_cpu",
            cites: "000 §3, Alg. 1",
            backends: GPU,
            body: gpu_beam_texels_equal_cpu,
        },
        Property {
            name: "gpu_cone_culling_equals_host",
            cites: "000 App. A",
            backends: GPU,
            body: gpu_cone_culling_equals_host,
        },
        Property { name: "gpu_whitted_equals_cpu", cites: "000 §7.3", backends: GPU, body: gpu_whitted_equals_cpu },
        Property { name: "gpu_images_equal_cpu", cites: "000 §3, §7", backends: GPU, body: gpu_images_equal_cpu },
        Property {
            name: "gpu_coarse_smesh_equals_cpu",
            cites: "000 §7.1",
            backends: GPU,
            body: gpu_coarse_smesh_equals_cpu,
        },
        Property { name: "gpu_eye_locates_as_cpu", cites: "000 §7.1", backends: GPU, body: gpu_eye_locates_as_cpu },
        Property { name: "gpu_shading_equals_cpu", cites: "000 §9.2", backends: GPU, body: gpu_shading_equals_cpu },
        Property {
            name: "gpu_glossy_gather_equals_cpu",
            cites: "002 §4.3",
            backends: GPU,
            body: gpu_glossy_gather_equals_cpu,
        },
        Property {
            name: "gpu_composite_equals_cpu", cites: "000 §7.3", backends: GPU, body: gpu_composite_equals_cpu
        },
        Property {
            name: "gpu_kept_level_equals_host_texels",
            cites: "000 §7.3",
            backends: GPU,
            body: gpu_kept_level_equals_host_texels,
        },
        Property {
            name: "gpu_summed_fits_equal_host_fits",
            cites: "000 §7.2",
            backends: GPU,
            body: gpu_summed_fits_equal_host_fits,
        },
        Property {
            name: "gpu_kept_level_images_equal_read_back",
            cites: "000 §7.3",
            backends: GPU,
            body: gpu_kept_level_images_equal_read_back,
        },
        Property {
            name: "gpu_images_fit_narrow_bindings",
            cites: "000 §3, §7.3",
            backends: GPU,
            body: gpu_images_fit_narrow_bindings,
        },
        Property {
            name: "gpu_gbuffer_irradiance_equals_cpu",
            cites: "001 §5, eq. 1",
            backends: GPU,
            body: gpu_gbuffer_irradiance_equals_cpu,
        },
        Property {
            name: "gpu_readbacks_reuse_buffers",
            cites: "000 §7.3 (host work per frame)",
            backends: GPU,
            body: gpu_readbacks_reuse_buffers,
        },
        Property {
            name: "gpu_glossy_gather_area_lights_equal_cpu",
            cites: "002 §4.3",
            backends: GPU,
            body: gpu_glossy_gather_area_lights_equal_cpu,
        },
        Property {
            name: "gpu_eye_beam_coverage_equals_cpu",
            cites: "001 §3",
            backends: GPU,
            body: gpu_eye_beam_coverage_equals_cpu,
        },
        Property {
            name: "gpu_textured_surfaces_equal_cpu",
            cites: "glTF 2.0 §3.9 (textures, alphaMode)",
            backends: GPU,
            body: gpu_textured_surfaces_equal_cpu,
        },
    ]
}

/// The bounding triangle beam-math computes for `tri` (what the CPU renderer rasterizes).
fn cpu_bounding_triangle(beam: &Beam, tri: &Triangle) -> Option<beam_math::nonlinear::BoundingTriangle> {
    let tb = beam.texel_beam();
    tb.bounding_triangle_of(&tb.s1_or_sn_bounds(), tri, &mut |q| tb.contains_s1(q))
}

/// How much larger than beam-math's a GPU bounding triangle may be where both take the same branch:
/// the shader's f32 margin (2e-3 of the base, in barycentric units) plus f32 rounding.
const TOLERANCE: f32 = 5e-3;

/// The WGSL bounding triangles (a compute entry point running the vertex stage's function) against
/// beam-math's on 36,000 (beam, triangle) pairs — S1, S3 and bump-mapped beams of three kinds,
/// triangles near and far, small and straddling. Where f32 decides every branch as beam-math's f64
/// does, the lower bounds are at most `TOLERANCE` (5e-3) below beam-math's (clamped at 0: every texel's
/// ω is ≥ 0); where it
/// cannot (a vertex within 1e-4 of a side surface, the base or the threshold plane) the shader
/// takes the larger branch. Always: the GPU triangle contains the CPU's,
/// and culls only what the CPU culls. At most 5% of these stress pairs (beams past their focus, mixed
/// directions) may take the larger branch.
pub fn gpu_bounding_triangles_match_math(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let check = NonlinearCheck::new(&gpu).map_err(|e| e.to_string())?;
    let beams = random_beams(21, 100);
    let mut rng = generate::rng(22);
    let mut cases = Vec::new();
    for (i, beam) in beams.iter().enumerate() {
        let s1 = match beam {
            Beam::S1(b) => *b,
            Beam::S3(b) => beam_math::nonlinear::NonlinearBeam::s1(b.base, b.dirs).ok_or("degenerate beam")?,
            Beam::Bumped(b) => b.beam.beam,
        };
        for _ in 0..40 {
            cases.push((i as u32, generate::scene_triangle(&mut rng, &s1)));
        }
    }
    let got = check.bounding_triangles(&gpu, &beams, &cases).map_err(|e| e.to_string())?;
    let (mut same, mut larger, mut worst) = (0u64, 0u64, 0.0f32);
    // Larger branches: the whole base where beam-math computed one, the general case where it used
    // the unique projection, kept where it culled.
    let mut why = [0u64; 3];
    let mut by_case = [0u64; 4];
    for ((i, tri), gpu_bt) in cases.iter().zip(&got) {
        let cpu = cpu_bounding_triangle(&beams[*i as usize], tri);
        let context =
            || format!("beam {i} ({:?}) triangle {tri:?}: CPU {cpu:?}, GPU {gpu_bt:?}", kind(&beams[*i as usize]));
        match (cpu, gpu_bt) {
            (None, None) => by_case[3] += 1,
            (_, None) => return Err(format!("GPU culled a triangle the CPU keeps: {}", context())),
            (None, Some(_)) => {
                larger += 1;
                why[2] += 1;
            }
            (Some(c), Some((lower, case))) => {
                // Every texel's ω is ≥ 0 (margin texels take the nearest point of the base's edge),
                // so bounds below 0 all mean the base's edge.
                let (g, m) = (Vec3::from_array(*lower).max(Vec3::ZERO), c.lower.max(Vec3::ZERO));
                if g.cmpgt(m).any() {
                    return Err(format!("GPU triangle does not contain the CPU's: {}", context()));
                }
                if *case == c.case {
                    same += 1;
                    worst = worst.max((g - m).abs().max_element());
                    by_case[match c.case {
                        BoundingCase::BruteForce => 0,
                        BoundingCase::General => 1,
                        BoundingCase::UniqueProjection => 2,
                    }] += 1;
                } else {
                    larger += 1;
                    why[usize::from(*case != BoundingCase::BruteForce)] += 1;
                }
            }
        }
    }
    let n = cases.len() as u64;
    if worst > TOLERANCE {
        return Err(format!("lower bounds differ by {worst:.1e} where the cases agree"));
    }
    if larger * 20 > n {
        return Err(format!("{larger} of {n} pairs took the larger branch (more than 5%): {why:?}"));
    }
    Ok(Outcome {
        cases: n,
        note: format!(
            "same case {same} (brute force {}, general {}, unique projection {}; culled {}), larger branch {larger} \
             (whole base {}, general for unique {}, kept {}); worst |Δm| {worst:.1e} (bounds clamped at 0)",
            by_case[0], by_case[1], by_case[2], by_case[3], why[0], why[1], why[2]
        ),
    })
}

/// The WGSL texel rays (eq. 1 by Bernstein sums; S1 rays tilted by the bump map for bumped beams)
/// against beam-math's on 36,000 base points: origins within 1e-5 of the base size, unit
/// directions within 1e-4 rad (bump tilts use the GPU's sine).
pub fn gpu_texel_rays_match_math(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let check = NonlinearCheck::new(&gpu).map_err(|e| e.to_string())?;
    let beams = random_beams(23, 100);
    let mut rng = generate::rng(24);
    let cases: Vec<(u32, Vec3)> = (0..beams.len())
        .flat_map(|i| (0..40).map(move |_| i as u32))
        .map(|i| (i, generate::barycentric(&mut rng)))
        .collect();
    let got = check.rays(&gpu, &beams, &cases).map_err(|e| e.to_string())?;
    let (mut worst_o, mut worst_d) = (0.0f32, 0.0f32);
    for ((i, w), (o, d)) in cases.iter().zip(&got) {
        let beam = &beams[*i as usize];
        let cpu = beam.ray_at(*w);
        let base = beam.texel_beam().base();
        let size = base[1].distance(base[0]).max(base[2].distance(base[0]));
        let eo = o.distance(cpu.origin) / size;
        let (a, b) = (d.normalize(), cpu.direction.normalize());
        let ed = a.cross(b).length().atan2(a.dot(b));
        worst_o = worst_o.max(eo);
        worst_d = worst_d.max(if ed.is_nan() { f32::INFINITY } else { ed });
        if eo > 1e-5 || !(ed <= 1e-4) {
            return Err(format!("{} beam {i} at ω={w}: GPU ({o}, {d}), CPU {cpu:?}", kind(beam)));
        }
    }
    Ok(Outcome {
        cases: cases.len() as u64,
        note: format!("worst origin error {worst_o:.1e} of the base size, direction {worst_d:.1e} rad"),
    })
}

/// The GPU's ray queries against the CPU's, both through [`RayQueries`](beam_render::queries::RayQueries) (`GpuBeams`: the compute
/// ray tracer, barycentric weights from the hit point; `CpuBeams`: the BVH traversal): camera rays
/// and random rays through the scene's box for closest hits, random segments for any hits, on
/// three built-ins. Rays exactly on an edge may be decided differently (the CPU refines in f64):
/// at most 1 in 10⁴; hit distances within 1e-5 relative, barycentric weights within 1e-4.
pub fn gpu_ray_hits_equal_cpu_hits(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_render::queries::RayQueries;
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let mut rng = generate::rng(7);
    let (mut total, mut notes) = (0u64, Vec::new());
    for name in ["cornell", "mirror-glass", "wavy-lake"] {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let on_gpu = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let bounds = scene.bounds();
        let camera = scene.camera.with_size(128, 128);
        let frame = camera.frame();
        let mut rays: Vec<Ray> = (0..128 * 128).map(|i| camera.pixel_ray(&frame, i)).collect();
        let mut segments = Vec::new();
        for k in 0..20_000 {
            let mut p = || bounds.min + (bounds.max - bounds.min) * Vec3::new(rng.random(), rng.random(), rng.random());
            let (a, b) = (p(), p());
            if k % 2 == 0 { rays.push(Ray::new(a, b - a)) } else { segments.push((Ray::new(a, b - a), 1.0)) }
        }
        let (got, want) = (
            on_gpu.closest_hits(&scene, &rays).map_err(|e| e.to_string())?,
            CpuBeams.closest_hits(&scene, &rays).map_err(|e| e.to_string())?,
        );
        let (mut mismatches, mut worst_t, mut worst_w) = (0usize, 0.0f32, 0.0f32);
        for (g, c) in got.iter().zip(&want) {
            match (g, c) {
                (None, None) => {}
                (Some(g), Some(c)) if g.prim == c.prim => {
                    worst_t = worst_t.max((c.t - g.t).abs() / c.t.max(1.0));
                    worst_w = worst_w.max((c.u - g.u).abs().max((c.v - g.v).abs()));
                }
                // Ties: another triangle at the same distance (shared edges, coplanar faces).
                (Some(g), Some(c)) if (c.t - g.t).abs() <= 1e-5 * c.t.max(1.0) => {}
                _ => mismatches += 1,
            }
        }
        let occluded = (
            on_gpu.any_hits(&scene, &segments).map_err(|e| e.to_string())?,
            CpuBeams.any_hits(&scene, &segments).map_err(|e| e.to_string())?,
        );
        mismatches += occluded.0.iter().zip(&occluded.1).filter(|(a, b)| a != b).count();
        let n = rays.len() + segments.len();
        if mismatches * 10_000 > n || worst_t > 1e-5 || worst_w > 1e-4 {
            return Err(format!(
                "{name}: {mismatches} mismatches of {n}, worst relative Δt {worst_t:.1e}, Δ(u, v) {worst_w:.1e}"
            ));
        }
        total += n as u64;
        notes.push(format!("{name} {mismatches} mismatches, Δt ≤ {worst_t:.1e}, Δ(u, v) ≤ {worst_w:.1e}"));
    }
    Ok(Outcome { cases: total, note: format!("{} ({})", notes.join("; "), gpu.describe()) })
}

/// The atlas pipeline (bounding triangles, then the nearest hits by 000's draws — fragment-stage
/// intersection, depth test — and, where the device has 64-bit atomics, by compute, its beams'
/// pairs also split into runs of 7 to exercise the merge) against the CPU's `render_beam` on the
/// level-1 beams off every third specular face of four built-ins (S1, S3, bumped, refracted; 16
/// texels per side): per texel the same nearest hit — the same triangle, or another at the same
/// distance (within 1e-4 relative: a shared edge); and at most twice the CPU's texels tested, so
/// the bounding triangles are in use and tight. At most 0.1% of the texels may differ.
pub fn gpu_beam_texels_equal_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (mut texels, mut notes) = (0u64, Vec::new());
    for (name, degree) in [
        ("mirror-glass-coarse", Degree::S3),
        ("facing-mirrors-coarse", Degree::S1),
        ("bumpy-mirror", Degree::S1),
        ("glass-lens-coarse", Degree::S3),
    ] {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let beams = level_one_beams(&scene, degree);
        let jobs: Vec<BeamJob<'_>> =
            beams.iter().map(|(beam, prim)| BeamJob { beam, size: 16, exclude: Exclude::base(*prim) }).collect();
        let on_cpu = CpuBeams.render_beams(&scene, &jobs).map_err(|e| e.to_string())?;
        // Every way to the nearest hits: 000's draws; where the device has 64-bit atomics, compute,
        // also with runs of 7 pairs, so that every beam's texels merge over many workgroups.
        let fresh = || GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string());
        let mut ways = vec![(fresh()?.rasterized(), "draws")];
        if GpuBeams::can_compute(&gpu) {
            ways.extend([(fresh()?, "compute"), (fresh()?.with_job_pairs(7), "compute, runs of 7")]);
        }
        for (renderer, way) in ways {
            let on_gpu = renderer.render_beams(&scene, &jobs).map_err(|e| e.to_string())?;
            let (mut n, mut d) = (0u64, 0u64);
            for (g, c) in on_gpu.iter().zip(&on_cpu) {
                for (a, b) in g.hits.iter().zip(&c.hits) {
                    n += 1;
                    let same = match (a, b) {
                        (None, None) => true,
                        (Some(a), Some(b)) => a.prim == b.prim || (a.t - b.t).abs() <= 1e-4 * a.t.abs().max(b.t.abs()),
                        _ => false,
                    };
                    d += u64::from(!same);
                }
            }
            if d * 1000 > n {
                return Err(format!("{name} by {way}: {d} of {n} texels differ"));
            }
            // The GPU's bounding triangles are used and tight: texels tested (overdraw) at most
            // twice the CPU's (the f32 margin and the whole-base fallbacks cost the difference).
            let tested = |t: &[beam_render::nonlinear::BeamTexture]| t.iter().map(|t| t.texels_tested).sum::<u64>();
            let ratio = tested(&on_gpu) as f64 / tested(&on_cpu).max(1) as f64;
            if !(ratio <= 2.0) {
                return Err(format!("{name} by {way}: the GPU tested {ratio:.2}× the CPU's texels"));
            }
            texels += n;
            notes.push(format!("{name} by {way} ({} beams) {d}, overdraw {ratio:.2}× the CPU's", beams.len()));
        }
    }
    Ok(Outcome { cases: texels, note: format!("texels differing: {}", notes.join(", ")) })
}

/// Nonlinear images (96², two tree levels) with every beam rendered by the GPU's atlases, the eye's
/// view by its ray tracer and the shading by its shading pass, against the CPU renderer's with the
/// same shading estimator (`TwinShading`), on five built-ins: at most 0.5% of the pixels differ by
/// more than 4/255 in a channel (sRGB); the mean error is stated.
pub fn gpu_images_equal_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (mut pixels, mut notes) = (0u64, Vec::new());
    for (name, degree) in [
        ("mirror-glass-coarse", Degree::S3),
        ("facing-mirrors-coarse", Degree::S1),
        ("glass-lens-coarse", Degree::S3),
        ("bumpy-mirror", Degree::S1),
        ("wavy-lake-coarse", Degree::S3),
    ] {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let options = NonlinearOptions {
            degree,
            texels: 32,
            bounces: 2,
            caustic_strata: CAUSTIC_STRATA,
            shading: RenderOptions::exact(96, 96),
        };
        let mut renderer = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let (on_gpu, _) =
            render_nonlinear_with(&scene, &options, &mut renderer, &CpuBeams).map_err(|e| e.to_string())?;
        let (on_cpu, _) = render_nonlinear_with(&scene, &options, &mut TwinShading::default(), &CpuBeams)
            .map_err(|e| e.to_string())?;
        let PixelDifference { differ, sum, n } = PixelDifference::of(&on_gpu, &on_cpu);
        if differ * 200 > n {
            return Err(format!("{name}: {differ} of {n} pixels differ by more than 4/255"));
        }
        pixels += n;
        notes.push(format!("{name} {:.2}% (mean {:.2}/255)", 100.0 * differ as f64 / n as f64, 255.0 * sum / n as f64));
    }
    Ok(Outcome { cases: pixels, note: format!("pixels differing by > 4/255: {}", notes.join(", ")) })
}

/// GPU shading (point lights by one shadow ray, area lights by 64 stratified shadow rays, all
/// through the GPU BVH; caustic irradiance maps) against its CPU twin `shade_twin` at every diffuse
/// point the eye sees (128²) on four built-ins — point-lit (where the twin is `shade_point` itself,
/// also checked) and lit by a quad light: within 1e-4 relative (+1e-6 absolute) per channel; at most
/// 0.1% of the points may differ by a shadow ray that grazes an edge. Against the CPU's exact soft
/// shadows the 64-ray estimate's relative RMS error is stated.
pub fn gpu_shading_equals_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_gpu::shade::PointShader;
    use beam_gpu::shade::twin::shade_twin;
    use beam_render::nonlinear::ShadePoint;
    use beam_render::nonlinear::caustics_by_beams;
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (mut total, mut notes) = (0u64, Vec::new());
    for name in ["cornell-point", "wavy-lake-coarse", "cornell", "mirror-glass"] {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let point_lit = scene.lights.iter().all(|l| matches!(l, scene::Light::Point { .. }));
        let mut shader = PointShader::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let tracer = RayTracer::new(&gpu, &GpuBvh::new(&scene.bvh, &scene.triangles).map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())?;
        let caustics = caustics_by_beams(&scene, Degree::S1, 16, CAUSTIC_STRATA, &CpuBeams)
            .map_err(|e| e.to_string())?
            .map(|c| c.0);
        let options = RenderOptions::exact(128, 128);
        let camera = scene.camera.with_size(128, 128);
        let frame = camera.frame();
        let points: Vec<ShadePoint> = (0..128 * 128)
            .filter_map(|i| {
                let ray = camera.pixel_ray(&frame, i);
                let hit = scene.wide.closest_hit(ray, f32::INFINITY)?;
                PointShader::shades(&scene, hit.prim).then(|| ShadePoint {
                    prim: hit.prim,
                    p: ray.at(hit.t),
                    d: ray.direction.normalize(),
                    seed: i as u64,
                })
            })
            .collect();
        let on_gpu = shader.shade(&gpu, &tracer, caustics.as_ref(), 64, &points).map_err(|e| e.to_string())?;
        let (mut differ, mut worst, mut sq, mut norm) = (0u64, 0.0f32, 0.0f64, 0.0f64);
        for (s, g) in points.iter().zip(&on_gpu) {
            let twin = shade_twin(&scene, caustics.as_ref(), 64, s);
            let exact = beam_cpu::render::shade_point(&scene, &options, caustics.as_ref(), s.prim, s.p, s.d, s.seed);
            if point_lit && (twin - exact).abs().cmpgt(1e-5 * exact.abs() + Vec3::splat(1e-7)).any() {
                return Err(format!("{name}: the twin {twin} differs from shade_point {exact} at {s:?}"));
            }
            sq += f64::from((twin - exact).length_squared());
            norm += f64::from(exact.length_squared());
            if (*g - twin).abs().cmpgt(1e-4 * twin.abs() + Vec3::splat(1e-6)).any() {
                differ += 1;
            } else {
                worst = worst.max(((*g - twin).abs() / (twin.abs() + Vec3::splat(1e-2))).max_element());
            }
        }
        if differ * 1000 > points.len() as u64 {
            return Err(format!("{name}: {differ} of {} points differ", points.len()));
        }
        total += points.len() as u64;
        notes.push(format!(
            "{name}: {differ} of {} differ, worst {worst:.1e}; 64 rays vs exact {:.1e} relative RMS",
            points.len(),
            (sq / norm.max(f64::MIN_POSITIVE)).sqrt()
        ));
    }
    Ok(Outcome { cases: total, note: notes.join("; ") })
}

/// The GPU's final composite (every level's radiance kept on the GPU as half floats, only the
/// pixels read back) against the CPU's `composite_levels` over the same beam trees (three levels,
/// 64², shading by `shade_twin` on both sides, mirror and glass points past the tree by Whitted
/// rays in waves: on the GPU by `GpuWhitted`) on four built-ins with mirrors (tinted and bumpy)
/// and glass (Fresnel, total internal reflection): every pixel within 4e-3 relative + 1e-4 (three
/// half-float roundings and the shading's 1e-4); at most 0.1% may differ by a shadow ray that
/// grazes an edge. The worst relative error is stated.
pub fn gpu_composite_equals_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_gpu::nonlinear::{GpuComposite, GpuWhitted, RestJob};
    use beam_gpu::shade::PointShader;
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (mut total, mut notes) = (0u64, Vec::new());
    for name in ["mirror-glass-coarse", "glass-lens-coarse", "bumpy-mirror", "wavy-lake-coarse"] {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let options = NonlinearOptions {
            degree: Degree::S3,
            texels: 32,
            bounces: 3,
            caustic_strata: CAUSTIC_STRATA,
            shading: RenderOptions::exact(64, 64),
        };
        let mut twin = TwinShading::default();
        let (on_cpu, _) = render_nonlinear_with(&scene, &options, &mut twin, &CpuBeams).map_err(|e| e.to_string())?;
        let (levels, caustics) = twin.0;
        let mut shader = PointShader::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let tracer = RayTracer::new(&gpu, &GpuBvh::new(&scene.bvh, &scene.triangles).map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())?;
        let whitted = GpuWhitted::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let prepared = shader.prepare(&gpu, caustics.as_ref());
        if let Some(map) = &caustics {
            // The same maps are uploaded once; changed, again.
            if shader.prepare(&gpu, Some(&map.clone())) != prepared {
                return Err(format!("{name}: the same caustic maps uploaded twice"));
            }
            let mut changed = map.clone();
            changed.add_texel(0, [0, 0], Vec3::ONE);
            if shader.prepare(&gpu, Some(&changed)) == prepared {
                return Err(format!("{name}: changed caustic maps not uploaded again"));
            }
        }
        let rest = |jobs: &[RestJob<'_>], checks: &mut ShadeChecks| {
            whitted.shade_into(&gpu, &tracer, (&shader, &prepared, 64), jobs, Some(checks))
        };
        let smesh = SMesh::specular(&scene);
        // The frame read back, and kept for display in a texture of the image's shape: the same
        // pixels.
        let composite = GpuComposite::new(&gpu).map_err(|e| e.to_string())?;
        let frame = |shape| {
            beam_gpu::buffers::checked(&gpu, || {
                let frame = shader.shade_checked(&gpu, |checks| {
                    let scene = (&scene, &smesh);
                    composite.run(&gpu, &tracer, &shader, scene, &prepared, 64, &levels, &[], &rest, shape, checks)
                })?;
                Ok((frame.texture().size(), frame.read_back(&gpu)?))
            })
            .map_err(|e| e.to_string())
        };
        let (_, on_gpu) = frame(None)?;
        let (size, displayed) = frame(Some((64, 64)))?;
        if (size.width, size.height) != (64, 64) || displayed != on_gpu {
            return Err(format!("{name}: the frame kept for display ({size:?}) is not the frame read back"));
        }
        let (mut differ, mut worst) = (0u64, 0.0f32);
        for (g, c) in on_gpu.iter().zip(&on_cpu.pixels) {
            let error = (*g - *c).abs();
            if error.cmpgt(4e-3 * c.abs() + Vec3::splat(1e-4)).any() {
                differ += 1;
            } else {
                worst = worst.max((error / (c.abs() + Vec3::splat(1e-2))).max_element());
            }
        }
        let n = on_cpu.pixels.len() as u64;
        if on_gpu.len() as u64 != n || differ * 1000 > n {
            return Err(format!("{name}: {differ} of {n} pixels differ ({} from the GPU)", on_gpu.len()));
        }
        total += n;
        let texels: usize = levels.iter().skip(1).map(|l| l.texels.len()).sum();
        notes
            .push(format!("{name} ({} levels, {texels} texels): {differ} differ, worst {worst:.1e}", levels.len() - 1));
    }
    Ok(Outcome { cases: total, note: notes.join("; ") })
}
