//! An animated camera: keyframes of the camera's position and target, linearly interpolated
//! between them (a scene file's `[[camera.keys]]`).

use super::camera::Camera;
use beam_math::glam::Vec3;

/// At frame `frame`, the camera stands at `position` looking at `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraKey {
    /// Frame number.
    pub frame: u32,
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub target: Vec3,
}

/// Keyframes in strictly increasing frame order. The path runs from frame 0 to its last key's frame:
/// before the first key the camera holds at it, between two keys its position and target move
/// linearly. The other settings (up, field of view, resolution) are the scene camera's.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    keys: Vec<CameraKey>,
}

impl CameraPath {
    /// The path through `keys`; `None` unless there is a key and the frames strictly increase.
    #[must_use]
    pub fn new(keys: Vec<CameraKey>) -> Option<Self> {
        let increasing = keys.windows(2).all(|w| w[0].frame < w[1].frame);
        (!keys.is_empty() && increasing).then_some(Self { keys })
    }

    /// The keys, in frame order.
    #[must_use]
    pub fn keys(&self) -> &[CameraKey] {
        &self.keys
    }

    /// The last frame of the path (its frames are `0..=last_frame`).
    #[must_use]
    pub fn last_frame(&self) -> u32 {
        self.keys.last().map_or(0, |k| k.frame)
    }

    /// `camera` moved to frame `frame` of the path; `None` past its last frame.
    #[must_use]
    pub fn camera_at(&self, camera: &Camera, frame: u32) -> Option<Camera> {
        let after = self.keys.iter().position(|k| k.frame >= frame)?;
        let b = self.keys[after];
        let (position, target) = match after.checked_sub(1).map(|i| self.keys[i]) {
            Some(a) if b.frame > frame => {
                let t = (f64::from(frame - a.frame) / f64::from(b.frame - a.frame)) as f32;
                (a.position.lerp(b.position, t), a.target.lerp(b.target, t))
            }
            _ => (b.position, b.target),
        };
        Some(Camera { position, target, ..*camera })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_held_and_interpolated() {
        let key = |frame, x: f32| CameraKey { frame, position: Vec3::new(x, 0.0, 5.0), target: Vec3::new(x, 0.0, 0.0) };
        assert!(CameraPath::new(vec![]).is_none());
        assert!(CameraPath::new(vec![key(2, 0.0), key(2, 1.0)]).is_none());
        let path = CameraPath::new(vec![key(2, 0.0), key(6, 4.0), key(7, -1.0)]).unwrap();
        let cam = Camera { position: Vec3::ZERO, target: Vec3::Z, up: Vec3::Y, fov_y: 30.0, width: 4, height: 3 };
        let x = |f| path.camera_at(&cam, f).map(|c| c.position.x);
        assert_eq!(
            [x(0), x(2), x(3), x(6), x(7), x(8)],
            [Some(0.0), Some(0.0), Some(1.0), Some(4.0), Some(-1.0), None]
        );
        let c = path.camera_at(&cam, 5).unwrap();
        assert_eq!((c.target.x, c.fov_y, c.width), (3.0, 30.0, 4));
        assert_eq!(path.last_frame(), 7);
    }
}
