//! The exact answer to one shadow-beam query on the CPU: the reference every backend's
//! [`BeamQueries::light_visibility`](beam_render::queries::BeamQueries::light_visibility) is held
//! to, and the wavefront's own path for the beams a backend gives up on.

use crate::render::lambert::{clip_above, polygon_irradiance};
use crate::render::shadow_beam::BeamStats;
use crate::render::shadow_beam::visible::visible_light;
use beam_bvh::FlatBvh;
use beam_math::Triangle;
use beam_render::queries::{LightPolygon, LightQuery, LightSeen};

/// What point `query.p` (normal `query.n`) sees of `light` (001 §5): the light clipped to the
/// half-space above the point's tangent plane where `query.clip_above` (001 eq. 1), its shadow
/// beam traced through `bvh` over `triangles` (split exactly at the triangles' edges), and of the visible
/// pieces Lambert's irradiance per unit radiance and their share of the (clipped) light's area.
/// Nothing where the point lies behind the light or the clip leaves no polygon. `query.light` is
/// not read: `light` is the light it names.
#[must_use]
pub fn light_seen(bvh: &FlatBvh, triangles: &[Triangle], light: &LightPolygon, query: &LightQuery) -> LightSeen {
    let (p, n) = (query.p, query.n);
    let polygon = if query.clip_above { clip_above(light.corners(), p, n) } else { light.corners().to_vec() };
    if polygon.len() < 3 {
        return LightSeen::default();
    }
    let mut stats = BeamStats::default();
    let Some(visible) = visible_light(bvh, triangles, p, &polygon, light.normal, &mut stats) else {
        return LightSeen::default();
    };
    let irradiance = visible.polygons().iter().map(|piece| polygon_irradiance(p, n, piece)).sum();
    LightSeen { irradiance, fraction: visible.fraction() }
}
