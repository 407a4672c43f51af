//! Sphere–cone overlap test of 000 App. A, used to cull scene objects against a beam's bounding cone.

use crate::float::Float;
use glam::Vec3;

/// An infinite cone with apex `P_C`, unit axis `d_C` and half-angle `θ_C` (000 App. A).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Apex `P_C`.
    pub apex: Vec3,
    /// Unit axis `d_C`.
    pub axis: Vec3,
    /// Half-angle `θ_C` in radians.
    pub angle: f32,
}

impl Cone {
    /// True when `q` lies inside the cone: `(q − P_C)/‖q − P_C‖ · d_C ≥ cos θ_C`.
    #[must_use]
    pub fn contains(&self, q: Vec3) -> bool {
        let v = q - self.apex;
        let l = v.length();
        l == 0.0 || v.dot(self.axis) >= l * self.angle.cos_()
    }
}

/// Sphere–cone test of 000 App. A: true when the apex is inside the sphere, or when
/// `(O − P_C)/‖O − P_C‖ · d_C > cos(θ_C + θ_S)` with `θ_S = asin(R / ‖O − P_C‖)`.
/// Conservative (never rejects an overlapping sphere); spheres wholly behind the apex are rejected.
#[must_use]
pub fn cone_sphere(cone: &Cone, center: Vec3, radius: f32) -> bool {
    let v = center - cone.apex;
    let dist = v.length();
    if dist <= radius {
        return true;
    }
    let theta_s = (radius / dist).asin_();
    let total = cone.angle + theta_s;
    if total >= core::f32::consts::PI {
        return true;
    }
    v.dot(cone.axis) / dist > total.cos_()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked() {
        let cone = Cone { apex: Vec3::ZERO, axis: Vec3::Z, angle: 0.5 };
        assert!(cone_sphere(&cone, Vec3::new(0.0, 0.0, 5.0), 0.1));
        assert!(!cone_sphere(&cone, Vec3::new(0.0, 0.0, -5.0), 1.0));
        // Centre at 45° off-axis, distance √2·5: θ_S = asin(R/d); touching when θ_C + θ_S > π/4.
        let c = Vec3::new(5.0, 0.0, 5.0);
        let d = c.length();
        let r_touch = d * (core::f32::consts::FRAC_PI_4 - 0.5).sin();
        assert!(cone_sphere(&cone, c, r_touch * 1.01));
        assert!(!cone_sphere(&cone, c, r_touch * 0.99));
        assert!(cone_sphere(&cone, Vec3::new(0.1, 0.0, 0.0), 0.2));
    }
}
