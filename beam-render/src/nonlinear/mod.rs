//! The host side of nonlinear beam tracing (000) that every backend shares: the S mesh over mirror
//! and glass surfaces (their own triangles, or a coarse S mesh given or simplified), the beams (S1, S3, bump-mapped), what a [`BeamRenderer`] is given and returns
//! (jobs, texel regions and hits, shade points, the levels of the radiance flow), bounding-cone
//! culling, and the Whitted waves that follow mirror and glass points past the tree. The renderers
//! themselves are beam-cpu's and beam-gpu's.

mod beam_tree;
mod coarse;
mod cull;
mod face;
mod fit;
mod nearest;
mod radiance;
mod renderer;
mod simplify;
mod smesh;
mod texture;
mod waves;

pub use beam_tree::{
    Beam, BumpedBeam, Degree, LOOKUP, LOOKUP_PREFERENCE, MIN_RISE, OUTSIDE_TEXELS, TEXEL_EPS, TexelBeam, child_beams,
    self_hit_at, self_hit_distance,
};
pub use cull::{ConeCull, SelfHitFloor, blocks_meeting, cone_blocks, cone_candidates, cone_cull};
pub use face::{Exclude, SFace};
pub use fit::Fit;
pub use radiance::{Composite, LevelRadiance, NodeChildren, TexelRadiance, composite, sample_region};
pub use renderer::{
    BeamRasterizer, BeamRenderer, ChildLookups, CoarseByRays, DeviceImage, DeviceWaits, EyeFaces, EyeView, FramePixels,
    KeepLevel, KeptFrame, KeptTotals, LevelLayout, LookupJob, PixelHits, PointShading, TreeShading, eye_by_rays,
};
pub use smesh::{MAX_NORMAL_SPREAD, SMesh};
pub use texture::{
    BeamJob, BeamTexture, ShadePoint, TEXELS, TEXELS_PER_SAMPLE, TexelHit, TexelPoint, region_size, region_texels,
};
pub use waves::{Path, Shade, shade_by_waves, trace_waves};
