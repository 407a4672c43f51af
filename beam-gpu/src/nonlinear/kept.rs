//! What one frame of [`super::GpuBeams`] keeps on the GPU between its stages ([`GpuKept`]), as a
//! value: the frame's caller holds it (in a [`KeptFrame`](beam_render::nonlinear::KeptFrame)) from
//! the eye's view to the composite.

use super::eye::KeptEyeHits;
use super::level::KeptLevel;
use super::lookups::LookupBeams;
use super::records::KeptPoints;

/// One frame's points and hits kept on the GPU, handed from stage to stage (per frame; nothing of
/// it outlives the frame's composite): the eye stage makes it
/// ([`EyeView::eye_view`](beam_render::nonlinear::EyeView::eye_view), `eye_faces`), each level of
/// the tree adds its points ([`BeamRasterizer::render_level`](beam_render::nonlinear::BeamRasterizer::render_level)),
/// and the composite ([`PointShading::shade_tree`](beam_render::nonlinear::PointShading::shade_tree))
/// consumes it; for a frame the caller shades after all, the `take_kept_*` methods read it back.
#[derive(Default)]
pub(super) struct GpuKept {
    /// The eye's diffuse, glossy and emissive points of the crop, per dispatch of its view.
    pub(super) eye_points: Option<Vec<KeptPoints>>,
    /// The eye's mirror and glass hits on S-mesh faces, and what located them (where the eye's
    /// view kept them).
    pub(super) eye_hits: Option<KeptEyeHits>,
    /// The points of each level the atlas stage kept, by level.
    pub(super) levels: Vec<KeptLevel>,
    /// The levels as the records of points under coarse S-mesh faces in the level above (the
    /// eye's, for the first) look them up, by level (on a coarse S mesh only).
    pub(super) child_levels: Vec<(usize, LookupBeams)>,
}
