//! CPU renderer properties: exact light visibility by shadow beams (001 §5) against closed forms
//! and against Monte-Carlo shadow rays, and beam images against ray-traced ones.

use crate::bvh::{cases, ray_set, scene_light};
use crate::generate::{self, uniform};
use crate::{Backend, Config, Outcome, Property};
use beam_bvh::{BuildOptions, FlatBvh, WideBvh};
use beam_cpu::render::{BeamStats, DEPTH_EPS, Method, RenderOptions, Shading, difference, render, visible_light};
use beam_math::glam::Vec3;
use beam_math::{Ray, Triangle};
use beam_scene::options::Occluders;
use beam_scene::scene;
use rand::Rng;
use rayon::prelude::*;

const CPU: &[Backend] = &[Backend::Cpu];

/// The CPU renderer properties.
#[must_use]
pub fn properties() -> Vec<Property> {
    vec![
        Property {
            name: "soft_shadow_closed_form",
            cites: "001 §5; square light, parallel square occluder",
            backends: CPU,
            body: soft_shadow_closed_form,
        },
        Property {
            name: "soft_shadow_vs_monte_carlo",
            cites: "001 §5, 65,536 shadow rays",
            backends: CPU,
            body: soft_shadow_vs_monte_carlo,
        },
        Property {
            name: "beam_and_ray_images_agree",
            cites: "001 §5.1",
            backends: CPU,
            body: beam_and_ray_images_agree,
        },
        Property {
            name: "hard_shadow_images_agree", cites: "001 §4.2", backends: CPU, body: hard_shadow_images_agree
        },
        Property {
            name: "silhouettes_equal_splitting",
            cites: "001 §3.2; soft shadow volumes made exact",
            backends: CPU,
            body: silhouettes_equal_splitting,
        },
        Property {
            name: "sampled_beams_stay_in_their_bound",
            cites: "ratio estimator (Heitz et al. 2018)",
            backends: CPU,
            body: sampled_beams_stay_in_their_bound,
        },
        Property {
            name: "primary_coverage_sums_to_one",
            cites: "001 §3-4",
            backends: CPU,
            body: primary_coverage_sums_to_one,
        },
    ]
}

/// Area of the overlap of two axis-aligned squares (centre, half-width) in the plane.
fn square_overlap(a: (f32, f32, f32), b: (f32, f32, f32)) -> f32 {
    let span = |c1: f32, h1: f32, c2: f32, h2: f32| ((c1 + h1).min(c2 + h2) - (c1 - h1).max(c2 - h2)).max(0.0);
    span(a.0, a.2, b.0, b.2) * span(a.1, a.2, b.1, b.2)
}

/// A square light of side `L` at height `H` above a point, a parallel square occluder of side `s` at
/// height `h`: the occluder's shadow on the light plane is a square scaled by `H/h` about the point,
/// so the visible fraction is `1 − overlap/L²` in closed form. 4,000 random configurations; the
/// exact visibility must match to 1e-4.
pub fn soft_shadow_closed_form(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut rng = generate::rng(30);
    let mut worst = 0.0f32;
    for i in 0..4_000 {
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
        let got =
            visible_light(&bvh, &occluder, p, &light, -Vec3::Z, &mut BeamStats::default()).ok_or("no beam")?.fraction();
        worst = worst.max((got - expected).abs());
        if (got - expected).abs() > 1e-4 {
            return Err(format!("case {i}: visible {got}, closed form {expected}"));
        }
    }
    Ok(Outcome { cases: 4_000, note: format!("max |exact − closed form| = {worst:.1e}") })
}

/// Exact visible fraction of the scene light from random shade points (camera-ray hits) against a
/// 65,536-ray Monte-Carlo estimate with uniform light samples, on the built-in Cornell box, the
/// procedural scene and every shared mesh (Sponza and the conference room among them). Each point
/// must agree within 6σ and at most 1% of points may lie beyond 3σ (σ² = f(1 − f)/N).
/// `Config::rays / 10` points per scene.
pub fn soft_shadow_vs_monte_carlo(_: Backend, config: &Config) -> Result<Outcome, String> {
    const N: u32 = 65_536;
    let points_per_scene = (config.rays / 10).max(20);
    let (mut meshes, skipped) = cases()?;
    let cornell = scene::builtin("cornell").map_err(|e| e.to_string())?;
    meshes.insert(0, crate::bvh::Case { name: "cornell".into(), triangles: cornell.triangles.clone() });
    let mut notes = Vec::new();
    let (mut total, mut beyond3, mut worst) = (0u64, 0u64, 0.0f64);
    for (k, case) in meshes.iter().enumerate() {
        let tris = &case.triangles;
        let bvh = FlatBvh::build(tris, &BuildOptions::sah());
        let wide = WideBvh::new(&bvh, tris);
        let bounds = bvh.nodes[0].bounds();
        let (lc, lu, lv) = if case.name == "cornell" {
            match cornell.lights[0] {
                scene::Light::Quad { corner, edge_u, edge_v, .. } => (corner + 0.5 * (edge_u + edge_v), edge_u, edge_v),
                _ => unreachable!("the Cornell light is a quad"),
            }
        } else {
            scene_light(bounds)
        };
        let light = [lc - 0.5 * (lu + lv), lc + 0.5 * (lu - lv), lc + 0.5 * (lu + lv), lc - 0.5 * (lu - lv)];
        let ln = Vec3::NEG_Y;
        let set = ray_set(tris, &bvh, points_per_scene, 300 + k as u64);
        let points: Vec<Vec3> = set.shadow.iter().map(|(r, _)| r.origin).filter(|p| ln.dot(*p - lc) > 0.0).collect();
        let results: Vec<(f32, f64)> = points
            .par_iter()
            .enumerate()
            .map(|(i, &p)| {
                let exact =
                    visible_light(&bvh, tris, p, &light, ln, &mut BeamStats::default()).map_or(0.0, |v| v.fraction());
                let mut rng = generate::rng(1_000 + i as u64 + 7919 * k as u64);
                let mut seen = 0u32;
                for _ in 0..N {
                    let q = light[0] + lu * rng.random::<f32>() + lv * rng.random::<f32>();
                    if !wide.any_hit(Ray::new(p, q - p), 1.0 - DEPTH_EPS) {
                        seen += 1;
                    }
                }
                (exact, f64::from(seen) / f64::from(N))
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
        note: format!("{beyond3} beyond 3σ (expected ≈0.3%), worst {worst:.2}σ; {}", notes.join("; ")),
    })
}

/// The Cornell box at 96×96: the beam image (exact primary visibility with box-filtered coverage,
/// exact soft shadows) against the ray image (16 stratified primary rays per pixel, 256 stratified
/// shadow rays per shade point), same shading (eq. 1): PSNR ≥ 40 dB and no bias (the mean
/// difference of linear radiance is within 3 standard errors of zero).
pub fn beam_and_ray_images_agree(_: Backend, _: &Config) -> Result<Outcome, String> {
    images_agree("cornell", 16)
}

/// Hard shadows from a point light by beams (001 §4.2: visible pieces connected to the light, lit
/// parts rasterized with exact coverage) against 64 stratified primary rays per pixel, each with its
/// shadow ray, on the Cornell box lit by a point light: the same box-filtered image within noise.
pub fn hard_shadow_images_agree(_: Backend, _: &Config) -> Result<Outcome, String> {
    images_agree("cornell-point", 64)
}

/// The beam image (eye beams, exact light visibility) against the ray image (`primary_spp` primary
/// rays, 256 shadow rays per area light) of a built-in scene at 96²: PSNR ≥ 40 dB and a mean
/// difference within 3 standard errors of zero (no bias).
fn images_agree(name: &str, primary_spp: u32) -> Result<Outcome, String> {
    let mut scene = scene::builtin(name).map_err(|e| e.to_string())?;
    // Seen directly, the light (radiance 15) saturates any pixel it covers by more than 1/15, so
    // box-filter noise at its edges would swamp the comparison: dim its surface to radiance 1.
    for m in &mut scene.materials {
        if let scene::Material::Emissive { radiance } = m {
            *radiance = Vec3::ONE;
        }
    }
    let opts = |method| RenderOptions {
        method,
        shading: Shading::Exact,
        spp: 256,
        primary_spp,
        primary_beams: true,
        width: 96,
        height: 96,
        seed: 5,
        region: None,
        occluders: Occluders::Auto,
        exact: true,
    };
    let (beam, _) = render(&scene, &opts(Method::Beam), || {});
    let (ray, _) = render(&scene, &opts(Method::Ray), || {});
    let d = difference(&beam, &ray).map_err(|e| e.to_string())?;
    let diffs: Vec<f64> =
        beam.pixels.iter().zip(&ray.pixels).map(|(a, b)| f64::from((*a - *b).element_sum()) / 3.0).collect();
    let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
    let var = diffs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (diffs.len() - 1) as f64;
    let stderr = (var / diffs.len() as f64).sqrt();
    if d.psnr < 40.0 || mean.abs() > 3.0 * stderr.max(1e-9) {
        return Err(format!("{name}: PSNR {:.1} dB, mean difference {mean:.2e} (standard error {stderr:.2e})", d.psnr));
    }
    Ok(Outcome {
        cases: 96 * 96,
        note: format!("{name}: PSNR {:.1} dB, mean difference {mean:.1e} ± {stderr:.1e}", d.psnr),
    })
}

/// Shadow beams whose occluders enter by their silhouette edges (the winding pass) against the same
/// beams split by every occluder one at a time: seeded random scenes of closed meshes (UV spheres,
/// some with jittered corners, a torus), open ones (spheres with faces taken out, a fin on three
/// triangles of one edge), under a quad or triangle light from 2% to 100% of the scene's width, a
/// point of view each, 40×40 with one primary ray per pixel. Every pixel's radiance must agree to
/// 1e-5 of the image's brightest, but for at most 0.1% of pixels within 5e-5 (the split path's
/// fuzzy side tests move its edges by 1e-6 of the light), and the winding pass must have shaded
/// most of the beams.
pub fn silhouettes_equal_splitting(_: Backend, _: &Config) -> Result<Outcome, String> {
    let (mut worst, mut beams, mut winding, mut cases, mut beyond) = (0.0f32, 0u64, 0u64, 0u64, 0u64);
    for seed in 0..24u64 {
        let scene = random_occluders(seed);
        let on = RenderOptions { occluders: Occluders::Edges, ..RenderOptions::exact(40, 40) };
        let (a, stats) = render(&scene, &on, || {});
        let (b, _) = render(&scene, &RenderOptions { occluders: Occluders::Split, ..on }, || {});
        let max = b.pixels.iter().fold(0.0f32, |m, p| m.max(p.max_element())).max(f32::MIN_POSITIVE);
        for (i, (x, y)) in a.pixels.iter().zip(&b.pixels).enumerate() {
            let d = (*x - *y).abs().max_element() / max;
            worst = worst.max(d);
            beyond += u64::from(d > 1e-5);
            if d > 5e-5 {
                return Err(format!("seed {seed} pixel {i}: {x} by edges, {y} split ({d:.2e} of the brightest)"));
            }
        }
        beams += stats.shadow_beams;
        winding += stats.silhouette_beams;
        cases += a.pixels.len() as u64;
    }
    // The split path's fuzzy side tests (a corner within 1e-6 of the light's size is on a line,
    // 001 App. A) move its pieces' edges by that much: a pixel may differ by a few 1e-6 of the light.
    if beyond * 1000 > cases {
        return Err(format!("{beyond} of {cases} pixels differ by more than 1e-5 of the brightest"));
    }
    if 2 * winding < beams {
        return Err(format!("the winding pass shaded {winding} of {beams} shadow beams"));
    }
    Ok(Outcome {
        cases,
        note: format!(
            "worst {worst:.1e} of the brightest, {beyond} pixels beyond 1e-5; {winding} of {beams} beams by edges"
        ),
    })
}

/// Shadow beams past their budget against the same beams traced to the end (`exact`), on the
/// built-in plant (thousands of small leaves) and seeded random scenes, with budgets of 4 and 16
/// rays: every pixel must lie within the largest error bound the render reports, the mean
/// difference of linear radiance within 3 standard errors of zero (the ratio estimator is
/// unbiased to first order), and some beams must have been sampled.
pub fn sampled_beams_stay_in_their_bound(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut notes = Vec::new();
    let mut cases = 0u64;
    let scenes = [scene::builtin("plant").map_err(|e| e.to_string())?, random_occluders(3), random_occluders(8)];
    for scene in &scenes {
        for spp in [4, 16] {
            let exact = RenderOptions { primary_beams: false, ..RenderOptions::exact(48, 48) };
            let (a, _) = render(scene, &exact, || {});
            let (b, stats) = render(scene, &RenderOptions { exact: false, spp, ..exact }, || {});
            if stats.sampled_beams == 0 {
                return Err(format!("{} at {spp} rays: no beam ran past its budget", scene.name));
            }
            let bound = stats.max_error_bound * (1.0 + 1e-4) + 1e-6;
            let d: Vec<f64> =
                a.pixels.iter().zip(&b.pixels).map(|(x, y)| f64::from((*y - *x).element_sum() / 3.0)).collect();
            if let Some(i) = d.iter().position(|v| v.abs() > f64::from(bound)) {
                return Err(format!("{} at {spp} rays: pixel {i} off by {} past the bound {bound}", scene.name, d[i]));
            }
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            let sd = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (d.len() - 1) as f64).sqrt();
            let se = sd / (d.len() as f64).sqrt();
            if mean.abs() > 3.0 * se + 1e-6 {
                return Err(format!(
                    "{} at {spp} rays: mean difference {mean:.2e} beyond 3 standard errors ({se:.2e})",
                    scene.name
                ));
            }
            cases += d.len() as u64;
            notes.push(format!(
                "{} {spp} rays: {} sampled beams, {:.0}% exact pixels, bound {:.3}",
                scene.name,
                stats.sampled_beams,
                100.0 * stats.exact_pixel_share,
                stats.max_error_bound
            ));
        }
    }
    Ok(Outcome { cases, note: notes.join("; ") })
}

/// A seeded scene of closed and open meshes over a ground plane under one area light.
fn random_occluders(seed: u64) -> scene::Scene {
    use beam_scene::scene::suite::closed_sphere;
    let mut rng = generate::rng(9_000 + seed);
    let mut tris: Vec<(Triangle, u32)> = Vec::new();
    let ground =
        [Vec3::new(-4.0, 0.0, -4.0), Vec3::new(-4.0, 0.0, 4.0), Vec3::new(4.0, 0.0, 4.0), Vec3::new(4.0, 0.0, -4.0)];
    tris.push((Triangle::new(ground[0], ground[1], ground[2]), 0));
    tris.push((Triangle::new(ground[0], ground[2], ground[3]), 0));
    for k in 0..rng.random_range(2..6) {
        let c = Vec3::new(uniform(&mut rng, -1.5, 1.5), uniform(&mut rng, 0.4, 2.0), uniform(&mut rng, -1.5, 1.5));
        let r = uniform(&mut rng, 0.2, 0.7);
        let (rings, segments) = (rng.random_range(4..20), rng.random_range(5..24));
        let mut mesh = closed_sphere(c, r, rings, segments, uniform(&mut rng, 0.0, 3.0));
        if k % 3 == 1 {
            // Corners moved along the radius: still closed, no longer convex.
            for p in &mut mesh.positions {
                *p = c + (*p - c) * uniform(&mut rng, 0.8, 1.2);
            }
        }
        let mut t = mesh.triangles();
        if k % 3 == 2 {
            // Open: every seventh face taken out.
            t = t.into_iter().enumerate().filter(|(i, _)| i % 7 != 3).map(|(_, t)| t).collect();
        }
        tris.extend(t.into_iter().map(|t| (t, 1)));
    }
    // A torus (closed, genus one) and a fin: three triangles on one edge.
    let (tc, big, small) = (Vec3::new(uniform(&mut rng, -1.0, 1.0), 1.2, uniform(&mut rng, -1.0, 1.0)), 0.6, 0.2);
    let (n, m) = (18u32, 8u32);
    let at = |i: u32, j: u32| {
        let (u, v) =
            (std::f32::consts::TAU * (i % n) as f32 / n as f32, std::f32::consts::TAU * (j % m) as f32 / m as f32);
        tc + Vec3::new((big + small * v.cos()) * u.cos(), small * v.sin(), (big + small * v.cos()) * u.sin())
    };
    for i in 0..n {
        for j in 0..m {
            tris.push((Triangle::new(at(i, j), at(i, j + 1), at(i + 1, j)), 1));
            tris.push((Triangle::new(at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)), 1));
        }
    }
    let (f0, f1) = (Vec3::new(0.3, 2.2, 0.1), Vec3::new(-0.3, 2.3, -0.2));
    for tip in [Vec3::new(0.0, 2.6, 0.4), Vec3::new(0.1, 1.9, 0.5), Vec3::new(0.0, 2.2, -0.6)] {
        tris.push((Triangle::new(f0, f1, tip), 1));
    }
    let size = 8.0 * uniform(&mut rng, 0.02, 1.0);
    let center = Vec3::new(uniform(&mut rng, -1.0, 1.0), 4.0, uniform(&mut rng, -1.0, 1.0));
    let radiance = Vec3::splat(5.0 / (size * size).max(0.05));
    let light = if seed % 2 == 0 {
        let (u, v) = (Vec3::X * size, Vec3::Z * size);
        scene::Light::Quad { corner: center - 0.5 * (u + v), edge_u: u, edge_v: v, radiance }
    } else {
        // Facing down: counter-clockwise seen from below.
        let v = [
            center + Vec3::new(-size, 0.0, -size),
            center + Vec3::new(size, 0.0, 0.0),
            center + Vec3::new(-size, 0.0, size),
        ];
        scene::Light::Triangle { v, radiance }
    };
    let position = Vec3::new(uniform(&mut rng, -5.0, 5.0), uniform(&mut rng, 2.0, 6.0), uniform(&mut rng, 4.0, 7.0));
    let camera =
        scene::Camera { position, target: Vec3::new(0.0, 0.8, 0.0), up: Vec3::Y, fov_y: 50.0, width: 40, height: 40 };
    let albedo = Vec3::splat(0.7);
    let materials = vec![scene::Material::Diffuse { albedo }, scene::Material::Diffuse { albedo }];
    scene::Scene::new(format!("random occluders {seed}"), tris, materials, vec![light], camera)
}

/// Exact primary visibility by eye beams: in every pixel the visible pieces' coverage sums to one
/// (1e-4), no crack, no overlap. Inside a closed room (a box around a sphere and a cube, camera
/// inside, 160×120 and 512×384) every piece sees a triangle; in the Cornell box (open at the front)
/// pieces and background together sum to one.
pub fn primary_coverage_sums_to_one(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_scene::mesh;
    use beam_scene::scene::{Camera, Material, Scene};
    let mut room = mesh::cuboid(Vec3::splat(-5.0), Vec3::splat(5.0));
    room.append(&mesh::sphere(Vec3::new(0.5, -1.0, -1.0), 1.5, 16, 32));
    room.append(&mesh::cuboid(Vec3::new(-3.0, -5.0, -3.0), Vec3::new(-1.5, -2.0, -1.5)));
    let camera = Camera {
        position: Vec3::new(1.0, 0.5, 4.0),
        target: Vec3::new(-0.5, -1.0, -1.0),
        up: Vec3::Y,
        fov_y: 70.0,
        width: 160,
        height: 120,
    };
    let closed = Scene::new(
        "closed room".into(),
        room.triangles().into_iter().map(|t| (t, 0)).collect(),
        vec![Material::Diffuse { albedo: Vec3::ONE }],
        vec![],
        camera,
    );
    let cornell = scene::builtin("cornell").map_err(|e| e.to_string())?;
    let mut worst = 0.0f32;
    let mut pixels = 0u64;
    for (scene, w, h, closed) in [(&closed, 160, 120, true), (&closed, 512, 384, true), (&cornell, 128, 128, false)] {
        for (i, &(total, owned)) in beam_cpu::render::primary_coverage(scene, w, h).iter().enumerate() {
            pixels += 1;
            let err = if closed { (1.0 - owned).abs().max((1.0 - total).abs()) } else { (1.0 - total).abs() };
            worst = worst.max(err);
            if err > 1e-4 {
                return Err(format!(
                    "{} {w}×{h} pixel ({}, {}): coverage {total} (seeing triangles {owned})",
                    scene.name,
                    i % w as usize,
                    i / w as usize
                ));
            }
        }
    }
    Ok(Outcome { cases: pixels, note: format!("largest |1 − Σ coverage| {worst:.1e}") })
}
