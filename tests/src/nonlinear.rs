//! Nonlinear beam tracing properties (000): texel rays against the BVH, beam-tree images against
//! the ray-traced ground truth, and S3's smoothness over S1.

use crate::property::{Backend, Config, Outcome, Property};
use beam_cpu::render::difference;
use beam_math::Ray;
use beam_math::collide::WatertightRay;
use beam_math::glam::Vec3;
use beam_render::options::RenderOptions;
use beam_scene::scene;
use rayon::prelude::*;

const CPU: &[Backend] = &[Backend::Cpu];
const CPU_AND_GPU: &[Backend] = &[Backend::Cpu, Backend::Gpu];

/// The nonlinear beam properties.
#[must_use]
pub fn properties() -> Vec<Property> {
    vec![
        Property {
            name: "nonlinear_texels_equal_ray_hits",
            cites: "000 Algs. 1-4",
            backends: CPU_AND_GPU,
            body: nonlinear_texels_equal_ray_hits,
        },
        Property {
            name: "nonlinear_images_vs_reference",
            cites: "000 §8, Figs. 9, 14",
            backends: CPU_AND_GPU,
            body: nonlinear_images_vs_reference,
        },
        Property {
            name: "caustics_match_photon_tracing",
            cites: "000 §9.2, Fig. 13",
            backends: CPU,
            body: caustics_match_photon_tracing,
        },
        Property {
            name: "area_light_caustics_converge",
            cites: "000 §9.2",
            backends: CPU,
            body: area_light_caustics_converge,
        },
        Property { name: "s3_removes_s1_kinks", cites: "000 §4, Fig. 4", backends: CPU, body: s3_removes_s1_kinks },
    ]
}

/// Side of the one large region [`nonlinear_texels_equal_ray_hits`] renders.
const LARGE_REGION: u32 = 2048;

/// Nonlinear beams off every third specular face of six built-in scenes (reflection beams, refraction
/// beams through glass, bumped beams off bumpy mirrors; S1 and S3, 16 texels per side), and on the
/// CPU of two more with coarse S meshes simplified from their fine ones (000 §7.1; the faces that
/// spawn beams, `SMesh::spawns_beams`), rendered by the
/// backend's beam rasterizer (the CPU's `render_beam`, the GPU's atlases): every texel's stored
/// nearest hit (bounding-cone culling, bounding triangles, per-texel intersection and depth test)
/// equals the BVH's closest hit of the same ray from the beam's parameterization (ignoring the
/// surface under the beam's base — its own triangle, or a coarse face's patch of fine triangles —
/// and a neighbouring face's hits within the S^n self-hit distance): the texel's hit is a real
/// intersection of its ray and none nearer exists, or at the same depth on the neighbour across a
/// shared edge. A bounding triangle that missed a texel would show as a texel that misses or hits
/// something farther. The first scene's first beam takes a region of 2048 texels a side (2.1
/// million texels, the GPU's read-back list of its rows found by a float root), checked at every
/// 128th texel each way: a texel read back from a wrong row would show there.
pub fn nonlinear_texels_equal_ray_hits(backend: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_math::nonlinear::{BumpBeam, NonlinearBeam, S3};
    use beam_render::nonlinear::{Beam, BeamJob, BumpedBeam, SMesh, self_hit_at};
    use beam_scene::scene::Simplify;
    let mut checked = 0u64;
    let mut notes = Vec::new();
    for (scene_index, (name, coarse)) in [
        ("mirror-glass", None),
        ("mirror-glass-coarse", None),
        ("facing-mirrors", None),
        ("bumpy-mirror", None),
        ("glass-lens-coarse", None),
        ("wavy-lake-coarse", None),
        ("mirror-teapot", Some(850)),
        ("mirror-glass", Some(150)),
    ]
    .into_iter()
    .enumerate()
    {
        if coarse.is_some() && backend == Backend::Gpu {
            // The shader skips one triangle per beam and applies no ring self-hit distance.
            notes.push(format!("{name} with a coarse S mesh on the CPU only"));
            continue;
        }
        let mut scene = scene::builtin(name).map_err(|e| e.to_string())?;
        scene.smesh.rest = coarse.map(Simplify::Faces);
        let smesh = SMesh::of(&scene);
        if coarse.is_some() && smesh.coarse_faces() == 0 {
            return Err(format!("{name}: no coarse S mesh"));
        }
        let eye = scene.camera.position;
        let extent = scene.bvh.nodes[0].bounds().extent().length();
        // Per face: reflection beams, through glass the refraction beams too (000 §7.2), S1 and S3;
        // on a bumpy mirror the perturbed beam (000 §6.3, eq. 5 bounding triangles).
        let mut beams: Vec<(Beam, &beam_render::nonlinear::SFace, usize)> = Vec::new();
        for (i, f) in smesh.faces.iter().enumerate().step_by(3).filter(|&(i, _)| smesh.spawns_beams(i)) {
            let dirs = f.reflected_directions(eye);
            let mut sets = vec![dirs];
            if let scene::Material::Glass { ior } = scene.material(f.prim) {
                let entering = (f.v[0] - eye).dot(f.normal) < 0.0;
                sets.push([0, 1, 2].map(|i| {
                    let d = (f.v[i] - eye).normalize();
                    let n = if entering { f.n[i] } else { -f.n[i] };
                    beam_render::specular::dielectric(d, n, ior, entering).1.unwrap_or(d - d.dot(n) * n)
                }));
            }
            for dirs in sets {
                beams.extend(NonlinearBeam::s1(f.v, dirs).map(|b| (Beam::S1(b), f, i)));
                beams.extend(NonlinearBeam::new(f.v, dirs, S3 { normals: f.n }).map(|b| (Beam::S3(b), f, i)));
            }
            if let scene::Material::Mirror { bump, .. } = scene.material(f.prim)
                && bump.delta > 0.0
            {
                beams.extend(
                    NonlinearBeam::s1(f.v, dirs).map(|beam| {
                        (Beam::Bumped(BumpedBeam { beam: BumpBeam { beam, delta: bump.delta }, bump }), f, i)
                    }),
                );
            }
        }
        let size = |k: usize| if scene_index == 0 && k == 0 { LARGE_REGION } else { 16 };
        let jobs: Vec<BeamJob<'_>> = beams
            .iter()
            .enumerate()
            .map(|(k, (beam, _, i))| BeamJob { beam, size: size(k), exclude: smesh.exclude(*i) })
            .collect();
        let textures = match crate::renderer::with_renderer(backend, &scene, |r| {
            r.render_beams(&scene, &jobs).map_err(|e| e.to_string())
        })? {
            Ok(t) => t,
            Err(skipped) => return Ok(skipped),
        };
        let results: Vec<Result<(u64, u64), String>> = beams
            .par_iter()
            .zip(textures)
            .map(|((beam, f, i), tex)| {
                let exclude = smesh.exclude(*i);
                let neighbour =
                    |p: u32| scene.triangles[p as usize].v.iter().any(|v| f.v.contains(v)) || exclude.near(p);
                let lift = beam.texel_beam().lift().max(exclude.thickness);
                let (mut n, mut ties) = (0u64, 0u64);
                let stride = (tex.size / 16).max(1) as usize;
                for y in (0..tex.size).step_by(stride) {
                    for x in (0..tex.size).step_by(stride) {
                        // Texels strictly inside the base: the margin and the diagonal row lie on the
                        // base's edge, where rays graze the neighbouring faces (and where a rare miss
                        // is still open, see docs/guide.md).
                        if x + y + 1 >= tex.size {
                            continue;
                        }
                        let ray = beam.ray_at(tex.barycentric(x, y));
                        let t_min = 1e-4 * extent / ray.direction.length();
                        // The distance below which a neighbour's hit is the surface meeting itself
                        // (S^n origins off the flat base, a coarse face's fine surface off its plane).
                        let normal = beam.texel_beam().base_normal();
                        let t_near = self_hit_at(lift, normal, ray, extent) / ray.direction.length();
                        // Closest hit beyond t_min that is not the surface under the base nor a
                        // neighbour's before t_near.
                        let mut expected = None;
                        let mut t0 = t_min;
                        while let Some(h) = scene
                            .wide
                            .closest_hit(Ray::new(ray.origin + ray.direction * t0, ray.direction), f32::INFINITY)
                        {
                            let self_hit = neighbour(h.prim) && h.t + t0 < t_near;
                            if !exclude.skips(h.prim) && !self_hit {
                                expected = Some((h.prim, h.t + t0));
                                break;
                            }
                            t0 += h.t + t_min;
                        }
                        let got = tex.hits[(y * tex.size + x) as usize].map(|h| (h.prim, h.t));
                        // The texel's hit is a real intersection of its ray, and no hit the ray
                        // tracer finds is nearer (a ray from the offset origin may miss a grazing
                        // hit on a neighbouring face that the texel keeps).
                        let real = |prim: u32, t: f32| {
                            WatertightRay::new(ray)
                                .intersect(&scene.triangles[prim as usize], t_min, f32::INFINITY)
                                .is_some_and(|h| (h.t - t).abs() <= t_min + 1e-3 * t)
                        };
                        // A hit at the ray tracer's depth on another triangle is the same point of a
                        // shared edge, which f32 gives to either (the GPU's fragment test is not the
                        // CPU's watertight one).
                        let tie = |ta: f32, tb: f32| (ta - tb).abs() <= t_min + 1e-5 * tb;
                        let agree = match (got, expected) {
                            (None, None) => true,
                            (Some((a, ta)), Some((_, tb))) => {
                                let nearest = real(a, ta) && ta <= tb + t_min + 1e-3 * tb;
                                ties += u64::from(!nearest && tie(ta, tb));
                                nearest || tie(ta, tb)
                            }
                            (Some((a, ta)), None) => real(a, ta),
                            (None, Some(_)) => false,
                        };
                        if !agree {
                            let kind = match beam {
                                Beam::S1(_) => "S1",
                                Beam::S3(_) => "S3",
                                Beam::Bumped(_) => "bumped",
                            };
                            let near = expected.is_some_and(|(p, _)| neighbour(p));
                            return Err(format!(
                                "{name}: face {i} (triangle {}) {kind} texel ({x}, {y}): beam {got:?}, ray {expected:?} \
                                 (a neighbour's: {near}; self-hit distance {t_near}, lift {lift})",
                                f.prim
                            ));
                        }
                        n += 1;
                    }
                }
                Ok((n, ties))
            })
            .collect();
        let (mut n, mut ties) = (0, 0);
        for r in results {
            let (a, b) = r?;
            (n, ties) = (n + a, ties + b);
        }
        let what = coarse.map_or(String::new(), |_| {
            format!(" ({} coarse S faces, {} too folded for beams)", smesh.coarse_faces(), smesh.faces_by_rays())
        });
        notes.push(format!("{name}{what}: {} beams, {n} texels ({ties} edge ties)", beams.len()));
        checked += n;
    }
    Ok(Outcome { cases: checked, note: format!("0 mismatches; {}", notes.join(", ")) })
}

/// The nonlinear renderer (beam trees of S1 and S3 beams, two levels, 48 texels per side at most,
/// the area lights' caustics by 2 × 2 strata of 24 texels per side) against the ray-traced ground truth (Whitted rays
/// about the interpolated normals, caustics by 1M photons from the whole area), at 128², on the
/// mirror and glass spheres at two S-mesh resolutions, the facing mirrors, the coarse glass lens and
/// the bump-mapped mirror: PSNR ≥ 33 dB, with the backend's renderer (the GPU's: atlases, rays and
/// its shading, area lights by 64 stratified shadow rays). (The lake's caustics are checked on
/// their irradiance maps by `caustics_match_photon_tracing`: at 128² an image comparison there
/// measures the photon noise of the reference.)
pub fn nonlinear_images_vs_reference(backend: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_cpu::nonlinear::CpuBeams;
    use beam_cpu::nonlinear::render_smooth_reference;
    use beam_render::nonlinear::Degree;
    use beam_render::nonlinear::{CAUSTIC_STRATA, NonlinearOptions, render_nonlinear_with};
    let shading = RenderOptions::exact(128, 128);
    let mut notes = Vec::new();
    // On a software GPU (lavapipe), rasterizing the area light's caustic beams off the spheres takes
    // 2-3 minutes a scene (9 s without them): there only the lens and the facing mirrors.
    let heavy = ["mirror-glass", "mirror-glass-coarse", "bumpy-mirror"];
    let software = crate::property::software_gpu(backend);
    for name in ["mirror-glass", "mirror-glass-coarse", "facing-mirrors", "glass-lens-coarse", "bumpy-mirror"] {
        if software && heavy.contains(&name) {
            notes.push(format!("{name} not on a software GPU"));
            continue;
        }
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let reference = render_smooth_reference(&scene, &shading, 1_000_000);
        // One renderer (on the GPU: one device and pipeline set) for both degrees.
        let images = crate::renderer::with_renderer(backend, &scene, |r| {
            [Degree::S1, Degree::S3]
                .map(|degree| {
                    let options =
                        NonlinearOptions { degree, texels: 48, bounces: 2, caustic_strata: CAUSTIC_STRATA, shading };
                    Ok((degree, render_nonlinear_with(&scene, &options, r, &CpuBeams).map_err(|e| e.to_string())?.0))
                })
                .into_iter()
                .collect::<Result<Vec<_>, String>>()
        })?;
        let images = match images {
            Ok(images) => images,
            Err(skipped) => return Ok(skipped),
        };
        for (degree, image) in images {
            let d = difference(&image, &reference).map_err(|e| e.to_string())?;
            if d.psnr < 33.0 {
                return Err(format!("{name} {degree:?}: PSNR {:.1} dB", d.psnr));
            }
            notes.push(format!("{name} {degree:?} {:.1} dB", d.psnr));
        }
    }
    let rendered = notes.iter().filter(|n| n.ends_with(" dB")).count() as u64;
    Ok(Outcome { cases: rendered * 128 * 128, note: notes.join(", ") })
}

/// 000 Fig. 4: on a coarse S mesh (the 8 × 16 mirror sphere of `mirror-glass-coarse`) S1's linearly
/// interpolated directions bend reflected lines at every S-mesh edge, while S3 is C¹ at the vertices.
/// Ground truth: the smooth sphere itself, approximated by the 24 × 48 mesh of `mirror-glass` traced
/// by rays. Over the pixels where both scenes see the mirror sphere (its silhouette excluded, where
/// the meshes differ), S3's PSNR must exceed S1's by 1 dB; and on the faces away from the silhouette,
/// S3's ray directions must be nearer the sphere's true reflections (at the radial projection of the
/// ray origin) than S1's.
pub fn s3_removes_s1_kinks(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_cpu::nonlinear::{render_nonlinear, render_smooth_reference};
    use beam_render::image::srgb_encode;
    use beam_render::nonlinear::Degree;
    use beam_render::nonlinear::{CAUSTIC_STRATA, NonlinearOptions};
    use beam_scene::scene::Material;
    let size = 256;
    let shading = RenderOptions::exact(size, size);
    let (coarse, fine) = (
        scene::builtin("mirror-glass-coarse").map_err(|e| e.to_string())?,
        scene::builtin("mirror-glass").map_err(|e| e.to_string())?,
    );
    let mirror_at = |scene: &scene::Scene| -> Vec<bool> {
        let camera = scene.camera.with_size(size, size);
        let frame = camera.frame();
        (0..(size * size) as usize)
            .map(|i| {
                let ray = camera.pixel_ray(&frame, i);
                scene
                    .wide
                    .closest_hit(ray, f32::INFINITY)
                    .is_some_and(|h| matches!(scene.material(h.prim), Material::Mirror { .. }))
            })
            .collect()
    };
    let (a, b) = (mirror_at(&coarse), mirror_at(&fine));
    let n = size as usize;
    let mask: Vec<usize> = (0..n * n)
        .filter(|&i| {
            let (x, y) = (i % n, i / n);
            x > 1
                && y > 1
                && x + 2 < n
                && y + 2 < n
                && [0, 1, 2, n, 2 * n].iter().all(|&d| a[i - d] && b[i - d] && a[i + d] && b[i + d])
        })
        .collect();
    let truth = render_smooth_reference(&fine, &shading, 1_000_000);
    let psnr = |degree| {
        let (image, _) = render_nonlinear(
            &coarse,
            &NonlinearOptions { degree, texels: 32, bounces: 2, caustic_strata: CAUSTIC_STRATA, shading },
        )
        .expect("a two-level tree fits");
        let sum: f64 = mask
            .iter()
            .map(|&i| {
                let d = image.pixels[i].map(srgb_encode) - truth.pixels[i].map(srgb_encode);
                f64::from(d.length_squared())
            })
            .sum();
        -10.0 * (sum / (3 * mask.len()).max(1) as f64).log10()
    };
    // The direction fields themselves: S1 and S3 rays of each face's reflection beam against the
    // sphere's true reflection at the radial projection of the ray origin.
    let (centre, radius) = (Vec3::new(185.0, 90.0, 170.0), 90.0);
    let eye = coarse.camera.position;
    let smesh = beam_render::nonlinear::SMesh::specular(&coarse);
    let (mut e1, mut e3, mut m) = (0.0f64, 0.0f64, 0u32);
    for f in smesh.faces.iter().filter(|f| matches!(coarse.material(f.prim), Material::Mirror { .. })) {
        let dirs = f.reflected_directions(eye);
        let (Some(b1), Some(b3)) = (
            beam_math::nonlinear::NonlinearBeam::s1(f.v, dirs),
            beam_math::nonlinear::NonlinearBeam::new(f.v, dirs, beam_math::nonlinear::S3 { normals: f.n }),
        ) else {
            continue;
        };
        // Away from the silhouette, where reflections graze and boundary directions are clamped.
        if (0..3).any(|i| (f.v[i] - eye).normalize().dot(f.n[i]).abs() < 0.5) {
            continue;
        }
        for (i, j) in [(1, 1), (2, 1), (1, 2), (3, 1), (2, 2), (1, 3)] {
            let w = Vec3::new((5 - i - j) as f32, i as f32, j as f32) / 5.0;
            let truth = |o: Vec3| {
                let p = centre + radius * (o - centre).normalize();
                let n = (p - centre).normalize();
                beam_render::specular::reflect((p - eye).normalize(), n)
            };
            let r1 = b1.ray_at(w);
            let r3 = b3.ray_at(w);
            e1 += f64::from(r1.direction.normalize().angle_between(truth(r1.origin)).powi(2));
            e3 += f64::from(r3.direction.normalize().angle_between(truth(r3.origin)).powi(2));
            m += 1;
        }
    }
    let (e1, e3) = ((e1 / f64::from(m)).sqrt().to_degrees(), (e3 / f64::from(m)).sqrt().to_degrees());
    let (s1, s3) = (psnr(Degree::S1), psnr(Degree::S3));
    let note = format!(
        "{} sphere pixels vs the smooth sphere: S1 {s1:.2} dB, S3 {s3:.2} dB; ray directions at {m} points: S1 {e1:.2}°, S3 {e3:.2}° rms",
        mask.len()
    );
    if mask.len() < 1000 || s3 < s1 + 1.0 || e3 >= e1 {
        return Err(note);
    }
    Ok(Outcome { cases: mask.len() as u64 + u64::from(m), note })
}

/// 000 §9.2, Fig. 13: the caustics and nonlinear shadows under the wavy lake's surface by light
/// beams (S1 and S3, 32 texels per side) against photon tracing through the same surface (rays
/// refracted about the interpolated normals at each photon's own point). Photon maps carry noise
/// that falls as 1/√N: the beam map's relative RMS difference from a 16M-photon map must lie within
/// 1.5× that of an independent 4M-photon map (whose own noise is twice the 16M map's), and the
/// total flux must agree within 1%.
pub fn caustics_match_photon_tracing(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_render::nonlinear::Degree;
    use beam_render::nonlinear::{CAUSTIC_STRATA, caustics_by_beams, caustics_by_photons};
    let scene = scene::builtin("wavy-lake").map_err(|e| e.to_string())?;
    let truth = caustics_by_photons(&scene, 16_000_000, 1).ok_or("no caustics")?;
    let photons = caustics_by_photons(&scene, 4_000_000, 2).ok_or("no caustics")?;
    let noise = photons.relative_rms(&truth);
    let mut notes = vec![format!("4M photons {noise:.3}")];
    for degree in [Degree::S1, Degree::S3] {
        let (beams, stats) = caustics_by_beams(&scene, degree, 32, CAUSTIC_STRATA, &beam_cpu::nonlinear::CpuBeams)
            .map_err(|e| e.to_string())?
            .ok_or("no caustics")?;
        let error = beams.relative_rms(&truth);
        let (a, b) = (beams.total_flux().element_sum(), truth.total_flux().element_sum());
        let note = format!("{degree:?} {error:.3} ({} beams, flux ratio {:.4})", stats.beams, a / b);
        if error > 1.5 * noise || (a / b - 1.0).abs() > 0.01 {
            return Err(format!("relative RMS vs 16M photons: {note}; {}", notes.join(", ")));
        }
        notes.push(note);
    }
    Ok(Outcome { cases: 3, note: format!("irradiance map relative RMS vs 16M photons: {}", notes.join(", ")) })
}

/// An area light's caustics by `k × k` stratified emitters (000 §9.2 traces from point lights)
/// converge to the photon tracing of the whole area: on the coarse glass lens under its square
/// ceiling light (S1 light beams, 64 texels per side over `k`), against 16M photons, the irradiance
/// map's relative RMS difference falls from k = 1 to k = 4 by at least a third (the k² overlaid
/// point-light caustics blur towards the area's), and its total flux is within 3% for k = 2 and 4
/// (one emitter at the centre is a one-point quadrature of the area, about 5% off here; 1–2.5%
/// remains, about 1% of it where rays leave the lens's rim, as with a point light).
pub fn area_light_caustics_converge(_: Backend, _: &Config) -> Result<Outcome, String> {
    use beam_cpu::nonlinear::CpuBeams;
    use beam_render::nonlinear::Degree;
    use beam_render::nonlinear::{caustics_by_beams, caustics_by_photons};
    let scene = scene::builtin("glass-lens-coarse").map_err(|e| e.to_string())?;
    let truth = caustics_by_photons(&scene, 16_000_000, 1).ok_or("no caustics")?;
    let mut runs = Vec::new();
    for k in [1, 2, 4] {
        let (map, stats) =
            caustics_by_beams(&scene, Degree::S1, 64, k, &CpuBeams).map_err(|e| e.to_string())?.ok_or("no caustics")?;
        let error = map.relative_rms(&truth);
        let ratio = map.total_flux().element_sum() / truth.total_flux().element_sum();
        runs.push((k, error, ratio, format!("k={k}: {error:.3} ({} beams, flux ratio {ratio:.4})", stats.beams)));
    }
    let notes: Vec<_> = runs.iter().map(|r| r.3.clone()).collect();
    if runs.iter().any(|&(k, _, ratio, _)| k > 1 && (ratio - 1.0).abs() > 0.03) {
        return Err(format!("total flux off by more than 3%: {}", notes.join(", ")));
    }
    if runs[2].1 > runs[0].1 * 2.0 / 3.0 {
        return Err(format!("no convergence with k: {}", notes.join(", ")));
    }
    Ok(Outcome { cases: 3, note: format!("relative RMS vs 16M photons: {}", notes.join(", ")) })
}
