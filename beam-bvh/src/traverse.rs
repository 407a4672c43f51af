//! Traversal of the compact layout: closest hit, any hit, batches, and the generic front-to-back
//! traversal that beam tracers drive with their own node test and leaf visitor.

use crate::flat::{FlatBvh, STACK_SIZE};
use crate::stats::{Counter, TraversalStats};
use beam_math::collide::WatertightRay;
use beam_math::glam::Vec3A;
use beam_math::{Aabb, Ray, Triangle};

/// A closest hit: the input triangle's index, the ray parameter and barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index of the triangle in the slice the BVH was built from.
    pub prim: u32,
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentric weight of vertex 1.
    pub u: f32,
    /// Barycentric weight of vertex 2.
    pub v: f32,
}

impl Hit {
    /// The hit of `ray` at parameter `t` on `tri` (index `prim`), its weights those of the point
    /// `ray.at(t)` (zeros on a degenerate triangle): for a hit whose triangle and `t` are known
    /// but not its barycentrics (a GPU's, or a plane's).
    #[must_use]
    pub fn on(tri: &Triangle, prim: u32, ray: &Ray, t: f32) -> Self {
        let w = tri.barycentric(ray.at(t)).unwrap_or_default();
        Self { prim, t, u: w.y, v: w.z }
    }
}

/// What a leaf visitor wants next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// Keep traversing.
    Continue,
    /// Stop the traversal.
    Stop,
}

/// A generic traversal client (beams, frusta, cones): decides which nodes to enter and in which
/// order, and receives the triangle references of the leaves it reaches, nearest first.
pub trait NodeVisitor {
    /// Entry distance of the query into `bounds` (used to order siblings front to back), or `None`
    /// to skip the node and its subtree.
    fn enter(&mut self, bounds: &Aabb) -> Option<f32>;
    /// Triangle references of a reached leaf.
    fn leaf(&mut self, prims: &[u32]) -> Control;
    /// Nodes whose entry distance exceeds this are skipped when popped (e.g. past a hit).
    fn cutoff(&self) -> f32 {
        f32::INFINITY
    }
}

/// Slab entry distance of a ray with reciprocal direction `inv` into a node, if it enters before
/// `t_max` (004 Alg. A.1; IEEE infinities handle axis-parallel rays).
#[inline(always)]
fn slab(min: &[f32; 3], max: &[f32; 3], origin: Vec3A, inv: Vec3A, t_max: f32) -> f32 {
    let t1 = (Vec3A::from_array(*min) - origin) * inv;
    let t2 = (Vec3A::from_array(*max) - origin) * inv;
    let near = t1.min(t2).max_element().max(0.0);
    let far = t1.max(t2).min_element().min(t_max);
    if near <= far { near } else { f32::INFINITY }
}

impl FlatBvh {
    /// The closest hit of `ray` with `t` in `[0, t_max]` (watertight triangle test).
    #[must_use]
    pub fn closest_hit(&self, triangles: &[Triangle], ray: Ray, t_max: f32) -> Option<Hit> {
        self.closest_hit_counted(triangles, ray, t_max, &mut ())
    }

    /// [`FlatBvh::closest_hit`], counting node visits and triangle tests into `stats`.
    #[must_use]
    pub fn closest_hit_stats(
        &self,
        triangles: &[Triangle],
        ray: Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.closest_hit_counted(triangles, ray, t_max, stats)
    }

    /// True when `ray` hits any triangle with `t` in `[0, t_max]` (shadow rays).
    #[must_use]
    pub fn any_hit(&self, triangles: &[Triangle], ray: Ray, t_max: f32) -> bool {
        self.any_hit_counted(triangles, ray, t_max, &mut ())
    }

    /// [`FlatBvh::any_hit`], counting work into `stats`.
    #[must_use]
    pub fn any_hit_stats(&self, triangles: &[Triangle], ray: Ray, t_max: f32, stats: &mut TraversalStats) -> bool {
        self.any_hit_counted(triangles, ray, t_max, stats)
    }

    fn closest_hit_counted<C: Counter>(&self, triangles: &[Triangle], ray: Ray, t_max: f32, c: &mut C) -> Option<Hit> {
        self.trace::<false, C>(triangles, ray, t_max, c).1
    }

    fn any_hit_counted<C: Counter>(&self, triangles: &[Triangle], ray: Ray, t_max: f32, c: &mut C) -> bool {
        self.trace::<true, C>(triangles, ray, t_max, c).0
    }

    /// Nearest-child-first traversal: with `ANY`, stop at the first hit in `[0, t_max]`; otherwise
    /// shrink `t_max` to each hit and skip pending nodes that start beyond it.
    fn trace<const ANY: bool, C: Counter>(
        &self,
        triangles: &[Triangle],
        ray: Ray,
        t_max: f32,
        c: &mut C,
    ) -> (bool, Option<Hit>) {
        let nodes = &self.nodes[..];
        if nodes.is_empty() {
            return (false, None);
        }
        let origin = Vec3A::from(ray.origin);
        let inv = Vec3A::from(ray.direction.recip());
        let wt = WatertightRay::new(ray);
        let mut best: Option<Hit> = None;
        let mut t_best = t_max;
        c.node();
        if slab(&nodes[0].min, &nodes[0].max, origin, inv, t_best) == f32::INFINITY {
            return (false, None);
        }
        let mut stack = [(0u32, 0.0f32); STACK_SIZE];
        let mut sp = 0usize;
        let mut node = 0usize;
        loop {
            let n = &nodes[node];
            if n.count > 0 {
                let first = n.right_or_first as usize;
                for &p in &self.prims[first..first + n.count as usize] {
                    c.triangle();
                    if let Some(h) = wt.intersect(&triangles[p as usize], 0.0, t_best) {
                        if ANY {
                            return (true, None);
                        }
                        t_best = h.t;
                        best = Some(Hit { prim: p, t: h.t, u: h.u, v: h.v });
                    }
                }
            } else {
                let (mut a, mut b) = (node + 1, n.right_or_first as usize);
                c.node();
                c.node();
                let mut da = slab(&nodes[a].min, &nodes[a].max, origin, inv, t_best);
                let mut db = slab(&nodes[b].min, &nodes[b].max, origin, inv, t_best);
                if db < da {
                    core::mem::swap(&mut a, &mut b);
                    core::mem::swap(&mut da, &mut db);
                }
                if da != f32::INFINITY {
                    if db != f32::INFINITY {
                        stack[sp] = (b as u32, db);
                        sp += 1;
                    }
                    node = a;
                    continue;
                }
            }
            // Pop the nearest pending node still in front of the best hit.
            loop {
                if sp == 0 {
                    return (best.is_some(), best);
                }
                sp -= 1;
                let (next, d) = stack[sp];
                if d <= t_best {
                    node = next as usize;
                    break;
                }
            }
        }
    }

    /// Generic front-to-back traversal: `visitor.enter` tests each node (children are visited
    /// nearest first) and `visitor.leaf` receives the references of every leaf reached; pending
    /// nodes farther than `visitor.cutoff()` are skipped.
    pub fn traverse<V: NodeVisitor>(&self, visitor: &mut V) {
        let nodes = &self.nodes[..];
        let Some(root) = nodes.first() else { return };
        let Some(d0) = visitor.enter(&root.bounds()) else {
            return;
        };
        let mut stack = Vec::with_capacity(64);
        stack.push((0usize, d0));
        while let Some((i, d)) = stack.pop() {
            if d > visitor.cutoff() {
                continue;
            }
            let n = &nodes[i];
            if n.is_leaf() {
                let first = n.right_or_first as usize;
                if visitor.leaf(&self.prims[first..first + n.count as usize]) == Control::Stop {
                    return;
                }
                continue;
            }
            let (a, b) = (i + 1, n.right_or_first as usize);
            let da = visitor.enter(&nodes[a].bounds());
            let db = visitor.enter(&nodes[b].bounds());
            match (da, db) {
                (Some(da), Some(db)) => {
                    // Push the farther first so the nearer is popped next.
                    if da <= db {
                        stack.push((b, db));
                        stack.push((a, da));
                    } else {
                        stack.push((a, da));
                        stack.push((b, db));
                    }
                }
                (Some(da), None) => stack.push((a, da)),
                (None, Some(db)) => stack.push((b, db)),
                (None, None) => {}
            }
        }
    }

    /// Closest hits of many rays (parallel with the `parallel` feature).
    #[must_use]
    pub fn closest_hits(&self, triangles: &[Triangle], rays: &[Ray], t_max: f32) -> Vec<Option<Hit>> {
        map_rays(rays, |r| self.closest_hit(triangles, *r, t_max))
    }

    /// Any-hit answers for many rays, each with its own `t_max` (parallel with `parallel`).
    #[must_use]
    pub fn any_hits(&self, triangles: &[Triangle], rays: &[Ray], t_max: &[f32]) -> Vec<bool> {
        map_segments(rays, t_max, |r, t| self.any_hit(triangles, r, t))
    }
}

#[cfg(feature = "parallel")]
pub(crate) fn map_rays<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    items.par_iter().with_min_len(256).map(f).collect()
}

#[cfg(not(feature = "parallel"))]
pub(crate) fn map_rays<T, R>(items: &[T], f: impl Fn(&T) -> R) -> Vec<R> {
    items.iter().map(f).collect()
}

/// `f` of each ray and its own `t_max` (in parallel with the `parallel` feature).
#[cfg(feature = "parallel")]
pub(crate) fn map_segments<R: Send>(rays: &[Ray], t_max: &[f32], f: impl Fn(Ray, f32) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    rays.par_iter().zip(t_max).with_min_len(256).map(|(r, t)| f(*r, *t)).collect()
}

/// `f` of each ray and its own `t_max`.
#[cfg(not(feature = "parallel"))]
pub(crate) fn map_segments<R>(rays: &[Ray], t_max: &[f32], f: impl Fn(Ray, f32) -> R) -> Vec<R> {
    rays.iter().zip(t_max).map(|(r, t)| f(*r, *t)).collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::{BuildOptions, RayDistribution};
    use beam_math::collide::ray_triangle;
    use beam_math::glam::Vec3;

    /// `n` small random triangles around random centres (a seeded LCG), for tests.
    /// A linear congruential generator of floats in `[0, 1)` (24 bits each), for tests.
    pub(crate) fn unit_rng(seed: u32) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    pub(crate) fn soup(n: usize, seed: u32) -> Vec<Triangle> {
        let mut unit = unit_rng(seed);
        let mut r = move || unit() * 2.0 - 1.0;
        (0..n)
            .map(|_| {
                let c = Vec3::new(r(), r(), r()) * 5.0;
                Triangle::new(
                    c + Vec3::new(r(), r(), r()) * 0.4,
                    c + Vec3::new(r(), r(), r()) * 0.4,
                    c + Vec3::new(r(), r(), r()) * 0.4,
                )
            })
            .collect()
    }

    #[test]
    fn matches_brute_force_on_a_soup() {
        let tris = soup(3000, 7);
        for options in [
            BuildOptions::sah(),
            BuildOptions::pah(RayDistribution::Pencil { origin: Vec3::new(0.0, 0.0, 12.0), forward: -Vec3::Z }),
        ] {
            let bvh = FlatBvh::build(&tris, &options);
            let rays: Vec<Ray> = soup(500, 99).iter().map(|t| Ray::new(t.v[0] * 2.0, t.v[1] - t.v[0] * 2.0)).collect();
            let hits = bvh.closest_hits(&tris, &rays, f32::INFINITY);
            for (ray, hit) in rays.iter().zip(hits) {
                let brute = tris
                    .iter()
                    .enumerate()
                    .filter_map(|(i, t)| ray_triangle(*ray, t).map(|h| (i, h.t)))
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                assert_eq!(hit.map(|h| h.prim as usize), brute.map(|b| b.0));
                let blocked = bvh.any_hit(&tris, *ray, 3.0);
                assert_eq!(blocked, brute.is_some_and(|b| b.1 <= 3.0));
            }
        }
    }

    struct CountLeaves(usize);

    impl NodeVisitor for CountLeaves {
        fn enter(&mut self, _: &Aabb) -> Option<f32> {
            Some(0.0)
        }
        fn leaf(&mut self, prims: &[u32]) -> Control {
            self.0 += prims.len();
            Control::Continue
        }
    }

    #[test]
    fn generic_traversal_reaches_every_leaf() {
        let tris = soup(1000, 3);
        let bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        let mut v = CountLeaves(0);
        bvh.traverse(&mut v);
        assert_eq!(v.0, 1000);
    }
}
