//! BVH properties: every builder's closest and any hits equal brute force on the shared meshes and
//! on built-in procedural scenes, before and after a refit.

use crate::generate;
use crate::property::{Backend, Config, Outcome, Property};
use beam_bvh::{BuildOptions, Bvh8, Collapse, FlatBvh, Kernel, RayDistribution, WideBvh};
use beam_math::glam::Vec3;
use beam_math::{Aabb, Triangle};
use beam_scene::mesh::{self, Mesh};

mod answers;
mod brute_force;
mod rays;
mod rounding;

pub use brute_force::brute_force_closest;
pub use rays::{RaySet, ray_set, scene_light};
pub use rounding::watertight_t_error;

use answers::{Agreement, Answers, compare, reference};

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
/// `t` within 1e-5 relative on the CPU layouts, which round as brute force does; on the GPU, whose
/// compiler may contract `a·b + c` into fused multiply-adds, within the larger of that and the two
/// evaluations' first-order rounding bounds, `answers::t_tolerance`), and any-hit answers of
/// shadow rays agree (either answer when brute force's closest hit is within that tolerance of
/// `t_max`). `Config::rays` rays of each kind per mesh.
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
        let mut agreement = Agreement::default();
        for (builder, options) in builders(&set, bounds) {
            let bvh = FlatBvh::build(tris, &options);
            if let Some(gpu) = &gpu {
                let answers = Answers::gpu(gpu, &bvh, tris, &set)?;
                agreement += compare(&case.name, &format!("{builder} gpu"), &answers, &set, &reference)?;
                total += 3 * config.rays as u64;
                continue;
            }
            agreement += compare(&case.name, builder, &Answers::flat(&bvh, tris, &set), &set, &reference)?;
            let wide = WideBvh::new(&bvh, tris);
            agreement +=
                compare(&case.name, &format!("{builder} 4-wide"), &Answers::wide(&wide, &set), &set, &reference)?;
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
                    agreement += compare(&case.name, &name, &Answers::wide8(&bvh8, &set), &set, &reference)?;
                    total += 3 * config.rays as u64;
                }
            }
        }
        let hit_rate = reference.camera.iter().filter(|h| h.is_some()).count() as f64 / set.camera.len() as f64;
        // On the GPU, how much of the rounding bound the hits took.
        let rounding = match gpu {
            Some(_) => format!(
                ", {} beyond 1e-5 relative, worst |Δt| {:.1e} of its tolerance",
                agreement.widened, agreement.worst
            ),
            None => String::new(),
        };
        notes.push(format!(
            "{} ({} tris, {} degenerate, {:.0}% camera hits, {} ties{rounding})",
            case.name,
            tris.len(),
            sah.degenerate,
            100.0 * hit_rate,
            agreement.ties
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
