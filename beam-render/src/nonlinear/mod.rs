//! Nonlinear beam tracing (000), all but the renderers: the frame driver every backend runs
//! ([`render_nonlinear_frame`]: the caustics, the eye's view, the beam tree level by level in
//! `tree`, the radiance flow and the shading), the S mesh over mirror and glass surfaces (their own
//! triangles, or a coarse S mesh given or simplified), the beams (S1, S3, bump-mapped), what a
//! [`BeamRenderer`] is given and returns (jobs, texel regions and hits, shade points, the levels of
//! the radiance flow), bounding-cone culling, and the Whitted waves that follow mirror and glass
//! points past the tree. The renderers themselves are beam-cpu's (`CpuBeams`, which also shades on
//! the host, [`HostShading`]) and beam-gpu's.

mod beam_tree;
mod caustics;
mod coarse;
mod composite;
mod cull;
mod error;
mod face;
mod fit;
mod frame;
mod host_shading;
mod nearest;
mod radiance;
mod rasterize;
mod renderer;
mod settings;
mod simplify;
mod smesh;
mod stages;
mod texture;
mod tree;
mod waves;

pub use beam_tree::{
    Beam, BumpedBeam, Degree, LOOKUP, LOOKUP_PREFERENCE, MIN_RISE, OUTSIDE_TEXELS, TEXEL_EPS, TexelBeam, child_beams,
    self_hit_at, self_hit_distance,
};
pub use caustics::{
    CAUSTIC_STRATA, CausticStats, MAX_CAUSTIC_STRATA, caustic_texel, caustics_by_beams, caustics_by_photons,
};
pub use composite::composite_levels;
pub use cull::{ConeCull, SelfHitFloor, blocks_meeting, cone_blocks, cone_candidates, cone_cull};
pub use error::NonlinearError;
pub use face::{Exclude, SFace};
pub use fit::Fit;
pub use frame::{FrameImage, NonlinearPrecomputed, render_nonlinear_frame, render_nonlinear_with};
pub use host_shading::{HostShading, shade_points};
pub use radiance::{Composite, LevelRadiance, NodeChildren, TexelRadiance, composite, sample_region};
pub use rasterize::render_beam;
pub use renderer::{
    BeamRasterizer, BeamRenderer, ChildLookups, CoarseByRays, DeviceImage, DeviceWaits, EyeFaces, EyeView, FramePixels,
    KeepLevel, KeptFrame, KeptTotals, LevelLayout, LookupJob, PixelHits, PointShading, TreeShading, eye_by_rays,
};
pub use settings::{MAX_TREE_BEAMS, NonlinearOptions, NonlinearStats};
pub use smesh::{MAX_NORMAL_SPREAD, SMesh};
pub use stages::Stage;
pub use texture::{
    BeamJob, BeamTexture, ShadePoint, TEXELS, TEXELS_PER_SAMPLE, TexelHit, TexelPoint, region_size, region_texels,
};
pub use tree::lookup::reproject;
pub use waves::{Path, Shade, shade_by_waves, trace_waves};
