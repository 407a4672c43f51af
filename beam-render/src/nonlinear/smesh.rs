//! The S mesh of 000 §7.1: the base triangles of the secondary beams, with smooth vertex normals.
//! By default it is the specular triangles themselves; a scene may ask for a coarse one
//! ([`SMeshPlan`](beam_scene::scene::SMeshPlan)), given or simplified, which the fine triangles are
//! mapped onto ([`SMesh::locate`]).

use super::coarse::{CoarseFaces, Group, coarse_faces};
use super::face::{Exclude, SFace, sliver_face};
use super::simplify::simplified;
use beam_math::Triangle;
use beam_math::collide::closest_point_on_triangle;
use beam_math::glam::Vec3;
use beam_scene::scene::{SMeshSource, Scene};
use std::ops::Range;

/// What a face's beams skip: ranges into [`SMesh::lists`], and the thickness of the surface under
/// the face.
#[derive(Clone, Debug, Default)]
struct Under {
    patch: Range<usize>,
    ring: Range<usize>,
    thickness: f32,
    /// Its vertex normals spread too far for beams ([`MAX_NORMAL_SPREAD`]).
    rays_only: bool,
}

/// Cosine of the widest angle between the vertex normals of a coarse face that spawns beams (90°):
/// a face folded over a thin part (a simplified handle's tube, normals 120° apart) has beams wider
/// than a half-space, whose bounding triangles (000 Algs. 3–4) were seen to miss texels; its points
/// are traced by rays instead. Fine faces always spawn beams.
pub const MAX_NORMAL_SPREAD: f32 = 0.5;

/// The S mesh of every mirror and glass surface of a scene, and the map from the scene's
/// triangles onto it.
#[derive(Clone, Debug, Default)]
pub struct SMesh {
    /// Its triangles.
    pub faces: Vec<SFace>,
    /// Per scene triangle, its candidates' range in `candidates` (empty for a triangle without
    /// S faces): a dense table, since it is looked up per pixel and per texel.
    of_prim: Vec<Range<u32>>,
    /// Candidate S faces of the scene triangles.
    candidates: Vec<u32>,
    /// Per face: what its beams skip (empty ranges for a face that is a scene triangle).
    under: Vec<Under>,
    /// Sorted lists of scene triangles (patches and rings).
    lists: Vec<u32>,
    /// Faces of coarse S meshes.
    coarse: usize,
}

impl SMesh {
    /// The S mesh of the scene's mirror and glass triangles: the triangles themselves (the scene
    /// gives specular surfaces at S-mesh resolution, slivers left out) with the scene's smooth
    /// vertex normals. The reference renderer's, and [`Self::of`]'s default.
    #[must_use]
    pub fn specular(scene: &Scene) -> Self {
        let mut s = Self::default();
        s.add_fine(scene, &specular_prims(scene));
        s
    }

    /// The S mesh `scene.smesh` asks for (000 §7.1): per specular surface, its own triangles
    /// ([`Self::specular`]), a coarse mesh given beside it, or its simplification by meshoptimizer
    /// to a face count or an error. A coarse S mesh's vertex normals are the fine mesh's smooth
    /// normals at (or nearest to) its vertices, so the S^n parameterization carries the curvature;
    /// every fine triangle maps to the coarse faces its points lie nearest ([`Self::locate`]).
    #[must_use]
    pub fn of(scene: &Scene) -> Self {
        if scene.smesh.is_fine() {
            return Self::specular(scene);
        }
        let mut s = Self::default();
        // Specular triangles (slivers too: they map onto coarse faces) by source.
        let specular = (0..scene.triangles.len() as u32).filter(|&p| scene.smooth_normals.contains_key(&p));
        let (mut fine, mut rest) = (Vec::new(), Vec::new());
        let mut parts: Vec<Vec<u32>> = vec![Vec::new(); scene.smesh.parts.len()];
        for p in specular {
            match scene.smesh.parts.iter().position(|(r, _)| r.contains(&p)) {
                Some(k) => parts[k].push(p),
                None => rest.push(p),
            }
        }
        let mut groups: Vec<Group> = Vec::new();
        for ((_, source), prims) in scene.smesh.parts.iter().zip(parts) {
            match source {
                SMeshSource::Fine => fine.extend(prims),
                SMeshSource::Given(mesh) if !prims.is_empty() => groups.push(Group {
                    prims,
                    positions: mesh.positions.clone(),
                    normals: None,
                    indices: mesh.indices.clone(),
                }),
                SMeshSource::Given(_) => {}
                SMeshSource::Simplified(target) => groups.extend(simplified(scene, &prims, *target)),
            }
        }
        match scene.smesh.rest {
            Some(target) => groups.extend(simplified(scene, &rest, target)),
            None => fine.extend(rest),
        }
        fine.retain(|&p| !sliver(scene, p));
        fine.sort_unstable();
        s.add_fine(scene, &fine);
        for g in groups {
            let before = s.faces.len();
            match coarse_faces(scene, &g) {
                Some(c) => s.add_coarse(&g.prims, c),
                // No usable face (a mesh of slivers): its triangles are their own S mesh.
                None => s.add_fine(scene, &g.prims.into_iter().filter(|&p| !sliver(scene, p)).collect::<Vec<_>>()),
            }
            s.coarse += s.faces.len() - before;
        }
        s
    }

    /// False for a coarse face whose vertex normals spread wider than [`MAX_NORMAL_SPREAD`]: it
    /// spawns no beams, and the points under it are traced by rays.
    #[must_use]
    pub fn spawns_beams(&self, face: usize) -> bool {
        self.under.get(face).is_none_or(|u| !u.rays_only)
    }

    /// Coarse faces that spawn no beams ([`Self::spawns_beams`]).
    #[must_use]
    pub fn faces_by_rays(&self) -> usize {
        self.under.iter().filter(|u| u.rays_only).count()
    }

    /// True when face `face` belongs to a coarse S mesh (it stands for fine triangles under it).
    #[must_use]
    pub fn is_coarse(&self, face: usize) -> bool {
        self.under.get(face).is_some_and(|u| !u.patch.is_empty())
    }

    /// Faces of coarse S meshes (0 when the S mesh is the specular triangles themselves).
    #[must_use]
    pub fn coarse_faces(&self) -> usize {
        self.coarse
    }

    /// The S face that point `p` of scene triangle `prim` maps to, and its barycentric coordinates
    /// there (projected onto the face's plane): the triangle's own face, or on a coarse S mesh the
    /// face nearest `p` among those the triangle's points lie nearest (a point just outside every
    /// face takes the nearest, its coordinates slightly outside). `None` for a triangle without an
    /// S face (not specular, or a sliver traced by rays).
    #[must_use]
    pub fn locate(&self, prim: u32, p: Vec3) -> Option<(usize, Vec3)> {
        let face = match self.candidates(prim) {
            [] => return None,
            [f] => *f as usize,
            candidates => self.nearest(candidates, p)? as usize,
        };
        Some((face, self.faces[face].barycentric(p)))
    }

    /// [`Self::locate`] where a backend chose `face` ([`TexelPoint::face`](super::TexelPoint):
    /// beam-gpu's kept levels, in f32 as here): its coordinates there when it is one of the
    /// candidates of `prim`, else the face `locate` chooses (a backend's choice is never taken on
    /// trust; [`u32::MAX`] for none made).
    #[must_use]
    pub fn locate_on(&self, prim: u32, face: u32, p: Vec3) -> Option<(usize, Vec3)> {
        match self.faces.get(face as usize) {
            Some(f) if self.candidates(prim).contains(&face) => Some((face as usize, f.barycentric(p))),
            _ => self.locate(prim, p),
        }
    }

    /// The face of `candidates` nearest `p`, the first of equally near ones: the least distance
    /// `d` by `f32::total_cmp`, as `min_by` keeps it. Each candidate's squared distance once;
    /// its root only where it may be nearer than the nearest so far (the root is monotone, so a
    /// root below the nearest's needs a square below it). The mirror teapot's eye view locates
    /// 182 K points a frame, about five candidates each.
    fn nearest(&self, candidates: &[u32], p: Vec3) -> Option<u32> {
        let squared =
            |f: u32| closest_point_on_triangle(p, &Triangle { v: self.faces[f as usize].v }).distance_squared(p);
        let (&first, rest) = candidates.split_first()?;
        let (mut best, mut best_squared) = (first, squared(first));
        for &f in rest {
            let s = squared(f);
            // `d < best` as `total_cmp` orders the roots; for numbers, only where `s < best_squared`.
            let nearer = if s.is_nan() || best_squared.is_nan() {
                s.sqrt().total_cmp(&best_squared.sqrt()).is_lt()
            } else {
                s < best_squared && s.sqrt() < best_squared.sqrt()
            };
            if nearer {
                (best, best_squared) = (f, s);
            }
        }
        Some(best)
    }

    /// The faces scene triangle `prim` may map to (those its points lie nearest; its own face on
    /// a fine S mesh), ascending.
    #[must_use]
    pub fn candidates(&self, prim: u32) -> &[u32] {
        let r = self.of_prim.get(prim as usize).cloned().unwrap_or_default();
        &self.candidates[r.start as usize..r.end as usize]
    }

    /// What the beams off face `face` skip ([`Exclude`]): the scene triangle it is, or on a coarse
    /// S mesh the fine triangles under it, and its neighbours' as the surface meeting itself.
    #[must_use]
    pub fn exclude(&self, face: usize) -> Exclude<'_> {
        let u = self.under.get(face).cloned().unwrap_or_default();
        Exclude {
            prim: self.faces.get(face).map_or(u32::MAX, |f| f.prim),
            patch: &self.lists[u.patch],
            ring: &self.lists[u.ring],
            thickness: u.thickness,
        }
    }

    /// Append the specular triangles `prims` as faces of their own.
    fn add_fine(&mut self, scene: &Scene, prims: &[u32]) {
        for &p in prims {
            let n = scene.smooth_normals.get(&p).copied().unwrap_or([scene.normal(p); 3]);
            self.push_candidates(p, &[self.faces.len() as u32]);
            self.faces.push(SFace { prim: p, v: scene.triangles[p as usize].v, n, normal: scene.normal(p) });
            self.under.push(Under::default());
        }
    }

    /// Append the faces of a coarse mesh over the specular triangles `prims` (a group's, in its
    /// order) and map those triangles onto them.
    fn add_coarse(&mut self, prims: &[u32], c: CoarseFaces) {
        let first = self.faces.len() as u32;
        for (&p, faces) in prims.iter().zip(&c.candidates) {
            self.push_candidates(p, &faces.iter().map(|&f| first + f).collect::<Vec<_>>());
        }
        for f in c.faces {
            self.push_coarse(f.face, &f.patch, &f.ring, f.thickness);
        }
    }

    /// Record the candidate faces of scene triangle `prim`.
    fn push_candidates(&mut self, prim: u32, faces: &[u32]) {
        let start = self.candidates.len() as u32;
        self.candidates.extend_from_slice(faces);
        if self.of_prim.len() <= prim as usize {
            self.of_prim.resize(prim as usize + 1, 0..0);
        }
        self.of_prim[prim as usize] = start..self.candidates.len() as u32;
    }

    /// Append a coarse face with its patch and ring of scene triangles (sorted) and thickness.
    fn push_coarse(&mut self, face: SFace, patch: &[u32], ring: &[u32], thickness: f32) {
        let at = self.lists.len();
        self.lists.extend_from_slice(patch);
        self.lists.extend_from_slice(ring);
        let (p, r) = (at..at + patch.len(), at + patch.len()..self.lists.len());
        let n = face.n;
        let rays_only = n[0].dot(n[1]).min(n[1].dot(n[2])).min(n[2].dot(n[0])) < MAX_NORMAL_SPREAD;
        self.faces.push(face);
        self.under.push(Under { patch: p, ring: r, thickness, rays_only });
    }
}

/// True for a sliver: narrower than 1e-4 of its longest edge (a sphere's pole triangles make no
/// beam worth having; the few pixels on them are traced by rays).
fn sliver(scene: &Scene, p: u32) -> bool {
    sliver_face(&scene.triangles[p as usize].v)
}

/// The specular triangles that are not slivers, ascending.
fn specular_prims(scene: &Scene) -> Vec<u32> {
    let mut prims: Vec<u32> = scene.smooth_normals.keys().copied().filter(|&p| !sliver(scene, p)).collect();
    prims.sort_unstable();
    prims
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_scene::scene::{Material, SMeshPlan, Simplify};

    /// Every fine specular triangle's centre maps to a face it lies under: within the face's
    /// thickness of its plane and in its patch; the face's normals on the fine surface's side.
    fn check_mapping(scene: &Scene, s: &SMesh) {
        for p in 0..scene.triangles.len() as u32 {
            if !scene.smooth_normals.contains_key(&p) || sliver(scene, p) {
                continue;
            }
            let c = (scene.triangles[p as usize].v.iter().sum::<Vec3>()) / 3.0;
            let (face, w) = s.locate(p, c).unwrap();
            let f = &s.faces[face];
            let ex = s.exclude(face);
            assert!(ex.skips(p), "triangle {p} not in the patch of face {face}");
            assert!((c - f.v[0]).dot(f.normal).abs() <= ex.thickness + 1e-3, "{p}");
            // The nearest of its triangle's candidates (a needle's coordinates may lie far outside).
            let d = |g: u32| closest_point_on_triangle(c, &Triangle { v: s.faces[g as usize].v }).distance(c);
            assert!(s.candidates(p).iter().all(|&g| d(g) >= d(face as u32)), "{p}: {w}");
            assert!(f.normal.dot(scene.normal(p)) > 0.0, "{p}");
            assert_eq!(scene.material(f.prim), scene.material(p));
        }
    }

    #[test]
    fn simplified_teapot_maps_every_triangle() {
        let mut scene = beam_scene::scene::showcase::mirror_teapot(12, 8);
        let fine = SMesh::of(&scene);
        assert_eq!(fine.coarse_faces(), 0);
        assert_eq!(fine.faces.len(), SMesh::specular(&scene).faces.len());
        scene.smesh = SMeshPlan { parts: Vec::new(), rest: Some(Simplify::Faces(300)) };
        let s = SMesh::of(&scene);
        assert!((200..=400).contains(&s.coarse_faces()), "{} coarse faces", s.coarse_faces());
        assert_eq!(s.coarse_faces(), s.faces.len());
        check_mapping(&scene, &s);
        // The S-mesh vertices are fine vertices, so their normals are the fine mesh's there.
        let fine_normal = |v: Vec3| {
            fine.faces.iter().find_map(|f| (0..3).find(|&i| f.v[i] == v).map(|i| f.n[i])).unwrap_or(Vec3::ZERO)
        };
        let close = s.faces.iter().flat_map(|f| (0..3).map(move |i| (f.v[i], f.n[i])));
        let agree = close.clone().filter(|&(v, n)| fine_normal(v).dot(n) > 0.999).count();
        assert!(agree * 10 >= close.count() * 9, "{agree}");
        // Rings are the neighbours' patches, outside the face's own.
        let ex = s.exclude(0);
        assert!(!ex.ring.is_empty() && ex.ring.iter().all(|p| ex.patch.binary_search(p).is_err()));
    }

    #[test]
    fn given_sphere_takes_the_fine_normals() {
        let mut scene = beam_scene::scene::load("mirror-glass").unwrap();
        let mirror: Vec<u32> = (0..scene.triangles.len() as u32)
            .filter(|&p| matches!(scene.material(p), Material::Mirror { .. }))
            .collect();
        let range = mirror[0]..mirror[mirror.len() - 1] + 1;
        assert_eq!(range.len(), mirror.len(), "the mirror sphere's triangles are consecutive");
        // A coarse sphere of the same centre, radius 95 (the fine one's 90), wound inwards.
        let c = Vec3::new(185.0, 90.0, 170.0);
        let mut coarse = beam_scene::mesh::sphere(c, 95.0, 6, 12);
        for t in &mut coarse.indices {
            t.swap(1, 2);
        }
        scene.smesh.parts.push((range, SMeshSource::Given(coarse)));
        let s = SMesh::of(&scene);
        assert!((100..=144).contains(&s.coarse_faces()), "{}", s.coarse_faces());
        for f in s.faces.iter().filter(|f| matches!(scene.material(f.prim), Material::Mirror { .. })) {
            // Turned outwards; vertex normals radial (the fine sphere's at the nearest point).
            assert!(f.normal.dot(f.v[0] - c) > 0.0, "{f:?}");
            assert!(!sliver_face(&f.v), "{f:?}");
            for i in 0..3 {
                assert!(f.n[i].dot((f.v[i] - c).normalize()) > 0.999, "{}", f.n[i]);
            }
        }
        check_mapping(&scene, &s);
    }

    #[test]
    fn sphere_normals_are_radial() {
        let scene = beam_scene::scene::load("mirror-glass").unwrap();
        let s = SMesh::specular(&scene);
        assert!(!s.faces.is_empty());
        // The mirror sphere of the built-in scene: centre (185, 90, 170). Max's weights give a
        // tessellated sphere's exact radial normals.
        let c = Vec3::new(185.0, 90.0, 170.0);
        for f in s.faces.iter().filter(|f| matches!(scene.material(f.prim), Material::Mirror { .. })) {
            for i in 0..3 {
                let radial = (f.v[i] - c).normalize();
                assert!(f.n[i].dot(radial).abs() > 0.9999, "{} {} {}", f.n[i].dot(radial), f.v[i], f.prim);
            }
            // Barycentric coordinates round-trip (slivers at the poles are ill-conditioned).
            if (f.v[1] - f.v[0]).cross(f.v[2] - f.v[0]).length() > 10.0 {
                let w = f.barycentric(0.2 * f.v[0] + 0.3 * f.v[1] + 0.5 * f.v[2]);
                assert!((w - Vec3::new(0.2, 0.3, 0.5)).abs().max_element() < 1e-3, "{w}");
            }
        }
    }

    /// `nearest` picks what the least distance by `total_cmp` picks (the first of equal ones),
    /// on points of a coarse teapot's triangles and off them, and on faces that tie.
    #[test]
    fn nearest_is_the_least_distance() {
        let mut scene = beam_scene::scene::showcase::mirror_teapot(12, 8);
        scene.smesh = SMeshPlan { parts: Vec::new(), rest: Some(Simplify::Faces(300)) };
        let s = SMesh::of(&scene);
        let least = |candidates: &[u32], p: Vec3| {
            let d = |f: u32| closest_point_on_triangle(p, &Triangle { v: s.faces[f as usize].v }).distance(p);
            candidates.iter().map(|&f| (d(f), f)).min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, f)| f)
        };
        let mut checked = 0;
        for prim in 0..scene.triangles.len() as u32 {
            let candidates = s.candidates(prim);
            if candidates.len() < 2 {
                continue;
            }
            let [a, b, c] = scene.triangles[prim as usize].v;
            for k in 0..20 {
                let (u, v) = ((k % 5) as f32 / 5.0, (k / 5) as f32 / 5.0);
                let off = scene.normal(prim) * (k as f32 - 10.0) * 0.01;
                let p = a + u * (b - a) + v * (1.0 - u) * (c - a) + off;
                assert_eq!(s.nearest(candidates, p), least(candidates, p), "{prim} {p}");
                checked += 1;
            }
            // A face listed twice ties with itself: the first is kept.
            let twice = [candidates[1], candidates[0], candidates[1]];
            assert_eq!(s.nearest(&twice, a), least(&twice, a));
        }
        assert!(checked > 1000, "{checked} points");
    }

    /// A backend's choice of face is taken where it is one of the triangle's candidates, and
    /// replaced by `locate`'s where it is not.
    #[test]
    fn locate_on_takes_only_candidates() {
        let mut scene = beam_scene::scene::showcase::mirror_teapot(12, 8);
        scene.smesh = SMeshPlan { parts: Vec::new(), rest: Some(Simplify::Faces(300)) };
        let s = SMesh::of(&scene);
        let prim = (0..scene.triangles.len() as u32).find(|&p| s.candidates(p).len() >= 2).unwrap();
        let p = scene.triangles[prim as usize].v.iter().sum::<Vec3>() / 3.0;
        for &g in s.candidates(prim) {
            assert_eq!(s.locate_on(prim, g, p), Some((g as usize, s.faces[g as usize].barycentric(p))));
        }
        let other = (0..s.faces.len() as u32).find(|g| !s.candidates(prim).contains(g)).unwrap();
        for g in [other, u32::MAX] {
            assert_eq!(s.locate_on(prim, g, p), s.locate(prim, p));
        }
        // A triangle without S faces has none, whatever the backend says.
        let plain = (0..scene.triangles.len() as u32).find(|&p| s.candidates(p).is_empty()).unwrap();
        assert_eq!(s.locate_on(plain, 0, p), None);
    }
}
