//! A composite dispatch's inputs sorted out of a level's texels by every thread, in two passes
//! over the texels (count, then fill) and no list in between: the points the shading pass shades
//! (as its inputs), the points the caller shades (mirrors and glass past the tree), where each
//! one's radiance goes, and the composite records, the S-mesh faces and child regions they
//! reference compacted to the dispatch's own. The fill writes wherever its caller says: into the
//! queue's staging memory for what goes to the GPU ([`crate::staging`]), no list in between.

use super::records::CompositeRecord;
use crate::GpuError;
use crate::interface::NONE;
use crate::shade::{PointShader, ShadeInput};
use crate::staging::split_by_counts;
use beam_math::glam::Vec3;
use beam_render::nonlinear::{Composite, SMesh, TexelRadiance};
use beam_render::parallel::piece_len;
use beam_scene::scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use wgpu::WriteOnly;

/// The first pass over one dispatch's texels: how many of each kind every piece holds, and the
/// faces and regions the records reference, compacted.
pub(super) struct Plan {
    /// Texels per piece of the passes.
    piece: usize,
    /// Per piece: its direct, other and composited texels.
    counts: Vec<[usize; 3]>,
    face_slot: Vec<u32>,
    region_slot: Vec<u32>,
    /// The S-mesh faces the records reference, by slot (ascending).
    pub faces: Vec<u32>,
    /// The child regions (beams of the level below) they reference, by slot (ascending).
    pub regions: Vec<u32>,
}

/// Where [`Plan::fill`] writes, each list in the texels' order.
pub(super) struct Outputs<'a> {
    /// The points the shading pass shades.
    pub direct: WriteOnly<'a, [ShadeInput]>,
    /// The points the caller shades.
    pub other: WriteOnly<'a, [ShadeInput]>,
    /// The texels of `direct`'s points, then of `other`'s.
    pub targets: WriteOnly<'a, [u32]>,
    /// The composited texels.
    pub records: WriteOnly<'a, [CompositeRecord]>,
}

/// Count `texels` (of a level whose S mesh has `faces` faces and whose level below has `regions`
/// regions) by kind: shaded by the shading pass, shaded by the caller, composited. An error for a
/// record that references a face or region past those.
pub(super) fn plan(
    scene: &Scene,
    texels: &[TexelRadiance],
    (faces, regions): (usize, usize),
) -> Result<Plan, GpuError> {
    let direct = |t: &TexelRadiance| PointShader::shades(scene, t.point.prim);
    let piece = piece_len(texels.len());
    let (face_used, region_used) = (flags(faces), flags(regions));
    // A flag is stored only while clear: the threads then share its cache line instead of
    // taking it from each other at every texel.
    let mark = |flags: &[AtomicBool], i: u32, unknown| -> Result<(), GpuError> {
        let flag = flags.get(i as usize).ok_or_else(|| GpuError::Internal(unknown))?;
        if !flag.load(Ordering::Relaxed) {
            flag.store(true, Ordering::Relaxed);
        }
        Ok(())
    };
    // Per piece: its direct, other and composited texels; the faces and regions used marked.
    let counts: Vec<[usize; 3]> = texels
        .par_chunks(piece)
        .map(|p| {
            let mut n = [0; 3];
            for t in p {
                match &t.composite {
                    Some(c) => {
                        mark(&face_used, c.face, "no such S-mesh face")?;
                        mark(&region_used, c.reflected, "no such child beam")?;
                        if let Some(b) = c.refracted {
                            mark(&region_used, b, "no such child beam")?;
                        }
                        n[2] += 1;
                    }
                    None => n[usize::from(!direct(t))] += 1,
                }
            }
            Ok(n)
        })
        .collect::<Result<_, GpuError>>()?;
    let (face_slot, faces) = slots(&face_used);
    let (region_slot, regions) = slots(&region_used);
    Ok(Plan { piece, counts, face_slot, region_slot, faces, regions })
}

impl Plan {
    /// Texels of each kind: shaded by the shading pass, by the caller, composited.
    pub(super) fn totals(&self) -> [usize; 3] {
        [0, 1, 2].map(|k| self.counts.iter().map(|n| n[k]).sum())
    }

    /// The second pass: every texel written to `out`, whose lists hold [`Plan::totals`] elements
    /// (`targets` the first two together). The same `texels` as [`plan`] counted; an error where
    /// the lists are too short.
    pub(super) fn fill(
        &self,
        (scene, smesh): (&Scene, &SMesh),
        texels: &[TexelRadiance],
        out: Outputs<'_>,
    ) -> Result<(), GpuError> {
        let direct = |t: &TexelRadiance| PointShader::shades(scene, t.point.prim);
        let [n_direct, ..] = self.totals();
        let short = || GpuError::Internal("composite lists shorter than their texels");
        let (direct_targets, other_targets) = out.targets.split_at_checked(n_direct).map_err(|_| short())?;
        let by = |k: usize| self.counts.iter().map(move |n| n[k]);
        let (direct_out, other_out) = (
            split_by_counts(out.direct, by(0)).ok_or_else(short)?,
            split_by_counts(out.other, by(1)).ok_or_else(short)?,
        );
        let direct_targets = split_by_counts(direct_targets, by(0)).ok_or_else(short)?;
        let other_targets = split_by_counts(other_targets, by(1)).ok_or_else(short)?;
        let records = split_by_counts(out.records, by(2)).ok_or_else(short)?;
        let record = |t: &TexelRadiance, c: &Composite| {
            // The shader looks the children up at `p`'s and `refracted_p`'s barycentric
            // coordinates on the face: under a coarse S-mesh face, the points of the face where
            // the CPU looks the reflection and the refraction up.
            let (p, refracted_p) = if smesh.is_coarse(c.face as usize) {
                let f = &smesh.faces[c.face as usize];
                let at = |w: Vec3| w.x * f.v[0] + w.y * f.v[1] + w.z * f.v[2];
                (at(c.reflected_at), at(c.refracted_at))
            } else {
                (t.point.p, t.point.p)
            };
            CompositeRecord {
                p: p.to_array(),
                texel: t.texel,
                d: t.point.d.to_array(),
                face: self.face_slot[c.face as usize],
                reflected: self.region_slot[c.reflected as usize],
                refracted: c.refracted.map_or(NONE, |b| self.region_slot[b as usize]),
                pad: [0; 2],
                refracted_p: refracted_p.to_array(),
                pad2: 0,
            }
        };
        texels
            .par_chunks(self.piece)
            .zip(direct_out)
            .zip(other_out)
            .zip(direct_targets)
            .zip(other_targets)
            .zip(records)
            .for_each(|(((((p, direct_out), other_out), direct_targets), other_targets), records)| {
                let (mut direct_out, mut other_out) = (direct_out.0.into_iter(), other_out.0.into_iter());
                let (mut direct_targets, mut other_targets) =
                    (direct_targets.0.into_iter(), other_targets.0.into_iter());
                let mut records = records.0.into_iter();
                for t in p {
                    // Each list holds exactly its kind's count of this piece (`plan`).
                    match &t.composite {
                        Some(c) => put(&mut records, record(t, c)),
                        None if direct(t) => {
                            put(&mut direct_out, ShadeInput::new(&t.point));
                            put(&mut direct_targets, t.texel);
                        }
                        None => {
                            put(&mut other_out, ShadeInput::new(&t.point));
                            put(&mut other_targets, t.texel);
                        }
                    }
                }
            });
        Ok(())
    }
}

/// Write `value` to the next of `slots`, if any is left.
fn put<'a, T: Copy + 'a>(slots: &mut impl Iterator<Item = WriteOnly<'a, T>>, value: T) {
    if let Some(slot) = slots.next() {
        slot.write(value);
    }
}

/// `len` flags, clear.
fn flags(len: usize) -> Vec<AtomicBool> {
    (0..len).map(|_| AtomicBool::new(false)).collect()
}

/// Per index, its slot ([`NONE`] where unused: the used indices numbered in ascending order); and
/// the used indices by slot.
fn slots(used: &[AtomicBool]) -> (Vec<u32>, Vec<u32>) {
    let mut slot = vec![NONE; used.len()];
    let mut by_slot = Vec::new();
    for (i, u) in used.iter().enumerate() {
        if u.load(Ordering::Relaxed) {
            slot[i] = by_slot.len() as u32;
            by_slot.push(i as u32);
        }
    }
    (slot, by_slot)
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_render::nonlinear::ShadePoint;
    use beam_scene::scene::{Simplify, builtin};
    use bytemuck::Zeroable;

    /// A dispatch's lists sorted into vectors.
    struct Sorted {
        direct: Vec<ShadeInput>,
        other: Vec<ShadeInput>,
        targets: Vec<u32>,
        records: Vec<CompositeRecord>,
        faces: Vec<u32>,
        regions: Vec<u32>,
    }

    fn sort(
        (scene, smesh): (&Scene, &SMesh),
        texels: &[TexelRadiance],
        (faces, regions): (usize, usize),
    ) -> Result<Sorted, GpuError> {
        let plan = plan(scene, texels, (faces, regions))?;
        fill_vectors(&plan, (scene, smesh), texels, 0)
    }

    /// `plan` filled into vectors of its totals, the records' `short` elements short.
    fn fill_vectors(
        plan: &Plan,
        (scene, smesh): (&Scene, &SMesh),
        texels: &[TexelRadiance],
        short: usize,
    ) -> Result<Sorted, GpuError> {
        let [d, o, r] = plan.totals();
        let (mut direct, mut other) = (vec![ShadeInput::zeroed(); d], vec![ShadeInput::zeroed(); o]);
        let (mut targets, mut records) = (vec![0; d + o], vec![CompositeRecord::zeroed(); r - short]);
        let out = Outputs {
            direct: WriteOnly::from_mut(&mut direct[..]),
            other: WriteOnly::from_mut(&mut other[..]),
            targets: WriteOnly::from_mut(&mut targets[..]),
            records: WriteOnly::from_mut(&mut records[..]),
        };
        plan.fill((scene, smesh), texels, out)?;
        Ok(Sorted { direct, other, targets, records, faces: plan.faces.clone(), regions: plan.regions.clone() })
    }

    /// The sorted lists are the texels filtered one kind at a time, in order, and each record
    /// references, through its slots, the face and regions of its texel's composite.
    #[test]
    fn sorts_like_filtering_one_kind_at_a_time() {
        // A coarse S mesh over the spheres (records looked up at points of their faces).
        let mut scene = builtin("mirror-glass").unwrap();
        scene.smesh.rest = Some(Simplify::Faces(60));
        let smesh = SMesh::of(&scene);
        assert!(smesh.coarse_faces() > 0);
        let shaded = (0..scene.triangles.len() as u32).find(|&p| PointShader::shades(&scene, p)).unwrap();
        let specular = (0..scene.triangles.len() as u32).find(|&p| !PointShader::shades(&scene, p)).unwrap();
        let (faces, regions) = (smesh.faces.len(), 40);
        // Every pattern of kinds, over enough texels for several pieces.
        let texels: Vec<TexelRadiance> = (0..70_000u32)
            .map(|i| {
                let point = ShadePoint {
                    prim: if i % 3 == 0 { specular } else { shaded },
                    p: Vec3::new(i as f32, 1.0, 2.0),
                    d: Vec3::Z,
                    seed: u64::from(i),
                };
                let composite = (i % 5 < 2).then(|| Composite {
                    face: (i * 7 % faces as u32),
                    reflected: i % 31,
                    refracted: (i % 2 == 0).then_some(i % 37 + 3),
                    reflected_at: Vec3::new(0.2, 0.3, 0.5),
                    refracted_at: Vec3::new(0.6, 0.2, 0.2),
                });
                TexelRadiance { texel: 3 * i + 1, point, composite }
            })
            .collect();
        let s = sort((&scene, &smesh), &texels, (faces, regions)).unwrap();
        let none = |t: &&TexelRadiance| t.composite.is_none();
        let direct: Vec<&TexelRadiance> =
            texels.iter().filter(none).filter(|t| PointShader::shades(&scene, t.point.prim)).collect();
        let other: Vec<&TexelRadiance> =
            texels.iter().filter(none).filter(|t| !PointShader::shades(&scene, t.point.prim)).collect();
        assert!(!direct.is_empty() && !other.is_empty());
        assert_eq!(s.direct, direct.iter().map(|t| ShadeInput::new(&t.point)).collect::<Vec<_>>());
        assert_eq!(s.other, other.iter().map(|t| ShadeInput::new(&t.point)).collect::<Vec<_>>());
        assert_eq!(s.targets, direct.iter().chain(&other).map(|t| t.texel).collect::<Vec<_>>());
        let composited: Vec<(&TexelRadiance, Composite)> =
            texels.iter().filter_map(|t| Some((t, t.composite?))).collect();
        assert_eq!(s.records.len(), composited.len());
        assert!(s.faces.is_sorted() && s.regions.is_sorted());
        for (r, (t, c)) in s.records.iter().zip(&composited) {
            assert_eq!((r.texel, r.d), (t.texel, t.point.d.to_array()));
            assert_eq!(s.faces[r.face as usize], c.face);
            assert_eq!(s.regions[r.reflected as usize], c.reflected);
            assert_eq!(c.refracted, (r.refracted != NONE).then(|| s.regions[r.refracted as usize]));
            // Under a coarse face, the points of the face where the children are looked up.
            let f = &smesh.faces[c.face as usize];
            let at = |w: Vec3| (w.x * f.v[0] + w.y * f.v[1] + w.z * f.v[2]).to_array();
            let want = if smesh.is_coarse(c.face as usize) {
                (at(c.reflected_at), at(c.refracted_at))
            } else {
                (t.point.p.to_array(), t.point.p.to_array())
            };
            assert_eq!((r.p, r.refracted_p), want);
        }
        // A reference past the faces or regions is an error, not a panic; so are lists too short.
        assert!(sort((&scene, &smesh), &texels, (faces, 30)).is_err());
        assert!(sort((&scene, &smesh), &texels, (1, regions)).is_err());
        let plan = plan(&scene, &texels, (faces, regions)).unwrap();
        assert!(fill_vectors(&plan, (&scene, &smesh), &texels, 1).is_err());
    }
}
