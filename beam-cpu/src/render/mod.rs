//! Renderers: beam-traced soft shadows (001) and the ray-traced reference, with the same shading.

mod clear_shafts;
mod compare;
mod coverage;
mod cut_outs;
mod eye_budget;
mod eye_regions;
mod hard_shadow;
mod lambert;
mod light_groups;
mod packet;
mod primary_beam;
mod primary_image;
pub(crate) mod renderer;
mod shadow_beam;
mod shaft;
mod silhouettes;
mod tile_shadows;

pub use compare::{Difference, difference, side_by_side};
pub use eye_regions::{REGION, TILE, primary_coverage, region_side};
pub use hard_shadow::lit_pieces;
pub use lambert::{clip_above, point_source_irradiance, polygon_irradiance};
pub use primary_beam::{NEAR, Piece, point_on_piece, visible_surface};
pub use primary_image::{CUT_OUT_RAYS, PrimaryStats, Visibility, pixel_samples, primary_image};
pub use renderer::{
    RenderStats, light_seen, pixel_fragments, render, render_queries, render_with, shade_point, stratified,
    trace_radiance,
};
pub use shadow_beam::BeamStats;
pub use shadow_beam::visible::{VisibleLight, visible_light};
