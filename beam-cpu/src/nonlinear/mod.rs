//! Nonlinear beam tracing (000): an S mesh over each mirror and glass surface, nonlinear beams per
//! S-mesh triangle (reflection, refraction; S1, S3 or bump-mapped), each beam rendered into its own
//! texel region by bounding triangles (Algs. 1–2) — on the CPU here, or on a GPU through
//! beam-render's [`BeamRenderer`](beam_render::nonlinear::BeamRenderer) trait (beam-gpu) — and the
//! final image textured from those regions. The host side of the beam tree that both backends share
//! is [`beam_render::nonlinear`]'s.

mod atlas;
mod caustics;
mod composite;
mod cpu_beams;
mod frame;
mod lookup;
mod radiance_flow;
mod reference;
mod settings;
mod source;
mod stages;
mod trace;
mod tree;

pub use atlas::render_beam;
pub use caustics::{
    CAUSTIC_STRATA, CausticStats, MAX_CAUSTIC_STRATA, caustic_texel, caustics_by_beams, caustics_by_photons,
};
pub use composite::composite_levels;
pub use cpu_beams::{CpuBeams, shade_points};
pub use frame::{FrameImage, NonlinearPrecomputed, render_nonlinear, render_nonlinear_frame, render_nonlinear_with};
pub use reference::{render_smooth_reference, render_smooth_reference_with};
pub use settings::{MAX_TREE_BEAMS, NonlinearOptions, NonlinearStats};
pub use stages::Stage;
