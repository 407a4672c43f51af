//! The errors of beam-cpu's renderers: [`RenderError`].

use beam_render::BackendError;
use beam_scene::SceneError;
use std::path::PathBuf;

/// An error of a render, an image comparison, or reading or writing an image. Renders on the CPU
/// alone never fail but for a scene they cannot render (a glossy render without a light); a render
/// through another backend (a GPU's) fails with that backend's error.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Writing an image failed (its file, its encoding).
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Reading an image failed (the file, or its decoding).
    #[error("{}: {source}", path.display())]
    ReadImage {
        /// The image file.
        path: PathBuf,
        /// What the decoder said.
        source: image::ImageError,
    },
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
    /// A frame given the S mesh and caustics precomputed for another scene
    /// (`beam_cpu::nonlinear::NonlinearPrecomputed`).
    #[error("the S mesh and caustics given were made for a scene of {made_for} triangles, not this one's {scene}")]
    Precomputed {
        /// Triangles of the scene they were made for.
        made_for: usize,
        /// Triangles of the scene rendered.
        scene: usize,
    },
    /// A one-shot render's renderer kept the frame on its device for display rather than read it
    /// back (beam-gpu's `GpuBeams::displaying`): take it from the renderer, or render with one that
    /// reads it back.
    #[error("the renderer kept the frame on its device for display; it was not read back")]
    FrameKept,
    /// A nonlinear beam tree of `bounces` levels too large to build: level `level` would take it
    /// past [`MAX_TREE_BEAMS`](crate::nonlinear::MAX_TREE_BEAMS) beams, or the whole tree is
    /// estimated past ten times that (from the beams of the levels before `level` and the faces
    /// `level` was asked for). Found before level `level` is built.
    #[error(
        "--bounces {bounces}: the nonlinear beam tree would hold about {estimate:.1e} beams (beams per level so far \
         {beams_per_level:?}, {requested} faces asked for at level {level}, growing about {growth:.1}× a level), past \
         the limit of {limit} beams; at most {fits} bounces fit (deeper bounces are traced by rays)"
    )]
    BeamTree {
        /// Levels asked for (`NonlinearOptions::bounces`, `--bounces`).
        bounces: u32,
        /// The level that was to be built next.
        level: u32,
        /// Beams of the levels built.
        beams_per_level: Vec<u64>,
        /// S-mesh faces the next level was asked for.
        requested: u64,
        /// Growth per level the estimate assumes.
        growth: f64,
        /// Estimated beams of the whole tree.
        estimate: f64,
        /// The limit ([`MAX_TREE_BEAMS`](crate::nonlinear::MAX_TREE_BEAMS)).
        limit: u64,
        /// Most levels whose estimated tree is within the limit.
        fits: u32,
    },
    /// The backend the render ran on failed (ray queries, beam textures, shading, the gather).
    #[error(transparent)]
    Backend(#[from] BackendError),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::{Image, difference};

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
