//! Builder options: one struct picks the heuristic and its parameters.

use beam_math::glam::Vec3;

/// The ray distribution a projected-area heuristic is built for (004 §1, Fig. 4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RayDistribution {
    /// Parallel rays along `direction` (an area light seen from afar): orthographic projection.
    Parallel {
        /// Common ray direction.
        direction: Vec3,
    },
    /// Rays through one point (a point light or a camera), looking along `forward`: perspective
    /// projection onto the plane at unit distance.
    Pencil {
        /// The common point.
        origin: Vec3,
        /// Mean direction of the rays.
        forward: Vec3,
    },
}

impl RayDistribution {
    /// The direction that split planes should face for [`BuildOptions::facing`]: the rays' mean
    /// direction.
    #[must_use]
    pub fn direction(&self) -> Vec3 {
        match *self {
            RayDistribution::Parallel { direction } => direction,
            RayDistribution::Pencil { forward, .. } => forward,
        }
    }
}

/// The cost model of the binned builder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Heuristic {
    /// Surface area heuristic: a node is hit with probability proportional to its surface area.
    Sah,
    /// Projected area heuristic (004): proportional to the node's projected area under the
    /// distribution's projection. Nodes the distribution does not apply to (a pencil's origin inside
    /// or behind a box) fall back to SAH.
    Pah(RayDistribution),
}

/// How the 8-wide builder turns a binary tree into eight-wide nodes ([`BuildOptions::collapse`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Collapse {
    /// A bottom-up pass picks leaves, then each node opens its child of largest area until it
    /// has eight.
    Greedy,
    /// The dynamic program of Ylitie et al. 2017 §3.1: the collapse of least SAH cost.
    Optimal,
}

/// How to build a BVH.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildOptions {
    /// The cost model.
    pub heuristic: Heuristic,
    /// Splitting-plane facing (004): besides the x, y and z axes, bin centroids along the two
    /// directions perpendicular to the rays, so that children separate in the rays' view and
    /// overlap less along them. Uses [`RayDistribution::direction`] of the PAH, or the given
    /// direction with SAH.
    pub facing: Option<Vec3>,
    /// Most bins per partition direction (a node of `n` references uses `min(bins, 4 + n/20)`).
    pub bins: usize,
    /// Largest leaf (a leaf is forced beyond this only for identical centroids).
    pub max_leaf: usize,
    /// Cost of traversing a node relative to one triangle test.
    pub traversal_cost: f32,
    /// Build subtrees in parallel (with the `parallel` feature).
    pub parallel: bool,
    /// The 8-wide builder's high-quality mode for static scenes: split large triangles into
    /// pieces with tight boxes before building, up to this fraction of extra references (0: off;
    /// 0.3 is a good budget). A triangle then lies in several leaves. The binary builder (beams,
    /// GPU) ignores it. Faster primary rays on Sponza, slower rays of every kind on the
    /// conference room: [`BuildOptions::high_quality`] leaves it off.
    pub presplit: f32,
    /// The 8-wide builder's tree optimization for static scenes (SAH only): build a binary tree
    /// of small leaves, optimize it by reinsertion (Bittner et al. 2013), and collapse it into
    /// eight-wide nodes, choosing leaves by a bottom-up cost pass. The binary builder (beams,
    /// GPU) and PAH builds ignore it.
    pub reinsert: bool,
    /// The 8-wide builder's light reinsertion (SAH, a binary tree collapsed; ignored with
    /// [`BuildOptions::reinsert`]): this fraction of the binary tree's nodes, the most
    /// inefficient of its upper part, are taken out and inserted back once where the SAH cost is
    /// least (0: off). The default, 0.003, removes 3–10% of the box tests of Sponza's and the
    /// conference room's rays (single-threaded, shadow rays 2–7% faster, primary 3–8%) for 4–7%
    /// more build work (`docs/benchmarks.md`).
    pub refine: f32,
    /// The 8-wide builder's spatial splits for static scenes (SAH only; Stich et al. 2009): the
    /// binary tree it collapses may also split a node by a plane across its box, a triangle the
    /// plane cuts going to both sides, up to this fraction of extra references (0: off). The
    /// binary builder (beams, GPU) and PAH builds ignore it.
    pub spatial: f32,
    /// The 8-wide builder (SAH only): build a binary tree of small leaves first and collapse it
    /// into eight-wide nodes this way (the default: [`Collapse::Optimal`]), or with `None` bin
    /// straight into eight-wide nodes as Embree does (builds about 20% faster; on the conference
    /// room its shadow rays are 13% slower, on Sponza 2% faster: `docs/benchmarks.md`). With
    /// [`BuildOptions::reinsert`] and no collapse given, [`Collapse::Greedy`].
    pub collapse: Option<Collapse>,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            heuristic: Heuristic::Sah,
            facing: None,
            bins: 32,
            max_leaf: 8,
            traversal_cost: 1.0,
            parallel: true,
            presplit: 0.0,
            reinsert: false,
            refine: 0.003,
            spatial: 0.0,
            collapse: Some(Collapse::Optimal),
        }
    }
}

impl BuildOptions {
    /// Binned SAH with default parameters.
    #[must_use]
    pub fn sah() -> Self {
        Self::default()
    }

    /// Binned SAH, then the tree optimized by reinsertion and collapsed with leaves of up to 16
    /// triangles: builds about ten times slower, faster queries, for static scenes (the 8-wide
    /// builder; see [`BuildOptions::reinsert`]).
    #[must_use]
    pub fn high_quality() -> Self {
        Self { reinsert: true, max_leaf: 16, collapse: Some(Collapse::Greedy), ..Self::default() }
    }

    /// Binned SAH with spatial splits (up to 30% more references), collapsed by the optimal
    /// collapse with leaves of up to 16 triangles: builds 2.5–4.5 times slower than the
    /// default, for static scenes (the 8-wide builder; see [`BuildOptions::spatial`]). On Sponza
    /// its primary rays are the fastest of our builds; on the conference room its shadow rays
    /// are slower than the default's (`docs/benchmarks.md`).
    #[must_use]
    pub fn spatial_splits() -> Self {
        Self { spatial: 0.3, max_leaf: 16, collapse: Some(Collapse::Optimal), ..Self::default() }
    }

    /// PAH for `distribution`, with splitting-plane facing along its direction.
    #[must_use]
    pub fn pah(distribution: RayDistribution) -> Self {
        Self { heuristic: Heuristic::Pah(distribution), facing: Some(distribution.direction()), ..Self::default() }
    }
}
