//! The nonlinear renderer (000 §7): the beam tree over the S mesh of every mirror and glass surface.
//! The eye sees the scene directly; each specular S-mesh face it sees spawns the level-1 beams
//! (mirror reflection; refraction by Snell's law too for glass; S1 or S3 over the vertex normals),
//! rendered into their texel regions (Algs. 1–2). A texel of a level-k beam that hits another
//! specular face spawns that face's level-(k+1) beams, whose directions at the face's vertices are
//! the parent beam's rays through them (projection, 000 §5, extrapolated past the parent's base).
//! Radiance flows back up (`radiance_flow.rs`): every texel and pixel on a specular face is
//! textured from its face's child beams, weighted by Fresnel for glass. The tree is built level by
//! level (000 §7.3's per-level atlases), each level's beams rendered in one batch by a
//! [`BeamRenderer`] (the CPU's, or a GPU's atlases in beam-gpu), then shaded deepest level first;
//! bounces past the last level are traced by rays. The reference (`reference.rs`) traces the same surfaces with rays about the
//! interpolated (Phong) normals.

use super::source::{from_eye, through};
use super::{FaceMap, Node, Scattered, Tree, TreeBeam, TreeMemos};
use crate::BackendError;
use crate::nonlinear::beam_tree::{Beam, Degree, child_beams};
use crate::nonlinear::error::NonlinearError;
use crate::nonlinear::fit::Fit;
use crate::nonlinear::renderer::{BeamRenderer, KeepLevel, KeptFrame, KeptTotals, LevelLayout};
use crate::nonlinear::settings::MAX_TREE_BEAMS;
use crate::nonlinear::stages::StageClock;
use crate::nonlinear::texture::{BeamJob, BeamTexture, TexelPoint, region_size};
use beam_math::glam::Vec3;
use rayon::prelude::*;
use std::sync::Arc;

/// A built beam tree: the children of the faces the eye sees, and the beams level by level; what the
/// renderer kept of the levels (texels none of the nodes hold), and per level whether it
/// composites the texels it handed back itself ([`KeptTotals::records`]).
pub(crate) struct Built {
    pub(crate) roots: FaceMap<Scattered>,
    pub(crate) levels: Vec<Vec<Node>>,
    pub(crate) kept: KeptTotals,
    pub(crate) records: Vec<bool>,
}

/// The light arriving at one S-mesh face, from which its beams are built: the fit over samples
/// (barycentric point, unit direction) of the pixels' or the parent texels' rays on it, standing
/// for `pixels`.
pub(crate) struct Request {
    /// The parent beam (index into the previous level), or the eye.
    pub(crate) parent: Option<usize>,
    pub(crate) face: usize,
    pub(crate) fit: Fit,
    pub(crate) pixels: f32,
}

/// How many times [`MAX_TREE_BEAMS`] a tree's estimated size must be for it to be refused before
/// its levels reach the limit ([`Tree::check_size`]).
const EARLY_MARGIN: f64 = 10.0;

/// What a parent beam's rays through face `face`'s vertices are a function of: the parent (its
/// beams' key, and whether it is the refracted one) and the face.
fn through_key(parent: &TreeBeam, face: usize) -> [u32; 13] {
    let mut key = [0; 13];
    key[..11].copy_from_slice(&parent.key);
    key[11] = u32::from(parent.refracted);
    key[12] = face as u32;
    key
}

/// What the beams of S-mesh face `face` are made of: the face (its vertices, normals and material),
/// the parameterization and the bits of the light's unit directions at its vertices.
fn children_key(face: usize, degree: Degree, incoming: [Vec3; 3]) -> [u32; 11] {
    let mut key = [0; 11];
    key[0] = face as u32;
    key[1] = degree as u32;
    for (slot, x) in key[2..].iter_mut().zip(incoming.iter().flat_map(|d| d.to_array())) {
        *slot = x.to_bits();
    }
    key
}

impl Tree<'_> {
    /// Requests for the faces that `samples` (face, barycentric point, unit direction of one
    /// pixel's or parent texel's ray, standing for `pixels_per_sample` pixels) land on.
    fn requests(
        parent: Option<usize>,
        samples: impl Iterator<Item = (usize, Vec3, Vec3)>,
        pixels_per_sample: f32,
    ) -> Vec<Request> {
        let mut on: FaceMap<Fit> = FaceMap::default();
        for (fi, w, d) in samples {
            on.entry(fi).or_default().add(w, d);
        }
        on.into_iter()
            .map(|(face, fit)| Request { parent, face, pixels: fit.samples() as f32 * pixels_per_sample, fit })
            .collect()
    }

    /// The beam tree level by level (000 §7.2–7.3, per-level atlases): each level's beams built from
    /// the light arriving at its faces, rendered in one batch by `renderer`, their texels' hits on
    /// specular faces the requests of the next level; what the renderer keeps of each level goes to
    /// the frame's `kept` (the value its eye's view returned). Returns the roots' children and the
    /// levels.
    pub(crate) fn build(
        &self,
        renderer: &mut dyn BeamRenderer,
        memos: &mut TreeMemos,
        roots: Vec<Request>,
        kept_frame: &mut KeptFrame,
        clock: &mut StageClock,
    ) -> Result<Built, NonlinearError> {
        memos.beams.next_frame();
        memos.through.next_frame();
        let mut levels: Vec<Vec<Node>> = Vec::new();
        let mut root_children = FaceMap::default();
        let mut kept_totals = KeptTotals::default();
        let mut records = Vec::new();
        let continues: Vec<bool> =
            (0..self.scene.triangles.len() as u32).map(|p| !self.smesh.candidates(p).is_empty()).collect();
        let mut requests = roots;
        // The faces the last level built was asked for: the tree's growth so far.
        let mut last_requested = None;
        for level in 1..=self.options.bounces {
            if requests.is_empty() {
                break;
            }
            self.check_size(level, &levels, requests.len(), last_requested)?;
            last_requested = Some(requests.len());
            let parents = levels.last();
            // The light arriving at each request's face (000 §7.2): from the eye, or fitted to its
            // parent's texel rays on it, else its parent's rays through its vertices (those the
            // last frame's tree found for the same parent and face found again). `Some` where known
            // without a projection (`Some(None)`: no beams), `None` where projected.
            let fitted: Vec<Option<Option<[Vec3; 3]>>> = requests
                .par_iter()
                .map(|r| {
                    if !self.smesh.spawns_beams(r.face) {
                        return Some(None);
                    }
                    match r.parent {
                        Some(_) => r.fit.directions().map(Some),
                        None => Some(from_eye(self.eye, &self.smesh.faces[r.face])),
                    }
                })
                .collect();
            let projected: Vec<(usize, &TreeBeam)> = fitted
                .iter()
                .enumerate()
                .filter(|(_, f)| f.is_none())
                .filter_map(|(i, _)| Some((i, &parents?[requests[i].parent?].beam)))
                .collect();
            let keys = projected.iter().map(|&(i, parent)| through_key(parent, requests[i].face)).collect();
            let found = memos.through.values(keys, |k| {
                let (i, parent) = projected[k];
                through(parent, &self.smesh.faces[requests[i].face])
            });
            let mut incoming: Vec<Option<[Vec3; 3]>> = fitted.into_iter().map(Option::flatten).collect();
            for (&(i, _), d) in projected.iter().zip(found) {
                incoming[i] = d;
            }
            // Their beams, those of the last frame's tree found again; a face whose beams are
            // degenerate is shaded by rays.
            let lit: Vec<(usize, [Vec3; 3])> =
                incoming.iter().enumerate().filter_map(|(i, d)| Some((i, (*d)?))).collect();
            let keys: Vec<[u32; 11]> =
                lit.iter().map(|&(i, d)| children_key(requests[i].face, self.options.degree, d)).collect();
            let made = memos.beams.values(keys.clone(), |k| {
                let (i, incoming) = lit[k];
                let (reflected, refracted) =
                    child_beams(self.scene, &self.smesh.faces[requests[i].face], incoming, self.options.degree)?;
                let refracted = match refracted {
                    Some(b) => Some(b?),
                    None => None,
                };
                Some(Arc::new((reflected, refracted)))
            });
            let mut built = vec![None; requests.len()];
            for ((&(i, _), b), key) in lit.iter().zip(made).zip(keys) {
                built[i] = b.map(|b| (b, key));
            }
            let mut beams = Vec::with_capacity(2 * lit.len());
            for (r, b) in requests.iter().zip(built) {
                let Some((b, key)) = b else { continue };
                let size = region_size(r.pixels, self.options.texels);
                let mut push = |refracted| {
                    beams.push((TreeBeam { beams: b.clone(), refracted, key }, r.face, r.pixels, size));
                    beams.len() - 1
                };
                let scattered = Scattered { reflected: push(false), refracted: b.1.is_some().then(|| push(true)) };
                match (r.parent, levels.last_mut()) {
                    (Some(p), Some(parents)) => parents[p].children.insert(r.face, scattered),
                    _ => root_children.insert(r.face, scattered),
                };
            }
            let jobs: Vec<BeamJob<'_>> = beams
                .iter()
                .map(|(beam, face, _, size)| BeamJob { beam, size: *size, exclude: self.smesh.exclude(*face) })
                .collect();
            clock.lap("tree: beams", renderer.waited_seconds());
            // A backend that shades the tree itself keeps the texels from which the tree does not
            // go on; lookups under coarse faces above read the hits all the same.
            let layout = self.layout(beams.iter().map(|&(_, face, _, size)| (face, size)));
            let keep = KeepLevel {
                level: level as usize,
                layout: &layout,
                options: &self.options.shading,
                with_hits: self.smesh.coarse_faces() > 0,
                faces: self.smesh.faces.len(),
                continues: if level < self.options.bounces { &continues } else { &[] },
            };
            let (textures, kept) = renderer.render_level(self.scene, &jobs, &keep, kept_frame)?;
            if let Some(k) = kept {
                kept_totals.points += k.points;
                kept_totals.curved += k.curved;
            }
            records.push(kept.is_some_and(|k| k.records));
            clock.lap("tree: rasterize beams", renderer.waited_seconds());
            let mut nodes: Vec<Node> = beams
                .into_par_iter()
                .zip(textures)
                .map(|((beam, face, pixels, _), mut tex)| {
                    // The hit texels in texel order, row by row: those the backend handed back with
                    // their points, else found here. Room for every texel of the region where the
                    // backend kept none, else only those from which the tree goes on (none past
                    // the last level: its textures, which a coarse face's lookups read, are not
                    // scanned for them).
                    let hits = if !tex.points.is_empty() {
                        std::mem::take(&mut tex.points)
                    } else if kept.is_some() && keep.continues.is_empty() {
                        Vec::new()
                    } else {
                        let room = if kept.is_none() { tex.texels() as usize } else { 0 };
                        let handed_back =
                            |prim: u32| kept.is_none() || keep.continues.get(prim as usize) == Some(&true);
                        Self::texel_hits(&beam, &tex, handed_back, room)
                    };
                    let bumped = matches!(*beam, Beam::Bumped(_));
                    Node { beam, bumped, face, pixels, tex, hits, located: Vec::new(), children: FaceMap::default() }
                })
                .collect();
            clock.lap("tree: texel hits", renderer.waited_seconds());
            requests = if level < self.options.bounces && kept.is_some_and(|k| k.fits) {
                // The backend summed each beam's fits on the faces its texels hit.
                nodes
                    .iter_mut()
                    .enumerate()
                    .flat_map(|(i, node)| {
                        let per_sample = node.pixels / node.tex.texels() as f32;
                        std::mem::take(&mut node.tex.fits).into_iter().map(move |(face, fit)| Request {
                            parent: Some(i),
                            face: face as usize,
                            pixels: fit.samples() as f32 * per_sample,
                            fit,
                        })
                    })
                    .collect()
            } else if level < self.options.bounces {
                nodes.par_iter_mut().for_each(|node| node.located = self.locate(&node.hits));
                nodes
                    .par_iter()
                    .enumerate()
                    .flat_map_iter(|(i, node)| {
                        let samples = node.hits.iter().zip(&node.located).filter_map(|(h, at)| {
                            let (g, w) = (*at)?;
                            Some((g, w, h.d))
                        });
                        Self::requests(Some(i), samples, node.pixels / node.tex.texels() as f32)
                    })
                    .collect()
            } else {
                Vec::new()
            };
            clock.lap("tree: next level's faces", renderer.waited_seconds());
            levels.push(nodes);
        }
        Ok(Built { roots: root_children, levels, kept: kept_totals, records })
    }

    /// Refuse a tree past [`MAX_TREE_BEAMS`] beams, before level `level` is built: `levels` are
    /// those built, `requested` the faces asked for at `level`, `last_requested` those asked for
    /// at the level before. Refused when level `level` would pass the limit, or early, when the
    /// whole tree of `options.bounces` levels is estimated past [`EARLY_MARGIN`] times it: the
    /// estimate takes each level to come as many times the one before as `level` is the last
    /// (beams per face as the last level's). Trees grow geometrically, so that a hopeless one is
    /// refused after its first cheap levels; the margin keeps the estimate (three times the
    /// truth on the bumpy mirror at 5 bounces) from refusing a tree that fits.
    fn check_size(
        &self,
        level: u32,
        levels: &[Vec<Node>],
        requested: usize,
        last_requested: Option<usize>,
    ) -> Result<(), NonlinearError> {
        let beams_per_level: Vec<u64> = levels.iter().map(|l| l.len() as u64).collect();
        let built: u64 = beams_per_level.iter().sum();
        let (growth, per_face) = match (last_requested, levels.last()) {
            (Some(r), Some(l)) if r > 0 => (requested as f64 / r as f64, (l.len() as f64 / r as f64).max(1.0)),
            _ => (1.0, 1.0),
        };
        let next = requested as f64 * per_face;
        // The tree's beams with levels `level..=last`.
        let estimate = |last: u32| {
            let (mut sum, mut term) = (built as f64, next);
            for _ in level..=last {
                sum += term;
                term = (term * growth).min(1e30);
            }
            sum
        };
        let bounces = self.options.bounces;
        let limit = MAX_TREE_BEAMS;
        if estimate(level) <= limit as f64 && estimate(bounces) <= EARLY_MARGIN * limit as f64 {
            return Ok(());
        }
        let fits = (level..bounces).take_while(|&l| estimate(l) <= limit as f64).last().unwrap_or(level - 1);
        Err(NonlinearError::BeamTree {
            bounces,
            level,
            beams_per_level,
            requested: requested as u64,
            growth,
            estimate: estimate(bounces),
            limit,
            fits,
        })
    }

    /// Into `levels`' beams, the texels from which the tree goes on that `renderer` kept in
    /// `kept_frame` and summed the fits of ([`KeptTotals::fits`]), with their faces: for a frame
    /// shaded here after all.
    pub(crate) fn kept_level_points(
        &self,
        renderer: &dyn BeamRenderer,
        kept_frame: &KeptFrame,
        levels: &mut [Vec<Node>],
    ) -> Result<(), BackendError> {
        for (li, nodes) in levels.iter_mut().enumerate() {
            let points = renderer.kept_level_points(li + 1, kept_frame)?;
            if points.is_empty() {
                continue;
            }
            if points.len() != nodes.len() {
                return Err(BackendError::new(
                    "renderer",
                    format!("texels of {} beams for level {}", points.len(), li + 1),
                ));
            }
            nodes.par_iter_mut().zip(points).for_each(|(node, hits)| {
                node.located = self.locate(&hits);
                node.hits = hits;
            });
        }
        Ok(())
    }

    /// The S-mesh face and barycentric coordinates of each of `hits` ([`SMesh::locate_on`]: the
    /// backend's face where it is a candidate).
    fn locate(&self, hits: &[TexelPoint]) -> Vec<Option<(usize, Vec3)>> {
        hits.iter().map(|h| self.smesh.locate_on(h.prim, h.face, h.p)).collect()
    }

    /// The texels of `tex` (`beam`'s) that hit a triangle `handed_back` names, in texel order,
    /// each with its hit point and the unit direction of its texel ray; with room for `room`.
    fn texel_hits(beam: &Beam, tex: &BeamTexture, handed_back: impl Fn(u32) -> bool, room: usize) -> Vec<TexelPoint> {
        let (size, tb) = (tex.size as usize, beam.texel_beam());
        let mut hits = Vec::with_capacity(room);
        for (y, row) in tex.hits.chunks_exact(size.max(1)).enumerate() {
            for (x, hit) in row.iter().enumerate() {
                let Some(hit) = hit.filter(|h| handed_back(h.prim)) else { continue };
                let ray = tb.texel_ray(tex.barycentric(x as u32, y as u32));
                let texel = (y * size + x) as u32;
                let (p, d) = (ray.at(hit.t), ray.direction.normalize());
                hits.push(TexelPoint { texel, prim: hit.prim, p, d, face: u32::MAX });
            }
        }
        hits
    }

    /// The layout of a level of beams `(face, texels per side)` in its radiance, as
    /// [`Self::radiance_levels`] lays it out.
    pub(crate) fn layout(&self, beams: impl Iterator<Item = (usize, u32)>) -> LevelLayout {
        let mut layout = LevelLayout::default();
        for (face, size) in beams {
            layout.firsts.push(layout.len as u32);
            layout.prims.push(self.smesh.faces[face].prim);
            layout.len += (size * size) as usize;
        }
        layout
    }
}
