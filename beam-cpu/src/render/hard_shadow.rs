//! Hard shadows from a point light by beams (001 §4.2): a visible piece of the eye beam (a polygon
//! on its triangle's plane) is connected to the light by a beam with the light as apex; traced like
//! a shadow beam, its miss pieces are the lit parts of the piece, exactly. They are projected back
//! through the eye onto the image plane, where they are rasterized with exact coverage like the
//! visible pieces themselves.

use super::primary_beam::{Piece, point_on_piece};
use super::shadow_beam::BeamStats;
use super::shadow_beam::visible::visible_section;
use beam_bvh::FlatBvh;
use beam_math::Triangle;
use beam_math::glam::{Vec2, Vec3};
use beam_math::polybeam::{BeamFrame, PolyBeam, Section};

/// The parts of `piece` (seen through the eye frame `eye`) lit by a point light at `light`, as
/// pieces of the image plane seeing the same triangle. Empty for the background and where the
/// triangle faces away from the light (or from the eye's side, the light lies behind it).
pub fn lit_pieces(
    bvh: &FlatBvh,
    triangles: &[Triangle],
    eye: &BeamFrame,
    piece: &Piece,
    light: Vec3,
    stats: &mut BeamStats,
) -> Vec<Piece> {
    match lit_parts(bvh, triangles, eye, piece, light, stats) {
        LitParts::Whole => vec![*piece],
        LitParts::Cut(pieces) => pieces,
    }
}

/// What a point light lights of a piece ([`lit_parts`]).
pub(crate) enum LitParts {
    /// All of it: no triangle hid any of the light's beam through it.
    Whole,
    /// These parts (none where the triangle faces away from the light).
    Cut(Vec<Piece>),
}

/// [`lit_pieces`], the piece itself where nothing hides it from the light: the beam's own parts (a
/// fan of quads) carried back to the image plane would cut it along lines that shade nothing.
pub(crate) fn lit_parts(
    bvh: &FlatBvh,
    triangles: &[Triangle],
    eye: &BeamFrame,
    piece: &Piece,
    light: Vec3,
    stats: &mut BeamStats,
) -> LitParts {
    let Some(prim) = piece.prim else { return LitParts::Cut(Vec::new()) };
    let tri = &triangles[prim as usize];
    let corners: Option<Vec<Vec3>> = piece.section.vertices().iter().map(|&c| point_on_piece(eye, piece, c)).collect();
    let Some(corners) = corners else { return LitParts::Cut(Vec::new()) };
    // The receiving side of the triangle is the one the eye sees; a light on the other side lights
    // nothing of it.
    let mut n = tri.scaled_normal();
    if n.dot(eye.apex - tri.v[0]) < 0.0 {
        n = -n;
    }
    if n.dot(light - tri.v[0]) <= 0.0 {
        return LitParts::Cut(Vec::new());
    }
    // The reference plane is the triangle's own, so that the triangle and its coplanar neighbours lie
    // at depth 1 to rounding and never shadow it; the corners are projected onto it.
    let Some(beam) = BeamFrame::new(light, tri.v[0], n, tri.v[1] - tri.v[0]).and_then(|f| PolyBeam::new(f, &corners))
    else {
        return LitParts::Cut(Vec::new());
    };
    let hits = stats.hit_beams;
    let lit = visible_section(bvh, triangles, &beam, stats);
    if stats.hit_beams == hits {
        // No triangle hit a part of the beam: its parts are the fan it started as.
        return LitParts::Whole;
    }
    LitParts::Cut(
        lit.pieces
            .iter()
            .filter_map(|s| {
                let mut image: Vec<Vec2> = s.vertices().iter().map(|&c| eye.project(lit.frame.point(c))).collect();
                if beam_math::collide::signed_area(&image) < 0.0 {
                    image.reverse();
                }
                Section::from_slice(&image).ok().map(|section| piece.with_section(section))
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::primary_beam::visible_surface;
    use beam_bvh::BuildOptions;

    /// A floor square z = 0 of half-width 4, a square occluder of half-width 1 at z = 1, a light at
    /// z = 2 above the centre: the shadow is the square of half-width 2 (similar triangles), so the
    /// lit area of the floor is 64 − 16 = 48 world units, whatever the eye sees of it.
    #[test]
    fn square_occluder_casts_its_similar_square() {
        let quad = |h: f32, z: f32| {
            [
                Triangle::new(Vec3::new(-h, -h, z), Vec3::new(h, -h, z), Vec3::new(h, h, z)),
                Triangle::new(Vec3::new(-h, -h, z), Vec3::new(h, h, z), Vec3::new(-h, h, z)),
            ]
        };
        let mut tris = quad(4.0, 0.0).to_vec();
        tris.extend(quad(1.0, 1.0));
        let bvh = FlatBvh::build(&tris, &BuildOptions::sah());
        // The eye straight above, looking down past the occluder from z = 10 with a wide window.
        let eye = BeamFrame::new(Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.0, 0.0, 9.0), -Vec3::Z, Vec3::X).unwrap();
        let mut stats = BeamStats::default();
        let pieces = visible_surface(&bvh, &tris, &eye, Vec2::splat(-1.0), Vec2::splat(1.0), &mut stats);
        // Image-plane area → floor area: the floor is 10 units away, the image plane 1 unit.
        let floor_area =
            |ps: &[Piece]| ps.iter().filter(|p| p.prim.is_some_and(|x| x < 2)).map(|p| p.section.area()).sum::<f32>();
        let light = Vec3::new(0.0, 0.0, 2.0);
        let mut lit = Vec::new();
        for p in &pieces {
            lit.extend(lit_pieces(&bvh, &tris, &eye, p, light, &mut stats));
        }
        // Seen floor: 64 − (occluder's 4 units seen from 9 above, covering 4·(10/9)² of floor).
        let seen = floor_area(&pieces) * 100.0;
        assert!((seen - (64.0 - 4.0 * (10.0f32 / 9.0).powi(2))).abs() < 1e-2, "{seen}");
        let lit_area = floor_area(&lit) * 100.0;
        assert!((lit_area - 48.0).abs() < 1e-2, "{lit_area}");
        // The occluder's top faces the light fully: all of what is seen of it is lit.
        let top =
            |ps: &[Piece]| ps.iter().filter(|p| p.prim.is_some_and(|x| x >= 2)).map(|p| p.section.area()).sum::<f32>();
        assert!((top(&lit) - top(&pieces)).abs() < 1e-6);
        assert!(stats.hit_beams > 0);
    }
}
