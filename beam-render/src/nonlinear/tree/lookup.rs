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

use super::{FaceMap, Node, Scattered, Tree};
use crate::BackendError;
use crate::nonlinear::beam_tree::{Beam, LOOKUP};
use crate::nonlinear::renderer::{BeamRenderer, LookupJob};
use crate::nonlinear::texture::{BeamTexture, ShadePoint};
use crate::parallel::piece_len;
use crate::specular::specular_rays;
use beam_math::glam::Vec3;
use beam_math::nonlinear::Projection;
use rayon::prelude::*;

/// A point to composite ([`Tree::composite`]), made by [`Tree::to_composite`]: the child beams of
/// the faces of its level, the point and its located face.
#[derive(Clone, Copy)]
pub(crate) struct ToComposite<'a> {
    pub(crate) children: &'a FaceMap<Scattered>,
    pub(crate) point: ShadePoint,
    pub(crate) located: Option<(usize, Vec3)>,
    /// Under a coarse face with child beams, the unit directions of the point's own scattered
    /// rays (reflected, refracted) that its lookups follow ([`reproject`]), found once for the
    /// lookups and the composite (on the mirror teapot three times a point before).
    pub(crate) own: Option<[Option<Vec3>; 2]>,
}

/// One lookup of a composite ([`Tree::composite`]'s `at`): a job for a backend (the next of
/// [`Asks::jobs`]), or its answer known without one (the face's own coordinates, 0 outside: no
/// child beam, no scattered ray, or a bump-mapped beam).
#[derive(Clone, Copy)]
enum Ask {
    Job,
    Known((Vec3, f32)),
}

/// The lookups of one face of a composite: in its reflection beam, and in its refraction beam.
#[derive(Clone, Copy)]
struct FaceAsks {
    reflected: Ask,
    refracted: Option<Ask>,
}

/// The lookups of a list of points, flat: per point how many faces ask, the faces' asks in order,
/// and the jobs among them in order. (A list per point was an allocation per point.)
#[derive(Default)]
struct Asks {
    lens: Vec<u32>,
    faces: Vec<FaceAsks>,
    jobs: Vec<LookupJob>,
}

/// The answers for one face of a composite ([`FaceAsks`]): coordinates on the child beam's base
/// and how far outside it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceAnswer {
    pub(crate) reflected: (Vec3, f32),
    pub(crate) refracted: Option<(Vec3, f32)>,
}

/// A backend's answers to the lookups of a list of points ([`Tree::lookups`]): per point, those of
/// its composite's faces with child beams in the composite's order (its located face's first), as
/// many as were made: the located faces' answers, then the other faces' (for the points whose
/// first lookup lay outside its beam's base), kept apart rather than copied into one list.
#[derive(Default)]
pub(crate) struct Lookups {
    located: Answers,
    others: Answers,
}

impl Lookups {
    /// The answers of point `k` in order (none where there are none: the host looks it up).
    pub(crate) fn of(&self, k: usize) -> impl Iterator<Item = &FaceAnswer> {
        self.located.of(k).iter().chain(self.others.of(k))
    }
}

/// One round of answers: per point, a span of `answers`.
#[derive(Default)]
struct Answers {
    spans: Vec<(u32, u32)>,
    answers: Vec<FaceAnswer>,
}

impl Answers {
    /// The answers of point `k` (empty where there are none).
    fn of(&self, k: usize) -> &[FaceAnswer] {
        self.spans.get(k).map_or(&[], |&(start, len)| &self.answers[start as usize..(start + len) as usize])
    }

    /// Per point, its faces' asks answered: the jobs' answers `answers` in order.
    fn answered(asks: &Asks, answers: &[(Vec3, f32)]) -> Self {
        let mut out =
            Self { spans: Vec::with_capacity(asks.lens.len()), answers: Vec::with_capacity(asks.faces.len()) };
        let mut jobs = answers.iter();
        let mut answer = |a: Ask| match a {
            Ask::Job => jobs.next().copied(),
            Ask::Known(k) => Some(k),
        };
        let mut faces = &asks.faces[..];
        for &n in &asks.lens {
            let (mine, rest) = faces.split_at(n as usize);
            faces = rest;
            let start = out.answers.len() as u32;
            for f in mine {
                // A face left unanswered ends the point's answers: the host looks up the rest.
                let Some(reflected) = answer(f.reflected) else { break };
                let refracted = match f.refracted.map(&mut answer) {
                    Some(None) => break,
                    r => r.flatten(),
                };
                out.answers.push(FaceAnswer { reflected, refracted });
            }
            out.spans.push((start, out.answers.len() as u32 - start));
        }
        out
    }
}

impl Asks {
    /// The lists of `pieces` one after another (each list made at its full length once).
    fn concat(pieces: Vec<Self>) -> Self {
        let total = |len: fn(&Self) -> usize| pieces.iter().map(len).sum::<usize>();
        let mut all = Self {
            lens: Vec::with_capacity(total(|p| p.lens.len())),
            faces: Vec::with_capacity(total(|p| p.faces.len())),
            jobs: Vec::with_capacity(total(|p| p.jobs.len())),
        };
        for p in pieces {
            all.lens.extend_from_slice(&p.lens);
            all.faces.extend_from_slice(&p.faces);
            all.jobs.extend_from_slice(&p.jobs);
        }
        all
    }
}

impl Tree<'_> {
    /// `point`, located at `located` (its S-mesh face and barycentric coordinates there) among
    /// faces with child beams `children`, ready to composite: with its own scattered rays where
    /// its face is coarse and has child beams.
    pub(crate) fn to_composite<'a>(
        &self,
        children: &'a FaceMap<Scattered>,
        point: ShadePoint,
        located: Option<(usize, Vec3)>,
    ) -> ToComposite<'a> {
        let own = located
            .filter(|&(face, _)| self.smesh.is_coarse(face) && children.contains_key(&face))
            .and_then(|_| specular_rays(self.scene, 0.0, point.prim, point.p, point.d))
            .map(|rays| rays.map(|r| r.map(|(ray, _)| ray.direction.normalize())));
        ToComposite { children, point, located, own }
    }

    /// Add to `out` the lookups of `point`'s composite ([`Tree::composite`]) in the child beams
    /// (nodes of `next`) of its located face, or with `others` of the other faces its triangle
    /// maps to in the composite's order, where the located face is coarse and has child beams and
    /// the point a reflected ray; none where the composite looks nothing up.
    fn lookup_asks(&self, next: &[Node], to: &ToComposite<'_>, others: bool, out: &mut Asks) {
        let (Some((face, at)), Some(own)) = (to.located, to.own) else { return };
        if own[0].is_none() {
            return;
        }
        let (far, p) = (self.far, to.point.p);
        // `at` of the composite: a job where `reproject` looks up, else its known answer.
        let mut ask = |child: usize, truth: Option<Vec3>, w: Vec3| match (next.get(child), truth) {
            (Some(n), Some(truth)) if !n.bumped && truth.is_finite() => {
                out.jobs.push(LookupJob { beam: child as u32, p, truth, w, far });
                Ask::Job
            }
            _ => Ask::Known((w, 0.0)),
        };
        let candidates = self.smesh.candidates(to.point.prim).iter().map(|&g| g as usize).filter(|&g| g != face);
        // The located face alone, or the others alone.
        let faces = (!others).then_some(face).into_iter().chain(candidates.filter(|_| others));
        for g in faces {
            let Some(c) = to.children.get(&g) else { continue };
            // The located face's coordinates were found with it (`SMesh::locate`).
            let w = if g == face { at } else { self.smesh.faces[g].barycentric(p) };
            let reflected = ask(c.reflected, own[0], w);
            let refracted = c.refracted.map(|t| ask(t, own[1], w));
            out.faces.push(FaceAsks { reflected, refracted });
        }
    }

    /// Whether `renderer` makes the lookups of composites into child beams `next`
    /// ([`Tree::lookups`]): it looks up, the S mesh has coarse faces and there are child beams.
    pub(crate) fn looks_up(&self, renderer: &dyn BeamRenderer, next: &[Node]) -> bool {
        renderer.looks_up() && self.smesh.coarse_faces() > 0 && !next.is_empty()
    }

    /// The lookups of `points` ([`Tree::lookup_asks`]) by `renderer` where it looks up
    /// ([`Tree::looks_up`]; the GPU), the beams of `next` with their textures: first each point's
    /// located face's, then the other faces' for the points whose first reflection lookup lies
    /// outside its beam's base. Empty where it does not, and each composite looks up on the host.
    pub(crate) fn lookups(
        &self,
        renderer: &dyn BeamRenderer,
        next: &[Node],
        points: &[Option<ToComposite<'_>>],
    ) -> Result<Lookups, BackendError> {
        if !self.looks_up(renderer, next) {
            return Ok(Lookups::default());
        }
        let beams: Vec<(&Beam, &BeamTexture)> = next.iter().map(|n| (&*n.beam, &n.tex)).collect();
        let piece = piece_len(points.len());
        let asks_of = |others: bool, wanted: &(dyn Fn(usize) -> bool + Sync)| -> Asks {
            let pieces = points.par_chunks(piece).enumerate().map(|(c, chunk)| {
                // Room for a face and a job a point (a point under a coarse face asks its located
                // face first: one reflection lookup, and a refraction through glass).
                let n = chunk.len();
                let mut asks =
                    Asks { lens: Vec::with_capacity(n), faces: Vec::with_capacity(n), jobs: Vec::with_capacity(n) };
                for (j, p) in chunk.iter().enumerate() {
                    let before = asks.faces.len();
                    if let Some(p) = p
                        && wanted(c * piece + j)
                    {
                        self.lookup_asks(next, p, others, &mut asks);
                    }
                    asks.lens.push((asks.faces.len() - before) as u32);
                }
                asks
            });
            Asks::concat(pieces.collect())
        };
        let answer = |asks: &Asks| -> Result<Option<Answers>, BackendError> {
            Ok(renderer.child_lookups(&beams, &asks.jobs)?.map(|answers| Answers::answered(asks, &answers)))
        };
        let Some(located) = answer(&asks_of(false, &|_| true))? else { return Ok(Lookups::default()) };
        let outside = |k: usize| located.of(k).first().is_some_and(|a| a.reflected.1 > 0.0);
        let others = answer(&asks_of(true, &outside))?.unwrap_or_default();
        Ok(Lookups { located, others })
    }
}

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
    use crate::nonlinear::texture::TexelHit;
    use beam_math::nonlinear::NonlinearBeam;

    #[test]
    fn finds_the_texel_whose_ray_reaches_the_same_point() {
        // A beam fanning out of the unit triangle in z = 0; every texel's ray hits the plane z = 10.
        let base = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let dirs = [Vec3::new(-0.1, -0.1, 1.0), Vec3::new(0.2, -0.1, 1.0), Vec3::new(-0.1, 0.2, 1.0)];
        let beam = Beam::S1(NonlinearBeam::s1(base, dirs).unwrap());
        let size = 32;
        let mut tex = BeamTexture {
            size,
            hits: vec![None; 1024],
            points: Vec::new(),
            fits: Vec::new(),
            triangles_after_culling: 0,
            texels_tested: 0,
        };
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
