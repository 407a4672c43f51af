//! What a nonlinear frame fails with: [`NonlinearError`].

use crate::BackendError;

/// An error of a nonlinear frame ([`render_nonlinear_frame`](super::render_nonlinear_frame)):
/// a beam tree too large to build, parts precomputed for another scene, a frame kept on the
/// device where it was to be read back, or the renderer's backend failing.
#[derive(Debug, thiserror::Error)]
pub enum NonlinearError {
    /// A frame given the S mesh and caustics precomputed for another scene
    /// ([`NonlinearPrecomputed`](super::NonlinearPrecomputed)).
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
    /// past [`MAX_TREE_BEAMS`](super::MAX_TREE_BEAMS) beams, or the whole tree is
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
        /// The limit ([`MAX_TREE_BEAMS`](super::MAX_TREE_BEAMS)).
        limit: u64,
        /// Most levels whose estimated tree is within the limit.
        fits: u32,
    },
    /// The renderer's backend failed (ray queries, beam textures, shading).
    #[error(transparent)]
    Backend(#[from] BackendError),
}
