//! The scene's lights: points, quads and triangles.

use beam_math::glam::Vec3;

/// A light source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// A point light of radiant intensity `intensity` (W/sr per channel).
    Point {
        /// Position.
        position: Vec3,
        /// Radiant intensity.
        intensity: Vec3,
    },
    /// A one-sided parallelogram `corner + s·edge_u + t·edge_v`, `s, t ∈ [0, 1]`, emitting `radiance`
    /// on the side of `edge_u × edge_v`.
    Quad {
        /// A corner.
        corner: Vec3,
        /// First edge.
        edge_u: Vec3,
        /// Second edge.
        edge_v: Vec3,
        /// Emitted radiance.
        radiance: Vec3,
    },
    /// A one-sided triangle emitting `radiance` on the side of its normal.
    Triangle {
        /// Vertices, counter-clockwise seen from the lit side.
        v: [Vec3; 3],
        /// Emitted radiance.
        radiance: Vec3,
    },
}

impl Light {
    /// A downward-facing quad light of `size` times the box's width and depth, centred just under
    /// the top of the box (a ceiling light for interiors).
    #[must_use]
    pub fn under_ceiling(bounds: beam_math::Aabb, size: f32, radiance: Vec3) -> Self {
        let e = bounds.extent();
        let center = Vec3::new(bounds.center().x, bounds.max.y - 0.02 * e.y, bounds.center().z);
        let (edge_u, edge_v) = (Vec3::new(size * e.x, 0.0, 0.0), Vec3::new(0.0, 0.0, size * e.z));
        // edge_u × edge_v points down.
        Light::Quad { corner: center - 0.5 * (edge_u + edge_v), edge_u, edge_v, radiance }
    }

    /// The emitting polygon's corners (counter-clockwise seen from the lit side); empty for a point.
    #[must_use]
    pub fn polygon(&self) -> Vec<Vec3> {
        match *self {
            Light::Point { .. } => Vec::new(),
            Light::Quad { corner, edge_u, edge_v, .. } => {
                vec![corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v]
            }
            Light::Triangle { v, .. } => v.to_vec(),
        }
    }

    /// Unit normal of the emitting side (zero for a point light).
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        match *self {
            Light::Point { .. } => Vec3::ZERO,
            Light::Quad { edge_u, edge_v, .. } => edge_u.cross(edge_v).normalize_or_zero(),
            Light::Triangle { v, .. } => (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero(),
        }
    }

    /// Area of the emitter (zero for a point light).
    #[must_use]
    pub fn area(&self) -> f32 {
        match *self {
            Light::Point { .. } => 0.0,
            Light::Quad { edge_u, edge_v, .. } => edge_u.cross(edge_v).length(),
            Light::Triangle { v, .. } => 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length(),
        }
    }

    /// Centre of the emitter.
    #[must_use]
    pub fn center(&self) -> Vec3 {
        match *self {
            Light::Point { position, .. } => position,
            Light::Quad { corner, edge_u, edge_v, .. } => corner + 0.5 * (edge_u + edge_v),
            Light::Triangle { v, .. } => (v[0] + v[1] + v[2]) / 3.0,
        }
    }

    /// Emitted radiance (area lights) or intensity (point lights).
    #[must_use]
    pub fn power(&self) -> Vec3 {
        match *self {
            Light::Point { intensity, .. } => intensity,
            Light::Quad { radiance, .. } | Light::Triangle { radiance, .. } => radiance,
        }
    }
}
