//! The tree's last level kept on the GPU (beam-gpu's `GpuLevelPoints`) against the host's texel
//! hits of the same level, its fits summed there against the host's, and the images rendered that
//! way against those with every level read back.

use super::beams::{face_beams, level_one_beams};
use super::device::adapter;
use super::pixels::PixelDifference;
use crate::property::{Backend, Config, Outcome};
use beam_cpu::nonlinear::CpuBeams;
use beam_gpu::nonlinear::GpuBeams;
use beam_gpu::shade::PointShader;
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_math::nonlinear::MIN_ELEVATION;
use beam_render::nonlinear::{Beam, BeamJob, BeamRasterizer, Degree, Exclude};
use beam_render::nonlinear::{CAUSTIC_STRATA, NonlinearOptions, render_nonlinear_with};
use beam_render::nonlinear::{EyeView, Fit, KeepLevel, KeptFrame, LevelLayout, SMesh, TexelHit};
use beam_render::options::RenderOptions;
use beam_scene::scene::{self, Simplify};
use std::collections::BTreeMap;

/// The layout of a level of `jobs` whose faces' scene triangles are `prims`: their regions one
/// after another.
fn layout_of(jobs: &[BeamJob<'_>], prims: impl Iterator<Item = u32>) -> LevelLayout {
    let mut layout = LevelLayout::default();
    for (job, prim) in jobs.iter().zip(prims) {
        layout.firsts.push(layout.len as u32);
        layout.prims.push(prim);
        layout.len += (job.size * job.size) as usize;
    }
    layout
}

/// Unit roundoff of f32.
const U: f32 = f32::EPSILON / 2.0;

/// How far the GPU's unit direction of a texel ray may be from the host's for a beam that is not
/// bumped. The S^n direction is a Bernstein sum of at most ten terms with nonnegative weights
/// (no cancellation) at the texel's barycentric point, and a normalization: first-order within
/// about 30 u (unit roundoffs) on each side however the GPU's compiler contracts `a·b + c` into
/// fused multiply-adds (that only drops roundings), with its divisions within 2.5 ULP and its
/// inverse square root within 2 ULP, so 3.6e-6 apart at most. 1e-5 (the sibling
/// `gpu_eye_view_equals_cpu`'s limit on primary rays) leaves room; lavapipe measures 2.4e-7.
const DIRECTION: f32 = 1e-5;

/// How far the GPU's hit point of a texel may be from the host's, apart from the direction's
/// error carried along the ray: the origin (a Bernstein sum of base points) and `o + t·d`, a few
/// roundings of the scene's largest coordinate on each side: 16 u of it (about 1e-6).
const ORIGIN: f32 = 16.0 * U;

/// The rounding of a bump map's tilt on each side, in units of `u·k·R` (`k = 2π/λ` its
/// wavenumber, `R` the scene's largest coordinate): the tilt is the sine of the phase
/// `k·(p_y + p_z)` of the base point `p = Σ ωᵢ Pᵢ`, whose few roundings are relative to the
/// coordinates. Measured on bumpy-mirror's 100,096 texels of level-1 bumped beams: the host's
/// tilt up to 1.6, the GPU's formula (reduced to one period, with and without FMA) up to 1.3,
/// against the exact tilt; 4 a side.
const TILT: f32 = 8.0 * U;

/// How far the GPU's unit direction of the texel ray of `beam` at `w` may be from the host's, in
/// a scene whose largest coordinate is `reach`: [`DIRECTION`], and for a bumped beam the tilt's
/// rounding carried through `perturb` (000 §6.3). That rotates the unit S1 direction `d` by
/// `δ·|tilt|` towards the tilt's direction `t` in the base plane: an error `ε` of the tilt moves
/// the angle by at most `δ·ε` and the plane of the rotation by `ε/(|tilt|·|d×t|)`, so the
/// direction by `δ·ε·(1 + 1/|d×t|)`. Rays grazing the base close to `t` are ill-conditioned, but
/// `|d×t| ≥ d·n ≥ MIN_ELEVATION` (the beam's directions are kept that far above its base). On
/// bumpy-mirror (`δ = 0.06`, `λ = 40`, `R = 555`) that is 1.9e-4 at its worst texel (`|d×t| =
/// 0.014`, elevation 0.013: there the host's f32 direction is 8.6e-6 from the exact one) and
/// 1e-5 + 7.5e-6 at `|d×t| = 0.5`. The former flat 1e-5 left no room for this: lavapipe's worst
/// was 9.3e-6 and the H200's (FMA-contracted) just over 1e-5; lavapipe's is now 0.12 of its
/// tolerance. A wrong tilt (its sign, its frame, its wavelength) moves directions by about
/// `δ·|tilt|`, 1e-2, and even a uniform 3e-5 on every bumped texel fails.
fn direction_tolerance(beam: &Beam, w: Vec3, reach: f32) -> f32 {
    let Beam::Bumped(bumped) = beam else { return DIRECTION };
    let s1 = &bumped.beam.beam;
    let base = Triangle { v: s1.base };
    let tilt = bumped.bump.tilt(&base, s1.normal, base.point(w));
    let u = (s1.base[1] - s1.base[0]).normalize_or_zero();
    let toward = (tilt.x * u + tilt.y * s1.normal.cross(u)).normalize_or_zero();
    let sine = s1.ray_at(w).direction.normalize_or_zero().cross(toward).length().max(MIN_ELEVATION);
    let tilt_error = TILT * std::f32::consts::TAU / bumped.bump.wavelength * reach;
    DIRECTION + bumped.beam.delta * (1.0 + 1.0 / sine) * tilt_error
}

/// The host's hit of a texel of the level, and how far the GPU's may be from it.
struct HostHit {
    /// The texel in the level's layout.
    texel: u32,
    /// The triangle hit.
    prim: u32,
    /// The hit point.
    p: Vec3,
    /// The texel ray's unit direction.
    d: Vec3,
    /// The point's seed.
    seed: u64,
    /// [`direction_tolerance`].
    d_within: f32,
    /// `ORIGIN·R` and the direction's tolerance times the distance from the ray's origin.
    p_within: f32,
}

/// The worst of the GPU's texel points against the host's so far.
#[derive(Clone, Copy, Default)]
struct Worst {
    /// The largest `|Δp|` over the scene's size.
    p: f32,
    /// The largest `|Δd|`.
    d: f32,
    /// The largest `|Δp|` or `|Δd|` over its tolerance.
    ratio: f32,
}

impl Worst {
    fn add(&mut self, want: &HostHit, p: Vec3, d: Vec3, extent: f32) {
        let (dp, dd) = ((p - want.p).length(), (d - want.d).length());
        self.p = self.p.max(dp / extent);
        self.d = self.d.max(dd);
        // (NaN counts as beyond: f32::max would drop it.)
        for ratio in [dp / want.p_within, dd / want.d_within] {
            self.ratio = if ratio.is_nan() { f32::INFINITY } else { self.ratio.max(ratio) };
        }
    }

    fn within(self) -> bool {
        self.ratio <= 1.0
    }
}

/// `render_level` on the level-1 beams off every third specular face of four built-ins (regions of
/// 16 and 9 texels a side in turn), by draws and by compute, against `render_beams` of the same
/// renderer, with the tree going on from no triangle, from the specular ones and from all: the
/// points `take_kept_levels` reads back are the host's texel hits on the other triangles one for
/// one — the same texels of the level's layout, triangles and seeds, the directions within
/// [`direction_tolerance`] (1e-5, more for bumped beams by their conditioning) and the hit points
/// within 16 u of the scene's largest coordinate plus that tolerance times the ray's length (the
/// texel rays made on the GPU, the host's on the CPU) — and so are the counts of points and of
/// points on curved triangles; the textures hold exactly the hits on triangles the tree goes on
/// from, as points in texel order within the same tolerances of the host's, or, asked for them,
/// every hit. A renderer reading levels back keeps none.
pub(super) fn gpu_kept_level_equals_host_texels(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let options = RenderOptions::exact(64, 64);
    let (mut points, mut notes) = (0u64, Vec::new());
    for (name, degree) in [
        ("mirror-glass-coarse", Degree::S3),
        ("facing-mirrors-coarse", Degree::S1),
        ("bumpy-mirror", Degree::S1),
        ("glass-lens-coarse", Degree::S3),
    ] {
        let scene = scene::builtin(name).map_err(|e| e.to_string())?;
        let bounds = scene.bounds();
        let extent = bounds.extent().length();
        let reach = bounds.min.abs().max(bounds.max.abs()).max_element();
        let beams = level_one_beams(&scene, degree);
        let jobs: Vec<BeamJob<'_>> = beams
            .iter()
            .enumerate()
            .map(|(i, (beam, prim))| BeamJob { beam, size: [16, 9][i % 2], exclude: Exclude::base(*prim) })
            .collect();
        let layout = layout_of(&jobs, beams.iter().map(|&(_, prim)| prim));
        let triangles = scene.triangles.len();
        let specular: Vec<bool> = (0..triangles as u32).map(|p| !PointShader::shades(&scene, p)).collect();
        let continuing = [("none", vec![false; triangles]), ("specular", specular), ("all", vec![true; triangles])];
        let keep = |continues, with_hits| KeepLevel {
            level: 1,
            layout: &layout,
            options: &options,
            with_hits,
            faces: 0,
            continues,
        };
        let fresh = || GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string());
        // (A renderer compiles every pipeline: one scene's is enough for this.)
        if name == "bumpy-mirror" {
            let mut reading_back = fresh()?.reading_levels_back();
            let level = reading_back.render_level(&scene, &jobs, &keep(&[], false), &mut KeptFrame::default());
            if level.map_err(|e| e.to_string())?.1.is_some() {
                return Err(format!("{name}: a renderer reading levels back kept a level"));
            }
        }
        let mut ways = vec![(fresh()?.rasterized(), "draws")];
        if GpuBeams::can_compute(&gpu) {
            ways.push((fresh()?, "compute"));
        }
        for (mut renderer, way) in ways {
            let textures = renderer.render_beams(&scene, &jobs).map_err(|e| e.to_string())?;
            // The host's texel hits of the level.
            let mut all = Vec::new();
            for (i, (job, tex)) in jobs.iter().zip(&textures).enumerate() {
                let (size, tb) = (job.size, job.beam.texel_beam());
                for (k, hit) in tex.hits.iter().enumerate() {
                    let Some(hit) = hit else { continue };
                    let (x, y) = (k as u32 % size, k as u32 / size);
                    let w = tex.barycentric(x, y);
                    let ray = tb.texel_ray(w);
                    let d_within = direction_tolerance(job.beam, w, reach);
                    let p = ray.at(hit.t);
                    all.push(HostHit {
                        texel: layout.firsts[i] + k as u32,
                        prim: hit.prim,
                        p,
                        d: ray.direction.normalize(),
                        seed: u64::from(layout.prims[i]) << 32 | k as u64,
                        d_within,
                        p_within: ORIGIN * reach + d_within * (p - ray.origin).length(),
                    });
                }
            }
            // Every hit asked for with the tree going on from the specular triangles only (a
            // coarse S mesh's lookups read them): the other two ways add nothing to it.
            let ways = continuing.iter().flat_map(|c| [(c, false), (c, true)]).filter(|(c, h)| !h || c.0 == "specular");
            for ((what, continues), with_hits) in ways {
                let fail = |m: String| format!("{name} by {way}, going on from {what} (hits: {with_hits}): {m}");
                let want: Vec<_> = all.iter().filter(|w| !continues[w.prim as usize]).collect();
                let curved = want.iter().filter(|w| scene.smooth_normals.contains_key(&w.prim)).count() as u64;
                let mut frame = KeptFrame::default();
                let level = renderer.render_level(&scene, &jobs, &keep(continues, with_hits), &mut frame);
                let (kept_textures, Some(totals)) = level.map_err(|e| e.to_string())? else {
                    return Err(fail("nothing kept".into()));
                };
                if (totals.points, totals.curved) != (want.len() as u64, curved) {
                    return Err(fail(format!("kept {totals:?}, the host has {} ({curved} curved)", want.len())));
                }
                // The hits handed back: every one asked for, else those the tree goes on from,
                // as texel points in texel order, each within the tolerances of the host's.
                let handed = |h: &Option<TexelHit>| h.filter(|h| with_hits || continues[h.prim as usize]);
                let mut worst_points = Worst::default();
                let mut hits_match = kept_textures.len() == textures.len();
                for (i, (k, t)) in kept_textures.iter().zip(&textures).enumerate() {
                    let full = || t.hits.iter().map(handed);
                    hits_match &= k.size == t.size;
                    if with_hits {
                        hits_match &= k.hits.iter().copied().eq(full()) && k.points.is_empty();
                        continue;
                    }
                    let square = layout.firsts[i]..layout.firsts[i] + t.size * t.size;
                    let want: Vec<_> =
                        all.iter().filter(|w| square.contains(&w.texel) && continues[w.prim as usize]).collect();
                    hits_match &= k.hits.is_empty() && k.points.len() == want.len();
                    for (g, w) in k.points.iter().zip(want) {
                        hits_match &= (layout.firsts[i] + g.texel, g.prim) == (w.texel, w.prim);
                        worst_points.add(w, g.p, g.d, extent);
                    }
                }
                if !hits_match || !worst_points.within() {
                    let Worst { p, d, ratio } = worst_points;
                    return Err(fail(format!(
                        "the textures' hits are not those handed back (points {p:.1e}, directions {d:.1e}, \
                         {ratio:.2} of their tolerances)"
                    )));
                }
                let taken = renderer.take_kept_levels(&mut frame).map_err(|e| e.to_string())?;
                let [(1, got)] = &taken[..] else {
                    return Err(fail(format!("{} levels taken", taken.len())));
                };
                let mut got = got.clone();
                got.sort_by_key(|t| t.texel);
                let mut worst = Worst::default();
                for (g, w) in got.iter().zip(&want) {
                    if (g.texel, g.point.prim, g.point.seed) != (w.texel, w.prim, w.seed) || g.composite.is_some() {
                        return Err(fail(format!("point {g:?}, the host's texel {}: triangle {}", w.texel, w.prim)));
                    }
                    worst.add(w, g.point.p, g.point.d, extent);
                }
                let Worst { p: worst_p, d: worst_d, ratio } = worst;
                if got.len() != want.len() || !worst.within() {
                    return Err(fail(format!(
                        "{} points read back for {}; points up to {worst_p:.1e} apart, directions {worst_d:.1e}, \
                         {ratio:.2} of their tolerances",
                        got.len(),
                        want.len()
                    )));
                }
                if !renderer.take_kept_levels(&mut frame).map_err(|e| e.to_string())?.is_empty() {
                    return Err(fail("points kept after they were taken".into()));
                }
                if !with_hits {
                    notes.push(format!(
                        "{name} by {way}, on from {what}: {} kept, points {worst_p:.1e}, directions {worst_d:.1e}, \
                         {ratio:.2} of their tolerances",
                        got.len()
                    ));
                }
                points += want.len() as u64;
            }
        }
    }
    Ok(Outcome { cases: points, note: notes.join("; ") })
}

/// Nonlinear images (64², two tree levels) by the GPU renderer keeping on the GPU what needs no host
/// (the levels' points, the eye's mirror and glass hits and their composite records, and those of
/// the texels the levels hand back) against the same renderer reading everything back (the host
/// makes them), on four built-ins (one under a coarse S mesh, whose composites look up every hit
/// of the level below): every level is kept, and so are pixels or texels (none read back), level
/// 1's texels on which the tree goes on are composited on the GPU (under coarse faces too), at most
/// 0.1% of the pixels differ by more than 4/255 (the texel rays made on the GPU instead of the
/// CPU), and the beams per level, the texels shaded and the specular points traced by rays are the
/// same.
pub(super) fn gpu_kept_level_images_equal_read_back(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (mut pixels, mut notes) = (0u64, Vec::new());
    for (name, degree, coarse) in [
        ("mirror-glass-coarse", Degree::S3, false),
        ("glass-lens-coarse", Degree::S3, false),
        ("wavy-lake-coarse", Degree::S1, false),
        ("mirror-glass", Degree::S3, true),
    ] {
        let mut scene = scene::builtin(name).map_err(|e| e.to_string())?;
        if coarse {
            scene.smesh.rest = Some(Simplify::Faces(60));
        }
        let options = NonlinearOptions {
            degree,
            texels: 32,
            bounces: 2,
            caustic_strata: CAUSTIC_STRATA,
            shading: RenderOptions::exact(64, 64),
        };
        let mut kept = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let mut read_back = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?.reading_levels_back();
        let (image, stats) =
            render_nonlinear_with(&scene, &options, &mut kept, &CpuBeams).map_err(|e| e.to_string())?;
        let (want, want_stats) =
            render_nonlinear_with(&scene, &options, &mut read_back, &CpuBeams).map_err(|e| e.to_string())?;
        let counts = |s: &beam_render::nonlinear::NonlinearStats| {
            (s.beams_per_level.clone(), s.texels_shaded, s.specular_by_rays)
        };
        // Points by rays: a curved point's side of a texel is an f32 decision on the GPU and on
        // the host, so one in a thousand may go the other way (1,102 against 1,101 on an AMD
        // EPYC's lavapipe); the beams and the texels must be equal.
        let (a, b) = (stats.specular_by_rays, want_stats.specular_by_rays);
        let same = |s: &beam_render::nonlinear::NonlinearStats| (s.beams_per_level.clone(), s.texels_shaded);
        let kept_somewhere = stats.kept_on_backend > 0 && want_stats.kept_on_backend == 0;
        if same(&stats) != same(&want_stats)
            || a.abs_diff(b) * 1_000 > a.max(b)
            || kept.times().levels_kept != stats.beams_per_level.len() as u64
            || !kept_somewhere
        {
            return Err(format!(
                "{name}: kept {:?} ({} on the GPU), read back {:?} ({})",
                counts(&stats),
                stats.kept_on_backend,
                counts(&want_stats),
                want_stats.kept_on_backend
            ));
        }
        if coarse != (stats.coarse_smesh_faces > 0) {
            return Err(format!("{name}: {} coarse S-mesh faces", stats.coarse_smesh_faces));
        }
        // Level 1's texels on which the tree goes on: composited on the GPU.
        let composited = kept.times().level_records;
        if (stats.beams_per_level.len() > 1) != (composited > 0) {
            return Err(format!("{name}: {composited} texels handed back composited on the GPU"));
        }
        let PixelDifference { differ, sum, n } = PixelDifference::of(&image, &want);
        if differ * 1000 > n || image.pixels.iter().all(|p| *p == Vec3::ZERO) {
            return Err(format!("{name}: {differ} of {n} pixels differ by more than 4/255"));
        }
        pixels += n;
        notes.push(format!(
            "{name}: {} texels shaded, {} pixels and texels kept on the GPU, mean difference {:.2}/255",
            stats.texels_shaded,
            stats.kept_on_backend,
            255.0 * sum / n as f64
        ));
    }
    Ok(Outcome { cases: pixels, note: notes.join("; ") })
}

/// The next level's fits summed on the GPU (beam-gpu's `FitTable`) against the host's sums of the
/// same texels: on a fine glass lens and a coarse S mesh (60 faces) of the mirror and glass, the
/// eye's view kept at 64² (its faces' candidates and corners go to the GPU), then the beams off
/// the S-mesh faces (regions of 16 texels a side) kept as level 1 with the tree going on from the
/// mirror and glass: the level reports its fits summed and hands no texel back; per beam, the
/// faces and sample counts equal those of the host's fits (`Fit::add`) of the texels
/// `kept_level_points` reads back, located by `SMesh::locate_on`, and every sum is within 2e-6 per
/// sample of the host's (the GPU's are in fixed point, the host's in f32); the same level kept
/// again gives the same bits.
pub(super) fn gpu_summed_fits_equal_host_fits(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let (mut samples, mut notes) = (0u64, Vec::new());
    for (name, coarse) in [("glass-lens-coarse", false), ("mirror-glass", true)] {
        let mut scene = scene::builtin(name).map_err(|e| e.to_string())?;
        if coarse {
            scene.smesh.rest = Some(Simplify::Faces(60));
        }
        let smesh = SMesh::of(&scene);
        let options = RenderOptions::exact(64, 64);
        let camera = scene.camera.with_size(64, 64);
        let mut renderer = GpuBeams::new(&gpu, &scene).map_err(|e| e.to_string())?;
        let (_, mut frame) = renderer.eye_faces(&scene, &smesh, &camera, &options).map_err(|e| e.to_string())?;
        let beams = face_beams(&scene, &smesh, (camera.position, Degree::S3), 0..smesh.faces.len());
        let jobs: Vec<BeamJob<'_>> =
            beams.iter().map(|(beam, f)| BeamJob { beam, size: 16, exclude: smesh.exclude(*f) }).collect();
        let layout = layout_of(&jobs, beams.iter().map(|(_, f)| smesh.faces[*f].prim));
        let continues: Vec<bool> = (0..scene.triangles.len() as u32).map(|p| !smesh.candidates(p).is_empty()).collect();
        let keep = KeepLevel {
            level: 1,
            layout: &layout,
            options: &options,
            with_hits: coarse,
            faces: smesh.faces.len(),
            continues: &continues,
        };
        let kept = |frame: &mut KeptFrame, renderer: &mut GpuBeams<'_>| {
            renderer.render_level(&scene, &jobs, &keep, frame).map_err(|e| e.to_string())
        };
        let (textures, totals) = kept(&mut frame, &mut renderer)?;
        if !totals.is_some_and(|t| t.fits) || textures.iter().any(|t| !t.points.is_empty()) {
            return Err(format!("{name}: fits not summed on the GPU ({totals:?})"));
        }
        let points = renderer.kept_level_points(1, &frame).map_err(|e| e.to_string())?;
        if points.len() != jobs.len() {
            return Err(format!("{name}: texels of {} beams read back for {}", points.len(), jobs.len()));
        }
        let mut worst = 0.0f32;
        for (i, (tex, points)) in textures.iter().zip(&points).enumerate() {
            let mut on: BTreeMap<u32, Fit> = BTreeMap::new();
            for h in points {
                if let Some((face, w)) = smesh.locate_on(h.prim, h.face, h.p) {
                    on.entry(face as u32).or_default().add(w, h.d);
                }
            }
            let shape = |fits: &mut dyn Iterator<Item = (u32, Fit)>| {
                fits.map(|(f, fit)| (f, fit.samples())).collect::<Vec<_>>()
            };
            if shape(&mut tex.fits.iter().copied()) != shape(&mut on.iter().map(|(f, fit)| (*f, *fit))) {
                return Err(format!("{name}, beam {i}: faces and samples {:?}, the host's {:?}", tex.fits, on));
            }
            for ((_, got), want) in tex.fits.iter().zip(on.values()) {
                let ((g, m), (wg, wm)) = (got.sums(), want.sums());
                let apart = (g - wg)
                    .to_cols_array()
                    .into_iter()
                    .chain((m - wm).to_cols_array())
                    .fold(0.0f32, |a, x| a.max(x.abs()));
                worst = worst.max(apart / got.samples() as f32);
                samples += got.samples() as u64;
            }
        }
        if worst > 2e-6 {
            return Err(format!("{name}: sums up to {worst:.1e} a sample from the host's"));
        }
        let (again, _) = kept(&mut frame, &mut renderer)?;
        if textures.iter().zip(&again).any(|(a, b)| a.fits != b.fits) {
            return Err(format!("{name}: the same level summed to other bits"));
        }
        let pairs: usize = textures.iter().map(|t| t.fits.len()).sum();
        notes.push(format!("{name}: {pairs} (beam, face) fits, sums within {worst:.0e} a sample"));
    }
    Ok(Outcome { cases: samples, note: notes.join("; ") })
}
