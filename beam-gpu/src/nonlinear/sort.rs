//! A composite dispatch's inputs sorted out of a level's texels by every thread, in two passes
//! over the texels (count, then fill) and no list in between: the points the shading pass shades
//! (as its inputs), the points the caller shades (mirrors and glass past the tree), where each
//! one's radiance goes, and the composite records, the S-mesh faces and child regions they
//! reference compacted to the dispatch's own.

use super::composite::{CompositeRecord, NONE};
use crate::GpuError;
use crate::shade::{PointShader, ShadeInput};
use beam_math::glam::Vec3;
use beam_scene::nonlinear::{Composite, SMesh, TexelRadiance};
use beam_scene::parallel::{piece_len, split_by_counts};
use beam_scene::scene::Scene;
use bytemuck::Zeroable;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// One dispatch's inputs, each list in the texels' order.
pub(super) struct Sorted {
    /// The points the shading pass shades.
    pub direct: Vec<ShadeInput>,
    /// The points the caller shades.
    pub other: Vec<ShadeInput>,
    /// The texels of `direct`'s points, then of `other`'s.
    pub targets: Vec<u32>,
    /// The composited texels.
    pub records: Vec<CompositeRecord>,
    /// The S-mesh faces the records reference, by slot (ascending).
    pub faces: Vec<u32>,
    /// The child regions (beams of the level below) they reference, by slot (ascending).
    pub regions: Vec<u32>,
}

/// Sort `texels`, whose composites reference S-mesh faces below `faces` and child regions below
/// `regions`.
pub(super) fn sort(
    (scene, smesh): (&Scene, &SMesh),
    texels: &[TexelRadiance],
    (faces, regions): (usize, usize),
) -> Result<Sorted, GpuError> {
    let direct = |t: &TexelRadiance| PointShader::shades(scene, t.point.prim);
    let piece = piece_len(texels.len());
    let (face_used, region_used) = (flags(faces), flags(regions));
    // A flag is stored only while clear: the threads then share its cache line instead of
    // taking it from each other at every texel.
    let mark = |flags: &[AtomicBool], i: u32, unknown| -> Result<(), GpuError> {
        let flag = flags.get(i as usize).ok_or(GpuError::Internal(unknown))?;
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
    let total = |k: usize| counts.iter().map(|n| n[k]).sum::<usize>();
    let mut out = Sorted {
        direct: vec![ShadeInput::zeroed(); total(0)],
        other: vec![ShadeInput::zeroed(); total(1)],
        targets: vec![0; total(0) + total(1)],
        records: vec![CompositeRecord::zeroed(); total(2)],
        faces,
        regions,
    };
    let (direct_targets, other_targets) = out.targets.split_at_mut(total(0));
    let direct_out = split_by_counts(&mut out.direct, counts.iter().map(|n| n[0]));
    let other_out = split_by_counts(&mut out.other, counts.iter().map(|n| n[1]));
    let direct_targets = split_by_counts(direct_targets, counts.iter().map(|n| n[0]));
    let other_targets = split_by_counts(other_targets, counts.iter().map(|n| n[1]));
    let records = split_by_counts(&mut out.records, counts.iter().map(|n| n[2]));
    let record = |t: &TexelRadiance, c: &Composite| {
        // The shader looks the children up at `p`'s and `refracted_p`'s barycentric coordinates on
        // the face: under a coarse S-mesh face, the points of the face where the CPU looks the
        // reflection and the refraction up.
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
            face: face_slot[c.face as usize],
            reflected: region_slot[c.reflected as usize],
            refracted: c.refracted.map_or(NONE, |b| region_slot[b as usize]),
            pad: [0; 2],
            refracted_p: refracted_p.to_array(),
            pad2: 0,
        }
    };
    texels
        .par_chunks(piece)
        .zip(direct_out)
        .zip(other_out)
        .zip(direct_targets)
        .zip(other_targets)
        .zip(records)
        .for_each(|(((((p, direct_out), other_out), direct_targets), other_targets), records)| {
            let mut at = [0; 3];
            for t in p {
                match &t.composite {
                    Some(c) => {
                        records[at[2]] = record(t, c);
                        at[2] += 1;
                    }
                    None if direct(t) => {
                        (direct_out[at[0]], direct_targets[at[0]]) = (ShadeInput::new(&t.point), t.texel);
                        at[0] += 1;
                    }
                    None => {
                        (other_out[at[1]], other_targets[at[1]]) = (ShadeInput::new(&t.point), t.texel);
                        at[1] += 1;
                    }
                }
            }
        });
    Ok(out)
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
    use beam_scene::nonlinear::ShadePoint;
    use beam_scene::scene::{Simplify, builtin};

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
        // A reference past the faces or regions is an error, not a panic.
        assert!(sort((&scene, &smesh), &texels, (faces, 30)).is_err());
        assert!(sort((&scene, &smesh), &texels, (1, regions)).is_err());
    }
}
