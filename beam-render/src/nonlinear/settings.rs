//! The nonlinear renderer's settings and the statistics of a render (000 §8).

use super::beam_tree::Degree;
use super::caustics::CausticStats;
use super::stages::Stage;
use crate::options::RenderOptions;

/// Most beams a render's beam tree may hold over all its levels. A tree grows by a factor per
/// level (each beam off a curved mirror or glass surface sees many S-mesh faces: 4 to 12 on the
/// built-in scenes), so that deep trees cannot be rendered. A render is refused
/// ([`super::NonlinearError::BeamTree`]) before a level that would pass this is built, or after its
/// first cheap levels where the tree's size at [`NonlinearOptions::bounces`] levels, estimated
/// from its growth so far, passes ten times this: not after hours. 50,000 beams take about a
/// minute of a core at 16 × 16 pixels, and gigabytes of textures at larger images.
pub const MAX_TREE_BEAMS: u64 = 50_000;

/// Settings of the nonlinear renderer.
#[derive(Clone, Copy, Debug)]
pub struct NonlinearOptions {
    /// Beam parameterization.
    pub degree: Degree,
    /// Most texels per side of a beam's region; each beam gets the smallest power of two that
    /// gives its face at least [`TEXELS_PER_SAMPLE`](super::TEXELS_PER_SAMPLE) texels per pixel covering it, no fewer than 4
    /// (or than this, when it is below 4). Taken within [`TEXELS`](super::TEXELS) (a value outside is clamped).
    pub texels: u32,
    /// Levels of the beam tree (specular bounces by beams); deeper bounces are traced by rays. A
    /// tree estimated past [`MAX_TREE_BEAMS`] beams is refused.
    pub bounces: u32,
    /// Strata per side of an area light in the caustic pass (0: area lights cast no caustics;
    /// at most [`super::MAX_CAUSTIC_STRATA`]); see [`super::caustics_by_beams`].
    pub caustic_strata: u32,
    /// Shading of everything the beams and the eye see.
    pub shading: RenderOptions,
}

/// What a nonlinear render did (000 §8's statistics).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct NonlinearStats {
    /// Wall time, seconds.
    pub seconds: f64,
    /// `s1` or `s3`.
    pub degree: String,
    /// Beams per level of the beam tree (level 1: beams off the S-mesh faces the eye sees).
    pub beams_per_level: Vec<u64>,
    /// S-mesh faces (000 §7.1).
    pub smesh_faces: u64,
    /// Of [`Self::smesh_faces`], those of coarse S meshes (given or simplified).
    pub coarse_smesh_faces: u64,
    /// Of [`Self::coarse_smesh_faces`], those whose normals spread too far for beams: the points
    /// under them are traced by rays.
    pub coarse_faces_by_rays: u64,
    /// Pixels and texels on mirrors and glass shaded by rays rather than textured from child beams
    /// (past the last level, on slivers, and under a coarse face where no child beam holds their
    /// scattered ray).
    pub specular_by_rays: u64,
    /// Of [`Self::specular_by_rays`], those under a coarse face whose child beams do not hold their
    /// scattered ray (000 §7.1's S mesh is coarser than the surface's reflections).
    pub uncovered_by_beams: u64,
    /// Mean scene triangles per beam after bounding-cone culling.
    pub triangles_per_beam: f64,
    /// Texels tested in bounding triangles over texels rendered (the overdraw of 000 Fig. 7).
    pub overdraw: f64,
    /// Texels rendered (every beam's region).
    pub texels_rendered: u64,
    /// Texels shaded (their ray hit the scene).
    pub texels_shaded: u64,
    /// Mirror and glass pixels of the eye and texels of the tree that the backend kept where it
    /// found them, never handed to the host (beam-gpu's composite shades them).
    pub kept_on_backend: u64,
    /// The light beams of the caustic pass.
    pub caustics: CausticStats,
    /// Where the frame's time went, stage by stage, and the host's share of each.
    pub stages: Vec<Stage>,
    /// Image width and height.
    pub width: u32,
    /// Image height.
    pub height: u32,
}
