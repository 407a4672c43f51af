//! The errors of beam-cpu's renderers: [`RenderError`].

use beam_render::BackendError;
use beam_scene::SceneError;

/// An error of a render, an image comparison, or reading or writing an image. Renders on the CPU
/// alone never fail but for a scene they cannot render (a glossy render without a light); a render
/// through another backend (a GPU's) fails with that backend's error.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Reading or writing an image failed (its file, its encoding).
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Two images compared that differ in size.
    #[error("sizes differ: {}×{} and {}×{}", first.0, first.1, second.0, second.1)]
    SizeMismatch {
        /// The first image's width and height.
        first: (u32, u32),
        /// The second image's width and height.
        second: (u32, u32),
    },
    /// A glossy render of a scene without an emitting light: light volumes are traced from point
    /// sources (area lights taken as stratified points).
    #[error(
        "scene `{scene}` has no light to trace light volumes from (a point light, or an area light of positive area)"
    )]
    NoEmitters {
        /// The scene's name.
        scene: String,
    },
    /// The backend the render ran on failed (ray queries, beam textures, shading, the gather).
    #[error(transparent)]
    Backend(#[from] BackendError),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::difference;
    use beam_render::image::Image;

    /// The messages are the ones these errors had as strings.
    #[test]
    fn messages_are_unchanged() {
        let e = difference(&Image::new(2, 1), &Image::new(1, 1)).unwrap_err();
        assert!(matches!(e, RenderError::SizeMismatch { first: (2, 1), second: (1, 1) }), "{e:?}");
        assert_eq!(e.to_string(), "sizes differ: 2×1 and 1×1");
        assert_eq!(
            RenderError::NoEmitters { scene: "dark".into() }.to_string(),
            "scene `dark` has no light to trace light volumes from (a point light, or an area light of positive area)"
        );
        let e = Image::load(std::path::Path::new("/no/such.png")).unwrap_err().to_string();
        assert!(e.starts_with("/no/such.png: "), "{e}");
    }
}
