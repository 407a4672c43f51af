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

    /// This cone with its apex moved back along the axis by `back` and its half-angle widened by
    /// `extra` radians: it contains this one (the apex is inside it, and every direction within
    /// the old half-angle of the axis is within the new one).
    #[must_use]
    pub fn widened(&self, extra: f32, back: f32) -> Self {
        Self { apex: self.apex - self.axis * back, axis: self.axis, angle: self.angle + extra }
    }

    /// True when `inner` lies inside this cone: its apex is inside, and its axis's angle to this
    /// axis plus its half-angle is at most this half-angle, less a thousandth of a radian for
    /// rounding. Then every point `apex + t·w` of `inner` is this apex plus two vectors within the
    /// half-angle of the axis, which a cone under π/2 (convex) holds; a wider cone holds none.
    #[must_use]
    pub fn contains_cone(&self, inner: &Self) -> bool {
        let between = self.axis.dot(inner.axis).clamp(-1.0, 1.0).acos_();
        let half_turn = core::f32::consts::FRAC_PI_2;
        self.angle < half_turn && between + inner.angle + 1e-3 <= self.angle && self.contains(inner.apex)
    }
}

/// Sphere–cone test of 000 App. A: true when the apex is inside the sphere, or when
/// `(O − P_C)/‖O − P_C‖ · d_C > cos(θ_C + θ_S)` with `θ_S = asin(R / ‖O − P_C‖)`.
/// Conservative (never rejects an overlapping sphere); spheres wholly behind the apex are rejected.
/// To test many spheres against one cone, prepare it once with [`ConeSpheres::new`].
#[must_use]
pub fn cone_sphere(cone: &Cone, center: Vec3, radius: f32) -> bool {
    ConeSpheres::new(cone).meets(center, radius)
}

/// A cone prepared for many [`cone_sphere`] tests: `cos θ_C` and `sin θ_C` taken once, so that a
/// test needs one square root and no trigonometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeSpheres {
    apex: Vec3,
    axis: Vec3,
    cos: f32,
    sin: f32,
}

impl ConeSpheres {
    /// Prepare `cone`.
    #[must_use]
    pub fn new(cone: &Cone) -> Self {
        Self { apex: cone.apex, axis: cone.axis, cos: cone.angle.cos_(), sin: cone.angle.sin_() }
    }

    /// The apex, unit axis, and cosine and sine of the half-angle, as [`ConeSpheres::meets`] reads
    /// them (for a shader that tests the same way).
    #[must_use]
    pub const fn terms(&self) -> (Vec3, Vec3, f32, f32) {
        (self.apex, self.axis, self.cos, self.sin)
    }

    /// [`cone_sphere`] of the sphere at `center` of `radius`. With `d = ‖O − P_C‖`,
    /// `cos θ_S = √(d² − R²)/d` and `sin θ_S = R/d`, so `d·cos(θ_C + θ_S) = cos θ_C √(d² − R²) −
    /// sin θ_C R`; `θ_C + θ_S ≥ π` (every direction) exactly when `θ_C ≥ π/2` and `R ≥ d sin θ_C`.
    /// The comparison is widened by `1e-5·d` so that rounding never rejects a sphere the angles'
    /// form accepts. Without branches (the square root of a negative number is NaN, and fails its
    /// comparison, only where the apex is inside the sphere, which passes anyway), so that
    /// [`ConeSpheres::meets_boxes`] can test its lanes in vector registers.
    #[must_use]
    #[inline]
    pub fn meets(&self, center: Vec3, radius: f32) -> bool {
        let v = center - self.apex;
        let d2 = v.length_squared();
        let dist = d2.sqrt_();
        let inside = d2 <= radius * radius;
        let wide = self.cos <= 0.0 && radius >= dist * self.sin;
        let bound = self.cos * (d2 - radius * radius).sqrt_() - self.sin * radius;
        inside | wide | (v.dot(self.axis) + 1e-5 * dist > bound)
    }

    /// [`ConeSpheres::meets`] of the spheres around eight boxes at once, as bit `i` of the
    /// result: box `i` spans `min[a][i]..max[a][i]` on axis `a`, its sphere is centred on it with
    /// half its diagonal as radius.
    #[must_use]
    pub fn meets_boxes(&self, min: [&[f32; 8]; 3], max: [&[f32; 8]; 3]) -> u32 {
        let hit: [bool; 8] = core::array::from_fn(|i| {
            let (lo, hi) = (Vec3::new(min[0][i], min[1][i], min[2][i]), Vec3::new(max[0][i], max[1][i], max[2][i]));
            self.meets(0.5 * (lo + hi), (0.5 * (hi - lo)).length())
        });
        hit.iter().enumerate().fold(0, |m, (i, &h)| m | u32::from(h) << i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cone contains its widened self, and every point sampled in a cone it says it contains
    /// (seeded cones near one another, some inside and some not).
    #[test]
    fn contained_cones_hold_their_points() {
        let mut next = uniform(0x0bad_cafe);
        let mut v = move || {
            let mut n = || next() - 0.5;
            (Vec3::new(n(), n(), n()), n() + 0.5)
        };
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..4000 {
            let ((a, s), (b, t), (c, u)) = (v(), v(), v());
            let axis = (Vec3::Z + 0.3 * a).normalize();
            let outer = Cone { apex: b, axis, angle: 0.05 + 1.2 * s };
            let wide = outer.widened(0.1 * t + 2e-3, u);
            assert!(wide.angle >= core::f32::consts::FRAC_PI_2 || wide.contains_cone(&outer), "{wide:?}");
            let ((d, w1), _) = (v(), v());
            let inner = Cone {
                apex: outer.apex + 0.2 * c,
                axis: (outer.axis + 0.2 * d).normalize(),
                angle: outer.angle * (0.5 + 0.6 * w1),
            };
            if !outer.contains_cone(&inner) {
                outside += 1;
                continue;
            }
            inside += 1;
            for _ in 0..50 {
                // A direction within the inner half-angle: the axis tilted towards a random side.
                let ((r, tilt), (_, far)) = (v(), v());
                let side = r.cross(inner.axis).normalize_or(inner.axis.any_orthonormal_vector());
                let tilt = inner.angle * tilt;
                let w = inner.axis * tilt.cos_() + side * tilt.sin_();
                let q = inner.apex + w * (20.0 * far);
                assert!(outer.contains(q), "{outer:?} holds {inner:?}, yet {q} is outside");
            }
        }
        assert!(inside > 200 && outside > 200, "{inside} inside, {outside} outside");
    }

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

    /// The angles' form of 000 App. A, as written there.
    fn by_angles(cone: &Cone, center: Vec3, radius: f32) -> bool {
        let v = center - cone.apex;
        let dist = v.length();
        if dist <= radius {
            return true;
        }
        let total = cone.angle + (radius / dist).asin_();
        total >= core::f32::consts::PI || v.dot(cone.axis) / dist > total.cos_()
    }

    /// Seeded xorshift numbers in [0, 1].
    fn uniform(seed: u32) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        }
    }

    #[test]
    fn prepared_test_keeps_every_sphere_the_angles_keep() {
        // A seeded grid of cones (half-angles up to 3 rad, past π/2) and spheres: the prepared test
        // accepts every sphere the angles' form accepts, and disagrees only at the boundary.
        let mut next = uniform(0x2545_f491);
        let (mut extra, n) = (0, 200_000);
        for _ in 0..n {
            let axis = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize_or(Vec3::Z);
            let cone = Cone { apex: Vec3::new(next(), next(), next()), axis, angle: 0.01 + 3.0 * next() };
            let center = Vec3::new(8.0 * next() - 4.0, 8.0 * next() - 4.0, 8.0 * next() - 4.0);
            let radius = 2.0 * next();
            let (angles, prepared) = (by_angles(&cone, center, radius), cone_sphere(&cone, center, radius));
            assert!(prepared || !angles, "{cone:?} {center} {radius}: rejected a sphere the angles keep");
            extra += usize::from(prepared && !angles);
        }
        assert!(extra < n / 1000, "{extra} of {n} extra spheres kept: more than boundary rounding");
    }

    /// Every bit of the eight-box test is `meets` of that box's sphere, on cones of every
    /// half-angle, boxes around the apex among them.
    #[test]
    fn box_lanes_answer_as_meets() {
        let mut next = uniform(0x1234_5679);
        let (mut kept, mut total) = (0, 0);
        for _ in 0..20_000 {
            let axis = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize_or(Vec3::Z);
            let cone = Cone { apex: Vec3::new(next(), next(), next()), axis, angle: 0.01 + 3.0 * next() };
            let spheres = ConeSpheres::new(&cone);
            let (mut min, mut max) = ([[0.0f32; 8]; 3], [[0.0f32; 8]; 3]);
            for i in 0..8 {
                for a in 0..3 {
                    let (p, q) = (6.0 * next() - 3.0, 6.0 * next() - 3.0);
                    (min[a][i], max[a][i]) = (p.min(q), p.max(q));
                }
            }
            let mask = spheres.meets_boxes([&min[0], &min[1], &min[2]], [&max[0], &max[1], &max[2]]);
            for i in 0..8 {
                let b = crate::Aabb::new(
                    Vec3::new(min[0][i], min[1][i], min[2][i]),
                    Vec3::new(max[0][i], max[1][i], max[2][i]),
                );
                let want = spheres.meets(b.center(), 0.5 * b.extent().length());
                assert_eq!(mask >> i & 1 == 1, want, "{cone:?} box {b:?}");
                kept += usize::from(want);
                total += 1;
            }
        }
        assert!(kept > total / 10 && kept < total * 9 / 10, "{kept} of {total} kept: both answers tested");
    }
}
