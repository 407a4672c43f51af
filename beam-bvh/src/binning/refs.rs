//! Primitive references and their summaries for the binned builders.

use beam_math::glam::Vec4;
use beam_math::{Aabb, Triangle};
use std::vec::Vec;

/// `w` of a reference's `hi` holds `INDEX_BIAS + index` as bits: a normal float for every index
/// below 2^30, so that the `w` lanes the box arithmetic carries along never hold denormals.
const INDEX_BIAS: u32 = 0x4000_0000;

/// A box as two `Vec4`s (`w` unused).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Box4 {
    pub lo: Vec4,
    pub hi: Vec4,
}

impl Box4 {
    pub(crate) const EMPTY: Self = Self { lo: Vec4::INFINITY, hi: Vec4::NEG_INFINITY };

    #[inline(always)]
    pub(crate) fn union(self, o: Self) -> Self {
        Self { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    #[inline(always)]
    pub(crate) fn aabb(self) -> Aabb {
        Aabb::new(self.lo.truncate(), self.hi.truncate())
    }
}

/// A triangle reference during a build: its box, and its index in `w` of `hi` (see
/// [`INDEX_BIAS`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PrimRef {
    pub lo: Vec4,
    pub hi: Vec4,
}

impl PrimRef {
    /// The reference to triangle `t` (number `index`), or `None` where [`Triangle::is_valid`] is
    /// false.
    #[inline(always)]
    fn of_valid(t: &Triangle, index: u32) -> Option<Self> {
        t.is_valid().then(|| Self::with_box(Aabb::from_points(&t.v), index))
    }

    /// A reference to triangle `index` with box `b` (part of the triangle's box, for a piece).
    pub(crate) fn with_box(b: Aabb, index: u32) -> Self {
        debug_assert!(index < INDEX_BIAS);
        Self { lo: b.min.extend(0.0), hi: b.max.extend(f32::from_bits(INDEX_BIAS + index)) }
    }

    /// Index of the triangle in the input slice.
    #[inline(always)]
    pub(crate) fn index(&self) -> u32 {
        self.hi.w.to_bits() - INDEX_BIAS
    }

    /// Twice the box centre (`lo + hi`: exactly twice `Aabb::center`, one operation fewer).
    #[inline(always)]
    pub(crate) fn centroid2(&self) -> Vec4 {
        self.lo + self.hi
    }

    #[inline(always)]
    pub(crate) fn bounds(&self) -> Box4 {
        Box4 { lo: self.lo, hi: self.hi }
    }
}

/// A node's references summarised: their boxes' union and the box of their doubled centroids.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Record {
    pub bounds: Box4,
    pub centroids: Box4,
}

impl Record {
    pub(crate) const EMPTY: Self = Self { bounds: Box4::EMPTY, centroids: Box4::EMPTY };

    #[inline(always)]
    pub(crate) fn add(&mut self, r: &PrimRef) {
        self.bounds = self.bounds.union(r.bounds());
        let c = r.centroid2();
        self.centroids = self.centroids.union(Box4 { lo: c, hi: c });
    }

    fn merge(self, o: Self) -> Self {
        Self { bounds: self.bounds.union(o.bounds), centroids: self.centroids.union(o.centroids) }
    }
}

/// References of the valid triangles (degenerate ones left out) and their record.
pub(crate) fn make_refs(triangles: &[Triangle], parallel: bool) -> (Vec<PrimRef>, Record) {
    let make = |(i, t): (usize, &Triangle)| PrimRef::of_valid(t, i as u32);
    assert!(triangles.len() < INDEX_BIAS as usize, "a BVH holds at most 2^30 triangles");
    #[cfg(feature = "parallel")]
    let refs: Vec<PrimRef> = if parallel && triangles.len() > PARALLEL_BINNING {
        // An indexed collect: each thread writes its part in place (a filtered one is gathered
        // on one thread), and the rare degenerate triangles are dropped after.
        use rayon::prelude::*;
        let (mut refs, valid): (Vec<PrimRef>, Vec<bool>) = triangles
            .par_iter()
            .enumerate()
            .with_min_len(4096)
            .map(|(i, t)| match PrimRef::of_valid(t, i as u32) {
                Some(r) => (r, true),
                None => (PrimRef::with_box(Aabb::EMPTY, 0), false),
            })
            .unzip();
        if valid.contains(&false) {
            let mut keep = valid.iter();
            refs.retain(|_| keep.next() == Some(&true));
        }
        refs
    } else {
        triangles.iter().enumerate().filter_map(make).collect()
    };
    #[cfg(not(feature = "parallel"))]
    let refs: Vec<PrimRef> = triangles.iter().enumerate().filter_map(make).collect();
    let record = record_of(&refs, parallel);
    (refs, record)
}

/// The record of `refs`.
pub(crate) fn record_of(refs: &[PrimRef], parallel: bool) -> Record {
    let f = |chunk: &[PrimRef]| {
        // Two records in turn: each `min`/`max` waits for the one before it in its own record
        // only. The merge is exact, so the result is the one record's.
        let (mut a, mut b) = (Record::EMPTY, Record::EMPTY);
        let pairs = chunk.chunks_exact(2);
        pairs.remainder().iter().for_each(|p| a.add(p));
        for pair in pairs {
            a.add(&pair[0]);
            b.add(&pair[1]);
        }
        a.merge(b)
    };
    reduce_chunks(refs, parallel, Record::EMPTY, f, Record::merge)
}

/// Nodes with more references than this bin in parallel chunks.
pub(crate) const PARALLEL_BINNING: usize = 32_768;

/// `f` over chunks of `refs` merged with `merge`, in parallel for large slices.
pub(crate) fn reduce_chunks<T: Send + Sync + Copy>(
    refs: &[PrimRef],
    parallel: bool,
    init: T,
    f: impl Fn(&[PrimRef]) -> T + Sync + Send,
    merge: impl Fn(T, T) -> T + Sync + Send,
) -> T {
    #[cfg(feature = "parallel")]
    if parallel && refs.len() > PARALLEL_BINNING {
        use rayon::prelude::*;
        return refs.par_chunks(PARALLEL_BINNING / 4).map(&f).reduce(|| init, &merge);
    }
    let _ = (parallel, &merge, init);
    f(refs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_math::glam::Vec3;

    /// A reference is made exactly where `Triangle::is_valid` holds, with the triangle's box and
    /// index, on every kind of bad vertex, on zero areas, on areas that underflow and on normals
    /// that overflow.
    #[test]
    fn references_are_made_for_exactly_the_valid_triangles() {
        let values = [0.0, 1.0, -2.5, 1e-30, 1e19, -1e20, 3e38, f32::MAX, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        let mut s = 3u32;
        let mut pick = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            values[(s >> 16) as usize % values.len()]
        };
        let mut valid = 0;
        for _ in 0..200_000 {
            let mut v = || Vec3::new(pick(), pick(), pick());
            let t = Triangle::new(v(), v(), v());
            let r = PrimRef::of_valid(&t, 7);
            assert_eq!(r.is_some(), t.is_valid(), "{t:?}");
            if let Some(r) = r {
                let b = Aabb::from_points(&t.v);
                assert_eq!((r.lo.truncate(), r.hi.truncate(), r.index()), (b.min, b.max, 7));
                valid += 1;
            }
        }
        assert!(valid > 100, "the test made valid triangles too: {valid}");
    }
}
