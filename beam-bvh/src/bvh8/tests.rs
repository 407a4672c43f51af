use super::roots::NODE_COST;
use super::*;
use crate::traverse::tests::soup;
use crate::{BuildOptions, Collapse, RayDistribution};
use beam_math::Aabb;
use beam_math::collide::WatertightRay;
use beam_math::glam::Vec3;
use beam_math::heuristics::surface_area;

/// A closed grid of quads (shared edges everywhere) with its diagonals, for watertightness.
pub(super) fn grid(n: usize) -> Vec<Triangle> {
    let mut out = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let o = Vec3::new(i as f32, j as f32, ((i * 7 + j * 3) % 5) as f32 * 0.1);
            let p = |di: usize, dj: usize| {
                let (x, y) = (i + di, j + dj);
                Vec3::new(x as f32, y as f32, ((x * 7 + y * 3) % 5) as f32 * 0.1)
            };
            out.push(Triangle::new(o, p(1, 0), p(1, 1)));
            out.push(Triangle::new(o, p(1, 1), p(0, 1)));
        }
    }
    out
}

fn brute(tris: &[Triangle], ray: Ray, t_max: f32) -> Option<(u32, f32)> {
    let wt = WatertightRay::new(ray);
    let mut best = None;
    let mut t_best = t_max;
    for (i, t) in tris.iter().enumerate() {
        if let Some(h) = wt.intersect(t, 0.0, t_best) {
            t_best = h.t;
            best = Some((i as u32, h.t));
        }
    }
    best
}

fn kernels() -> Vec<Kernel> {
    [Kernel::Portable, Kernel::Avx2, Kernel::Avx512].into_iter().filter(|k| k.is_available()).collect()
}

fn check(tris: &[Triangle], bvh: &mut Bvh8, rays: &[Ray], t_any: f32) {
    for k in kernels() {
        assert!(bvh.set_kernel(k));
        let mut last = None;
        for (i, ray) in rays.iter().enumerate() {
            let want = brute(tris, *ray, f32::INFINITY);
            let got = bvh.closest_hit(*ray, f32::INFINITY);
            // The same triangle, or a tie within rounding: a hit a few ulps before a box's entry
            // distance is found only if that box is entered before the other hit.
            match (got, want) {
                (Some(g), Some(w)) => {
                    assert!((g.t - w.1).abs() <= 1e-6 * w.1, "{k} ray {i}: {g:?} vs {w:?}");
                    let h = WatertightRay::new(*ray).intersect(&tris[g.prim as usize], 0.0, f32::INFINITY);
                    assert_eq!(h.map(|h| h.t), Some(g.t), "{k} ray {i}");
                }
                (g, w) => assert_eq!(g.map(|g| g.prim), w.map(|w| w.0), "{k} ray {i}"),
            }
            // Any hit: the brute-force answer, except for a hit within rounding of `t_any`, which the
            // kernels' division-free range test may count either way.
            let boundary = want.is_some_and(|w| (w.1 - t_any).abs() <= 1e-6 * t_any);
            if !boundary {
                let any = want.is_some_and(|w| w.1 <= t_any);
                assert_eq!(bvh.any_hit(*ray, t_any), any, "{k} ray {i}");
                // With the last ray's occluder, another block, or none first: the same answer, by a
                // block that holds a triangle the ray hits in range.
                let mut next = last;
                for hint in [last, Some(i as u32 % bvh.blocks.len() as u32), Some(u32::MAX - 1), None] {
                    let block = bvh.occluding_block(*ray, t_any, hint);
                    if hint == last {
                        next = block.or(last);
                    }
                    assert_eq!(block.is_some(), any, "{k} ray {i} hint {hint:?}");
                    if let Some(b) = block {
                        let lanes = &bvh.prims[4 * b as usize..4 * b as usize + 4];
                        let wt = WatertightRay::new(*ray);
                        assert!(
                            lanes
                                .iter()
                                .any(|&p| p != u32::MAX && wt.intersect(&tris[p as usize], 0.0, t_any).is_some()),
                            "{k} ray {i}: block {b} is not hit"
                        );
                    }
                }
                last = next;
            }
            let mut stats = TraversalStats::default();
            let counted = bvh.closest_hit_stats(*ray, f32::INFINITY, &mut stats);
            match (counted, got) {
                (Some(c), Some(g)) => assert!((c.t - g.t).abs() <= 1e-6 * g.t, "{k} ray {i}"),
                (c, g) => assert_eq!(c, g, "{k} ray {i}"),
            }
        }
    }
}

#[test]
fn every_kernel_equals_brute_force() {
    let tris = soup(3000, 7);
    let rays: Vec<Ray> = soup(400, 99).iter().map(|t| Ray::new(t.v[0] * 2.0, t.v[1] - t.v[0] * 2.0)).collect();
    for options in [
        BuildOptions::sah(),
        BuildOptions { parallel: false, max_leaf: 16, ..BuildOptions::sah() },
        BuildOptions { collapse: None, ..BuildOptions::sah() },
        BuildOptions { collapse: None, parallel: false, max_leaf: 16, ..BuildOptions::sah() },
        BuildOptions { presplit: 1.0, ..BuildOptions::high_quality() },
        BuildOptions { reinsert: true, ..BuildOptions::sah() },
        BuildOptions { reinsert: true, presplit: 1.0, max_leaf: 16, parallel: false, ..BuildOptions::sah() },
        BuildOptions { collapse: Some(Collapse::Optimal), ..BuildOptions::high_quality() },
        BuildOptions { collapse: Some(Collapse::Optimal), max_leaf: 16, ..BuildOptions::sah() },
        BuildOptions { collapse: Some(Collapse::Optimal), max_leaf: 1, ..BuildOptions::sah() },
        BuildOptions::spatial_splits(),
        BuildOptions { spatial: 1.0, reinsert: true, parallel: false, ..BuildOptions::sah() },
        BuildOptions::pah(RayDistribution::Pencil { origin: Vec3::new(0.0, 0.0, 12.0), forward: -Vec3::Z }),
    ] {
        let mut bvh = Bvh8::build(&tris, &options);
        check(&tris, &mut bvh, &rays, 3.0);
    }
}

#[test]
fn shared_edges_stay_closed() {
    let tris = grid(40);
    for options in [
        BuildOptions::sah(),
        BuildOptions { presplit: 2.0, ..BuildOptions::sah() },
        BuildOptions { reinsert: true, ..BuildOptions::sah() },
        BuildOptions { collapse: Some(Collapse::Optimal), ..BuildOptions::high_quality() },
        BuildOptions { collapse: None, ..BuildOptions::sah() },
        BuildOptions::spatial_splits(),
    ] {
        shared_edges_stay_closed_with(&tris, &options);
    }
}

fn shared_edges_stay_closed_with(tris: &[Triangle], options: &BuildOptions) {
    let mut bvh = Bvh8::build(tris, options);
    // Rays through inner grid vertices and edge midpoints: exactly on shared edges.
    let h = |x: usize, y: usize| ((x * 7 + y * 3) % 5) as f32 * 0.1;
    let eye = Vec3::new(20.0, 20.0, 30.0);
    let rays: Vec<Ray> = (0..38 * 38 * 2)
        .map(|i| {
            let (x, y) = (1 + (i / 2) % 38, 1 + (i / 2) / 38);
            let target = if i % 2 == 0 {
                Vec3::new(x as f32, y as f32, h(x, y))
            } else {
                Vec3::new(x as f32 + 0.5, y as f32, 0.5 * (h(x, y) + h(x + 1, y)))
            };
            Ray::new(eye, target - eye)
        })
        .collect();
    check(tris, &mut bvh, &rays, 1.0);
    for k in kernels() {
        bvh.set_kernel(k);
        assert!(rays.iter().all(|r| bvh.closest_hit(*r, f32::INFINITY).is_some()), "{k}: a ray fell through");
    }
}

#[test]
fn every_valid_triangle_is_in_one_lane() {
    let mut tris = soup(5000, 3);
    tris.push(Triangle::new(Vec3::ZERO, Vec3::X, 2.0 * Vec3::X));
    tris.push(Triangle::new(Vec3::NAN, Vec3::X, Vec3::Y));
    let bvh = Bvh8::build(&tris, &BuildOptions::sah());
    assert_eq!(bvh.degenerate, 2);
    let mut seen: Vec<u32> = bvh.prims.iter().copied().filter(|&p| p != u32::MAX).collect();
    seen.sort_unstable();
    assert_eq!(seen, (0..5000).collect::<Vec<_>>());
    // Reinserted and collapsed: the same.
    let ri = Bvh8::build(&tris, &BuildOptions { reinsert: true, ..BuildOptions::sah() });
    assert_eq!(ri.degenerate, 2);
    let mut seen: Vec<u32> = ri.prims.iter().copied().filter(|&p| p != u32::MAX).collect();
    seen.sort_unstable();
    assert_eq!(seen, (0..5000).collect::<Vec<_>>());
    // Pre-split, or with spatial splits: every triangle in some lane, none twice in a leaf.
    let presplit = Bvh8::build(&tris, &BuildOptions { presplit: 1.0, ..BuildOptions::sah() });
    let spatial = Bvh8::build(&tris, &BuildOptions::spatial_splits());
    for hq in [&presplit, &spatial] {
        split_triangles_are_kept_once_per_leaf(hq, 5000);
    }
    // Child boxes hold their subtrees (a split triangle's leaves hold only their part of it).
    for bvh in [&bvh, &ri] {
        child_boxes_hold_their_subtrees(bvh);
    }
    let direct = Bvh8::build(&tris, &BuildOptions { collapse: None, ..BuildOptions::sah() });
    for bvh in [&bvh, &ri, &presplit, &spatial, &direct] {
        siblings_are_grouped(bvh);
    }
}

/// Every node lists its inner children first, at `base`, `base + 1`, … after itself, then its
/// leaves, then unused slots; every node but the root is the child of exactly one node.
fn siblings_are_grouped(bvh: &Bvh8) {
    let mut parents = vec![0usize; bvh.nodes.len()];
    for (i, n) in bvh.nodes.iter().enumerate() {
        let kind = |s: usize| match n.child[s] {
            Node8::UNUSED => 2,
            c if c & Node8::LEAF != 0 => 1,
            _ => 0,
        };
        assert!((1..8).all(|s| kind(s - 1) <= kind(s)), "node {i}: slots out of order");
        assert_eq!((0..8).filter(|&s| kind(s) == 0).count(), n.inner as usize, "node {i}");
        for s in 0..n.inner as usize {
            assert_eq!(n.child[s], n.base + s as u32, "node {i} slot {s}");
            assert!(n.child[s] as usize > i);
            parents[n.child[s] as usize] += 1;
        }
    }
    assert!(parents[1..].iter().all(|&p| p == 1));
}

/// Some of the `n` triangles of `hq` lie in several leaves, every one in some leaf, none twice in
/// one leaf.
fn split_triangles_are_kept_once_per_leaf(hq: &Bvh8, n: u32) {
    let mut seen: Vec<u32> = hq.prims.iter().copied().filter(|&p| p != u32::MAX).collect();
    assert!(seen.len() > n as usize, "some triangles split");
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen, (0..n).collect::<Vec<_>>());
    for n in &hq.nodes {
        for s in 0..8 {
            if n.child[s] & Node8::LEAF != 0 && n.child[s] != Node8::UNUSED {
                let (first, count) = Node8::leaf_blocks(n.child[s]);
                let mut lanes: Vec<u32> =
                    hq.prims[4 * first..4 * (first + count)].iter().copied().filter(|&p| p != u32::MAX).collect();
                let len = lanes.len();
                lanes.sort_unstable();
                lanes.dedup();
                assert_eq!(lanes.len(), len, "a triangle twice in one leaf");
            }
        }
    }
}

fn child_boxes_hold_their_subtrees(bvh: &Bvh8) {
    for n in &bvh.nodes {
        for s in 0..8 {
            let c = n.child[s];
            if c == Node8::UNUSED {
                continue;
            }
            let b = n.child_bounds(s);
            let inner = if c & Node8::LEAF != 0 {
                build::leaf_bounds(&bvh.blocks, &bvh.prims, c)
            } else {
                (0..8).map(|i| bvh.nodes[c as usize].child_bounds(i)).fold(Aabb::EMPTY, Aabb::union)
            };
            assert!(inner.min.cmpge(b.min).all() && inner.max.cmple(b.max).all());
        }
    }
}

/// SAH cost of an eight-wide tree as the collapses count it: `c_t · A` per node (the root's box
/// is the tree's), `A · blocks` per leaf.
fn wide_cost(bvh: &Bvh8, traversal_cost: f32) -> f64 {
    let mut cost = 0.0;
    let mut stack = vec![(0usize, bvh.bounds)];
    while let Some((i, b)) = stack.pop() {
        cost += f64::from(traversal_cost * surface_area(b));
        let n = &bvh.nodes[i];
        let used: Vec<usize> = (0..8).filter(|&s| n.child[s] != Node8::UNUSED).collect();
        assert!(i == 0 || used.len() >= 2, "an inner node of one child");
        for s in used {
            if n.child[s] & Node8::LEAF != 0 {
                let (_, blocks) = Node8::leaf_blocks(n.child[s]);
                assert_eq!(blocks, usize::from(n.tris[s]).div_ceil(4), "leaf blocks of four");
                cost += f64::from(surface_area(n.child_bounds(s))) * blocks as f64;
            } else {
                stack.push((n.child[s] as usize, n.child_bounds(s)));
            }
        }
    }
    cost
}

#[test]
fn optimal_collapse_is_exact_and_cheapest() {
    let mut tris = soup(5000, 3);
    tris.extend(grid(30));
    let all = tris.len() as u32;
    for reinsert in [false, true] {
        for max_leaf in [4, 8, 16] {
            let options = BuildOptions { reinsert, max_leaf, parallel: false, ..BuildOptions::sah() };
            let greedy = Bvh8::build(&tris, &BuildOptions { collapse: Some(Collapse::Greedy), ..options });
            let optimal = Bvh8::build(&tris, &BuildOptions { collapse: Some(Collapse::Optimal), ..options });
            for bvh in [&greedy, &optimal] {
                let mut seen: Vec<u32> = bvh.prims.iter().copied().filter(|&p| p != u32::MAX).collect();
                seen.sort_unstable();
                assert_eq!(seen, (0..all).collect::<Vec<_>>(), "every triangle in exactly one lane");
                child_boxes_hold_their_subtrees(bvh);
            }
            let (g, o) = (wide_cost(&greedy, NODE_COST), wide_cost(&optimal, NODE_COST));
            assert!(o <= g * (1.0 + 1e-5), "reinsert {reinsert}, leaves ≤ {max_leaf}: optimal {o} > greedy {g}");
        }
    }
}

#[test]
fn tiny_and_empty_trees() {
    let one = soup(1, 1);
    let bvh = Bvh8::build(&one, &BuildOptions::sah());
    let c = one[0].v.iter().sum::<Vec3>() / 3.0;
    assert_eq!(bvh.closest_hit(Ray::new(c + Vec3::Z * 10.0, -Vec3::Z), f32::INFINITY).map(|h| h.prim), Some(0));
    let dp = Bvh8::build(&one, &BuildOptions { collapse: Some(Collapse::Optimal), ..BuildOptions::sah() });
    assert_eq!(dp.closest_hit(Ray::new(c + Vec3::Z * 10.0, -Vec3::Z), f32::INFINITY).map(|h| h.prim), Some(0));
    let none = Bvh8::build(&[], &BuildOptions { collapse: Some(Collapse::Optimal), ..BuildOptions::sah() });
    assert!(none.closest_hit(Ray::new(Vec3::ZERO, Vec3::X), f32::INFINITY).is_none());
    let none = Bvh8::build(&[], &BuildOptions::sah());
    assert!(none.closest_hit(Ray::new(Vec3::ZERO, Vec3::X), f32::INFINITY).is_none());
    assert!(!none.any_hit(Ray::new(Vec3::ZERO, Vec3::X), 1.0));
}

#[test]
fn deep_trees_fall_back_to_a_heap_stack() {
    // Triangles of doubling size around one point: a chain, deeper than the x86 stack.
    let tris: Vec<Triangle> = (0..300)
        .map(|i| {
            let s = 1.1f32.powi(i);
            Triangle::new(Vec3::new(-s, -s, 0.0), Vec3::new(s, -s, 0.0), Vec3::new(0.0, s, 0.0))
        })
        .collect();
    let mut bvh = Bvh8::build(&tris, &BuildOptions { max_leaf: 1, ..BuildOptions::sah() });
    let rays: Vec<Ray> = (0..50).map(|i| Ray::new(Vec3::new(i as f32 * 0.01, 0.0, 5.0), -Vec3::Z)).collect();
    check(&tris, &mut bvh, &rays, 2.0);
}

#[test]
fn refit_follows_moved_triangles() {
    let mut tris = soup(2000, 11);
    let mut bvh = Bvh8::build(&tris, &BuildOptions::sah());
    for t in &mut tris {
        for v in &mut t.v {
            *v += Vec3::new((v.y * 0.7).sin(), (v.z * 0.5).cos(), 0.3);
        }
    }
    bvh.refit(&tris);
    let rays: Vec<Ray> = soup(300, 5).iter().map(|t| Ray::new(t.v[0] * 2.0, t.v[1] - t.v[0] * 2.0)).collect();
    check(&tris, &mut bvh, &rays, 3.0);
}

/// Spatial splits on inputs that defeat them: identical triangles (no split separates them),
/// coplanar ones (a flat box), long slivers crossing many bins beside small triangles, and one
/// huge triangle over all of them. Every query still equals brute force.
#[test]
fn spatial_splits_survive_awkward_inputs() {
    let flat: Vec<Triangle> = grid(12)
        .into_iter()
        .map(|t| {
            Triangle::new(
                t.v[0] * Vec3::new(1.0, 1.0, 0.0),
                t.v[1] * Vec3::new(1.0, 1.0, 0.0),
                t.v[2] * Vec3::new(1.0, 1.0, 0.0),
            )
        })
        .collect();
    let same = vec![Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y); 300];
    let mut mixed = soup(1500, 11);
    for i in 0..200 {
        let y = i as f32 * 0.01 - 1.0;
        mixed.push(Triangle::new(Vec3::new(-3.0, y, 0.0), Vec3::new(3.0, y + 0.001, 0.1), Vec3::new(3.0, y, -0.1)));
    }
    mixed.push(Triangle::new(Vec3::new(-50.0, -50.0, 0.3), Vec3::new(50.0, -50.0, 0.2), Vec3::new(0.0, 60.0, -0.1)));
    for tris in [&flat, &same, &mixed] {
        // Rays at the triangles' centroids from off their plane, and some at random.
        let mut rays: Vec<Ray> = tris
            .iter()
            .step_by(7)
            .map(|t| {
                let c = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
                let o = c + Vec3::new(0.3, 0.2, 4.0);
                Ray::new(o, c - o)
            })
            .collect();
        rays.extend(soup(100, 5).iter().map(|t| Ray::new(t.v[0] * 3.0, t.v[1] - t.v[0] * 3.0)));
        for options in
            [BuildOptions::spatial_splits(), BuildOptions { spatial: 4.0, parallel: false, ..BuildOptions::sah() }]
        {
            let mut bvh = Bvh8::build(tris, &options);
            check(tris, &mut bvh, &rays, 3.0);
            let aimed = tris.len().div_ceil(7);
            assert!(
                rays[..aimed].iter().all(|r| bvh.closest_hit(*r, f32::INFINITY).is_some()),
                "a ray aimed at a centroid missed"
            );
        }
    }
}

/// Odd query ranges and directions answer on every kernel what the portable kernel answers (up to
/// ties), and a tree whose nodes do not declare their inner children (`inner == 0`) answers the
/// same.
#[test]
fn odd_ranges_and_directions_agree_across_kernels() {
    let tris = grid(12);
    let mut bvh = Bvh8::build(&tris, &BuildOptions::sah());
    let mut plain = bvh.clone();
    for n in &mut plain.nodes {
        n.inner = 0;
    }
    let mut rays: Vec<Ray> =
        soup(200, 17).iter().map(|t| Ray::new(t.v[0] * 2.0 + Vec3::Z * 3.0, t.v[1] - t.v[0])).collect();
    rays.push(Ray::new(Vec3::new(3.5, 4.5, 2.0), Vec3::new(0.0, 0.0, f32::NEG_INFINITY)));
    rays.push(Ray::new(Vec3::new(3.5, 4.5, 2.0), Vec3::new(f32::INFINITY, 0.0, -1.0)));
    rays.push(Ray::new(Vec3::new(3.0, 4.0, 2.0), Vec3::new(0.0, 0.0, -1.0)));
    let ranges = [f32::INFINITY, 0.0, -0.0, -1.0, f32::NAN, 1e-30, f32::MAX];
    // A ray through an edge or vertex ties between the triangles that meet there and may name
    // either, depending on the order the kernel visits them: the distance must be equal and the
    // triangle named must be hit there.
    let answer = |b: &Bvh8, r: &Ray, t: f32| {
        let hit = b.closest_hit(*r, t);
        if let Some(h) = hit {
            let own = WatertightRay::new(*r).intersect(&tris[h.prim as usize], 0.0, t);
            assert_eq!(own.map(|o| o.t), Some(h.t), "{h:?}");
        }
        (hit.map(|h| h.t.to_bits()), b.any_hit(*r, t))
    };
    assert!(bvh.set_kernel(Kernel::Portable));
    let want: Vec<_> = rays.iter().flat_map(|r| ranges.iter().map(|&t| answer(&bvh, r, t))).collect();
    assert!(want.iter().any(|w| w.0.is_some()) && want.iter().any(|w| w.0.is_none()));
    for k in kernels() {
        for b in [&mut bvh, &mut plain] {
            assert!(b.set_kernel(k));
            let got: Vec<_> = rays.iter().flat_map(|r| ranges.iter().map(|&t| answer(b, r, t))).collect();
            assert_eq!(got, want, "{k}");
        }
    }
}

/// Issue 67: an OBJ mesh of the input fuzzer (the conference room's first faces, mutated to one
/// vertex at z = −10³⁰ and one at x = −1.8·10¹⁹) has a root box whose `f32` surface area is
/// infinite. The optimal collapse's leaf cost (infinite past the leaf limit) then tied with the
/// root's infinite cost as a node, and the root became one leaf of all its triangles, past the 64
/// a leaf holds: a debug assertion, and in release a count wrapped in a `u8`. Every collapse now
/// keeps each leaf within the limit, and the tree answers as brute force does.
#[test]
fn far_vertices_keep_leaves_within_the_limit() {
    let mut tris = grid(8);
    tris.push(Triangle::new(Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 1.0, 0.0), Vec3::new(1.0, 2.0, -1e30)));
    tris.push(Triangle::new(Vec3::new(-1.8e19, 3.0, 0.0), Vec3::new(3.0, 3.0, 0.0), Vec3::new(3.0, 4.0, 0.0)));
    assert!(surface_area(Aabb::from_points(&tris.iter().flat_map(|t| t.v).collect::<Vec<_>>())).is_infinite());
    let eye = Vec3::new(4.0, 4.0, 10.0);
    let rays: Vec<Ray> =
        (0..81).map(|i| Ray::new(eye, Vec3::new((i % 9) as f32 + 0.3, (i / 9) as f32 + 0.6, 0.0) - eye)).collect();
    for options in [
        BuildOptions::sah(),
        BuildOptions { parallel: false, max_leaf: 16, ..BuildOptions::sah() },
        BuildOptions { collapse: Some(Collapse::Greedy), ..BuildOptions::sah() },
        BuildOptions { collapse: None, ..BuildOptions::sah() },
        BuildOptions::high_quality(),
    ] {
        let mut bvh = Bvh8::build(&tris, &options);
        let mut leaves = 0;
        for n in &bvh.nodes {
            for s in 0..8 {
                assert!(usize::from(n.tris[s]) <= 4 * Node8::MAX_LEAF_BLOCKS, "{options:?}");
                leaves += usize::from(n.tris[s]);
            }
        }
        assert_eq!(leaves, tris.len(), "{options:?}");
        check(&tris, &mut bvh, &rays, 5.0);
    }
}
