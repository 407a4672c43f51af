//! A pinhole camera.

use beam_math::Ray;
use beam_math::glam::Vec3;

/// `v` scaled to unit length, also where its squared length overflows or underflows `f32` (a view
/// from the origin to a target at 10²⁰: scaled by its largest coordinate first); `None` for a zero
/// or non-finite `v`.
fn unit(v: Vec3) -> Option<Vec3> {
    v.try_normalize().or_else(|| {
        let m = v.abs().max_element();
        if !(m > 0.0 && m.is_finite()) {
            return None;
        }
        (v / m).try_normalize()
    })
}

/// `v` for a message: each coordinate as Rust's `{:?}` writes it (`3e38`, not 39 digits).
fn show(v: Vec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

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

    /// Whether the camera can see ([`Camera::check_view`] finds nothing wrong).
    #[must_use]
    pub fn has_view(&self) -> bool {
        self.check_view().is_ok()
    }

    /// Why the camera cannot see, if it cannot: it needs a field of view strictly between 0° and
    /// 180°, a non-zero resolution, finite position, target and up, a view direction
    /// `target − position` that neither vanishes nor overflows, an up vector not along it, and an
    /// eye near enough to the origin that 32-bit floats place its image plane (at distance 1) to
    /// 1% of the plane's half extent. Renderers take only such cameras (a camera without a view
    /// renders nothing).
    pub fn check_view(&self) -> Result<(), String> {
        if !(self.fov_y > 0.0 && self.fov_y < 180.0) {
            return Err(format!("field of view {}° must lie strictly between 0° and 180°", self.fov_y));
        }
        if self.width == 0 || self.height == 0 {
            return Err(format!("resolution {}×{} must be at least 1×1", self.width, self.height));
        }
        let (p, t, up) = (self.position, self.target, self.up);
        let (ps, ts, ups) = (show(p), show(t), show(up));
        if !(p.is_finite() && t.is_finite() && up.is_finite()) {
            return Err(format!("position {ps}, target {ts} and up {ups} must be finite"));
        }
        let view = t - p;
        if !view.is_finite() {
            return Err(format!("the view direction target − position overflows (position {ps}, target {ts})"));
        }
        if unit(view).is_none() {
            // A target one unit ahead of an eye at 10⁸ rounds onto it (a glTF camera's).
            let far = if p.abs().max_element() >= 1e7 {
                ": the eye is too far from the origin for 32-bit floats"
            } else {
                ""
            };
            return Err(format!("position {ps} and target {ts} coincide{far}"));
        }
        let f = self.frame();
        if unit(f.forward.cross(up)).is_none() {
            return Err(format!("up {ups} is zero or along the view direction {}", show(view)));
        }
        if !(f.half_width > 0.0 && f.half_height > 0.0 && f.half_width.is_finite() && f.half_height.is_finite()) {
            return Err(format!(
                "field of view {}° gives no image plane at {}×{}",
                self.fov_y, self.width, self.height
            ));
        }
        // The image plane as the renderers place it: `position + forward`, rounded.
        let rounding = ((p + f.forward) - p - f.forward).length();
        let tolerance = 0.01 * f.half_width.min(f.half_height).min(1.0);
        if !(rounding <= tolerance) {
            return Err(format!(
                "the eye at {ps} is too far from the origin for 32-bit floats to place its image plane \
                 (rounding {rounding:.1e}, allowed {tolerance:.1e} at a {}° field of view): move the scene and camera \
                 nearer the origin",
                self.fov_y
            ));
        }
        Ok(())
    }

    /// The same camera rendering `width × height` pixels (at least one each way).
    #[must_use]
    pub fn with_size(self, width: u32, height: u32) -> Self {
        Self { width: width.max(1), height: height.max(1), ..self }
    }

    /// The camera's frame.
    #[must_use]
    pub fn frame(&self) -> CameraFrame {
        let forward = unit(self.target - self.position).unwrap_or(Vec3::NEG_Z);
        let right = unit(forward.cross(self.up)).unwrap_or_else(|| forward.any_orthonormal_vector());
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
