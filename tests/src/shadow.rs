//! Exact soft shadows (001 §5) on every backend that traces shadow beams: beam-cpu's beam tracer and
//! beam-gpu's compute shadow beams (`shadow_beam.wgsl`). One body per property; the backend decides
//! only where the beams are traced (`Beams`).

use crate::bvh::{cases, ray_set, scene_light};
use crate::generate::{self, uniform};
use crate::property::{Backend, Config, Outcome, Property};
use beam_bvh::gpu::GpuBvh;
use beam_bvh::{BuildOptions, FlatBvh, WideBvh};
use beam_cpu::nonlinear::CpuBeams;
use beam_cpu::render::{difference, light_seen, polygon_irradiance, render, render_queries};
use beam_gpu::Gpu;
use beam_gpu::queries::GpuQueries;
use beam_gpu::shadow_beam::{MAX_PIECES, ShadowBeams, Walk};
use beam_math::glam::Vec3;
use beam_math::{Ray, Triangle};
use beam_render::options::{Method, RenderOptions};
use beam_render::queries::{LightPolygon, LightQuery, LightSeen};
use beam_render::tolerance::DEPTH_EPS;
use beam_scene::scene;
use rand::Rng;
use rayon::prelude::*;

const CPU_AND_GPU: &[Backend] = &[Backend::Cpu, Backend::Gpu];
const GPU: &[Backend] = &[Backend::Gpu];

/// The shadow-beam properties.
#[must_use]
pub fn properties() -> Vec<Property> {
    vec![
        Property {
            name: "soft_shadow_closed_form",
            cites: "001 §5; square light, parallel square occluder",
            backends: CPU_AND_GPU,
            body: soft_shadow_closed_form,
        },
        Property {
            name: "soft_shadow_vs_monte_carlo",
            cites: "001 §5, 65,536 shadow rays",
            backends: CPU_AND_GPU,
            body: soft_shadow_vs_monte_carlo,
        },
        Property {
            name: "gpu_images_of_beam_and_ray_equal_cpu",
            cites: "001 §5 (beam), stratified shadow rays (ray)",
            backends: GPU,
            body: gpu_images_of_beam_and_ray_equal_cpu,
        },
        Property {
            name: "gpu_shadow_beams_equal_cpu",
            cites: "001 §3.2, §5",
            backends: GPU,
            body: gpu_shadow_beams_equal_cpu,
        },
        Property {
            name: "gpu_beams_walking_together_equal_alone",
            cites: "001 §5; one BVH walk per workgroup",
            backends: GPU,
            body: gpu_beams_walking_together_equal_alone,
        },
    ]
}

/// Where shadow beams are traced: on the CPU, or on a GPU (its pipeline compiled once, the BVH
/// uploaded per scene). Beams the GPU answers `None` (past its pieces or its budget) are traced on
/// the CPU, as the renderers do, and counted.
enum Beams {
    Cpu,
    Gpu { gpu: Box<Gpu>, beams: Option<ShadowBeams>, overflowed: [u64; 4] },
}

impl Beams {
    /// The beams of `backend`; `Ok(Err(outcome))` when it is the GPU and there is no adapter.
    fn of(backend: Backend) -> Result<Result<Self, Outcome>, String> {
        Ok(match backend {
            Backend::Gpu => {
                crate::gpu::adapter()?.map(|gpu| Beams::Gpu { gpu: Box::new(gpu), beams: None, overflowed: [0; 4] })
            }
            _ => Ok(Beams::Cpu),
        })
    }

    /// What each query sees of `lights` past `tris` (BVH `bvh`).
    fn seen(
        &mut self,
        tris: &[Triangle],
        bvh: &FlatBvh,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<LightSeen>, String> {
        let on_cpu = |q: &LightQuery| light_seen(bvh, tris, &lights[q.light as usize], q);
        match self {
            Beams::Cpu => Ok(queries.par_iter().map(on_cpu).collect()),
            Beams::Gpu { gpu, beams, overflowed } => {
                let uploaded = GpuBvh::new(bvh, tris).map_err(|e| e.to_string())?;
                let next = match beams {
                    Some(b) => b.with_bvh(gpu, &uploaded),
                    None => ShadowBeams::new(gpu, &uploaded),
                };
                let b = beams.insert(next.map_err(|e| e.to_string())?);
                let answers = b.answers(gpu, lights, queries).map_err(|e| e.to_string())?;
                Ok(answers
                    .iter()
                    .zip(queries)
                    .map(|(a, q)| {
                        a.seen().unwrap_or_else(|| {
                            overflowed[(a.status as usize).min(3)] += 1;
                            on_cpu(q)
                        })
                    })
                    .collect())
            }
        }
    }

    /// A note on the beams the GPU left to the CPU.
    fn note(&self, total: u64) -> String {
        match self {
            Beams::Cpu => String::new(),
            Beams::Gpu { overflowed: [_, pieces, budget, cut], .. } => format!(
                "; of {total} GPU beams {pieces} needed more than {MAX_PIECES} pieces, {budget} passed their budget, \
                 {cut} were cut short (all traced again on the CPU)"
            ),
        }
    }
}

/// Area of the overlap of two axis-aligned squares (centre, half-width) in the plane.
fn square_overlap(a: (f32, f32, f32), b: (f32, f32, f32)) -> f32 {
    let span = |c1: f32, h1: f32, c2: f32, h2: f32| ((c1 + h1).min(c2 + h2) - (c1 - h1).max(c2 - h2)).max(0.0);
    span(a.0, a.2, b.0, b.2) * span(a.1, a.2, b.1, b.2)
}

/// A square light of side `L` at height `H` above a point, a parallel square occluder of side `s` at
/// height `h`: the occluder's shadow on the light plane is a square scaled by `H/h` about the point,
/// so the visible fraction is `1 − overlap/L²` in closed form. 4,000 random configurations (1,000
/// on the GPU, one upload each); the exact visibility must match to 1e-4.
pub fn soft_shadow_closed_form(backend: Backend, _: &Config) -> Result<Outcome, String> {
    let mut beams = match Beams::of(backend)? {
        Ok(b) => b,
        Err(skipped) => return Ok(skipped),
    };
    let cases = if backend == Backend::Gpu { 1_000 } else { 4_000 };
    let mut rng = generate::rng(30);
    let mut worst = 0.0f32;
    for i in 0..cases {
        let (big_h, side) = (uniform(&mut rng, 1.0, 4.0), uniform(&mut rng, 0.2, 2.0));
        let light_c = Vec3::new(uniform(&mut rng, -1.0, 1.0), uniform(&mut rng, -1.0, 1.0), big_h);
        let hl = 0.5 * side;
        let light = [
            light_c + Vec3::new(-hl, -hl, 0.0),
            light_c + Vec3::new(hl, -hl, 0.0),
            light_c + Vec3::new(hl, hl, 0.0),
            light_c + Vec3::new(-hl, hl, 0.0),
        ];
        let h = uniform(&mut rng, 0.1, 0.9) * big_h;
        let occ_c = Vec3::new(uniform(&mut rng, -1.0, 1.0), uniform(&mut rng, -1.0, 1.0), h);
        let ho = uniform(&mut rng, 0.05, 0.6);
        let q = |x: f32, y: f32| occ_c + Vec3::new(x, y, 0.0);
        let occluder =
            vec![Triangle::new(q(-ho, -ho), q(ho, -ho), q(ho, ho)), Triangle::new(q(-ho, -ho), q(ho, ho), q(-ho, ho))];
        let bvh = FlatBvh::build(&occluder, &BuildOptions::sah());
        let p = Vec3::new(uniform(&mut rng, -1.5, 1.5), uniform(&mut rng, -1.5, 1.5), 0.0);
        let k = big_h / h;
        let shadow = (p.x + (occ_c.x - p.x) * k, p.y + (occ_c.y - p.y) * k, ho * k);
        let expected = 1.0 - square_overlap((light_c.x, light_c.y, hl), shadow) / (side * side);
        let lights = [LightPolygon::new(&light, -Vec3::Z).ok_or("light")?];
        let query = LightQuery { p, n: Vec3::Z, light: 0, clip_above: false };
        let got = beams.seen(&occluder, &bvh, &lights, &[query])?[0].fraction;
        worst = worst.max((got - expected).abs());
        if (got - expected).abs() > 1e-4 {
            return Err(format!("case {i}: visible {got}, closed form {expected}"));
        }
    }
    Ok(Outcome { cases, note: format!("max |exact − closed form| = {worst:.1e}{}", beams.note(cases)) })
}

/// Exact visible fraction of the scene light from random shade points (camera-ray hits) against a
/// 65,536-ray Monte-Carlo estimate with uniform light samples, on the built-in Cornell box, the
/// procedural scene and every shared mesh (Sponza and the conference room among them). Each point
/// must agree within 6σ and at most 1% of points may lie beyond 3σ (σ² = f(1 − f)/N).
/// `Config::rays / 10` points per scene.
pub fn soft_shadow_vs_monte_carlo(backend: Backend, config: &Config) -> Result<Outcome, String> {
    const N: u32 = 65_536;
    let mut beams = match Beams::of(backend)? {
        Ok(b) => b,
        Err(skipped) => return Ok(skipped),
    };
    let points_per_scene = (config.rays / 10).max(20);
    let (meshes, skipped) = scenes()?;
    let mut notes = Vec::new();
    let (mut total, mut beyond3, mut worst) = (0u64, 0u64, 0.0f64);
    for (k, (case, light, ln)) in meshes.iter().enumerate() {
        let tris = &case.triangles;
        let bvh = FlatBvh::build(tris, &BuildOptions::sah());
        let wide = WideBvh::new(&bvh, tris);
        let (lu, lv) = (light[1] - light[0], light[3] - light[0]);
        let lc = 0.25 * light.iter().sum::<Vec3>();
        let set = ray_set(tris, &bvh, points_per_scene, 300 + k as u64);
        let points: Vec<Vec3> = set.shadow.iter().map(|(r, _)| r.origin).filter(|p| ln.dot(*p - lc) > 0.0).collect();
        let lights = [LightPolygon::new(light, *ln).ok_or("light")?];
        let queries: Vec<LightQuery> =
            points.iter().map(|&p| LightQuery { p, n: -*ln, light: 0, clip_above: false }).collect();
        let exact = beams.seen(tris, &bvh, &lights, &queries)?;
        let results: Vec<(f32, f64)> = points
            .par_iter()
            .zip(&exact)
            .enumerate()
            .map(|(i, (&p, seen))| {
                let mut rng = generate::rng(1_000 + i as u64 + 7919 * k as u64);
                let mut lit = 0u32;
                for _ in 0..N {
                    let q = light[0] + lu * rng.random::<f32>() + lv * rng.random::<f32>();
                    if !wide.any_hit(Ray::new(p, q - p), 1.0 - DEPTH_EPS) {
                        lit += 1;
                    }
                }
                (seen.fraction, f64::from(lit) / f64::from(N))
            })
            .collect();
        let mut scene_worst = 0.0f64;
        for (i, &(exact, mc)) in results.iter().enumerate() {
            let f = f64::from(exact);
            let sigma = (f * (1.0 - f) / f64::from(N)).sqrt().max(1.0 / f64::from(N));
            let z = (f - mc).abs() / sigma;
            scene_worst = scene_worst.max(z);
            beyond3 += u64::from(z > 3.0);
            if z > 6.0 {
                return Err(format!(
                    "{} point {i} ({}): exact {exact}, Monte Carlo {mc} ({z:.1}σ)",
                    case.name, points[i]
                ));
            }
        }
        total += results.len() as u64;
        worst = worst.max(scene_worst);
        let mean_vis = results.iter().map(|r| f64::from(r.0)).sum::<f64>() / results.len().max(1) as f64;
        notes.push(format!(
            "{} ({} points, mean visibility {mean_vis:.2}, worst {scene_worst:.1}σ)",
            case.name,
            results.len()
        ));
    }
    if beyond3 as f64 > 0.01 * total as f64 {
        return Err(format!("{beyond3} of {total} points beyond 3σ (more than 1%)"));
    }
    if let Some(reason) = skipped {
        notes.push(format!("shared meshes skipped: {reason}"));
    }
    Ok(Outcome {
        cases: total,
        note: format!(
            "{beyond3} beyond 3σ (expected ≈0.3%), worst {worst:.2}σ; {}{}",
            notes.join("; "),
            beams.note(total)
        ),
    })
}

/// The GPU's shadow beams against the CPU's, point by point, on the scenes of
/// [`soft_shadow_vs_monte_carlo`] and on seeded soups of random triangles under lights of random
/// size and tilt, with tilted shade normals (so that the light is clipped at the tangent plane):
/// visible fractions within 1e-5, Lambert irradiances within 1e-4 of the most the light gives at
/// the point (facing it; the GPU sums Lambert's terms in f32, the CPU in f64), at 99% of the
/// queries, and all within 1e-3 (f32 rounding of triangles clipped at the near plane, projected
/// far out, can tip a fuzzy side test). Beams past the GPU's limits are counted in the note.
pub fn gpu_shadow_beams_equal_cpu(backend: Backend, config: &Config) -> Result<Outcome, String> {
    let mut beams = match Beams::of(backend)? {
        Ok(b) => b,
        Err(skipped) => return Ok(skipped),
    };
    let mut rng = generate::rng(77);
    let (mut cases, skipped) = scenes()?;
    for s in 0..6 {
        let tris: Vec<Triangle> = (0..40 + 60 * s)
            .map(|_| {
                let c =
                    Vec3::new(uniform(&mut rng, -1.0, 1.0), uniform(&mut rng, 0.2, 1.8), uniform(&mut rng, -1.0, 1.0));
                let mut corner = || c + 0.3 * Vec3::new(rng.random(), rng.random(), rng.random()) - 0.15;
                Triangle::new(corner(), corner(), corner())
            })
            .collect();
        let half = uniform(&mut rng, 0.05, 1.5);
        let tilt = Vec3::new(uniform(&mut rng, -0.3, 0.3), 0.0, uniform(&mut rng, -0.3, 0.3));
        let light = [
            Vec3::new(-half, 2.0, -half),
            Vec3::new(half, 2.0, -half),
            Vec3::new(half, 2.0, half),
            Vec3::new(-half, 2.0, half),
        ]
        .map(|c| c + tilt * c.x);
        let ln = (light[1] - light[0]).cross(light[3] - light[0]).normalize();
        let ln = if ln.y > 0.0 { -ln } else { ln };
        cases.push((crate::bvh::Case { name: format!("soup {s}"), triangles: tris }, light, ln));
    }
    let (mut total, mut beyond, mut worst_f, mut worst_e) = (0u64, 0u64, 0.0f32, 0.0f32);
    for (k, (case, light, ln)) in cases.iter().enumerate() {
        let tris = &case.triangles;
        let bvh = FlatBvh::build(tris, &BuildOptions::sah());
        let points: Vec<Vec3> = if case.name.starts_with("soup") {
            (0..config.rays / 4)
                .map(|_| Vec3::new(uniform(&mut rng, -1.5, 1.5), 0.0, uniform(&mut rng, -1.5, 1.5)))
                .collect()
        } else {
            ray_set(tris, &bvh, config.rays / 4, 500 + k as u64).shadow.iter().map(|(r, _)| r.origin).collect()
        };
        let lights = [LightPolygon::new(light, *ln).ok_or("light")?];
        let mut queries = Vec::new();
        for &p in &points {
            let n = (-*ln + Vec3::new(uniform(&mut rng, -1.5, 1.5), 0.0, uniform(&mut rng, -1.5, 1.5))).normalize();
            queries.push(LightQuery { p, n, light: 0, clip_above: false });
            queries.push(LightQuery { p, n, light: 0, clip_above: true });
        }
        let on_gpu = beams.seen(tris, &bvh, &lights, &queries)?;
        let on_cpu: Vec<LightSeen> = queries.par_iter().map(|q| light_seen(&bvh, tris, &lights[0], q)).collect();
        for (i, ((g, c), q)) in on_gpu.iter().zip(&on_cpu).zip(&queries).enumerate() {
            // The most the light gives at p (facing it): the scale of the irradiance's rounding.
            let centre = 0.25 * light.iter().sum::<Vec3>();
            let most = polygon_irradiance(q.p, (centre - q.p).normalize_or_zero(), light).max(1e-30);
            let (df, de) = ((g.fraction - c.fraction).abs(), (g.irradiance - c.irradiance).abs() / most);
            worst_f = worst_f.max(df);
            worst_e = worst_e.max(if q.clip_above { de } else { 0.0 });
            let off = df > 1e-5 || (q.clip_above && de > 1e-4);
            beyond += u64::from(off);
            if df > 1e-3 || (q.clip_above && de > 1e-3) {
                return Err(format!("{} query {i} at {} (normal {}): GPU {g:?}, CPU {c:?}", case.name, q.p, q.n));
            }
        }
        total += queries.len() as u64;
    }
    if beyond * 100 > total {
        return Err(format!("{beyond} of {total} beams differ by more than 1e-5 (fraction) or 1e-4 (irradiance)"));
    }
    let mut note = format!(
        "{beyond} beyond 1e-5 / 1e-4, max |Δ fraction| {worst_f:.1e}, max |Δ irradiance| / facing irradiance {worst_e:.1e}{}",
        beams.note(total)
    );
    if let Some(reason) = skipped {
        note.push_str(&format!("; shared meshes skipped: {reason}"));
    }
    Ok(Outcome { cases: total, note })
}

/// The GPU's two walks of the shadow beams ([`Walk`]): a workgroup's beams walking the BVH together
/// against each down its own path, on the Cornell box, the procedural
/// scene and every shared mesh under their quad lights, from camera hits in Morton order (so that
/// a workgroup holds neighbours, as a renderer's rows do), clipped at the tangent plane and not.
/// Every beam that both walks finish answers the same (together a beam skips the descendants of a
/// node it found outside, so it tests the nodes and meets the triangles it meets alone, in the same
/// order): within f32 rounding, 1e-6 relative (the two entry points are compiled apart, and a
/// compiler may contract them differently; lavapipe gives the same bits, counted in the note), and
/// the together walk finishes at least a quarter of all beams (its walks end at 5 beams' budgets
/// summed over the group, since its loop holds barriers: 40,960 iterations on a software device).
pub fn gpu_beams_walking_together_equal_alone(backend: Backend, config: &Config) -> Result<Outcome, String> {
    let gpu = match crate::gpu::adapter()? {
        Ok(g) if backend == Backend::Gpu => g,
        Ok(_) => return Err("a GPU property".into()),
        Err(skipped) => return Ok(skipped),
    };
    let (cases, skipped) = scenes()?;
    let (mut total, mut both, mut same_bits, mut together_done) = (0u64, 0u64, 0u64, 0u64);
    let mut notes = Vec::new();
    for (k, (case, light, ln)) in cases.iter().enumerate() {
        let tris = &case.triangles;
        let bvh = FlatBvh::build(tris, &BuildOptions::sah());
        let uploaded = GpuBvh::new(&bvh, tris).map_err(|e| e.to_string())?;
        let mut points: Vec<(Vec3, Vec3)> = ray_set(tris, &bvh, config.rays / 32, 900 + k as u64)
            .shadow
            .iter()
            .map(|(r, _)| (r.origin, -*ln))
            .collect();
        let bounds = bvh.nodes.first().map(|n| n.bounds()).ok_or("an empty mesh")?;
        points.sort_by_key(|(p, _)| morton(((*p - bounds.min) / bounds.extent().max(Vec3::splat(1e-30))).to_array()));
        let queries: Vec<LightQuery> = points
            .iter()
            .flat_map(|&(p, n)| [false, true].map(|clip_above| LightQuery { p, n, light: 0, clip_above }))
            .collect();
        let lights = [LightPolygon::new(light, *ln).ok_or("light")?];
        let answers = |walk| -> Result<Vec<_>, String> {
            let beams =
                ShadowBeams::new(&gpu, &uploaded).and_then(|b| b.walking(&gpu, walk)).map_err(|e| e.to_string())?;
            beams.answers(&gpu, &lights, &queries).map_err(|e| e.to_string())
        };
        let (alone, together) = (answers(Walk::Alone)?, answers(Walk::Together)?);
        let mut done = 0u64;
        for (i, (a, t)) in alone.iter().zip(&together).enumerate() {
            let (a, t) = (a.seen(), t.seen());
            done += u64::from(t.is_some());
            if let (Some(a), Some(t)) = (a, t) {
                both += 1;
                let bits = |s: &LightSeen| (s.irradiance.to_bits(), s.fraction.to_bits());
                same_bits += u64::from(bits(&a) == bits(&t));
                let off = |x: f32, y: f32| (x - y).abs() > 1e-6 * x.abs().max(y.abs()).max(1.0e-30);
                if off(a.irradiance, t.irradiance) || (a.fraction - t.fraction).abs() > 1e-6 {
                    return Err(format!("{} query {i} at {}: alone {a:?}, together {t:?}", case.name, queries[i].p));
                }
            }
        }
        notes.push(format!("{} {done} of {}", case.name, queries.len()));
        together_done += done;
        total += queries.len() as u64;
    }
    if together_done * 4 < total {
        return Err(format!("the walk together finished {together_done} of {total} beams, under a quarter"));
    }
    let mut note = format!(
        "{both} beams finished by both walks, all equal ({same_bits} to the bit); finished together: {}",
        notes.join(", ")
    );
    if let Some(reason) = skipped {
        note.push_str(&format!("; shared meshes skipped: {reason}"));
    }
    Ok(Outcome { cases: total, note })
}

/// The Morton code of a point of the unit cube, 10 bits an axis.
fn morton(unit: [f32; 3]) -> u32 {
    let spread = |x: f32| {
        let mut v = ((x.clamp(0.0, 1.0) * 1023.0) as u32) & 0x3ff;
        v = (v | (v << 16)) & 0x0300_00ff;
        v = (v | (v << 8)) & 0x0300_f00f;
        v = (v | (v << 4)) & 0x030c_30c3;
        (v | (v << 2)) & 0x0924_9249
    };
    spread(unit[0]) | (spread(unit[1]) << 1) | (spread(unit[2]) << 2)
}

/// A mesh, a quad light's corners (counter-clockwise) and its unit normal.
type LitCase = (crate::bvh::Case, [Vec3; 4], Vec3);

/// The Cornell box with its own light, the procedural scene and every shared mesh under a quad
/// light a third of its width under its top, each light's corners counter-clockwise and its unit
/// normal (downwards).
fn scenes() -> Result<(Vec<LitCase>, Option<String>), String> {
    let (meshes, skipped) = cases()?;
    let cornell = scene::builtin("cornell").map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    let corners = |(lc, lu, lv): (Vec3, Vec3, Vec3)| {
        [lc - 0.5 * (lu + lv), lc + 0.5 * (lu - lv), lc + 0.5 * (lu + lv), lc - 0.5 * (lu - lv)]
    };
    let cornell_light = match cornell.lights[0] {
        scene::Light::Quad { corner, edge_u, edge_v, .. } => (corner + 0.5 * (edge_u + edge_v), edge_u, edge_v),
        _ => return Err("the Cornell light is not a quad".into()),
    };
    out.push((
        crate::bvh::Case { name: "cornell".into(), triangles: cornell.triangles.clone() },
        corners(cornell_light),
        Vec3::NEG_Y,
    ));
    for case in meshes {
        let finite = case.triangles.iter().flat_map(|t| t.v).filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        let light = corners(scene_light(beam_math::Aabb::new(lo, hi)));
        out.push((case, light, Vec3::NEG_Y));
    }
    Ok((out, skipped))
}

/// The `beam` and `ray` images on the GPU (`render_queries` over [`GpuQueries`]: primary rays,
/// exact shadow beams or shadow rays on the device) against the CPU's `render` with the same
/// options (primary rays, every beam traced to the end): PSNR ≥ 50 dB on every built-in scene at
/// 48² and on Sponza (a bare OBJ, its default key light) at 64², where the shared scenes are; and
/// with every beam forced past the GPU's budget, the same image with the overflow counted.
pub fn gpu_images_of_beam_and_ray_equal_cpu(backend: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match crate::gpu::adapter()? {
        Ok(g) if backend == Backend::Gpu => g,
        Ok(_) => return Err("a GPU property".into()),
        Err(skipped) => return Ok(skipped),
    };
    let mut scenes: Vec<(String, u32)> = scene::BUILTIN.iter().map(|n| ((*n).to_string(), 48)).collect();
    let sponza = beam_scene::scenes::shared_meshes()
        .ok()
        .and_then(|paths| paths.into_iter().find(|p| p.file_stem().is_some_and(|s| s == "sponza")));
    let skipped = match &sponza {
        Some(p) => {
            scenes.push((p.display().to_string(), 64));
            String::new()
        }
        None => "; Sponza skipped (no shared scenes)".into(),
    };
    let (mut worst, mut cells, mut overflow) = (f64::INFINITY, 0u64, 0u64);
    for (name, size) in &scenes {
        let scene = scene::load(name).map_err(|e| e.to_string())?;
        let queries = GpuQueries::new(&gpu, &scene).map_err(|e| e.to_string())?;
        for method in [Method::Beam, Method::Ray] {
            let options = RenderOptions { method, spp: 16, ..RenderOptions::exact(*size, *size) };
            let (cpu, _) = render(&scene, &options, || {});
            let (on_gpu, stats) = render_queries(&scene, &options, &queries, || {}).map_err(|e| e.to_string())?;
            let d = difference(&cpu, &on_gpu).map_err(|e| e.to_string())?;
            if d.psnr < 50.0 {
                return Err(format!("{name} {method:?}: PSNR {:.1} dB (max {:.3})", d.psnr, d.max));
            }
            worst = worst.min(d.psnr);
            cells += 1;
            overflow += stats.overflow_beams;
        }
    }
    // Eye beams: the GPU's fragments against the CPU's, each shaded the same way.
    let mut eye_worst = f64::INFINITY;
    let mut left = 0u64;
    for (name, _) in scenes.iter().filter(|(n, _)| !n.ends_with(".obj")) {
        let scene = scene::load(name).map_err(|e| e.to_string())?;
        let queries = GpuQueries::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let options = RenderOptions { primary_beams: true, ..RenderOptions::exact(32, 32) };
        let (cpu, _) = render_queries(&scene, &options, &CpuBeams, || {}).map_err(|e| e.to_string())?;
        let (on_gpu, stats) = render_queries(&scene, &options, &queries, || {}).map_err(|e| e.to_string())?;
        let d = difference(&cpu, &on_gpu).map_err(|e| e.to_string())?;
        if d.psnr < 50.0 {
            return Err(format!("{name} eye beams: PSNR {:.1} dB (max {:.3})", d.psnr, d.max));
        }
        eye_worst = eye_worst.min(d.psnr);
        left += stats.overflow_pixels;
        cells += 1;
    }
    // Beams forced past the GPU's limits (a budget of 64 loop iterations) are traced on the CPU:
    // the same image, and the stats say how many.
    let scene = scene::builtin("cornell").map_err(|e| e.to_string())?;
    let tight = GpuQueries::new(&gpu, &scene).map_err(|e| e.to_string())?.with_budget(64);
    let options = RenderOptions::exact(48, 48);
    let (cpu, _) = render(&scene, &options, || {});
    let (on_gpu, stats) = render_queries(&scene, &options, &tight, || {}).map_err(|e| e.to_string())?;
    let d = difference(&cpu, &on_gpu).map_err(|e| e.to_string())?;
    if stats.overflow_beams == 0 || d.psnr < 50.0 {
        return Err(format!("budget 64: {} beams overflowed, PSNR {:.1} dB", stats.overflow_beams, d.psnr));
    }
    Ok(Outcome {
        cases: cells + 1,
        note: format!(
            "lowest PSNR {worst:.1} dB; {overflow} shadow beams past the GPU's limits, traced on the CPU{skipped}; \
             eye beams at 32² on every built-in: lowest PSNR {eye_worst:.1} dB, {left} pixels left to the CPU; \
             budget 64 on cornell: {} of {} beams traced on the CPU, PSNR {:.1} dB",
            stats.overflow_beams, stats.shadow_beams, d.psnr
        ),
    })
}
