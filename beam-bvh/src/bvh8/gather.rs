//! Culling by a volume: the triangles of the leaves that a test on the children's boxes lets
//! through, eight boxes at a time.

use super::node::Node8;
use super::tree::Bvh8;
use core::ops::ControlFlow;
use std::vec::Vec;

impl Bvh8 {
    /// Append to `out` the input index of every triangle in the leaves reached from the root
    /// through the children that `enter` accepts: `enter(node)` returns a mask of the slots to
    /// visit (bit `s` for `node.child[s]`; unused slots are never visited). For culling by a
    /// volume (a cone, a frustum), `enter` tests the eight boxes of [`Node8::bounds`] at once. A
    /// triangle split across leaves (pre-splitting, spatial splits) comes once per leaf reached.
    pub fn gather(&self, enter: impl FnMut(&Node8) -> u32, out: &mut Vec<u32>) {
        self.visit_leaves(enter, |first, count| {
            out.extend(self.prims[4 * first..4 * (first + count)].iter().filter(|&&p| p != u32::MAX));
            ControlFlow::Continue(())
        });
    }

    /// Like [`Bvh8::gather`], but append the leaves' blocks instead of their triangles: block `b`
    /// holds the triangles `prims[4b..4b + 4]` (`u32::MAX` in an unused lane). For a device that
    /// culls triangle by triangle what the host culled by boxes.
    pub fn gather_blocks(&self, enter: impl FnMut(&Node8) -> u32, out: &mut Vec<u32>) {
        self.visit_leaves(enter, |first, count| {
            out.extend(first as u32..(first + count) as u32);
            ControlFlow::Continue(())
        });
    }

    /// Call `leaf(first block, blocks)` for every leaf reached from the root through the children
    /// `enter` accepts (as [`Bvh8::gather`] does), until `leaf` breaks: block `b` is
    /// [`Bvh8::blocks`]`[b]`, its triangles `prims[4b..4b + 4]`. For a volume test of the
    /// triangles themselves, four at a time.
    pub fn visit_leaves(
        &self,
        mut enter: impl FnMut(&Node8) -> u32,
        mut leaf: impl FnMut(usize, usize) -> ControlFlow<()>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack: Vec<u32> = Vec::with_capacity(8 * self.stack_need.max(1));
        let mut cur = 0u32;
        loop {
            if cur & Node8::LEAF != 0 {
                let (first, count) = Node8::leaf_blocks(cur);
                if leaf(first, count).is_break() {
                    return;
                }
            } else {
                let n = &self.nodes[cur as usize];
                let mut mask = enter(n) & used(n);
                while mask != 0 {
                    stack.push(n.child[mask.trailing_zeros() as usize]);
                    mask &= mask - 1;
                }
            }
            match stack.pop() {
                Some(next) => cur = next,
                None => return,
            }
        }
    }
}

/// The mask of the slots of `n` that hold a child.
fn used(n: &Node8) -> u32 {
    n.child.iter().enumerate().fold(0, |m, (s, &c)| m | u32::from(c != Node8::UNUSED) << s)
}

#[cfg(test)]
mod tests {
    use super::super::tests::grid;
    use super::*;
    use crate::BuildOptions;

    /// Accepting every child gathers every triangle once; a box test gathers every triangle
    /// inside the region it tests and leaves out some of the rest; rejecting every child gathers
    /// nothing.
    #[test]
    fn gathers_what_the_box_test_lets_through() {
        let tris = grid(40);
        let bvh = Bvh8::build(&tris, &BuildOptions::sah());
        let mut all = Vec::new();
        bvh.gather(|_| 0xff, &mut all);
        all.sort_unstable();
        assert_eq!(all, (0..tris.len() as u32).collect::<Vec<_>>());

        // Children whose boxes reach below x = 10.
        let left = |n: &Node8| (0..8).fold(0, |m, s| m | u32::from(n.bounds[0][s] < 10.0) << s);
        let mut some = Vec::new();
        bvh.gather(left, &mut some);
        assert!(some.len() < tris.len(), "{} of {}", some.len(), tris.len());
        for (i, t) in tris.iter().enumerate() {
            if t.v.iter().all(|v| v.x < 10.0) {
                assert!(some.contains(&(i as u32)), "triangle {i} inside the region was culled");
            }
        }
        // The same leaves by blocks.
        let mut blocks = Vec::new();
        bvh.gather_blocks(left, &mut blocks);
        let mut lanes: Vec<u32> =
            blocks.iter().flat_map(|&b| bvh.prims[4 * b as usize..][..4].iter().copied()).collect();
        lanes.retain(|&p| p != u32::MAX);
        assert_eq!(lanes, some);
        let mut none = Vec::new();
        bvh.gather(|_| 0, &mut none);
        assert!(none.is_empty());
        Bvh8::default().gather(|_| 0xff, &mut none);
        assert!(none.is_empty());
    }
}
