//! Nonlinear beam tracing (000) on the CPU: [`CpuBeams`], the renderer behind beam-render's
//! [`BeamRenderer`](beam_render::nonlinear::BeamRenderer) trait that renders each beam into its own
//! texel region by bounding triangles (Algs. 1–2, beam-render's
//! [`render_beam`](beam_render::nonlinear::render_beam)) and shades points on the host
//! ([`HostShading`](beam_render::nonlinear::HostShading)); [`render_nonlinear`], a whole frame with
//! it; and the ray-traced ground truth ([`render_smooth_reference`]). The frame driver, the beam
//! tree and the rest of the host side every backend shares are [`beam_render::nonlinear`]'s.

mod cpu_beams;
mod reference;

pub use cpu_beams::{CpuBeams, render_nonlinear};
pub use reference::{render_smooth_reference, render_smooth_reference_with};
