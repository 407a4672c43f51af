//! The 4-wide CPU layout: the canonical binary tree collapsed into nodes of up to four children
//! whose boxes are tested together with SIMD lanes, and triangles copied in leaf order so that a
//! leaf's triangles are contiguous in memory (the references stay in `prims`).

use crate::flat::{FlatBvh, STACK_SIZE};
use crate::stats::{Counter, TraversalStats};
use crate::traverse::Hit;
use beam_math::collide::WatertightRay;
use beam_math::glam::{BVec4A, Vec3, Vec4};
use beam_math::{Aabb, Ray, Triangle};
use std::vec::Vec;

/// A node of four children in structure-of-arrays form. Child `i` is an inner node when
/// `count[i] == 0` (index `child[i]` into the node array), a leaf of `count[i]` triangles starting
/// at `child[i]` otherwise; unused slots have `child[i] == WideNode::UNUSED`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct WideNode {
    /// Box minima per child, x.
    pub min_x: [f32; 4],
    /// Box minima per child, y.
    pub min_y: [f32; 4],
    /// Box minima per child, z.
    pub min_z: [f32; 4],
    /// Box maxima per child, x.
    pub max_x: [f32; 4],
    /// Box maxima per child, y.
    pub max_y: [f32; 4],
    /// Box maxima per child, z.
    pub max_z: [f32; 4],
    /// Child node index or first triangle.
    pub child: [u32; 4],
    /// Triangle count of a leaf child, 0 for an inner child.
    pub count: [u32; 4],
    /// Bit `i` set when slot `i` is used.
    pub used: u32,
}

const _: () = assert!(size_of::<WideNode>() == 144);

impl WideNode {
    /// Unused slots have `child == UNUSED` and no bit in `used`.
    const EMPTY: Self = Self {
        min_x: [f32::INFINITY; 4],
        min_y: [f32::INFINITY; 4],
        min_z: [f32::INFINITY; 4],
        max_x: [f32::INFINITY; 4],
        max_y: [f32::INFINITY; 4],
        max_z: [f32::INFINITY; 4],
        child: [Self::UNUSED; 4],
        count: [0; 4],
        used: 0,
    };

    /// Marks an unused child slot.
    pub const UNUSED: u32 = u32::MAX;

    fn set_bounds(&mut self, i: usize, b: Aabb) {
        self.min_x[i] = b.min.x;
        self.min_y[i] = b.min.y;
        self.min_z[i] = b.min.z;
        self.max_x[i] = b.max.x;
        self.max_y[i] = b.max.y;
        self.max_z[i] = b.max.z;
    }

    /// Box of child `i`.
    #[must_use]
    pub fn bounds(&self, i: usize) -> Aabb {
        Aabb::new(
            Vec3::new(self.min_x[i], self.min_y[i], self.min_z[i]),
            Vec3::new(self.max_x[i], self.max_y[i], self.max_z[i]),
        )
    }
}

/// A 4-wide BVH with its triangles in leaf order.
#[derive(Clone, Debug, Default)]
pub struct WideBvh {
    /// Nodes; node 0 is the root (its children are the tree's top).
    pub nodes: Vec<WideNode>,
    /// Triangles in leaf order (copies).
    pub triangles: Vec<Triangle>,
    /// Input index of each entry of `triangles`.
    pub prims: Vec<u32>,
    /// Bounds of the whole tree.
    pub bounds: Aabb,
}

impl WideBvh {
    /// Collapse `flat` (built over `triangles`) into four-wide nodes: each node takes its binary
    /// node's two children and keeps opening the inner child of largest surface area until it has
    /// four children or only leaves.
    #[must_use]
    pub fn new(flat: &FlatBvh, triangles: &[Triangle]) -> Self {
        let mut out = Self {
            triangles: flat.prims.iter().map(|&p| triangles[p as usize]).collect(),
            prims: flat.prims.clone(),
            ..Self::default()
        };
        let Some(root) = flat.nodes.first() else {
            return out;
        };
        out.bounds = root.bounds();
        out.nodes.push(WideNode::EMPTY);
        // (wide node index, binary node index)
        let mut work = vec![(0usize, 0usize)];
        while let Some((w, b)) = work.pop() {
            let mut children: Vec<usize> =
                if flat.nodes[b].is_leaf() { vec![b] } else { vec![b + 1, flat.nodes[b].right_or_first as usize] };
            while children.len() < 4 {
                let open = children
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| !flat.nodes[**c].is_leaf())
                    .max_by(|a, b| {
                        beam_math::heuristics::surface_area(flat.nodes[*a.1].bounds())
                            .total_cmp(&beam_math::heuristics::surface_area(flat.nodes[*b.1].bounds()))
                    })
                    .map(|(i, _)| i);
                let Some(i) = open else { break };
                let c = children.swap_remove(i);
                children.push(c + 1);
                children.push(flat.nodes[c].right_or_first as usize);
            }
            for (slot, &c) in children.iter().enumerate() {
                let n = &flat.nodes[c];
                out.nodes[w].set_bounds(slot, n.bounds());
                out.nodes[w].used |= 1 << slot;
                if n.is_leaf() {
                    out.nodes[w].child[slot] = n.right_or_first;
                    out.nodes[w].count[slot] = n.count;
                } else {
                    let id = out.nodes.len();
                    out.nodes.push(WideNode::EMPTY);
                    out.nodes[w].child[slot] = id as u32;
                    work.push((id, c));
                }
            }
        }
        out
    }

    /// The closest hit with `t` in `[0, t_max]`.
    #[must_use]
    pub fn closest_hit(&self, ray: Ray, t_max: f32) -> Option<Hit> {
        self.traverse::<false, ()>(ray, t_max, &mut ()).1
    }

    /// [`WideBvh::closest_hit`], counting node visits (box tests) and triangle tests.
    #[must_use]
    pub fn closest_hit_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) -> Option<Hit> {
        self.traverse::<false, _>(ray, t_max, stats).1
    }

    /// True when `ray` hits anything with `t` in `[0, t_max]`.
    #[must_use]
    pub fn any_hit(&self, ray: Ray, t_max: f32) -> bool {
        self.traverse::<true, ()>(ray, t_max, &mut ()).0
    }

    /// [`WideBvh::any_hit`], counting work.
    #[must_use]
    pub fn any_hit_stats(&self, ray: Ray, t_max: f32, stats: &mut TraversalStats) -> bool {
        self.traverse::<true, _>(ray, t_max, stats).0
    }

    fn traverse<const ANY: bool, C: Counter>(&self, ray: Ray, t_max: f32, c: &mut C) -> (bool, Option<Hit>) {
        if self.nodes.is_empty() {
            return (false, None);
        }
        let inv = ray.direction.recip();
        let (ox, oy, oz) = (Vec4::splat(ray.origin.x), Vec4::splat(ray.origin.y), Vec4::splat(ray.origin.z));
        let (ix, iy, iz) = (Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z));
        let wt = WatertightRay::new(ray);
        let mut best: Option<Hit> = None;
        let mut t_best = t_max;
        let mut stack = [(0u32, 0u32, 0.0f32); STACK_SIZE];
        // (node or first triangle, count (0 = inner), entry distance)
        stack[0] = (0, 0, 0.0);
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            let (index, count, dist) = stack[sp];
            if dist > t_best {
                continue;
            }
            if count > 0 {
                for k in index..index + count {
                    c.triangle();
                    if let Some(h) = wt.intersect(&self.triangles[k as usize], 0.0, t_best) {
                        if ANY {
                            return (true, None);
                        }
                        t_best = h.t;
                        best = Some(Hit { prim: self.prims[k as usize], t: h.t, u: h.u, v: h.v });
                    }
                }
                continue;
            }
            let n = &self.nodes[index as usize];
            for _ in 0..4 {
                c.node();
            }
            let t1x = (Vec4::from_array(n.min_x) - ox) * ix;
            let t2x = (Vec4::from_array(n.max_x) - ox) * ix;
            let t1y = (Vec4::from_array(n.min_y) - oy) * iy;
            let t2y = (Vec4::from_array(n.max_y) - oy) * iy;
            let t1z = (Vec4::from_array(n.min_z) - oz) * iz;
            let t2z = (Vec4::from_array(n.max_z) - oz) * iz;
            let near = t1x.min(t2x).max(t1y.min(t2y)).max(t1z.min(t2z)).max(Vec4::ZERO);
            let far = t1x.max(t2x).min(t1y.max(t2y)).min(t1z.max(t2z)).min(Vec4::splat(t_best));
            let hit: BVec4A = near.cmple(far);
            // Unused slots (the last ones) can pass the slab test when t_best is infinite.
            let mask = hit.bitmask() & n.used;
            if mask == 0 {
                continue;
            }
            // Push hit children farthest first so that the nearest is popped next.
            let near = near.to_array();
            let mut order = [0usize; 4];
            let mut m = 0;
            for i in 0..4 {
                if mask & (1 << i) != 0 {
                    let mut j = m;
                    while j > 0 && near[order[j - 1]] < near[i] {
                        order[j] = order[j - 1];
                        j -= 1;
                    }
                    order[j] = i;
                    m += 1;
                }
            }
            for &i in &order[..m] {
                stack[sp] = (n.child[i], n.count[i], near[i]);
                sp += 1;
            }
        }
        (best.is_some(), best)
    }

    /// Closest hits of many rays (parallel with the `parallel` feature).
    #[must_use]
    pub fn closest_hits(&self, rays: &[Ray], t_max: f32) -> Vec<Option<Hit>> {
        crate::traverse::map_rays(rays, |r| self.closest_hit(*r, t_max))
    }

    /// Any-hit answers for many rays, each with its own `t_max`.
    #[must_use]
    pub fn any_hits(&self, rays: &[Ray], t_max: &[f32]) -> Vec<bool> {
        crate::traverse::map_segments(rays, t_max, |r, t| self.any_hit(r, t))
    }

    /// Refit after the input triangles moved: refresh the leaf-order copies, then every child box
    /// bottom-up (children are created after their parents, so a reverse pass suffices).
    pub fn refit(&mut self, triangles: &[Triangle]) {
        for (copy, &p) in self.triangles.iter_mut().zip(&self.prims) {
            *copy = triangles[p as usize];
        }
        let mut node_bounds = vec![Aabb::EMPTY; self.nodes.len()];
        for i in (0..self.nodes.len()).rev() {
            let mut all = Aabb::EMPTY;
            for s in 0..4 {
                let n = self.nodes[i];
                if n.child[s] == WideNode::UNUSED {
                    continue;
                }
                let b = if n.count[s] > 0 {
                    self.triangles[n.child[s] as usize..(n.child[s] + n.count[s]) as usize]
                        .iter()
                        .fold(Aabb::EMPTY, |b, t| b.grow(t.v[0]).grow(t.v[1]).grow(t.v[2]))
                } else {
                    node_bounds[n.child[s] as usize]
                };
                self.nodes[i].set_bounds(s, b);
                all = all.union(b);
            }
            node_bounds[i] = all;
        }
        self.bounds = node_bounds.first().copied().unwrap_or(Aabb::EMPTY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BuildOptions;

    #[test]
    fn wide_equals_binary() {
        let tris: Vec<Triangle> = (0..2000)
            .map(|i| {
                let f = i as f32;
                let c = Vec3::new((f * 0.37).sin() * 5.0, (f * 0.71).cos() * 5.0, (f * 0.13).sin() * 5.0);
                Triangle::new(c, c + Vec3::new(0.3, 0.1, 0.0), c + Vec3::new(0.0, 0.2, 0.3))
            })
            .collect();
        let flat = FlatBvh::build(&tris, &BuildOptions::sah());
        let wide = WideBvh::new(&flat, &tris);
        for i in 0..500 {
            let f = i as f32;
            let ray =
                Ray::new(Vec3::new(0.0, 0.0, -12.0), Vec3::new((f * 0.05).sin() * 0.4, (f * 0.09).cos() * 0.4, 1.0));
            let a = flat.closest_hit(&tris, ray, f32::INFINITY);
            let b = wide.closest_hit(ray, f32::INFINITY);
            assert_eq!(a.map(|h| h.t), b.map(|h| h.t));
            assert_eq!(flat.any_hit(&tris, ray, 10.0), wide.any_hit(ray, 10.0));
        }
    }
}
