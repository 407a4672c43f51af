//! The eye's stage of a frame on [`GpuBeams`] (000 §7.3): the eye's view by [`GpuEye`] where the
//! composite will shade the frame, its kept points and hits returned in the frame's value
//! ([`GpuKept`]) and read back from it for a frame the caller shades after all.

use super::composite::GpuComposite;
use super::eye::{EyeFaceMap, EyeHit, EyeOut, KeptEyeHits, fine_faces};
use super::kept::GpuKept;
use super::records::LocateTable;
use super::renderer::GpuBeams;
use crate::GpuError;
use crate::buffers::{checked, read_all};
use crate::shade::ShadeInput;
use crate::texels;
use beam_bvh::Hit;
use beam_math::glam::Vec3;
use beam_math::{Ray, Triangle};
use beam_render::BackendError;
use beam_render::nonlinear::{EyeFaces, EyeView, KeptFrame, PixelHits, SMesh, ShadePoint, TexelRadiance, eye_by_rays};
use beam_render::options::RenderOptions;
use beam_scene::scene::{Camera, Scene};
use rayon::prelude::*;
use std::time::Instant;

impl GpuBeams<'_> {
    /// The eye's view on the GPU with `faces` (where given, its mirror and glass hits on them kept),
    /// or `None` where the composite will not shade the frame (the GPU does not shade it,
    /// [`GpuBeams::shades`], or the eye's level is past one texture).
    fn eye_on_gpu(
        &self,
        camera: &Camera,
        options: &RenderOptions,
        faces: Option<EyeFaceMap<'_>>,
    ) -> Result<Option<EyeOut>, GpuError> {
        let pixels = camera.width as usize * camera.height as usize;
        if !self.shades(options) || !texels::fits(self.gpu, pixels) {
            return Ok(None);
        }
        let start = Instant::now();
        let out = checked(self.gpu, || self.eye.run(self.gpu, &self.tracer, camera, options.region(), faces));
        self.add_times(|t| t.ray_seconds += start.elapsed().as_secs_f64());
        Ok(Some(out?))
    }

    /// `hits` (the tracer's triangle and t) as `(pixel, ray, hit)` with the barycentric weights of
    /// each hit point. Written in place by an indexed collect where every hit names a triangle of
    /// the scene (a filtered collect gathers lists and copies them once more).
    fn eye_hits(scene: &Scene, camera: &Camera, hits: &[EyeHit]) -> Vec<(usize, Ray, Hit)> {
        let frame = camera.frame();
        let hit = |h: &EyeHit, tri: &Triangle| {
            let ray = camera.pixel_ray(&frame, h.pixel as usize);
            (h.pixel as usize, ray, Hit::on(tri, h.prim, &ray, h.t))
        };
        let on = |h: &EyeHit| scene.triangles.get(h.prim as usize);
        if hits.par_iter().all(|h| on(h).is_some()) {
            let mut out = Vec::with_capacity(hits.len());
            hits.par_iter().map(|h| hit(h, &scene.triangles[h.prim as usize])).collect_into_vec(&mut out);
            return out;
        }
        hits.par_iter().filter_map(|h| Some(hit(h, on(h)?))).collect()
    }
}

impl EyeView for GpuBeams<'_> {
    /// On the GPU (`GpuEye`) where the composite will shade the frame (the GPU shades it, the eye's
    /// level within one texture): the diffuse, glossy and emissive pixels of the region are kept
    /// there, in the frame's `GpuKept`. Otherwise by the compute ray tracer, keeping none.
    fn eye_view(
        &self,
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Result<(PixelHits, KeptFrame), BackendError> {
        let Some(out) = self.eye_on_gpu(camera, options, None)? else {
            return Ok((eye_by_rays(self, scene, camera)?, KeptFrame::default()));
        };
        let kept = GpuKept { eye_points: Some(out.kept), ..GpuKept::default() };
        Ok((Self::eye_hits(scene, camera, &out.others), KeptFrame::new(kept)))
    }

    /// Keeps the mirror and glass hits on S-mesh faces too, fine or coarse, each at its face
    /// (under a coarse one, the candidate its point lies nearest), unless
    /// [`GpuBeams::reading_levels_back`], where the composite takes the whole S mesh in one
    /// binding.
    fn eye_faces(
        &self,
        scene: &Scene,
        smesh: &SMesh,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Result<(EyeFaces, KeptFrame), BackendError> {
        if !self.atlas.keep_levels || !GpuComposite::faces_fit(self.gpu, smesh.faces.len()) {
            let (hits, frame) = self.eye_view(scene, camera, options)?;
            return Ok((EyeFaces::handed_back(hits, smesh), frame));
        }
        let face_of = fine_faces(self.gpu, scene, smesh);
        let locate = LocateTable::new(self.gpu, scene, smesh);
        let faces = EyeFaceMap { face_of: &face_of, locate: Some(&locate), faces: smesh.faces.len() };
        let Some(out) = self.eye_on_gpu(camera, options, Some(faces))? else {
            return Ok((EyeFaces::handed_back(eye_by_rays(self, scene, camera)?, smesh), KeptFrame::default()));
        };
        let kept = out.specular.iter().map(|l| u64::from(l.count)).sum();
        let hits = KeptEyeHits { lists: out.specular, face_of, locate, view: (*camera, options.region()) };
        let frame = GpuKept { eye_points: Some(out.kept), eye_hits: Some(hits), ..GpuKept::default() };
        let faces = EyeFaces { hits: Self::eye_hits(scene, camera, &out.others), seen: out.seen, kept };
        Ok((faces, KeptFrame::new(frame)))
    }

    /// The kept hits read back.
    fn take_kept_eye_hits(&self, scene: &Scene, frame: &mut KeptFrame) -> Result<Vec<(usize, Ray, Hit)>, BackendError> {
        let Some(kept) = frame.get_mut::<GpuKept>().and_then(|k| k.eye_hits.take()) else {
            return Ok(Vec::new());
        };
        let sources = kept.lists.iter().map(|l| (&*l.hits, u64::from(l.count) * size_of::<EyeHit>() as u64));
        let mut hits: Vec<EyeHit> = checked(self.gpu, || read_all(self.gpu, Vec::new(), sources))?;
        hits.par_sort_unstable_by_key(|h| h.pixel);
        Ok(Self::eye_hits(scene, &kept.view.0, &hits))
    }

    /// The kept points read back; the shader's seed of each is its pixel.
    fn take_kept_eye(&self, frame: &mut KeptFrame) -> Result<Vec<TexelRadiance>, BackendError> {
        let Some(kept) = frame.get_mut::<GpuKept>().and_then(|k| k.eye_points.take()) else {
            return Ok(Vec::new());
        };
        let sources = kept.iter().map(|k| (&*k.inputs, u64::from(k.count) * size_of::<ShadeInput>() as u64));
        let inputs: Vec<ShadeInput> = checked(self.gpu, || read_all(self.gpu, Vec::new(), sources))?;
        Ok(inputs
            .par_iter()
            .map(|s| TexelRadiance {
                texel: s.seed,
                point: ShadePoint {
                    prim: s.prim,
                    p: Vec3::from_array(s.p),
                    d: Vec3::from_array(s.d),
                    seed: u64::from(s.seed),
                },
                composite: None,
            })
            .collect())
    }
}
