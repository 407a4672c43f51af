//! The ray queries and point shading of [`GpuBeams`] as a backend of the nonlinear renderer: rays
//! by the compute ray tracer, points by the shading pass and Whitted waves, the beam tree's
//! radiance by the composite on the GPU (the frame's last stage, which consumes what the frame
//! kept, [`GpuKept`]), a coarse S mesh's lookups by `lookups.wgsl`.

use super::composite::{GpuComposite, KeptHere};
use super::eye::fine_faces;
use super::kept::GpuKept;
use super::level::KeptLevel;
use super::renderer::GpuBeams;
use super::whitted::{GpuWhitted, RestJob, RestPoints};
use crate::GpuError;
use crate::buffers::{checked, output, read_all, storage};
use crate::checks::ShadeChecks;
use crate::raytrace::{GpuHit, GpuRay, closest_of, occluded_of};
use crate::shade::ShadeInput;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::cut_outs::{blocked_there, closest_there};
use beam_render::irradiance_map::IrradianceMap;
use beam_render::nonlinear::{
    Beam, BeamTexture, ChildLookups, CoarseByRays, DeviceImage, DeviceWaits, FramePixels, KeptFrame, LevelRadiance,
    LookupJob, PointShading, SMesh, ShadePoint, TreeShading,
};
use beam_render::options::RenderOptions;
use beam_render::queries::RayQueries;
use beam_scene::scene::Scene;
use rayon::prelude::*;
use std::time::Instant;

impl GpuBeams<'_> {
    /// `rays` traced on the GPU (in dispatches that fit its bindings), timed as ray time.
    fn trace(&self, rays: Vec<GpuRay>) -> Result<Vec<GpuHit>, GpuError> {
        let start = Instant::now();
        let out = checked(self.gpu, || self.tracer.trace(self.gpu, &rays));
        self.add_times(|t| t.ray_seconds += start.elapsed().as_secs_f64());
        out
    }

    /// Exact shading of `points` on the GPU: diffuse, glossy and emissive points by the shading
    /// pass; mirrors and glass by Whitted rays traced on the GPU in waves ([`GpuWhitted`]), the
    /// points they end on shaded by the same pass.
    fn shade_exact(&mut self, caustics: Option<&IrradianceMap>, points: &[ShadePoint]) -> Result<Vec<Vec3>, GpuError> {
        let start = Instant::now();
        let prepared = self.shader.prepare(self.gpu, caustics);
        let mut out = Vec::with_capacity(points.len());
        for part in points.chunks(GpuWhitted::per_dispatch(self.gpu)) {
            let bytes = (part.len() * 16) as u64;
            let part: Vec<ShadeInput> = part.par_iter().map(ShadeInput::new).collect();
            let radiance: Vec<[f32; 4]> = checked(self.gpu, || {
                let radiance = output(self.gpu, "radiance", bytes);
                let job = RestJob { points: RestPoints::Host(&part), radiance: &radiance, first: 0 };
                self.whitted.shade_into(
                    self.gpu,
                    &self.tracer,
                    (&self.shader, &prepared, self.light_samples),
                    &[job],
                    None,
                )?;
                read_all(self.gpu, Vec::new(), std::iter::once((&radiance, bytes)))
            })?;
            out.extend(radiance.iter().map(|r| Vec3::new(r[0], r[1], r[2])));
        }
        self.add_times(|t| t.shade_seconds += start.elapsed().as_secs_f64());
        Ok(out)
    }
}

/// The coarse S mesh's lookups by `lookups.wgsl`, in f32.
impl ChildLookups for GpuBeams<'_> {
    fn looks_up(&self) -> bool {
        true
    }

    fn child_lookups(
        &self,
        beams: &[(&Beam, &BeamTexture)],
        jobs: &[LookupJob],
    ) -> Result<Option<Vec<(Vec3, f32)>>, BackendError> {
        let answers = self.lookups.run(self.gpu, beams, jobs)?;
        if answers.is_some() {
            self.add_times(|t| t.lookups += jobs.len() as u64);
        }
        Ok(answers)
    }
}

impl DeviceWaits for GpuBeams<'_> {
    fn waited_seconds(&self) -> f64 {
        self.gpu.traffic().waited_seconds
    }
}

impl GpuBeams<'_> {
    /// The nearest hit of each of `rays` by the compute ray tracer, whatever its surface.
    fn nearest(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        Ok(closest_of(scene, rays, self.trace(rays.par_iter().map(GpuRay::closest).collect())?))
    }
}

/// By the compute ray tracer, which tests no alpha: in a scene with cut-outs, each hit on one is
/// checked on the host and the ray sent on past it ([`beam_render::cut_outs`]).
impl RayQueries for GpuBeams<'_> {
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        closest_there(scene, rays, |rays| self.nearest(scene, rays))
    }

    fn any_hits(&self, scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        let blocked = occluded_of(&self.trace(segments.par_iter().map(|(r, t_max)| GpuRay::any(r, *t_max)).collect())?);
        blocked_there(scene, segments, blocked, |rays| self.nearest(scene, rays))
    }
}

impl PointShading for GpuBeams<'_> {
    fn shade_points(
        &mut self,
        _scene: &Scene,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Result<Option<Vec<Vec3>>, BackendError> {
        // The GPU's shading pass does exact shading (001 eq. 1 by shadow rays) of constant
        // materials only.
        if !self.shades(options) {
            return Ok(None);
        }
        self.shade_exact(caustics, points).map(Some).map_err(BackendError::from)
    }

    fn shade_tree(
        &mut self,
        scene: &Scene,
        smesh: &SMesh,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        levels: &[LevelRadiance],
        frame: KeptFrame,
    ) -> Result<TreeShading, BackendError> {
        if !self.shades(options) || !GpuComposite::fits(self.gpu, levels) {
            return Ok(TreeShading::HandedBack(frame));
        }
        // Points under coarse faces (the eye's, a level's) look their child beams up in the level
        // below theirs, and their faces among the eye's candidates: where a level did not fit one
        // binding, the host composites the frame.
        if smesh.coarse_faces() > 0 {
            let state = frame.get::<GpuKept>();
            let child_levels = state.map_or(&[][..], |k| &k.child_levels);
            let kept_levels = state.map_or(&[][..], |k| &k.levels);
            let has = |l: usize| l >= levels.len() || child_levels.iter().any(|(c, _)| *c == l);
            let located = state.is_some_and(|k| k.eye_hits.is_some());
            let ready =
                (!located || has(1)) && kept_levels.iter().all(|l| l.host.is_empty() || (located && has(l.level + 1)));
            if !ready {
                return Ok(TreeShading::HandedBack(frame));
            }
        }
        let start = Instant::now();
        // The frame's kept points and hits, consumed here.
        let GpuKept { eye_points, eye_hits, levels: kept_levels, child_levels } =
            frame.into_inner::<GpuKept>().unwrap_or_default();
        let kept = eye_points.unwrap_or_default();
        let far = self.extent;
        // What the records under coarse faces of level `level` (0: the eye's) read.
        let coarse = |level: usize| {
            let child_level = child_levels.iter().find(|(l, _)| *l == level + 1).map(|(_, b)| b);
            let locate = eye_hits.as_ref().map(|k| &k.locate);
            self.eye.coarse(locate, child_level, &self.whitted, far)
        };
        // The eye's mirror and glass hits kept on the GPU: their composite records.
        let records = match (&eye_hits, levels.first()) {
            (Some(k), Some(eye)) => {
                let children = storage(self.gpu, "eye children", &eye.children, wgpu::BufferUsages::empty());
                checked(self.gpu, || self.eye.records(self.gpu, k, &children, &coarse(0)))?
            }
            _ => Vec::new(),
        };
        // The records of the texels the levels handed to the host, where the GPU composites them.
        let made;
        let face_of = match &eye_hits {
            Some(k) => &k.face_of,
            None => {
                made = fine_faces(self.gpu, scene, smesh);
                &made
            }
        };
        let level_records = checked(self.gpu, || {
            let of = |l: &KeptLevel| {
                let level = levels.get(l.level).ok_or(GpuError::Internal("a kept level past the tree"))?;
                if l.host.is_empty() {
                    return Ok(Vec::new());
                }
                if level.node_children.is_empty() {
                    return Err(GpuError::Internal("texels handed back without their beams' children"));
                }
                self.atlas.level.records(self.gpu, l, (face_of, &level.node_children), &coarse(l.level))
            };
            kept_levels.iter().map(of).collect::<Result<Vec<_>, _>>()
        })?;
        let composited: u64 = level_records.iter().flatten().map(|r| u64::from(r.count + r.rest.count)).sum();
        let all_records = || records.iter().chain(level_records.iter().flatten());
        let coarse_count = |i: usize| all_records().map(|r| u64::from(r.coarse[i])).sum::<u64>();
        self.add_times(|t| {
            t.level_records += composited;
            t.coarse_records += coarse_count(0);
        });
        let coarse_by_rays = CoarseByRays { uncovered: coarse_count(1), curved: coarse_count(2) };
        // Per level of the flow (the eye's first), the points kept on the GPU.
        let mut here = vec![KeptHere::default(); levels.len()];
        here[0] = KeptHere { direct: &kept, rest: &[], records: &records };
        for (l, records) in kept_levels.iter().zip(&level_records) {
            let at = here.get_mut(l.level).ok_or(GpuError::Internal("a kept level past the tree"))?;
            *at = KeptHere { direct: &l.direct, rest: &l.other, records };
        }
        // Mirror and glass points past the tree by Whitted rays, their host time apart.
        // The scene's shading and caustics, uploaded once for the composite and every wave.
        let prepared = self.shader.prepare(self.gpu, caustics);
        let rest = |jobs: &[RestJob<'_>], checks: &mut ShadeChecks| {
            let (start, waited) = (Instant::now(), self.gpu.traffic().waited_seconds);
            let shading = (&self.shader, &prepared, self.light_samples);
            let out = self.whitted.shade_into(self.gpu, &self.tracer, shading, jobs, Some(checks));
            let host = start.elapsed().as_secs_f64() - (self.gpu.traffic().waited_seconds - waited);
            self.add_times(|t| t.whitted_host_seconds += host);
            out
        };
        // A displayed frame's texture has the image's shape; one read back, the texels' layout
        // (whose rows are whole copy alignments).
        let shape = self.display.then_some((options.width, options.height));
        let composite = |checks: &mut ShadeChecks| {
            let (scene, shading) = ((scene, smesh), &prepared);
            let frame = self.composite.run(
                self.gpu,
                &self.tracer,
                &self.shader,
                scene,
                shading,
                self.light_samples,
                levels,
                &here,
                &rest,
                shape,
                checks,
            )?;
            Ok(frame)
        };
        let pixels = checked(self.gpu, || {
            let frame = self.shader.shade_checked(self.gpu, composite)?;
            if self.display {
                return Ok(FramePixels::Kept(DeviceImage::new(frame)));
            }
            frame.read_back(self.gpu).map(FramePixels::Read)
        });
        self.add_times(|t| {
            t.shade_seconds += start.elapsed().as_secs_f64();
            t.gpu_composites += u64::from(pixels.is_ok());
        });
        Ok(TreeShading::Shaded { pixels: pixels?, coarse_by_rays })
    }
}
