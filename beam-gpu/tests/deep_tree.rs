//! Degenerate, deeply nested meshes against the GPU traversal's stack: stacks of parallel
//! triangles whose BVH peels one triangle off per level. A tree that needs the whole stack
//! ([`GPU_STACK_SIZE`] entries) and one the builder makes within it trace on the GPU exactly as on
//! the CPU (same triangle, same distance); a tree one level deeper, and one the builder makes past
//! the stack, are refused by [`GpuBvh::new`]: never a silent miss. The GPU halves are skipped,
//! loudly, without an adapter.

mod common;

use beam_bvh::gpu::{GPU_STACK_SIZE, GpuBvh, GpuBvhError, stack_entries};
use beam_bvh::{BuildOptions, FlatBvh, FlatNode, TreeStats};
use beam_gpu::Gpu;
use beam_gpu::interface::MISS;
use beam_gpu::raytrace::{GpuRay, RayTracer};
use beam_math::glam::Vec3;
use beam_math::{Aabb, Ray, Triangle};
use common::adapter;

/// The triangle over the unit right triangle of the y–z plane at `x`.
fn plane(x: f32) -> Triangle {
    Triangle::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x, 1.0, 0.0), Vec3::new(x, 0.0, 1.0))
}

/// `m` triangles at x = 0, −h, −2h, … in a hand-built chain: inner node `k` holds triangles
/// `k..m`, its right child the leaf of triangle `k`, its left the rest; depth `m − 1`. The builder
/// never makes a tree this deep (it splits at the median past 96 levels), so it is built here.
fn chain(m: usize) -> (FlatBvh, Vec<Triangle>) {
    let tris: Vec<Triangle> = (0..m).map(|k| plane(-0.01 * k as f32)).collect();
    let bounds = |k: usize| tris[k..].iter().fold(Aabb::EMPTY, |b, t| b.union(Aabb::from_points(&t.v)));
    let node = |b: Aabb, right_or_first: usize, count: u32| FlatNode {
        min: b.min.to_array(),
        right_or_first: right_or_first as u32,
        max: b.max.to_array(),
        count,
    };
    let inner = m - 1;
    // Inner nodes 0..inner, then the leaves in depth-first order: triangle m − 1 (the last inner
    // node's left child), then the right children from the deepest up (triangle k at 2·inner − k).
    let mut nodes: Vec<FlatNode> = (0..inner).map(|k| node(bounds(k), 2 * inner - k, 0)).collect();
    let prims: Vec<u32> = (0..m as u32).rev().collect();
    nodes.extend(prims.iter().enumerate().map(|(j, &p)| node(Aabb::from_points(&tris[p as usize].v), j, 1)));
    (FlatBvh { nodes, prims, degenerate: 0, input_triangles: m }, tris)
}

/// `n` triangles at x = 2^−k: with 2 bins per axis the binned SAH splits the one nearest x = 1
/// off into a leaf at every level, down to the builder's median splits.
fn peeled(n: usize) -> (FlatBvh, Vec<Triangle>) {
    let tris: Vec<Triangle> = (0..n).map(|k| plane((-(k as f32)).exp2())).collect();
    (FlatBvh::build(&tris, &BuildOptions { bins: 2, ..BuildOptions::sah() }), tris)
}

/// Rays along ±x through a grid of the triangles' y–z footprint (off its edges), from x = `near`
/// (the deepest triangles first) and from x = `far`, slightly tilted; and rays between random
/// points of `bounds` grown by 0.5, or with `from_near` from random points of the plane x = `near`
/// mostly along +x (where the triangles crowd towards x = 0: so that no two lie at the same
/// distance in f32).
fn rays(near: f32, far: f32, bounds: Aabb, from_near: bool) -> Vec<Ray> {
    let mut out = Vec::new();
    for i in 0..20 {
        for j in 0..20 {
            let (y, z) = ((i as f32 + 0.3) / 20.0, (j as f32 + 0.6) / 20.0);
            let tilt = Vec3::new(0.0, 0.01 * (i % 3) as f32 - 0.01, 0.01 * (j % 3) as f32 - 0.01);
            out.push(Ray::new(Vec3::new(near, y, z), Vec3::X + tilt));
            out.push(Ray::new(Vec3::new(far, y, z), -Vec3::X + tilt));
        }
    }
    let mut s = 12345u32;
    let mut r = move || {
        s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (s >> 8) as f32 / (1u32 << 24) as f32
    };
    let (lo, size) = (bounds.min - Vec3::splat(0.5), bounds.extent() + Vec3::splat(1.0));
    for _ in 0..2000 {
        let a = lo + size * Vec3::new(r(), r(), r());
        let b = lo + size * Vec3::new(r(), r(), r());
        out.push(if from_near {
            // Mostly along +x, so that the distances to the crowded planes are x's.
            Ray::new(Vec3::new(near, a.y, a.z), Vec3::new(1.0, 1.8 * r() - 0.9, 1.8 * r() - 0.9))
        } else {
            Ray::new(a, b - a)
        });
    }
    out
}

/// Closest hits (same triangle, distance within 1e-5 relative + 1e-6: NVIDIA's FMAs moved a
/// t of 1.6e-3 by 5e-8) and any hits (within t = 1) of
/// `rays` on the GPU and the CPU: the number of hits.
fn gpu_equals_cpu(gpu: &Gpu, bvh: &FlatBvh, tris: &[Triangle], rays: &[Ray]) -> usize {
    let tracer = RayTracer::new(gpu, &GpuBvh::new(bvh, tris).unwrap()).unwrap();
    let closest: Vec<GpuRay> = rays.iter().map(GpuRay::closest).collect();
    let any: Vec<GpuRay> = rays.iter().map(|r| GpuRay::any(r, 1.0)).collect();
    let (closest, any) = (tracer.trace(gpu, &closest).unwrap(), tracer.trace(gpu, &any).unwrap());
    let mut hits = 0;
    for (i, ray) in rays.iter().enumerate() {
        let cpu = bvh.closest_hit(tris, *ray, f32::INFINITY);
        match cpu {
            None => assert_eq!(closest[i].prim, MISS, "ray {i} {ray:?}: the GPU hits, the CPU does not"),
            Some(h) => {
                hits += 1;
                assert_eq!(closest[i].prim, h.prim, "ray {i} {ray:?}: GPU {:?}, CPU {h:?}", closest[i]);
                assert!(
                    (closest[i].t - h.t).abs() <= 1e-5 * h.t + 1e-6,
                    "ray {i}: GPU t {}, CPU {}",
                    closest[i].t,
                    h.t
                );
            }
        }
        assert_eq!(any[i].t > 0.5, bvh.any_hit(tris, *ray, 1.0), "ray {i} {ray:?}: any hit");
    }
    hits
}

#[test]
fn a_tree_needing_the_whole_stack_traces_as_on_the_cpu() {
    let (bvh, tris) = chain(GPU_STACK_SIZE);
    assert_eq!(TreeStats::of(&bvh).depth, GPU_STACK_SIZE - 1);
    assert_eq!(stack_entries(&bvh), GPU_STACK_SIZE);
    let Some(gpu) = adapter() else { return };
    // Along +x the leaf of each level is the farther child, so every one waits on the stack.
    let hits = gpu_equals_cpu(&gpu, &bvh, &tris, &rays(-2.0, 1.0, bvh.nodes[0].bounds(), false));
    eprintln!("chain of depth {}: {hits} hits equal on {}", GPU_STACK_SIZE - 1, gpu.describe());
}

#[test]
fn built_trees_trace_as_on_the_cpu_or_are_refused() {
    // Within the stack: the GPU traces it as the CPU does.
    let (bvh, tris) = peeled(60);
    let depth = TreeStats::of(&bvh).depth;
    eprintln!("built tree over {} triangles: depth {depth}, {} stack entries", tris.len(), stack_entries(&bvh));
    assert!(depth > 32 && stack_entries(&bvh) == depth + 1 && depth < GPU_STACK_SIZE, "depth {depth}");
    // Past it (the builder allows 96 + log2 n levels): refused, with the depth it would need.
    let (deep, deep_tris) = peeled(100);
    let deep_depth = TreeStats::of(&deep).depth;
    assert!(deep_depth >= GPU_STACK_SIZE, "depth {deep_depth}");
    assert_eq!(
        GpuBvh::new(&deep, &deep_tris).unwrap_err(),
        GpuBvhError::TooDeep { depth: deep_depth, entries: deep_depth + 1, limit: GPU_STACK_SIZE }
    );
    eprintln!("built tree of depth {deep_depth} refused");
    let Some(gpu) = adapter() else { return };
    // From x = 0 along +x the deepest triangle is the nearest (t = 2^−k, no ties).
    let hits = gpu_equals_cpu(&gpu, &bvh, &tris, &rays(0.0, 2.0, bvh.nodes[0].bounds(), true));
    eprintln!("built tree of depth {depth}: {hits} hits equal on {}", gpu.describe());
}

#[test]
fn a_tree_one_level_deeper_is_refused() {
    let (bvh, tris) = chain(GPU_STACK_SIZE + 1);
    assert_eq!(
        GpuBvh::new(&bvh, &tris).unwrap_err(),
        GpuBvhError::TooDeep { depth: GPU_STACK_SIZE, entries: GPU_STACK_SIZE + 1, limit: GPU_STACK_SIZE }
    );
}
