//! Tolerances both backends share, so that they decide alike.

use beam_scene::scene::Scene;

/// Occluders are counted only strictly between the point and the light: depths (in units of the
/// light-plane distance) within `[DEPTH_EPS, 1 − DEPTH_EPS]`.
pub const DEPTH_EPS: f32 = 1e-4;

/// Offset of secondary ray origins from surfaces: 1e-4 of the scene's diagonal.
#[must_use]
pub fn shading_eps(scene: &Scene) -> f32 {
    1e-4 * scene.bounds().extent().length()
}
