//! Nonlinear beam tracing (000): an S mesh over each mirror and glass surface, nonlinear beams per
//! S-mesh triangle (reflection, refraction; S1, S3 or bump-mapped), each beam rendered into its own
//! texel region by bounding triangles (Algs. 1–2) — on the CPU here, or on a GPU through the
//! [`BeamRenderer`] trait (beam-gpu) — and the final image textured from those regions.

mod atlas;
mod caustics;
mod composite;
mod reference;
mod smesh;
mod trace;

pub use atlas::{BeamTexture, BumpedBeam, TexelBeam, TexelHit, cone_candidates, render_beam, self_hit_distance};
pub use caustics::{
    CAUSTIC_STRATA, CausticStats, MAX_CAUSTIC_STRATA, caustic_texel, caustics_by_beams, caustics_by_photons,
};
pub use composite::{Composite, LevelRadiance, TexelRadiance, composite, composite_levels, sample_region};
pub use reference::{Shade, render_smooth_reference, render_smooth_reference_with, shade_by_waves};
pub use smesh::{SFace, SMesh};
pub use trace::{
    Beam, BeamJob, BeamRenderer, CpuBeams, Degree, NonlinearOptions, NonlinearStats, ShadePoint, TEXELS,
    TEXELS_PER_SAMPLE, child_beams, region_size, render_nonlinear, render_nonlinear_with,
};
