//! The radiance flow of a built beam tree (000 §7.3): every texel of every level that hit, with
//! the composite of its point from its face's child beams where they hold its scattered rays
//! ([`Tree::composite`]: looked up at the point's own coordinates, or under a coarse face where its
//! rays reach), else shaded; levels the renderer composites itself get their nodes' children
//! instead.

use super::lookup::{FaceAnswer, Lookups, ToComposite, reproject};
use super::{Node, Tree};
use crate::BackendError;
use crate::nonlinear::beam_tree::{LOOKUP_PREFERENCE, OUTSIDE_TEXELS};
use crate::nonlinear::radiance::{Composite, LevelRadiance, NodeChildren, TexelRadiance};
use crate::nonlinear::renderer::{BeamRenderer, LevelLayout};
use crate::nonlinear::texture::{ShadePoint, TexelPoint};
use crate::parallel::par_flatten;
use beam_math::glam::Vec3;
use rayon::prelude::*;

impl Tree<'_> {
    /// The tree's levels for the radiance flow: per level, every beam's region and every texel
    /// that hit, composited from its face's children where it has them; where `records[level]`,
    /// the renderer composites the level's texels itself, given their faces' children.
    pub(crate) fn radiance_levels(
        &self,
        renderer: &dyn BeamRenderer,
        levels: &[Vec<Node>],
        records: &[bool],
    ) -> Result<Vec<LevelRadiance>, BackendError> {
        let point = |node: &Node, h: &TexelPoint| {
            let prim = self.smesh.faces[node.face].prim;
            ShadePoint { prim: h.prim, p: h.p, d: h.d, seed: u64::from(prim) << 32 | u64::from(h.texel) }
        };
        levels
            .iter()
            .enumerate()
            .map(|(li, nodes)| {
                let LevelLayout { firsts, len, .. } = self.layout(nodes.iter().map(|n| (n.face, n.tex.size)));
                let regions: Vec<(u32, u32)> = firsts.into_iter().zip(nodes.iter().map(|n| n.tex.size)).collect();
                if records.get(li) == Some(&true) {
                    let node_children = node_children(nodes);
                    return Ok(LevelRadiance { regions, len, node_children, ..LevelRadiance::default() });
                }
                let next = levels.get(li + 1).map_or(&[][..], |l| &l[..]);
                // Each node's first texel in the level's list of texels that hit.
                let offsets: Vec<usize> = nodes
                    .iter()
                    .scan(0, |at, n| {
                        *at += n.hits.len();
                        Some(*at - n.hits.len())
                    })
                    .collect();
                // Not located on the last level: no child beam composites it.
                let to_composite = |i: usize, k: usize| {
                    let n = &nodes[i];
                    self.to_composite(&n.children, point(n, &n.hits[k]), n.located.get(k).copied().flatten())
                };
                let points = self.looks_up(renderer, next).then(|| {
                    par_flatten(
                        nodes,
                        None,
                        |_, n| n.hits.len(),
                        |i, n, push| {
                            (0..n.hits.len()).for_each(|k| push(Some(to_composite(i, k))));
                        },
                    )
                });
                let looked_up = match &points {
                    Some(points) => self.lookups(renderer, next, points)?,
                    None => Lookups::default(),
                };
                let texels = par_flatten(
                    nodes,
                    TexelRadiance::default(),
                    |_, node| node.hits.len(),
                    |i, node, push| {
                        for (k, h) in node.hits.iter().enumerate() {
                            let at = offsets[i] + k;
                            let to = points.as_ref().and_then(|p| p[at]).unwrap_or_else(|| to_composite(i, k));
                            let composite = self.composite(next, &to, looked_up.of(at));
                            push(TexelRadiance { texel: regions[i].0 + h.texel, point: to.point, composite });
                        }
                    },
                );
                let missed = self.missed(nodes, &regions);
                Ok(LevelRadiance { regions, len, texels, missed, ..LevelRadiance::default() })
            })
            .collect()
    }

    /// The composite of `to`'s point, at its located face and barycentric coordinates there, when
    /// the face has child beams (nodes of `next`): looked up at the point's own coordinates, or
    /// under a coarse face where the point's own scattered rays reach
    /// ([`reproject`]; near an edge, through whichever of the faces its triangle maps to has the
    /// reflection beam that holds its reflected ray). `None` too where no child beam holds the
    /// point's scattered ray within [`OUTSIDE_TEXELS`] of its base: the point is traced by rays.
    /// `looked_up`: the lookups a backend made ([`Tree::lookups`]), per face with child beams in
    /// the order tried here (the located face first); the faces past its end are looked up here.
    pub(crate) fn composite<'l>(
        &self,
        next: &[Node],
        to: &ToComposite<'_>,
        looked_up: impl Iterator<Item = &'l FaceAnswer>,
    ) -> Option<Composite> {
        let (mut face, w) = to.located?;
        let mut sc = *to.children.get(&face)?;
        let (mut reflected_at, mut refracted_at) = (w, w);
        if let Some(rays) = to.own {
            let at = |child: usize, truth: Option<Vec3>, w: Vec3| match (next.get(child), truth) {
                (Some(n), Some(truth)) => reproject(&n.beam, &n.tex, to.point.p, truth, w, self.far),
                _ => (w, 0.0),
            };
            let mut best = f32::INFINITY;
            // How far outside a child's base (barycentric units) a lookup may fall.
            let slack = |child: usize| next.get(child).map_or(0.0, |n| OUTSIDE_TEXELS / n.tex.size as f32);
            let located = face;
            let others =
                self.smesh.candidates(to.point.prim).iter().map(|&g| g as usize).filter(move |&g| g != located);
            let (mut answers, mut refracted) = (looked_up, None);
            for g in std::iter::once(located).chain(others) {
                // No lookup lies less than 0 outside: once one lies inside, no other face wins.
                if best <= 0.0 {
                    break;
                }
                let Some(&c) = to.children.get(&g) else { continue };
                // The located face's coordinates were found with it (`SMesh::locate`).
                let wg = if g == located { w } else { self.smesh.faces[g].barycentric(to.point.p) };
                let known = answers.next();
                let (at_g, outside) = known.map_or_else(|| at(c.reflected, rays[0], wg), |a| a.reflected);
                if outside < best - LOOKUP_PREFERENCE {
                    (best, face, sc, reflected_at, refracted_at) = (outside, g, c, at_g, wg);
                    refracted = known.and_then(|a| a.refracted);
                }
            }
            if best > slack(sc.reflected) {
                self.by_rays.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                return None;
            }
            if let Some(t) = sc.refracted {
                let (at_t, outside) = refracted.unwrap_or_else(|| at(t, rays[1], refracted_at));
                if outside > slack(t) {
                    self.by_rays.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    return None;
                }
                refracted_at = at_t;
            }
        }
        Some(Composite {
            face: face as u32,
            reflected: sc.reflected as u32,
            refracted: sc.refracted.map(|r| r as u32),
            reflected_at,
            refracted_at,
        })
    }

    /// The texels of `nodes` (a level whose beams start at `regions`) whose rays leave the scene,
    /// with their rays' directions, where the environment they then show is not black.
    fn missed(&self, nodes: &[Node], regions: &[(u32, u32)]) -> Vec<(u32, Vec3)> {
        if self.scene.environment.is_black() {
            return Vec::new();
        }
        let regions_and_nodes = regions.par_iter().zip(nodes);
        regions_and_nodes
            .flat_map_iter(|(&(first, size), n)| {
                let mut hit = vec![false; (size * size) as usize];
                for h in &n.hits {
                    hit[h.texel as usize] = true;
                }
                (0..size * size)
                    .filter(move |&k| !hit[k as usize] && n.tex.in_region(k % size, k / size))
                    .map(move |k| (first + k, n.beam.ray_at(n.tex.barycentric(k % size, k / size)).direction))
            })
            .collect()
    }
}

/// Per node of a level, the child beams of the faces its texels hit, ascending by face.
fn node_children(nodes: &[Node]) -> NodeChildren {
    let mut table = NodeChildren { firsts: Vec::with_capacity(nodes.len() + 1), entries: Vec::new() };
    for node in nodes {
        table.firsts.push(table.entries.len() as u32);
        let at = table.entries.len();
        let none = u32::MAX;
        table.entries.extend(
            node.children
                .iter()
                .map(|(&face, c)| [face as u32, c.reflected as u32, c.refracted.map_or(none, |r| r as u32)]),
        );
        table.entries[at..].sort_unstable_by_key(|e| e[0]);
    }
    table.firsts.push(table.entries.len() as u32);
    table
}
