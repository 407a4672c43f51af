//! CPU renderer properties: beam images against ray-traced ones, silhouettes against splitting,
//! sampled beams within their bounds, primary coverage (the shadow-beam properties that run on
//! every backend are in [`crate::shadow`]).

use crate::generate::{self, uniform};
use crate::property::{Backend, Config, Outcome, Property};
use beam_cpu::render::{difference, render};
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_render::options::Occluders;
use beam_render::options::{Method, RenderOptions, Shading};
use beam_scene::scene;
use rand::Rng;

const CPU: &[Backend] = &[Backend::Cpu];

/// The CPU renderer properties.
#[must_use]
pub fn properties() -> Vec<Property> {
    vec![
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
/// built-in plant (thousands of small leaves) and seeded random scenes, with budgets of 4, 16 and
/// 256 rays (at 256 sampled in rounds, which end where one sees the whole light lit): every pixel
/// must lie within the largest error bound the render reports, the mean difference of linear
/// radiance within 3 standard errors of zero (the ratio estimator is unbiased to first order), and
/// some beams must have been sampled.
pub fn sampled_beams_stay_in_their_bound(_: Backend, _: &Config) -> Result<Outcome, String> {
    let mut notes = Vec::new();
    let mut cases = 0u64;
    let scenes = [scene::builtin("plant").map_err(|e| e.to_string())?, random_occluders(3), random_occluders(8)];
    for scene in &scenes {
        for spp in [4, 16, 256] {
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
