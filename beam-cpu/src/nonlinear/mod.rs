//! Nonlinear beam tracing (000) on the CPU, doing what the GPU pipeline does: an S mesh over each
//! mirror, one nonlinear beam per S-mesh triangle (mirror reflection, S1 or S3), each beam rendered
//! into its own texel region by bounding triangles (Algs. 1–2), and the final image textured from
//! those regions.

mod atlas;
mod caustics;
mod reference;
mod smesh;
mod trace;

pub use atlas::{BeamTexture, BumpedBeam, TexelBeam, TexelHit, cone_candidates, render_beam, self_hit_distance};
pub use caustics::{CausticStats, caustic_texel, caustics_by_beams, caustics_by_photons};
pub use reference::{render_smooth_reference, render_smooth_reference_with};
pub use smesh::{SFace, SMesh};
pub use trace::{
    Beam, BeamJob, BeamRenderer, CpuBeams, Degree, NonlinearOptions, NonlinearStats, TEXELS_PER_SAMPLE, child_beams,
    render_nonlinear, render_nonlinear_with,
};
