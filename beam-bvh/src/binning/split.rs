//! What a binned split search works with: the build's constants ([`Context`]), where the bins lie
//! ([`Grid`]), how areas are measured ([`Measure`]), the split found ([`Split`]) and the bins'
//! contents ([`Bins`]). The searches themselves (the parent module, [`super::sweep`],
//! [`super::directions`], [`super::small`]) all build on it.

use super::refs::{Box4, PrimRef};
use crate::options::{BuildOptions, Heuristic, RayDistribution};
use beam_math::Aabb;
use beam_math::glam::{Vec3, Vec4};
use beam_math::heuristics::{projected_area_orthographic_fast, projected_area_perspective_fast, surface_area};

/// Largest number of bins.
pub(crate) const MAX_BINS: usize = 32;

/// Per-build constants.
pub(crate) struct Context {
    pub options: BuildOptions,
    pub(crate) directions: [Vec3; 5],
    pub(super) direction_count: usize,
    /// Leaves are intersected in blocks of `1 << block_shift` triangles: the cost of `n`
    /// references is that of `⌈n / 2^block_shift⌉` blocks.
    pub block_shift: u32,
    /// Where the candidate planes lie.
    pub grid: Grid,
}

/// Where a binned search puts its `bins − 1` candidate planes across the centroids' range.
/// Neither is better everywhere: with [`Grid::Equal`] the direct 8-wide builder's Sponza tree
/// costs its shadow rays 5% fewer box and 16% fewer triangle tests (and traces them 6% faster),
/// and the collapsed tree's Sponza rays trace 3–4% faster; on the conference room the collapsed
/// tree costs primary rays 21% more box tests with it and traces 1–5% slower (spatial splits
/// there: 8–17% faster). Sponza's shadow rays, the slowest against Embree, decide: every 8-wide
/// tree bins on it (`docs/benchmarks.md`).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Grid {
    /// Bin `k` holds the coordinates nearest to the `k`-th of `bins` points spanning the range:
    /// the first and last bins are half as wide as the others. The binary BVH's (beams, GPU).
    Centred,
    /// `bins` bins of equal width over the range widened by 1%, as Embree's binner makes them.
    /// Every 8-wide tree's.
    Equal,
}

impl Grid {
    /// The scale from centroid coordinates (less the range's low end) to bin coordinates, for a
    /// range of width `width`.
    pub(super) fn scale(self, bins: usize, width: f32) -> f32 {
        match self {
            Grid::Centred => (bins - 1) as f32 / width,
            Grid::Equal => 0.99 * bins as f32 / width,
        }
    }

    /// Subtracted from a bin coordinate before rounding it to the nearest integer: the bin is the
    /// nearest point (`Centred`) or the floor (`Equal`, but at ties).
    pub(super) fn shift(self) -> f32 {
        match self {
            Grid::Centred => 0.0,
            Grid::Equal => 0.5,
        }
    }
}

impl Context {
    pub(crate) fn new(options: &BuildOptions, block_shift: u32, grid: Grid) -> Self {
        let mut directions = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ZERO, Vec3::ZERO];
        let mut direction_count = 3;
        if let Some(d) = options.facing.and_then(Vec3::try_normalize) {
            let u = d.any_orthonormal_vector();
            directions[3] = u;
            directions[4] = d.cross(u);
            direction_count = 5;
        }
        let mut options = *options;
        options.bins = options.bins.clamp(2, MAX_BINS);
        options.max_leaf = options.max_leaf.max(1);
        Self { options, directions, direction_count, block_shift, grid }
    }

    /// Cost units of a leaf of `n` references.
    #[inline(always)]
    pub(crate) fn blocks(&self, n: usize) -> f32 {
        ((n + (1 << self.block_shift) - 1) >> self.block_shift) as f32
    }

    /// The area measure for the children of a node with box `parent`: projected area when the
    /// distribution applies to the whole node, surface area otherwise (004's fallback).
    pub(crate) fn measure(&self, parent: Aabb) -> Measure {
        match self.options.heuristic {
            Heuristic::Sah => Measure::Surface,
            Heuristic::Pah(RayDistribution::Parallel { direction }) => Measure::Orthographic(direction),
            Heuristic::Pah(RayDistribution::Pencil { origin, forward }) => {
                if projected_area_perspective_fast(parent, origin, forward).is_some() {
                    Measure::Perspective(origin, forward)
                } else {
                    Measure::Surface
                }
            }
        }
    }
}

/// How a node's area is measured.
#[derive(Clone, Copy)]
pub(crate) enum Measure {
    Surface,
    Orthographic(Vec3),
    Perspective(Vec3, Vec3),
}

impl Measure {
    /// [`Measure::area`] of a box in `Vec4`s: the surface area without the conversion (the same
    /// operations as `surface_area`, an empty box included: its clamped extent is 0).
    #[inline(always)]
    pub(crate) fn area4(self, b: Box4) -> f32 {
        match self {
            Measure::Surface => {
                let e = (b.hi - b.lo).max(Vec4::ZERO);
                2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
            }
            _ => self.area(b.aabb()),
        }
    }

    pub(crate) fn area(self, b: Aabb) -> f32 {
        if !b.is_valid() {
            return 0.0;
        }
        match self {
            Measure::Surface => surface_area(b),
            Measure::Orthographic(d) => projected_area_orthographic_fast(b, d),
            Measure::Perspective(o, f) => projected_area_perspective_fast(b, o, f).unwrap_or(f32::INFINITY),
        }
    }
}

/// What a split separates along.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Plane {
    /// Coordinate `axis` of the doubled centroid.
    Axis(usize),
    /// The doubled centroid's projection on a direction.
    Direction(Vec3),
}

/// The best partition of a node: references with bin `< bin` go left.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Split {
    pub(crate) plane: Plane,
    pub(crate) lo: f32,
    pub(crate) scale: f32,
    /// [`Grid::shift`].
    pub(crate) shift: f32,
    pub(crate) bins: usize,
    pub(crate) bin: usize,
    /// `A(L)·blocks(N_L) + A(R)·blocks(N_R)` under the node's measure.
    pub cost: f32,
}

impl Split {
    #[inline(always)]
    pub(crate) fn bin_of(&self, r: &PrimRef) -> usize {
        let x = match self.plane {
            Plane::Axis(a) => r.centroid2().to_array()[a],
            Plane::Direction(d) => r.centroid2().truncate().dot(d),
        };
        bin_index(((x - self.lo) * self.scale - self.shift).min((self.bins - 1) as f32))
    }
}

/// Added to a bin coordinate in `[0, 2^22)`, this puts its value rounded to the nearest integer in
/// the low mantissa bits: a float-to-integer conversion without the checks of `as`.
pub(super) const ROUNDER: f32 = 12_582_912.0;

/// The bin of bin coordinate `x` less the grid's shift (at most `bins − 1`): `x` rounded to the
/// nearest integer. The vector binning in [`super::find_split`] computes the same for three lanes at
/// once.
#[inline(always)]
fn bin_index(x: f32) -> usize {
    ((x + ROUNDER).to_bits() - ROUNDER.to_bits()) as usize
}

/// Bin contents of the three axes.
#[derive(Clone, Copy)]
pub(crate) struct Bins {
    pub(super) bounds: [[Box4; MAX_BINS]; 3],
    pub(super) counts: [[u32; MAX_BINS]; 3],
}

impl Bins {
    pub(crate) const EMPTY: Self = Self { bounds: [[Box4::EMPTY; MAX_BINS]; 3], counts: [[0; MAX_BINS]; 3] };

    pub(super) fn clear(&mut self, bins: usize) {
        for a in 0..3 {
            self.bounds[a][..bins].fill(Box4::EMPTY);
            self.counts[a][..bins].fill(0);
        }
    }

    pub(super) fn merge_first(&mut self, o: &Self, bins: usize) {
        for a in 0..3 {
            for b in 0..bins {
                self.bounds[a][b] = self.bounds[a][b].union(o.bounds[a][b]);
                self.counts[a][b] += o.counts[a][b];
            }
        }
    }

    pub(super) fn merge(mut self, o: Self) -> Self {
        for a in 0..3 {
            for b in 0..MAX_BINS {
                self.bounds[a][b] = self.bounds[a][b].union(o.bounds[a][b]);
                self.counts[a][b] += o.counts[a][b];
            }
        }
        self
    }
}
