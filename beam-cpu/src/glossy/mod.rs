//! Glossy light volumes (002): backward polygon beams from point emitters (point lights, and area
//! lights as stratified points with cosine emission: [`emitters`](beam_render::glossy::emitters))
//! through specular and glossy scatterers (mirrors, glass, thin stained-glass panes, glossy
//! reflectors), negative shadow beams for first-order shadows, and the gather at every receiver
//! point the eye sees (specular eq. 1, glossy eq. 3 with beam-math's Gaussian volumes), through a
//! hierarchy of bounding cones over the beams (002 §5.2's future work). The ground truth traces
//! photons with the same micro-facet model.
//! The light volumes themselves (emitters, beams, cone tree, the gather at a point) are
//! [`beam_render::glossy`]'s, shared with beam-gpu.

mod direct;
mod kernel;
mod photons;
mod render;

pub use direct::{SKY_RAYS, reference_direct, sky_irradiance};
pub use kernel::PhotonKernel;
pub use photons::{glossy_photons, photon_texel};
pub use render::{
    Gather, GlossyStats, gather_on_cpu, render_glossy, render_glossy_photons, render_glossy_photons_in,
    render_glossy_reference, render_glossy_reference_in, render_glossy_with,
};
