//! The nonlinear frame driver (beam-render's) run with the CPU's renderer: frames that share what
//! they precompute equal frames that make it, and lookups answered by a backend in batches equal
//! lookups made in place.

use beam_bvh::Hit;
use beam_cpu::nonlinear::CpuBeams;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::BackendError;
use beam_render::nonlinear::{
    Beam, BeamJob, BeamRasterizer, BeamTexture, ChildLookups, Degree, DeviceWaits, EyeView, LookupJob, NonlinearError,
    NonlinearOptions, NonlinearPrecomputed, NonlinearStats, PointShading, render_nonlinear_frame,
    render_nonlinear_with, reproject,
};
use beam_render::options::RenderOptions;
use beam_render::queries::RayQueries;
use beam_scene::scene::{Scene, Simplify, builtin};
use std::sync::atomic::{AtomicU64, Ordering};

/// A frame with the caustics made before is the frame that makes them: the same pixels, bit
/// for bit, and the same caustic statistics (the point-lit wavy lake, whose light beams off the
/// water deposit on the lake's bed).
#[test]
fn frames_sharing_caustics_equal_frames_making_them() {
    let scene = builtin("wavy-lake").unwrap();
    let options = NonlinearOptions {
        degree: Degree::S1,
        texels: 8,
        bounces: 2,
        caustic_strata: 1,
        shading: RenderOptions::exact(40, 32),
    };
    let mut shared = NonlinearPrecomputed::new(&scene, &options, &CpuBeams).unwrap();
    assert!(shared.stats().beams > 0 && shared.stats().texels_deposited > 0, "{:?}", shared.stats());
    let (made, made_stats) = render_nonlinear_with(&scene, &options, &mut CpuBeams, &CpuBeams).unwrap();
    let (again, again_stats) =
        render_nonlinear_frame(&scene, &options, &mut CpuBeams, &CpuBeams, Some(&mut shared)).unwrap();
    assert_eq!(Some(made.pixels), again.read().map(|a| a.pixels));
    let counts = |s: &NonlinearStats| (s.caustics.beams, s.caustics.texels_deposited, s.texels_shaded);
    assert_eq!(counts(&made_stats), counts(&again_stats));
}

/// A coarse S mesh made once serves every frame: the same pixels, bit for bit, as a frame that
/// simplifies it itself; made for another scene, the frame fails instead of indexing it.
#[test]
fn frames_sharing_a_coarse_smesh_equal_frames_making_it() {
    let mut scene = builtin("mirror-teapot").unwrap();
    scene.smesh.rest = Some(Simplify::Faces(60));
    let options = NonlinearOptions {
        degree: Degree::S3,
        texels: 8,
        bounces: 1,
        caustic_strata: 0,
        shading: RenderOptions::exact(32, 24),
    };
    let mut shared = NonlinearPrecomputed::new(&scene, &options, &CpuBeams).unwrap();
    assert!(shared.smesh().coarse_faces() > 0);
    let (made, made_stats) = render_nonlinear_with(&scene, &options, &mut CpuBeams, &CpuBeams).unwrap();
    let (again, again_stats) =
        render_nonlinear_frame(&scene, &options, &mut CpuBeams, &CpuBeams, Some(&mut shared)).unwrap();
    assert_eq!(Some(made.pixels), again.read().map(|a| a.pixels));
    assert_eq!(made_stats.coarse_smesh_faces, again_stats.coarse_smesh_faces);
    let other = builtin("wavy-lake").unwrap();
    let wrong = render_nonlinear_frame(&other, &options, &mut CpuBeams, &CpuBeams, Some(&mut shared));
    assert!(matches!(wrong, Err(NonlinearError::Precomputed { .. })), "{:?}", wrong.map(|_| ()));
}

/// The CPU backend that takes the composites' lookups in batches (the tree's `lookups`) and
/// answers them with [`reproject`], counting the jobs.
#[derive(Default)]
struct HostBatches(AtomicU64);

impl RayQueries for HostBatches {
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        CpuBeams.closest_hits(scene, rays)
    }

    fn any_hits(&self, scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        CpuBeams.any_hits(scene, segments)
    }
}

impl BeamRasterizer for HostBatches {
    fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, BackendError> {
        CpuBeams.render_beams(scene, jobs)
    }
}

impl EyeView for HostBatches {}
impl PointShading for HostBatches {}
impl DeviceWaits for HostBatches {}

impl ChildLookups for HostBatches {
    fn looks_up(&self) -> bool {
        true
    }

    fn child_lookups(
        &self,
        beams: &[(&Beam, &BeamTexture)],
        jobs: &[LookupJob],
    ) -> Result<Option<Vec<(Vec3, f32)>>, BackendError> {
        self.0.fetch_add(jobs.len() as u64, Ordering::Relaxed);
        let at = |j: &LookupJob| {
            let (beam, tex) = beams[j.beam as usize];
            reproject(beam, tex, j.p, j.truth, j.w, j.far)
        };
        Ok(Some(jobs.iter().map(at).collect()))
    }
}

/// The composites' lookups gathered in batches and answered by a backend give the image of the
/// lookups made in place, bit for bit, and points under coarse faces do go to the backend:
/// the mirror teapot and its glass ball, and the glass lens, under coarse S meshes
/// (reflections, refractions and candidate faces).
#[test]
fn batched_lookups_equal_lookups_in_place() {
    for (name, faces) in [("mirror-teapot", 200), ("glass-lens", 60)] {
        let mut scene = builtin(name).unwrap();
        scene.smesh.rest = Some(Simplify::Faces(faces));
        let options = NonlinearOptions {
            degree: Degree::S3,
            texels: 8,
            bounces: 2,
            caustic_strata: 0,
            shading: RenderOptions::exact(48, 36),
        };
        let (in_place, in_place_stats) = render_nonlinear_with(&scene, &options, &mut CpuBeams, &CpuBeams).unwrap();
        let mut batches = HostBatches::default();
        let (batched, batched_stats) = render_nonlinear_with(&scene, &options, &mut batches, &CpuBeams).unwrap();
        assert!(batches.0.load(Ordering::Relaxed) > 0, "{name}: no lookup went to the backend");
        assert_eq!(in_place.pixels, batched.pixels, "{name}");
        assert_eq!(in_place_stats.uncovered_by_beams, batched_stats.uncovered_by_beams, "{name}");
    }
}
