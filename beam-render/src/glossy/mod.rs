//! The host side of the glossy light volumes (002) that both backends share: the point emitters
//! (point lights, and area lights as stratified points with cosine emission), the backward polygon
//! beams they send through specular and glossy scatterers with the negative shadow beams, the
//! hierarchy of bounding cones over them, and the gather at one receiver point (specular eq. 1,
//! glossy eq. 3). beam-cpu gathers with it per pixel; beam-gpu uploads the beams and the cone tree.

mod beams;
mod cones;
mod emitters;
mod gather;
mod options;

pub use beams::{GlossyBeam, Scatter, is_scatterer, scatterings, trace_light_beams};
pub use cones::{BoundingCone, ConeNode, ConeTree, GLOSSY_REACH};
pub use emitters::{
    AREA_STRATA, Emitter, MAX_EMITTERS, REFERENCE_AREA_RAYS, area_point, area_strata, emitters, stratified, whole,
};
pub use gather::{Gathered, LightVolumes, Occluded, blocked, covers};
pub use options::GlossyOptions;
