//! The area lights' geometry, computed once per render (the shading loop reads it at every shade
//! point), and the lights a tile of shade points can receive light from at all.

use beam_math::glam::Vec3;
use beam_scene::scene::Light;

/// An area light's polygon, plane and size (a point light: no polygon).
#[derive(Clone, Copy, Debug)]
pub(super) struct Emitter {
    corners: [Vec3; 4],
    len: usize,
    /// Unit normal of the emitting side.
    pub(super) normal: Vec3,
    pub(super) center: Vec3,
    pub(super) area: f32,
    /// Largest distance from the centre to a corner.
    radius: f32,
}

impl Emitter {
    pub(super) fn of(light: &Light) -> Self {
        let mut corners = [Vec3::ZERO; 4];
        let polygon = light.polygon();
        corners[..polygon.len()].copy_from_slice(&polygon);
        let center = light.center();
        let radius = polygon.iter().map(|&v| (v - center).length()).fold(0.0, f32::max);
        Self { corners, len: polygon.len(), normal: light.normal(), center, area: light.area(), radius }
    }

    /// The light's corners in order (empty for a point light).
    pub(super) fn polygon(&self) -> &[Vec3] {
        &self.corners[..self.len]
    }

    /// Whether the light can light point `p` of normal `n` at all: `p` is on its emitting side and
    /// some corner is above `p`'s tangent plane (`tangent`: with exact shading, whose integrand
    /// vanishes below it).
    pub(super) fn may_light(&self, p: Vec3, n: Vec3, tangent: bool) -> bool {
        self.normal.dot(p - self.center) > 0.0 && (!tangent || self.polygon().iter().any(|&v| n.dot(v - p) > 0.0))
    }

    /// An upper bound on the integrand `cos θ cos θ′ / r²` of the irradiance the light gives a
    /// point `p` on its emitting side, times the light's area: so a bound on both the unoccluded
    /// irradiance per unit radiance and every estimate of it by samples of the light. With `d`
    /// the distance from `p` to the light's plane and `r ≥ r₀ = max(d, |p − centre| − radius)`,
    /// the integrand is at most `cos θ′ / r² = d / r³ ≤ d / r₀³`.
    pub(super) fn irradiance_bound(&self, p: Vec3) -> f32 {
        let d = self.normal.dot(p - self.center);
        let r0 = d.max((p - self.center).length() - self.radius);
        self.area * d / (r0 * r0 * r0)
    }

    /// Whether the light faces some point of the box `[lo, hi]` (a tile's shade points): some
    /// corner of the box is on its emitting side.
    pub(super) fn faces_box(&self, lo: Vec3, hi: Vec3) -> bool {
        // The box corner farthest along the normal.
        let far = Vec3::select(self.normal.cmpge(Vec3::ZERO), hi, lo);
        self.normal.dot(far - self.center) > 0.0
    }
}
