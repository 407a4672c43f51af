//! # beam-render
//!
//! The backend-neutral render layer of beam, between the scenes of `beam-scene` and the backends
//! that render them: `beam-cpu` (on the CPU) and `beam-gpu` (wgpu) implement its traits and share
//! its host-side code, so that what a frame is and how it is asked for has one home.
//!
//! - [`queries`]: ray queries ([`RayQueries`](queries::RayQueries)), one vocabulary for every
//!   backend; [`error`]: what a backend behind the traits fails with ([`BackendError`]).
//! - [`options`]: render settings; [`tolerance`]: the offsets every backend uses; [`specular`]: the
//!   mirror and glass bounce; [`irradiance_map`]: caustic irradiance on receiving planes.
//! - [`nonlinear`]: nonlinear beam tracing (000) but for its renderers: the frame driver
//!   ([`render_nonlinear_frame`](nonlinear::render_nonlinear_frame)), the beam tree, the caustics,
//!   the renderer traits ([`BeamRenderer`](nonlinear::BeamRenderer),
//!   [`HostShading`](nonlinear::HostShading)), the S mesh, the tree's beams, their texel regions, the
//!   radiance flow, culling and the Whitted waves.
//! - [`glossy`]: the host side of the glossy light volumes (002): emitters, beams, the cone tree and
//!   the gather at a point.
//! - [`image`]: the linear RGB image every render returns, and its PNG and OpenEXR files.
//! - [`memo`]: values kept from one frame for the next; [`parallel`]: flattening in parallel;
//!   [`ordered`]: parallel sums that come out the same on any number of threads;
//!   [`cpu_clock`]: CPU time of the calling thread and of rayon's workers (benchmarks, host time
//!   beside a software GPU).

pub mod cpu_clock;
pub mod cut_outs;
pub mod error;
pub mod glossy;
pub mod image;
pub mod irradiance_map;
pub mod memo;
pub mod nonlinear;
pub mod options;
pub mod ordered;
pub mod parallel;
pub mod queries;
pub mod specular;
pub mod tolerance;

pub use error::BackendError;
