//! A pinhole camera.

use beam_math::Ray;
use beam_math::glam::Vec3;

/// A pinhole camera: position, look-at target, up vector, vertical field of view and resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// The camera's orthonormal frame and the half-extents of its image plane at distance 1.
#[derive(Clone, Copy, Debug)]
pub struct CameraFrame {
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit right vector.
    pub right: Vec3,
    /// Unit up vector.
    pub up: Vec3,
    /// Half width of the image plane at distance 1.
    pub half_width: f32,
    /// Half height of the image plane at distance 1.
    pub half_height: f32,
}

impl Camera {
    /// An interior view of a scene box (Sponza, the conference room, Sibenik): a fifth of the box
    /// behind its centre along the longest horizontal axis and a fifth of its height below, looking
    /// along that axis slightly upwards, 60° field of view.
    #[must_use]
    pub fn interior(bounds: beam_math::Aabb, width: u32, height: u32) -> Self {
        let (c, e) = (bounds.center(), bounds.extent());
        let axis = if e.x >= e.z { Vec3::X } else { Vec3::Z };
        let position = c - axis * (0.2 * e.dot(axis)) - Vec3::Y * (0.2 * e.y);
        let forward = (axis + Vec3::Y * 0.15).normalize();
        Self { position, target: position + forward, up: Vec3::Y, fov_y: 60.0, width, height }
    }

    /// Whether the camera can see: a field of view strictly between 0° and 180°, a non-zero
    /// resolution, a position other than the target and an up vector not along the view, all finite.
    #[must_use]
    pub fn has_view(&self) -> bool {
        let sideways = self.up.cross(self.target - self.position);
        self.fov_y > 0.0
            && self.fov_y < 180.0
            && self.width > 0
            && self.height > 0
            && sideways.length_squared() > 0.0
            && sideways.is_finite()
    }

    /// The same camera rendering `width × height` pixels (at least one each way).
    #[must_use]
    pub fn with_size(self, width: u32, height: u32) -> Self {
        Self { width: width.max(1), height: height.max(1), ..self }
    }

    /// The camera's frame.
    #[must_use]
    pub fn frame(&self) -> CameraFrame {
        let forward = (self.target - self.position).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(self.up).try_normalize().unwrap_or_else(|| forward.any_orthonormal_vector());
        let up = right.cross(forward);
        let half_height = (self.fov_y.to_radians() * 0.5).tan();
        let half_width = half_height * self.width as f32 / self.height.max(1) as f32;
        CameraFrame { forward, right, up, half_width, half_height }
    }

    /// The point of the image plane (distance 1) at continuous pixel coordinates `(x, y)` (origin at
    /// the top-left corner, y down).
    #[must_use]
    pub fn image_point(&self, frame: &CameraFrame, x: f32, y: f32) -> Vec3 {
        let sx = (2.0 * x / self.width as f32 - 1.0) * frame.half_width;
        let sy = (1.0 - 2.0 * y / self.height as f32) * frame.half_height;
        self.position + frame.forward + frame.right * sx + frame.up * sy
    }

    /// The primary ray through the centre of pixel `i` (row-major).
    #[must_use]
    pub fn pixel_ray(&self, frame: &CameraFrame, i: usize) -> Ray {
        let w = self.width.max(1) as usize;
        self.ray(frame, (i % w) as f32 + 0.5, (i / w) as f32 + 0.5)
    }

    /// The primary ray through continuous pixel coordinates `(x, y)`.
    #[must_use]
    pub fn ray(&self, frame: &CameraFrame, x: f32, y: f32) -> Ray {
        Ray::new(self.position, self.image_point(frame, x, y) - self.position)
    }
}
