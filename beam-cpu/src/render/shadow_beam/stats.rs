//! What beams (eye and shadow beams) count of their work.

/// Work done by beams (eye or shadow beams).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BeamStats {
    /// BVH nodes tested against the beam frustum (001's "BVH steps").
    pub bvh_steps: u64,
    /// Triangles set up against a beam (projected once each, 001 §3.4).
    pub triangle_tests: u64,
    /// Beam–triangle split operations (001's "intersections").
    pub intersections: u64,
    /// Hit pieces produced (001's "hit beams").
    pub hit_beams: u64,
    /// Miss pieces made by splits.
    pub pieces: u64,
    /// Pieces joined into a neighbour that sees the same thing.
    pub joins: u64,
    /// Shadow beams whose small occluders entered by their silhouette edges.
    pub silhouette_beams: u64,
    /// Projected edges those beams weighed (silhouette, boundary and split-set edges over the light).
    pub silhouette_edges: u64,
    /// Silhouette passes given up on an exact tie or too many edges (the beam was split instead).
    pub silhouette_fallbacks: u64,
}

impl BeamStats {
    /// What was counted since `before` (a copy of these counters taken earlier).
    #[must_use]
    pub fn since(&self, before: &Self) -> Self {
        Self {
            bvh_steps: self.bvh_steps - before.bvh_steps,
            triangle_tests: self.triangle_tests - before.triangle_tests,
            intersections: self.intersections - before.intersections,
            hit_beams: self.hit_beams - before.hit_beams,
            pieces: self.pieces - before.pieces,
            joins: self.joins - before.joins,
            silhouette_beams: self.silhouette_beams - before.silhouette_beams,
            silhouette_edges: self.silhouette_edges - before.silhouette_edges,
            silhouette_fallbacks: self.silhouette_fallbacks - before.silhouette_fallbacks,
        }
    }
}

impl core::ops::AddAssign for BeamStats {
    fn add_assign(&mut self, o: Self) {
        self.bvh_steps += o.bvh_steps;
        self.triangle_tests += o.triangle_tests;
        self.intersections += o.intersections;
        self.hit_beams += o.hit_beams;
        self.pieces += o.pieces;
        self.joins += o.joins;
        self.silhouette_beams += o.silhouette_beams;
        self.silhouette_edges += o.silhouette_edges;
        self.silhouette_fallbacks += o.silhouette_fallbacks;
    }
}
