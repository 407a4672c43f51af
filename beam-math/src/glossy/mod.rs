//! Glossy light volumes of 002 §3–4: specular and glossy polygon beams traced from a point light,
//! flux planes and flux triangles, and the Gaussian volume over the scatter-angle domain.

mod flux;
mod gather;
mod gaussian;

pub use flux::{LightBeam, in_beam, solid_angle, specular_irradiance};
pub use gather::{VolumeMethod, angular_domain};
pub use gaussian::{gaussian, gaussian_volume, gaussian_volume_tessellated, owens_t, sector_volume};
