//! Point lights on the lit fragments of eye beams (001 §4.2): what a point light gives the
//! diffuse or glossy points of one triangle, found once for all the fragments of a piece, then
//! summed over each fragment's quadrature points.

use super::context::Context;
use beam_math::glam::Vec3;
use beam_scene::scene::{Light, Material, Scene};

impl Context<'_> {
    /// What point light `light` gives the diffuse or glossy points of `prim` seen from `camera`, of
    /// which `q` is one (`None` for another material or light): the triangle's side that faces the
    /// camera and its albedo, found once for all the fragments of a piece.
    pub(super) fn point_lit(&self, prim: u32, light: usize, camera: Vec3, q: Vec3) -> Option<PointLit<'_>> {
        let (Light::Point { position, intensity }, Material::Diffuse { albedo } | Material::Glossy { albedo, .. }) =
            (self.scene.lights[light], self.scene.material(prim))
        else {
            return None;
        };
        // One side of the triangle's plane faces the camera for all its points.
        let mut n = self.scene.normal(prim);
        if n.dot(q - camera) > 0.0 {
            n = -n;
        }
        // Without textures, vertex colours or vertex normals, one albedo and one normal hold over
        // the triangle: no lookup per point.
        let surfaces = &self.scene.surfaces;
        let plain = surfaces.is_plain() && surfaces.normals.is_empty();
        Some(PointLit {
            scene: self.scene,
            prim,
            position,
            intensity: intensity / std::f32::consts::PI,
            n,
            albedo,
            plain,
        })
    }
}

/// What a point light gives the points of one triangle ([`Context::point_lit`]).
pub(super) struct PointLit<'a> {
    scene: &'a Scene,
    prim: u32,
    position: Vec3,
    /// The light's intensity over π (Lambert's BRDF).
    intensity: Vec3,
    /// The unit normal of the triangle's side that faces the camera.
    n: Vec3,
    albedo: Vec3,
    /// Whether `albedo` and `n` hold at every point (no texture, vertex colour or vertex normal).
    plain: bool,
}

impl PointLit<'_> {
    /// Radiance towards the camera of the triangle's points `points`, unoccluded (the fragment is
    /// known to be lit, 001 §4.2), summed with their weights (a quadrature over the fragment):
    /// `Σ w · ρ/π · I · max(n·l, 0) / r²`, `l` the unit direction to the light at distance `r`.
    pub(super) fn radiance(&self, points: &[(f32, Vec3)]) -> Vec3 {
        // `w · max(n·(P − q), 0) / r³` for the light at `P`, the albedo outside the sum where it
        // is one.
        let term = |w: f32, q: Vec3, n: Vec3| {
            let to = self.position - q;
            let r2 = to.length_squared();
            w * n.dot(to).max(0.0) / (r2 * r2.sqrt())
        };
        let sum = if self.plain {
            self.albedo * points.iter().map(|&(w, q)| term(w, q, self.n)).sum::<f32>()
        } else {
            points
                .iter()
                .map(|&(w, q)| {
                    let n = self.scene.mapped_normal(self.prim, q, self.n);
                    self.scene.albedo_at(self.prim, q) * term(w, q, n)
                })
                .sum()
        };
        sum * self.intensity
    }
}
