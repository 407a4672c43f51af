//! `beam bench bvh`: build with each of our builders and trace primary, shadow and diffuse rays,
//! single-threaded and on all cores, beside the peers measured in the same run on the same rays.

mod ours;
mod paired;
mod timing;

pub(crate) use timing::Clock;

use super::peer_set::peers;
use super::stats::median;
use super::tracer::Tracer;
use beam_bvh::{BuildOptions, Bvh8, Collapse, FlatBvh, Kernel, RayDistribution, TraversalStats, WideBvh};
use beam_math::glam::Vec3;
use beam_math::{Ray, Triangle};
use beam_render::cpu_clock::thread_cpu_seconds;
use beam_scene::scene::{Camera, Light};
use ours::{Binary, Counted, Wide4, Wide8};
use paired::Paired;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;
use timing::{KINDS, Rays, throughput};

/// One row of the JSON output.
#[derive(Serialize, Clone)]
pub(crate) struct Row {
    name: String,
    ray_kind: &'static str,
    threads: usize,
    build_ms: f64,
    mrays_per_s: f64,
}

/// A pinhole camera inside the scene box looking along its longest horizontal axis (an interior
/// view for Sponza, the conference room and Sibenik), `width × height` primary rays; from the
/// primary hits one shadow ray to a random point of the quad light under the ceiling and one
/// cosine-distributed diffuse bounce each.
fn make_rays(bvh: &FlatBvh, tris: &[Triangle], width: usize, height: usize) -> Rays {
    let b = bvh.nodes[0].bounds();
    let e = b.extent();
    let camera = Camera::interior(b, width as u32, height as u32);
    let frame = camera.frame();
    let primary: Vec<Ray> = (0..width * height)
        .map(|i| {
            let r = camera.ray(&frame, (i % width) as f32 + 0.5, (i / width) as f32 + 0.5);
            Ray::new(r.origin, r.direction.normalize())
        })
        .collect();
    let hits = bvh.closest_hits(tris, &primary, f32::INFINITY);
    let (lc, lu, lv) = scene_light(b);
    let mut rng = Pcg64::seed_from_u64(77);
    let eps = 1e-4 * e.length();
    let mut shadow = Vec::new();
    let mut diffuse = Vec::new();
    for (ray, hit) in primary.iter().zip(&hits) {
        let Some(h) = hit else { continue };
        let mut n = tris[h.prim as usize].scaled_normal().normalize_or_zero();
        if n.dot(ray.direction) > 0.0 {
            n = -n;
        }
        let p = ray.at(h.t) + n * eps;
        let target = lc + lu * uniform(&mut rng, -0.5, 0.5) + lv * uniform(&mut rng, -0.5, 0.5);
        shadow.push((Ray::new(p, target - p), 0.999));
        let (u1, u2) = (uniform(&mut rng, 0.0, 1.0), uniform(&mut rng, 0.0, 1.0));
        let t = n.any_orthonormal_vector();
        let phi = std::f32::consts::TAU * u2;
        let d = t * u1.sqrt() * phi.cos() + n.cross(t) * u1.sqrt() * phi.sin() + n * (1.0 - u1).sqrt();
        diffuse.push(Ray::new(p, d));
    }
    Rays { primary, shadow, diffuse, eye: camera.position, forward: frame.forward }
}

/// The centre and the two edges of the quad light under the ceiling of a scene box (as the BVH
/// properties of the conformance suite place it).
fn scene_light(bounds: beam_math::Aabb) -> (Vec3, Vec3, Vec3) {
    match Light::under_ceiling(bounds, 0.33, Vec3::ONE) {
        Light::Quad { corner, edge_u, edge_v, .. } => (corner + 0.5 * (edge_u + edge_v), edge_u, edge_v),
        _ => unreachable!("under_ceiling is a quad"),
    }
}

/// Uniform in `[lo, hi)`, as the conformance suite's generator draws it (the same rays, seed for seed).
fn uniform(rng: &mut Pcg64, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * rng.random::<f32>()
}

/// Timing rounds: every tracer is timed once per round on every ray kind and keeps its best, so
/// that a drift in the machine's speed (a shared virtual machine) meets all tracers alike rather
/// than the ones timed last.
const ROUNDS: usize = 3;

/// Disagreements of a tracer with the reference (closest-hit distance beyond 1e-4 relative, or a
/// different occlusion answer) over all rays.
fn disagreements(t: &dyn Tracer, reference: &dyn Tracer, rays: &Rays) -> usize {
    let close = |a: Option<f32>, b: Option<f32>| match (a, b) {
        (Some(a), Some(b)) => (a - b).abs() <= 1e-4 * b.abs().max(1e-3),
        (None, None) => true,
        _ => false,
    };
    let c = rays
        .primary
        .par_iter()
        .chain(rays.diffuse.par_iter())
        .filter(|r| !close(t.closest(r), reference.closest(r)))
        .count();
    c + rays.shadow.par_iter().filter(|(r, m)| t.occluded(r, *m) != reference.occluded(r, *m)).count()
}

/// Run the benchmark on the OBJ at `scene`, print the table and optionally write JSON.
pub(crate) fn run(scene: &Path, json: Option<&Path>, width: usize, sah_only: bool, clock: Clock) -> Result<(), String> {
    let mesh = beam_scene::mesh::load_obj(scene).map_err(|e| e.to_string())?;
    let all = mesh.triangles();
    // Peers get the same triangles our builders keep: degenerate ones removed.
    let tris: Vec<Triangle> = all.iter().copied().filter(|t| t.is_valid()).collect();
    let threads = rayon::current_num_threads();
    println!(
        "scene {}: {} triangles ({} degenerate removed), {} threads",
        scene.display(),
        tris.len(),
        all.len() - tris.len(),
        threads
    );
    let probe = FlatBvh::build(&tris, &BuildOptions::sah());
    let rays = make_rays(&probe, &tris, width, width);
    println!(
        "rays: {} primary ({}²), {} shadow, {} diffuse",
        rays.primary.len(),
        width,
        rays.shadow.len(),
        rays.diffuse.len()
    );
    let clock = match clock {
        Clock::Thread if thread_cpu_seconds().is_none() => {
            println!("timing: no thread CPU clock here: wall clock");
            Clock::Wall
        }
        Clock::Thread => {
            println!("timing: 1-thread rows by the thread's CPU time (--cpu-time), others by wall clock");
            Clock::Thread
        }
        Clock::Wall => Clock::Wall,
    };
    let light_dir = Vec3::Y;
    let builders = [
        ("beam-sah", BuildOptions::sah()),
        ("beam-pah-light", BuildOptions::pah(RayDistribution::Parallel { direction: light_dir })),
        ("beam-pah-eye", BuildOptions::pah(RayDistribution::Pencil { origin: rays.eye, forward: rays.forward })),
    ];
    let builders = if sah_only { &builders[..1] } else { &builders[..] };
    // The high-quality mode and pre-splitting exist for the 8-wide layout only.
    let hq = ("beam-hq", BuildOptions::high_quality());
    let mut binaries = Vec::new();
    let mut wides = Vec::new();
    let mut wides8 = Vec::new();
    for (name, options) in builders {
        let mut bvh = FlatBvh::default();
        let build_ms = median_ms(|| bvh = FlatBvh::build(&tris, options));
        let s = Instant::now();
        let wide = WideBvh::new(&bvh, &tris);
        let convert_ms = s.elapsed().as_secs_f64() * 1e3;
        let mut bvh8 = Bvh8::default();
        let build8_ms = median_ms(|| bvh8 = Bvh8::build(&tris, options));
        wides8.push(Wide8 { name: format!("{name}-8wide"), bvh: bvh8, build_ms: build8_ms });
        wides.push(Wide4 { name: format!("{name}-4wide"), bvh: wide, build_ms: build_ms + convert_ms });
        binaries.push(Binary { name: (*name).into(), bvh, tris: &tris, build_ms });
    }
    // The static-scene modes and the default's neighbours: reinserted binary trees collapsed
    // greedily and by the dynamic program, the default with leaves of up to 16 and without the
    // light reinsertion, the tree binned straight into eight-wide nodes (Embree's way), pre-split
    // triangles, spatial splits.
    let dp = Some(Collapse::Optimal);
    let modes = [
        hq,
        ("beam-hq-dp", BuildOptions { collapse: dp, ..BuildOptions::high_quality() }),
        ("beam-dp16", BuildOptions { max_leaf: 16, ..BuildOptions::sah() }),
        ("beam-unrefined", BuildOptions { refine: 0.0, ..BuildOptions::sah() }),
        ("beam-direct", BuildOptions { collapse: None, ..BuildOptions::sah() }),
        ("beam-presplit", BuildOptions { presplit: 0.3, ..BuildOptions::sah() }),
        ("beam-sbvh", BuildOptions::spatial_splits()),
    ];
    let extra: Vec<Wide8> = modes
        .iter()
        .map(|(name, options)| {
            let mut bvh8 = Bvh8::default();
            let build_ms = median_ms(|| bvh8 = Bvh8::build(&tris, options));
            Wide8 { name: format!("{name}-8wide"), bvh: bvh8, build_ms }
        })
        .collect();
    let kernel = wides8[0].bvh.kernel();
    println!("8-wide traversal kernel: {kernel} (run-time dispatch: {})", dispatch_note());
    let mut portable = None;
    if kernel != Kernel::Portable {
        let mut bvh = wides8[0].bvh.clone();
        bvh.set_kernel(Kernel::Portable);
        let name = format!("{}-{}", wides8[0].name, "portable");
        portable = Some(Wide8 { name, bvh, build_ms: wides8[0].build_ms });
    }
    let peer_tracers = peers(&tris)?;
    // The reference for disagreements and ratios is the first: our SAH tree in the 8-wide layout.
    let ours: Vec<&dyn Tracer> = wides8
        .iter()
        .map(|o| o as &dyn Tracer)
        .chain(extra.iter().map(|o| o as &dyn Tracer))
        .chain(portable.iter().map(|o| o as &dyn Tracer))
        .chain(wides.iter().map(|o| o as &dyn Tracer))
        .chain(binaries.iter().map(|o| o as &dyn Tracer))
        .collect();
    let ours_count = ours.len();
    let tracers: Vec<&dyn Tracer> = ours.into_iter().chain(peer_tracers.iter().map(|p| p.as_ref())).collect();
    let mut rows = Vec::new();
    println!();
    println!(
        "{:<22} {:>9} {:>3}  {:>9} {:>9} {:>9}  (Mrays/s)  disagreements",
        "name", "build ms", "T", "primary", "shadow", "diffuse"
    );
    // best[tracer][threaded][kind], the best of the rounds.
    let mut best = vec![[[0.0f64; 3]; 2]; tracers.len()];
    for _ in 0..ROUNDS {
        for (t, b) in tracers.iter().zip(&mut best) {
            for (parallel, row) in [false, true].into_iter().zip(b.iter_mut()) {
                for (kind, v) in KINDS.iter().zip(row.iter_mut()) {
                    *v = v.max(throughput(*t, &rays, kind, parallel, clock));
                }
            }
        }
    }
    for (i, t) in tracers.iter().enumerate() {
        let wrong = if i == 0 { 0 } else { disagreements(*t, tracers[0], &rays) };
        for (parallel, m) in [false, true].into_iter().zip(&best[i]) {
            let n = if parallel { threads } else { 1 };
            for (k, v) in KINDS.iter().zip(m) {
                rows.push(Row { name: t.name(), ray_kind: k, threads: n, build_ms: t.build_ms(), mrays_per_s: *v });
            }
            println!(
                "{:<22} {:>9.1} {:>3}  {:>9.2} {:>9.2} {:>9.2}  {}",
                t.name(),
                t.build_ms(),
                n,
                m[0],
                m[1],
                m[2],
                if parallel { String::new() } else { wrong.to_string() }
            );
        }
    }
    // Ratios for our default build and the static-scene modes (`extra` follows `wides8`).
    let modes_compared = ["beam-hq", "beam-hq-dp", "beam-direct", "beam-sbvh"]
        .iter()
        .filter_map(|name| modes.iter().position(|(n, _)| n == name).map(|i| wides8.len() + i));
    let compared: Vec<usize> = std::iter::once(0).chain(modes_compared).collect();
    let paired = paired::alternate(&tris, &BuildOptions::sah(), tracers[0], &tracers[ours_count..], &rays, clock);
    print_ratios(&rows, ours_count, &tracers, &compared, &paired);
    let counted: Vec<&dyn Counted> = (0..builders.len())
        .flat_map(|i| [&binaries[i] as &dyn Counted, &wides[i] as &dyn Counted, &wides8[i] as &dyn Counted])
        .chain(extra.iter().map(|o| o as &dyn Counted))
        .collect();
    print_work(&binaries, &counted, &rays);
    if let Some(path) = json {
        let text = serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())?;
        beam_scene::io::write_atomic(path, text.as_bytes()).map_err(|e| e.to_string())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Median of three timings of `f`, in milliseconds.
fn median_ms(mut f: impl FnMut()) -> f64 {
    median(
        (0..3)
            .map(|_| {
                let s = Instant::now();
                f();
                s.elapsed().as_secs_f64() * 1e3
            })
            .collect(),
    )
}

/// What the CPU offers the 8-wide kernels.
fn dispatch_note() -> String {
    let has: Vec<String> = [Kernel::Avx512, Kernel::Avx2, Kernel::Portable]
        .iter()
        .map(|k| format!("{k} {}", if k.is_available() { "yes" } else { "no" }))
        .collect();
    has.join(", ")
}

/// Ratios of our tracers `compared` (indices into `tracers`) to every peer; from `paired` (timed
/// in alternation) where it has the pair, else from the table.
fn print_ratios(rows: &[Row], ours: usize, tracers: &[&dyn Tracer], compared: &[usize], paired: &[Paired]) {
    if tracers.len() == ours {
        println!("\n(no peers in this build: `--features peers` adds Embree 3 and obvhs)");
        return;
    }
    println!("\nratios ours/peer (Mrays/s; build: peer ms / our ms, >1 means we build faster)");
    let get = |name: &str, kind: &str, threads: usize| {
        rows.iter().find(|r| r.name == name && r.ray_kind == kind && r.threads == threads).map(|r| r.mrays_per_s)
    };
    let threads = rows.iter().map(|r| r.threads).max().unwrap_or(1);
    for peer in &tracers[ours..] {
        for our in compared.iter().filter(|&&i| i < ours).map(|&i| tracers[i]) {
            let pair = paired.iter().find(|p| p.ours == our.name() && p.peer == peer.name());
            let build = match pair.and_then(|p| p.build_ms) {
                Some((a, b)) => b / a,
                None => peer.build_ms() / our.build_ms(),
            };
            let mut parts = vec![format!("build {build:.2}")];
            for (parallel, t) in [(false, 1), (true, threads)] {
                for (k, kind) in KINDS.iter().enumerate() {
                    let ratio = match pair {
                        Some(p) => Some(p.ratios[usize::from(parallel)][k]),
                        None => get(&our.name(), kind, t).zip(get(&peer.name(), kind, t)).map(|(a, b)| a / b),
                    };
                    if let Some(r) = ratio {
                        parts.push(format!("{kind}/{t}T {r:.2}"));
                    }
                }
            }
            let how = if pair.is_some() { " (in alternation)" } else { "" };
            println!("  {} / {}{how}: {}", our.name(), peer.name(), parts.join(", "));
        }
    }
}

/// Work per ray of every layout (PAH vs SAH, binary vs wide): box tests / triangle tests for
/// primary and shadow rays; SAH cost of each binary tree.
fn print_work(binaries: &[Binary<'_>], counted: &[&dyn Counted], rays: &Rays) {
    println!("\nwork per ray (single thread): box tests / triangle tests; SAH cost of the binary tree");
    println!("{:<24} {:>18} {:>18} {:>9}", "layout", "primary", "shadow", "SAH cost");
    for c in counted {
        let (pn, pt, sn, st) = visits(rays, |r, st| c.closest_stats(r, st), |r, m, st| c.any_stats(r, m, st));
        let sah = binaries.iter().find(|b| b.name == c.name()).map(|b| beam_bvh::TreeStats::of(&b.bvh).sah_cost);
        let sah = sah.map(|s| format!("{s:>9.1}")).unwrap_or_default();
        println!("{:<24} {pn:>9.1} / {pt:>6.2} {sn:>9.1} / {st:>6.2} {sah}", c.name());
    }
}

/// Box tests and triangle tests per ray of one layout: `closest` and `any` trace a ray with a
/// statistics sink (primary rays: closest hit; shadow rays: any hit before their `t_max`).
fn visits(
    rays: &Rays,
    closest: impl Fn(Ray, &mut TraversalStats),
    any: impl Fn(Ray, f32, &mut TraversalStats),
) -> (f64, f64, f64, f64) {
    let mut p = TraversalStats::default();
    rays.primary.iter().for_each(|r| closest(*r, &mut p));
    let mut s = TraversalStats::default();
    rays.shadow.iter().for_each(|(r, m)| any(*r, *m, &mut s));
    let (np, ns) = (rays.primary.len().max(1) as f64, rays.shadow.len().max(1) as f64);
    (p.node_visits as f64 / np, p.triangle_tests as f64 / np, s.node_visits as f64 / ns, s.triangle_tests as f64 / ns)
}
