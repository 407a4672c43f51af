//! Where a point of a specular surface looks its child beams up (000 §7.3's final composite): on a
//! face that is a scene triangle, at the point's own barycentric coordinates (the texture mapped
//! onto the surface, as 000 does); under a coarse S-mesh face (000 §7.1), where the child beam's
//! ray meets the point's own scattered ray. A coarse face's S^n rays interpolate the directions at
//! its three vertices, which stray from the fine surface's reflections inside the face by about
//! twice the error of its interpolated normals (degrees on a face of a few hundred of the fine
//! triangles); the fine mesh is rendered, so each of its points knows its true scattered ray
//! (about its own interpolated normal, as the ray-traced reference scatters it), and the texel to
//! read is the one whose ray reaches what that ray reaches: the projection (000 §5) onto the beam
//! of the point at the depth the beam's texel there sees.

use beam_math::glam::Vec3;
use beam_math::nonlinear::Projection;
use beam_scene::nonlinear::{Beam, BeamTexture, LOOKUP};

/// Barycentric coordinates on `beam`'s base where point `p` of the fine surface, looked up at `w`
/// by its place on the face, reads `beam`'s texture `tex` for its own scattered unit direction
/// `truth`: twice, the depth `s` of the hit of the texel at the current coordinates (`far`, the
/// scene's size, where its ray leaves the scene), then the projection of `p + s·truth` onto the
/// beam (000 §5, polished as [`LOOKUP`] says), clamped to the base. The first projection
/// starts Newton's method from `w` at parameter `s` (the point lies about `s` along the beam's ray
/// there), the second from the first's answer ([`Beam::project_in`] with a guess). Returns the
/// coordinates and how far outside the base the last projection lay (its most negative
/// coordinate, negated; 0 inside); `w` and 0 when a projection fails.
#[must_use]
pub fn reproject(beam: &Beam, tex: &BeamTexture, p: Vec3, truth: Vec3, w: Vec3, far: f32) -> (Vec3, f32) {
    if matches!(beam, Beam::Bumped(_)) || !truth.is_finite() {
        return (w, 0.0); // a bump map tilts the rays texel by texel: the face's own coordinates
    }
    let (mut at, mut outside, mut guess) = (w, 0.0, None);
    for _ in 0..2 {
        let s = depth(beam, tex, at).map_or(far, |x| x.distance(p));
        let start = guess.unwrap_or(Projection { bary: w, t: s });
        match beam.project_in(p + truth * s, LOOKUP, Some(start)) {
            Some(next) if next.bary.is_finite() => {
                (at, outside, guess) = (clamped(next.bary), (-next.bary.min_element()).max(0.0), Some(next));
            }
            _ => break,
        }
    }
    (at, outside)
}

/// The hit point of the texel of `tex` nearest barycentric coordinates `w`, if its ray hits.
fn depth(beam: &Beam, tex: &BeamTexture, w: Vec3) -> Option<Vec3> {
    let n = tex.size;
    let cell = |c: f32| ((c * n as f32).floor().max(0.0) as u32).min(n.saturating_sub(1));
    let (mut x, mut y) = (cell(w.y), cell(w.z));
    while !tex.in_region(x, y) && x + y > 0 {
        if x >= y { x -= 1 } else { y -= 1 }
    }
    let hit = tex.hits.get((y * n + x) as usize).copied().flatten()?;
    Some(beam.ray_at(tex.barycentric(x, y)).at(hit.t))
}

/// `w` moved onto the base triangle (negative coordinates to 0, then scaled to sum 1).
fn clamped(w: Vec3) -> Vec3 {
    let w = w.max(Vec3::ZERO);
    let sum = w.x + w.y + w.z;
    if sum > 0.0 { w / sum } else { Vec3::splat(1.0 / 3.0) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_math::nonlinear::NonlinearBeam;
    use beam_scene::nonlinear::TexelHit;

    #[test]
    fn finds_the_texel_whose_ray_reaches_the_same_point() {
        // A beam fanning out of the unit triangle in z = 0; every texel's ray hits the plane z = 10.
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let dirs = [Vec3::new(-0.1, -0.1, 1.0), Vec3::new(0.2, -0.1, 1.0), Vec3::new(-0.1, 0.2, 1.0)];
        let beam = Beam::S1(NonlinearBeam::s1(base, dirs).unwrap());
        let size = 32;
        let mut tex = BeamTexture { size, hits: vec![None; 1024], triangles_after_culling: 0, texels_tested: 0 };
        for y in 0..size {
            for x in 0..size {
                let ray = beam.ray_at(tex.barycentric(x, y));
                tex.hits[(y * size + x) as usize] =
                    Some(TexelHit { prim: 0, t: (10.0 - ray.origin.z) / ray.direction.z });
            }
        }
        // A point of the base whose own ray leans 0.05 more towards +x than the beam's there.
        let w = Vec3::new(0.5, 0.25, 0.25);
        let p = base[1] * 0.25 + base[2] * 0.25;
        let truth = (beam.ray_at(w).direction.normalize() + Vec3::new(0.05, 0.0, 0.0)).normalize();
        let target = p + truth * (10.0 / truth.z);
        let (at, outside) = reproject(&beam, &tex, p, truth, w, 100.0);
        assert_eq!(outside, 0.0);
        let reached = beam.ray_at(at);
        let on_plane = reached.at((10.0 - reached.origin.z) / reached.direction.z);
        assert!(on_plane.distance(target) < 0.05, "{on_plane} vs {target}");
        let plain = beam.ray_at(w);
        let plain = plain.at((10.0 - plain.origin.z) / plain.direction.z);
        assert!(on_plane.distance(target) < 0.1 * plain.distance(target), "{plain}");
        // A point whose own ray is the beam's keeps its coordinates.
        let (same, _) = reproject(&beam, &tex, p, beam.ray_at(w).direction.normalize(), w, 100.0);
        assert!((same - w).abs().max_element() < 1e-3, "{same}");
    }
}
