//! BVH properties: every builder's closest and any hits equal brute force on the shared meshes and
//! on built-in procedural scenes, before and after a refit.

use crate::generate::{self, Rng64, uniform};
use crate::{Backend, Config, Outcome, Property};
use beam_bvh::{BuildOptions, Bvh8, Collapse, FlatBvh, Hit, Kernel, RayDistribution, WideBvh};
use beam_math::collide::WatertightRay;
use beam_math::glam::Vec3;
use beam_math::{Aabb, Ray, Triangle};
use beam_scene::mesh::{self, Mesh};

mod answers;

use answers::{Answers, compare, reference};

const BVH: &[Backend] = &[Backend::Bvh];

/// The BVH properties.
#[must_use]
pub fn properties() -> Vec<Property> {
    vec![
        Property {
            name: "bvh_hits_equal_brute_force",
            cites: "BVH issue; 004 App. A.1, A.3",
            backends: &[Backend::Bvh, Backend::Gpu],
            body: hits_equal_brute_force,
        },
        Property {
            name: "bvh_refit_hits_equal_brute_force",
            cites: "BVH issue (refit)",
            backends: BVH,
            body: refit_hits_equal_brute_force,
        },
    ]
}

/// A named triangle set.
pub struct Case {
    /// Mesh name.
    pub name: String,
    /// Its triangles, degenerate ones included.
    pub triangles: Vec<Triangle>,
}

/// The built-in procedural scene: a sphere (with degenerate pole triangles) inside a room, a random
/// soup, and explicit degenerate and non-finite triangles.
#[must_use]
pub fn procedural_case() -> Case {
    let mut m = mesh::cuboid(Vec3::splat(-4.0), Vec3::splat(4.0));
    m.indices.iter_mut().for_each(|t| t.swap(1, 2));
    m.append(&mesh::sphere(Vec3::new(0.5, -1.0, 0.3), 1.5, 24, 48));
    let mut rng = generate::rng(40);
    let mut triangles = m.triangles();
    for _ in 0..3000 {
        let c = generate::point(&mut rng, 3.5);
        triangles.push(Triangle::new(c, c + generate::point(&mut rng, 0.3), c + generate::point(&mut rng, 0.3)));
    }
    triangles.push(Triangle::new(Vec3::ZERO, Vec3::X, 2.0 * Vec3::X));
    triangles.push(Triangle::new(Vec3::NAN, Vec3::X, Vec3::Y));
    triangles.push(Triangle::new(Vec3::INFINITY, Vec3::X, Vec3::Y));
    Case { name: "procedural".into(), triangles }
}

/// The procedural case and every shared mesh; the second value says why shared meshes are missing.
pub fn cases() -> Result<(Vec<Case>, Option<String>), String> {
    let mut out = vec![procedural_case()];
    match beam_scene::scenes::shared_meshes() {
        Ok(paths) => {
            for p in paths {
                let m: Mesh = mesh::load_obj(&p).map_err(|e| e.to_string())?;
                out.push(Case {
                    name: p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
                    triangles: m.triangles(),
                });
            }
            Ok((out, None))
        }
        Err(reason) => Ok((out, Some(reason.to_string()))),
    }
}

/// Rays of the three kinds for one mesh.
pub struct RaySet {
    /// Camera rays: from an eye inside the scene's box and from one outside looking in.
    pub camera: Vec<Ray>,
    /// Shadow rays from camera hits to random points of a quad light under the top of the box, each
    /// with `t_max` just short of the light.
    pub shadow: Vec<(Ray, f32)>,
    /// Cosine-distributed bounces from camera hits.
    pub diffuse: Vec<Ray>,
    /// The quad light's centre and downward normal (for the PAH builders).
    pub light: (Vec3, Vec3),
    /// The outside eye (for the PAH builders).
    pub eye: Vec3,
}

/// The scene light (centre and edges): [`beam_scene::scene::Light::under_ceiling`] of a third of the
/// box's width.
#[must_use]
pub fn scene_light(bounds: Aabb) -> (Vec3, Vec3, Vec3) {
    match beam_scene::scene::Light::under_ceiling(bounds, 0.33, Vec3::ONE) {
        beam_scene::scene::Light::Quad { corner, edge_u, edge_v, .. } => {
            (corner + 0.5 * (edge_u + edge_v), edge_u, edge_v)
        }
        _ => unreachable!("under_ceiling is a quad"),
    }
}

/// Generate `n` rays of each kind, seeded; `bvh` only finds the camera hits to start from.
pub fn ray_set(triangles: &[Triangle], bvh: &FlatBvh, n: usize, seed: u64) -> RaySet {
    let mut rng = generate::rng(seed);
    let bounds = bvh.nodes.first().map_or(Aabb::new(Vec3::ZERO, Vec3::ONE), |r| r.bounds());
    let c = bounds.center();
    let e = bounds.extent();
    let inside = c + e * Vec3::new(0.11, 0.13, -0.07);
    let eye = c + e.length() * Vec3::new(0.6, 0.35, 0.9);
    let camera: Vec<Ray> = (0..n)
        .map(|i| {
            if i % 2 == 0 {
                Ray::new(inside, generate::unit(&mut rng))
            } else {
                let target = c + e
                    * 0.5
                    * Vec3::new(
                        uniform(&mut rng, -1.0, 1.0),
                        uniform(&mut rng, -1.0, 1.0),
                        uniform(&mut rng, -1.0, 1.0),
                    );
                Ray::new(eye, target - eye)
            }
        })
        .collect();
    let hits = bvh.closest_hits(triangles, &camera, f32::INFINITY);
    let (lc, lu, lv) = scene_light(bounds);
    let mut shadow = Vec::with_capacity(n);
    let mut diffuse = Vec::with_capacity(n);
    let eps = 1e-4 * e.length();
    let mut k = 0;
    while shadow.len() < n && k < 50 * n {
        let i = k % n;
        k += 1;
        let Some(h) = hits[i] else { continue };
        let ray = camera[i];
        let tri = &triangles[h.prim as usize];
        let mut normal = tri.scaled_normal().normalize_or_zero();
        if normal.dot(ray.direction) > 0.0 {
            normal = -normal;
        }
        let p = ray.at(h.t) + normal * eps;
        let target = lc + lu * uniform(&mut rng, -0.5, 0.5) + lv * uniform(&mut rng, -0.5, 0.5);
        shadow.push((Ray::new(p, target - p), 0.999));
        diffuse.push(Ray::new(p, cosine_direction(&mut rng, normal)));
    }
    // Meshes where few camera rays hit: fill with rays from the eyes.
    while shadow.len() < n {
        let r = camera[shadow.len() % n];
        shadow.push((r, 1.0));
        diffuse.push(r);
    }
    RaySet { camera, shadow, diffuse, light: (lc, Vec3::NEG_Y), eye }
}

fn cosine_direction(rng: &mut Rng64, n: Vec3) -> Vec3 {
    let (u1, u2) = (uniform(rng, 0.0, 1.0), uniform(rng, 0.0, 1.0));
    let r = u1.sqrt();
    let phi = std::f32::consts::TAU * u2;
    let t = n.any_orthonormal_vector();
    let b = n.cross(t);
    (t * r * phi.cos() + b * r * phi.sin() + n * (1.0 - u1).max(0.0).sqrt()).normalize()
}

/// Closest hit by testing every triangle (the reference).
#[must_use]
pub fn brute_force_closest(triangles: &[Triangle], ray: Ray, t_max: f32) -> Option<Hit> {
    let wt = WatertightRay::new(ray);
    let mut best: Option<Hit> = None;
    let mut t_best = t_max;
    for (i, t) in triangles.iter().enumerate() {
        if let Some(h) = wt.intersect(t, 0.0, t_best) {
            t_best = h.t;
            best = Some(Hit { prim: i as u32, t: h.t, u: h.u, v: h.v });
        }
    }
    best
}

/// The builders every property runs: SAH, PAH for the light's parallel bundle, PAH for the eye's
/// pencil.
#[must_use]
pub fn builders(set: &RaySet, bounds: Aabb) -> Vec<(&'static str, BuildOptions)> {
    vec![
        ("sah", BuildOptions::sah()),
        ("pah-light", BuildOptions::pah(RayDistribution::Parallel { direction: set.light.1 })),
        ("pah-eye", BuildOptions::pah(RayDistribution::Pencil { origin: set.eye, forward: bounds.center() - set.eye })),
    ]
}

/// For every mesh (the procedural scene and each shared mesh), every builder (SAH, PAH for the
/// light, PAH for the eye) and every CPU layout (binary, 4-wide, and 8-wide built by its own
/// builder (SAH: a binary tree lightly reinserted and collapsed by the dynamic program), SAH also
/// in the high-quality mode (reinsertion, greedy and optimal collapse), with more and with no light
/// reinsertion, binned straight
/// into eight-wide nodes, with pre-split triangles and with spatial splits, traced by each kernel
/// this CPU runs: portable, AVX2, AVX-512) — on the `gpu`
/// backend the GPU layout traced by beam-gpu's compute ray tracer instead: BVH closest hits equal
/// brute-force closest hits for camera and diffuse rays (same triangle, or a tie at the same `t`;
/// `t` within 1e-5 relative), and any-hit answers of shadow rays agree. `Config::rays` rays of each
/// kind per mesh.
pub fn hits_equal_brute_force(backend: Backend, config: &Config) -> Result<Outcome, String> {
    let gpu = match backend {
        Backend::Gpu => match crate::gpu::adapter()? {
            Ok(gpu) => Some(gpu),
            Err(skipped) => return Ok(skipped),
        },
        _ => None,
    };
    let (cases, skipped) = cases()?;
    let mut notes = Vec::new();
    let mut total = 0u64;
    for (k, case) in cases.iter().enumerate() {
        let tris = &case.triangles;
        let sah = FlatBvh::build(tris, &BuildOptions::sah());
        let bounds = sah.nodes[0].bounds();
        let set = ray_set(tris, &sah, config.rays, 100 + k as u64);
        let reference = reference(tris, &set);
        let mut ties = 0;
        for (builder, options) in builders(&set, bounds) {
            let bvh = FlatBvh::build(tris, &options);
            if let Some(gpu) = &gpu {
                let answers = Answers::gpu(gpu, &bvh, tris, &set)?;
                ties += compare(&case.name, &format!("{builder} gpu"), &answers, &set, &reference)?;
                total += 3 * config.rays as u64;
                continue;
            }
            ties += compare(&case.name, builder, &Answers::flat(&bvh, tris, &set), &set, &reference)?;
            let wide = WideBvh::new(&bvh, tris);
            ties += compare(&case.name, &format!("{builder} 4-wide"), &Answers::wide(&wide, &set), &set, &reference)?;
            total += 6 * config.rays as u64;
            // The 8-wide layout, by this builder and (SAH) in the high-quality mode, collapsed by
            // the dynamic program after reinsertion, binned straight into eight-wide nodes, with
            // more and with no light reinsertion, pre-split, and with spatial splits.
            let hq = (builder == "sah").then(|| {
                let presplit = BuildOptions { presplit: 0.3, ..BuildOptions::sah() };
                let dp = Some(Collapse::Optimal);
                let hq_dp = BuildOptions { collapse: dp, ..BuildOptions::high_quality() };
                let direct = BuildOptions { collapse: None, ..BuildOptions::sah() };
                [
                    ("sah-hq", BuildOptions::high_quality()),
                    ("sah-hq-dp", hq_dp),
                    ("sah-direct", direct),
                    ("sah-refine", BuildOptions { refine: 0.02, ..BuildOptions::sah() }),
                    ("sah-unrefined", BuildOptions { refine: 0.0, ..BuildOptions::sah() }),
                    ("sah-presplit", presplit),
                    ("sah-sbvh", BuildOptions::spatial_splits()),
                ]
            });
            for (builder, options) in [(builder, options)].into_iter().chain(hq.into_iter().flatten()) {
                let mut bvh8 = Bvh8::build(tris, &options);
                for kernel in kernels() {
                    bvh8.set_kernel(kernel);
                    let name = format!("{builder} 8-wide {kernel}");
                    ties += compare(&case.name, &name, &Answers::wide8(&bvh8, &set), &set, &reference)?;
                    total += 3 * config.rays as u64;
                }
            }
        }
        let hit_rate = reference.camera.iter().filter(|h| h.is_some()).count() as f64 / set.camera.len() as f64;
        notes.push(format!(
            "{} ({} tris, {} degenerate, {:.0}% camera hits, {ties} ties)",
            case.name,
            tris.len(),
            sah.degenerate,
            100.0 * hit_rate
        ));
    }
    if let Some(reason) = skipped {
        notes.push(format!("shared meshes skipped: {reason}"));
    }
    Ok(Outcome { cases: total, note: format!("{} rays/kind/mesh; {}", config.rays, notes.join("; ")) })
}

/// The 8-wide kernels this CPU runs.
fn kernels() -> Vec<Kernel> {
    [Kernel::Portable, Kernel::Avx2, Kernel::Avx512].into_iter().filter(|k| k.is_available()).collect()
}

/// Deform every mesh (a smooth displacement of up to 2% of its size), refit the SAH BVH in every
/// CPU layout and compare
/// with brute force on the deformed mesh, as in [`hits_equal_brute_force`] (a quarter of the rays).
pub fn refit_hits_equal_brute_force(_: Backend, config: &Config) -> Result<Outcome, String> {
    let (cases, skipped) = cases()?;
    let mut total = 0u64;
    let n = (config.rays / 4).max(100);
    for (k, case) in cases.iter().enumerate() {
        let mut tris = case.triangles.clone();
        let mut bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        let bounds = bvh.nodes[0].bounds();
        let size = bounds.extent().length();
        let f = 6.0 / size;
        for t in &mut tris {
            for v in &mut t.v {
                *v += 0.02 * size * Vec3::new((v.y * f).sin(), (v.z * f).cos(), (v.x * f).sin()) * 0.577;
            }
        }
        let mut wide = WideBvh::new(&bvh, &case.triangles);
        let mut bvh8 = Bvh8::build(&case.triangles, &BuildOptions::sah());
        bvh.refit(&tris);
        wide.refit(&tris);
        bvh8.refit(&tris);
        let set = ray_set(&tris, &bvh, n, 200 + k as u64);
        // A refit keeps the tree's triangles: those left out as degenerate at build stay out even if
        // the deformation gave them area, so the reference leaves them out too.
        let kept: Vec<Triangle> = case
            .triangles
            .iter()
            .zip(&tris)
            .map(
                |(before, after)| {
                    if before.is_valid() { *after } else { Triangle::new(Vec3::NAN, Vec3::NAN, Vec3::NAN) }
                },
            )
            .collect();
        let reference = reference(&kept, &set);
        compare(&case.name, "sah refit", &Answers::flat(&bvh, &tris, &set), &set, &reference)?;
        compare(&case.name, "sah 4-wide refit", &Answers::wide(&wide, &set), &set, &reference)?;
        total += 6 * n as u64;
        for kernel in kernels() {
            bvh8.set_kernel(kernel);
            compare(&case.name, &format!("sah 8-wide {kernel} refit"), &Answers::wide8(&bvh8, &set), &set, &reference)?;
            total += 3 * n as u64;
        }
    }
    let note = match skipped {
        Some(reason) => format!("{n} rays/kind/mesh; shared meshes skipped: {reason}"),
        None => format!("{n} rays/kind/mesh on {} meshes", cases.len()),
    };
    Ok(Outcome { cases: total, note })
}
