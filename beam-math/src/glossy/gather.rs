//! Glossy gather at a receiver fragment (002 §4.2–4.3): the scatter-angle domain `ABC` built from
//! the flux triangle (Fig. 9), the split point `D` when the fragment is outside (Fig. 12), and the
//! irradiance `E = Φs/A⊥ · cos θ · min(P_E, 1)` (eq. 3 with the Gaussian volume `P_E`).

use super::flux::LightBeam;
use super::gaussian::{gaussian_volume, gaussian_volume_tessellated};
use crate::float::Float;
use crate::shapes::Triangle;
use glam::{Vec2, Vec3};

/// How the Gaussian volume `P_E` is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeMethod {
    /// Exact volume over `ABC` (Owen's T): [`gaussian_volume`].
    Exact,
    /// The paper's tessellation (Figs. 11–12): [`gaussian_volume_tessellated`].
    Tessellated,
}

/// Angle between `f − origin` and the scattered direction `dir` (the `φ` of 002 §4.2.1).
fn scatter_angle(origin: Vec3, dir: Vec3, f: Vec3) -> f32 {
    let to_f = (f - origin).normalize_or_zero();
    to_f.dot(dir.normalize_or_zero()).clamp(-1.0, 1.0).acos_()
}

/// The triangular scatter-angle domain of 002 §4.2.1 (Fig. 9): `A = φ_a·l̄_a` etc. in a 2D frame of
/// the flux plane, where `l̄_a` is the unit vector from the fragment to `A_F` and `φ_a` the angle at
/// `A_W` between `F − A_W` and the scattered direction.
#[must_use]
pub fn angular_domain(beam: &LightBeam, flux: &Triangle, f: Vec3, frame: (Vec3, Vec3)) -> [Vec2; 3] {
    core::array::from_fn(|i| {
        let l = (flux.v[i] - f).normalize_or_zero();
        scatter_angle(beam.origins[i], beam.dirs[i], f) * Vec2::new(l.dot(frame.0), l.dot(frame.1))
    })
}

/// Bounds of the tail factor.
const TAIL_RANGE: (f32, f32) = (0.5, 2.0);

/// Eq. 3's tail correction: `(φ/sin φ)·A⊥ / (r²·|ABC|)` for a fragment at `to` from its source
/// point, whose scattered direction is `dir`, flux-triangle area `A⊥` and angular domain area `|ABC|`.
/// Eq. 3 spreads the flux over the flux triangle, as a specular beam does, which is exact where the
/// Gaussian volume `P_E` is whole; in the lobe's tail, where the domain is small against σ, the
/// micro-facet model sends the flux from the scatterer with density `ρ(φ)·φ/sin φ` per steradian,
/// so that `E = Φs·cos θ·ρ·(φ/sin φ)/r²` while eq. 3 gives `Φs·cos θ·ρ·|ABC|/A⊥`. Their ratio is
/// this factor; [`LightBeam::glossy_irradiance`] weighs it by `1 − P_E` and clamps it to
/// `TAIL_RANGE` (the single source point stands for the whole scatterer only while the beam is small
/// against its distance). Without it eq. 3 falls short by up to a half where light leaves a pane
/// far off its specular direction. 1 where it is undefined.
fn tail_factor(to: Vec3, dir: Vec3, area: f32, domain: f32) -> f32 {
    let r2 = to.length_squared();
    if !(r2 > 0.0 && domain > 0.0) {
        return 1.0;
    }
    let phi = (to / r2.sqrt_()).dot(dir).clamp(-1.0, 1.0).acos_();
    let stretch = if phi > 1e-4 { phi / phi.sin_() } else { 1.0 };
    stretch * area / (r2 * domain)
}

impl LightBeam {
    /// Glossy irradiance at fragment `f` with unit normal `normal` for micro-facet standard
    /// deviation `sigma` (radians): `E = Φs/A⊥ · cos θ · P_E` with `P_E ≤ 1` (002 eq. 3, Figs. 11–12),
    /// `θ` between the receiver's normal and the light's arrival from its [`Self::source_point`],
    /// times `P_E + (1 − P_E)·t` with `t` the clamped tail factor of `tail_factor` (the core keeps
    /// eq. 3, the tail gets the micro-facet model's point-source falloff).
    /// With [`VolumeMethod::Tessellated`] the split point `D` is found as in 002 §4.3 step 2–3: on the
    /// flux-triangle edge facing the fragment, `D_F` where the line from the opposite vertex through
    /// `F` crosses it; the edge parameter `s` gives `D_W` on the scatterer and `S_D = D_F − D_W`,
    /// hence `φ_d` (zero on the boundary, so the estimate is continuous there).
    #[must_use]
    pub fn glossy_irradiance(&self, f: Vec3, normal: Vec3, sigma: f32, method: VolumeMethod) -> f32 {
        let Some(plane) = self.flux_plane(f) else {
            return 0.0;
        };
        let Some(flux) = self.flux_triangle(plane) else {
            return 0.0;
        };
        if !self.in_front(f) {
            return 0.0;
        }
        let area = flux.area();
        if !(area > 0.0) {
            return 0.0;
        }
        let n = plane.normal;
        let u = n.any_orthonormal_vector();
        let frame = (u, n.cross(u));
        let [a, b, c] = angular_domain(self, &flux, f, frame);
        // The cosine along the light's arrival from its source point (002 takes the flux plane's
        // normal, which loses light turned towards a receiver the beam itself grazes).
        let source = self.source_ray(&flux, f);
        let arrival = source.map_or(n, |(s, _)| (f - s).normalize_or_zero());
        let cos_theta = (-arrival).dot(normal).max(0.0);
        let p_e = match method {
            VolumeMethod::Exact => gaussian_volume(a, b, c, sigma),
            VolumeMethod::Tessellated => self.tessellated_volume(&flux, f, frame, [a, b, c], sigma),
        }
        .min(1.0);
        let tail = source.map_or(1.0, |(s, d)| tail_factor(f - s, d, area, 0.5 * (b - a).perp_dot(c - a).abs()));
        super::flux::specular_irradiance(self.flux, area, cos_theta)
            * p_e
            * (p_e + (1.0 - p_e) * tail.clamp(TAIL_RANGE.0, TAIL_RANGE.1))
    }

    /// The scatterer point whose light reaches `f`: the scatterer vertices weighted by `f`'s
    /// barycentric coordinates in the flux triangle (clamped to it for points beside the beam).
    #[must_use]
    pub fn source_point(&self, f: Vec3) -> Option<Vec3> {
        self.source_ray(&self.flux_triangle(self.flux_plane(f)?)?, f).map(|r| r.0)
    }

    /// The source point through flux triangle `flux` and its scattered direction (the unit
    /// directions with the same weights, normalised).
    fn source_ray(&self, flux: &Triangle, f: Vec3) -> Option<(Vec3, Vec3)> {
        let w = flux.barycentric(f)?.max(Vec3::ZERO);
        let w = w / (w.x + w.y + w.z).max(f32::MIN_POSITIVE);
        let at = |v: [Vec3; 3]| v[0] * w.x + v[1] * w.y + v[2] * w.z;
        Some((at(self.origins), at(self.dirs).normalize_or_zero()))
    }

    fn tessellated_volume(&self, flux: &Triangle, f: Vec3, frame: (Vec3, Vec3), abc: [Vec2; 3], sigma: f32) -> f32 {
        let nf = flux.scaled_normal();
        // Edge k joins vertices k and k+1; its outward normal in the flux plane.
        let outward = |k: usize| {
            let e = flux.v[(k + 1) % 3] - flux.v[k];
            let m = e.cross(nf);
            let centroid = (flux.v[0] + flux.v[1] + flux.v[2]) / 3.0;
            if m.dot(flux.v[k] - centroid) < 0.0 { -m } else { m }
        };
        for k in 0..3 {
            // D lies on edge k when F is outside that edge and inside the other two's wedge.
            let (i, j, o) = (k, (k + 1) % 3, (k + 2) % 3);
            let beyond = outward(k).dot(f - flux.v[i]) > 0.0;
            if !beyond {
                continue;
            }
            // D_F: the line from the opposite vertex through F meets edge ij.
            let dir = f - flux.v[o];
            let e = flux.v[j] - flux.v[i];
            let m = dir.cross(e);
            let mm = m.length_squared();
            if mm == 0.0 {
                continue;
            }
            let s = (flux.v[i] - flux.v[o]).cross(dir).dot(m) / mm;
            if !(0.0..=1.0).contains(&s) {
                continue;
            }
            let d_f = flux.v[i] + s * e;
            let d_w = self.origins[i].lerp(self.origins[j], s);
            // The scatter direction at D_W that reaches D_F. Interpolating the vertex directions
            // instead (the paper's wording) misses D_F, since the flux triangle's edge is not the
            // ruled surface between the two edge rays, and breaks continuity at the boundary.
            let s_d = (d_f - d_w).normalize_or_zero();
            let phi_d = scatter_angle(d_w, s_d, f);
            let l = (d_f - f).normalize_or_zero();
            let d = phi_d * Vec2::new(l.dot(frame.0), l.dot(frame.1));
            return gaussian_volume_tessellated(abc[i], abc[j], abc[o], Some(d), sigma);
        }
        gaussian_volume_tessellated(abc[0], abc[1], abc[2], None, sigma)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glossy_tends_to_specular_for_small_sigma() {
        let beam = LightBeam {
            origins: [Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 1.0, 2.0)],
            dirs: [-Vec3::Z; 3],
            flux: 1.0,
        };
        let f = Vec3::new(0.2, 0.2, 0.0);
        let spec = beam.specular_irradiance(f, Vec3::Z);
        let glossy = beam.glossy_irradiance(f, Vec3::Z, 1e-3, VolumeMethod::Exact);
        assert!((spec - glossy).abs() < 1e-3 * spec, "{spec} {glossy}");
        // Outside the beam a glossy scatterer still lights the fragment a little.
        let out = beam.glossy_irradiance(Vec3::new(0.7, 0.7, 0.0), Vec3::Z, 0.2, VolumeMethod::Exact);
        assert!(out > 0.0 && out < spec);
        let tess = beam.glossy_irradiance(Vec3::new(0.7, 0.7, 0.0), Vec3::Z, 0.2, VolumeMethod::Tessellated);
        assert!(tess > 0.0);
    }
}
