//! The GPU's nonlinear renderer ([`GpuBeams`]): a thin holder of the frame's stages, each with its
//! own passes, for one scene. The eye's view ([`GpuEye`], `eye_stage.rs`), the tree levels'
//! atlases ([`GpuAtlas`]) and the final composite ([`GpuComposite`], with the shading pass and the
//! Whitted rays past the tree, `queries.rs`) hand a frame's kept points and hits to each other as
//! a value ([`GpuKept`], in the caller's [`KeptFrame`]), not through the renderer. Rays (the eye's
//! view where not on the GPU, the reference's Whitted rays) go to the compute ray tracer; the
//! radiance flows up the tree on the GPU: diffuse, glossy and emissive points shaded by
//! [`PointShader`] (area lights by stratified shadow rays, where the CPU's default is exact),
//! specular ones composited from their child beams, only the pixels read back.

use super::atlas::GpuAtlas;
use super::composite::GpuComposite;
use super::cut_outs::see_through_cut_outs;
use super::eye::GpuEye;
use super::kept::GpuKept;
use super::lookups::GpuLookups;
use super::page::AtlasPages;
use super::times::{GpuTimes, SummedTimes};
use super::whitted::GpuWhitted;
use crate::buffers::checked;
use crate::interface::TEXEL_JOB_PAIRS;
use crate::raytrace::RayTracer;
use crate::shade::PointShader;
use crate::{Gpu, GpuError};
use beam_bvh::gpu::GpuBvh;
use beam_render::BackendError;
use beam_render::nonlinear::{
    BeamJob, BeamRasterizer, BeamTexture, KeepLevel, KeptFrame, KeptTotals, TexelPoint, TexelRadiance,
};
use beam_render::options::{RenderOptions, Shading};
use beam_scene::scene::Scene;

/// The GPU's beam renderer for one scene: its triangles uploaded, every stage's passes compiled.
/// It holds what lives as long as it does (the passes, the scene's buffers, the tree levels' memo
/// across frames in `GpuAtlas`, the times summed); a frame's kept points and hits are the
/// frame's value (`GpuKept`), and a frame left on the GPU for display is returned
/// ([`beam_render::nonlinear::FramePixels::Kept`], a [`super::GpuFrame`]).
pub struct GpuBeams<'g> {
    pub(super) gpu: &'g Gpu,
    /// The tree levels' stage: the atlas's passes and the level-points pass.
    pub(super) atlas: GpuAtlas<'g>,
    /// The eye's view stage.
    pub(super) eye: GpuEye,
    /// The final composite's passes.
    pub(super) composite: GpuComposite,
    /// Shading on the GPU (the composite's, and [`beam_render::nonlinear::PointShading::shade_points`]).
    pub(super) shader: PointShader,
    /// The Whitted rays past the tree on the GPU.
    pub(super) whitted: GpuWhitted,
    /// The compute ray tracer (the eye's view, the Whitted rays, ray queries).
    pub(super) tracer: RayTracer,
    /// The coarse S mesh's lookups.
    pub(super) lookups: GpuLookups,
    /// Whether it leaves each frame on the GPU ([`GpuBeams::displaying`]).
    pub(super) display: bool,
    /// Shadow rays per area light and shade point.
    pub(super) light_samples: u32,
    /// The scene's diagonal.
    pub(super) extent: f32,
    /// Whether the GPU's shading and composite see the scene as it is: constant materials, with
    /// no texture or vertex colour ([`Surfaces::is_plain`](beam_scene::scene::surface::Surfaces::is_plain)),
    /// and a black environment (texels that leave the scene are black). Else every point is
    /// handed back to the host, which reads the textures and shows the environment.
    pub(super) as_is: bool,
    /// Where the eye's view, the rays and the composite spent their time, summed over the
    /// renderer's life (the atlas stage sums its own).
    pub(super) times: SummedTimes,
}

impl<'g> GpuBeams<'g> {
    /// Upload `scene` and compile the pipeline; pages of up to 4096² texels (less where the adapter
    /// allows less).
    pub fn new(gpu: &'g Gpu, scene: &Scene) -> Result<Self, GpuError> {
        let as_is = scene.surfaces.is_plain() && scene.environment.is_black();
        let mut atlas = GpuAtlas::new(gpu, scene)?;
        // Where the host shades the frame, no level is kept on the GPU for it.
        atlas.keep_levels = as_is;
        Ok(Self {
            gpu,
            atlas,
            eye: GpuEye::new(gpu, scene)?,
            composite: GpuComposite::new(gpu)?,
            shader: PointShader::new(gpu, scene)?,
            whitted: GpuWhitted::new(gpu, scene)?,
            tracer: RayTracer::new(gpu, &GpuBvh::new(&scene.bvh, &scene.triangles)?)?,
            lookups: GpuLookups::new(gpu)?,
            display: false,
            light_samples: 64,
            extent: scene.bounds().extent().length(),
            as_is,
            times: SummedTimes::default(),
        })
    }

    /// This renderer with `n` shadow rays per area light and shade point (default 64).
    #[must_use]
    pub fn with_light_samples(mut self, n: u32) -> Self {
        self.light_samples = n.max(1);
        self
    }

    /// This renderer splitting a beam's pairs into runs of at most `n` (1 to [`TEXEL_JOB_PAIRS`], the
    /// default) in the compute pass, each run a workgroup's; fewer pairs a run spread a beam over
    /// more workgroups, merged by the atomic max.
    #[must_use]
    pub fn with_job_pairs(mut self, n: u32) -> Self {
        self.atlas.job_pairs = n.clamp(1, TEXEL_JOB_PAIRS);
        self
    }

    /// This renderer finding the atlas's nearest hits by rasterization (000's way: a draw per beam,
    /// the depth test keeping the nearest) even where the device could find them by compute.
    #[must_use]
    pub fn rasterized(mut self) -> Self {
        self.atlas.pages.rasterized();
        self
    }

    /// This renderer reading every tree level's hits and the eye's mirror and glass hits back for
    /// the host instead of keeping on the GPU what needs no host ([`super::GpuLevelPoints`],
    /// [`GpuEye`]): the way every level went before, which the tests compare with.
    #[must_use]
    pub fn reading_levels_back(mut self) -> Self {
        self.atlas.keep_levels = false;
        self
    }

    /// This renderer, leaving each frame's pixels on the GPU for display rather than reading them
    /// back: where the GPU composites the frame (exact shading, each level within one texture of
    /// the device), `beam_render`'s `render_nonlinear_frame` returns the frame as the GPU keeps it
    /// ([`super::GpuFrame::from_device`] takes it), in a texture of the whole image's size (pixels
    /// outside a `region` black); elsewhere the image comes back as before.
    #[must_use]
    pub fn displaying(mut self) -> Self {
        self.display = true;
        self
    }

    /// Whether this renderer finds the atlas's nearest hits by compute.
    #[must_use]
    pub fn by_compute(&self) -> bool {
        self.atlas.by_compute()
    }

    /// Whether `gpu` has the 64-bit atomics that finding the atlas's nearest hits by compute takes
    /// (`SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX`, which [`Gpu::new`] asks for).
    #[must_use]
    pub fn can_compute(gpu: &Gpu) -> bool {
        AtlasPages::can_compute(gpu)
    }

    /// Whether the GPU shades the points of a frame with `options`: where the shading is exact
    /// (001 eq. 1 by shadow rays, all its shading pass does) and it sees the scene
    /// [as it is](Self::as_is). Elsewhere it hands them back to the host.
    pub(super) fn shades(&self, options: &RenderOptions) -> bool {
        options.shading == Shading::Exact && self.as_is
    }

    /// [`see_through_cut_outs`] for `textures`, the GPU's of `jobs`, counted.
    fn see_through_cut_outs(&self, scene: &Scene, jobs: &[BeamJob<'_>], textures: &mut [BeamTexture]) {
        let again = see_through_cut_outs(scene, jobs, textures);
        if again > 0 {
            self.add_times(|t| t.cut_out_beams += again);
        }
    }

    /// Time spent so far.
    #[must_use]
    pub fn times(&self) -> GpuTimes {
        self.times.get().plus(&self.atlas.times.get())
    }

    /// Add what `f` adds to the times.
    pub(super) fn add_times(&self, f: impl FnOnce(&mut GpuTimes)) {
        self.times.add(f);
    }

    /// The scene triangles the GPU keeps for each of `jobs` after culling by the BVH's boxes on the
    /// host and triangle by triangle on the device, each with [`crate::interface::PAIR_NEAR`]
    /// where it is in the beam's ring; in the order of the beam's blocks. For checks against
    /// [`beam_render::nonlinear::cone_candidates`]; all the jobs as one page.
    pub fn culled_triangles(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<Vec<u32>>, GpuError> {
        self.atlas.pages.culled_triangles(scene, jobs)
    }
}

/// The tree levels by the atlas stage (`GpuAtlas`); a level it keeps goes to the frame's
/// `GpuKept`.
impl BeamRasterizer for GpuBeams<'_> {
    /// On the GPU; a beam that sees through a cut-out, again on the host (`nonlinear/cut_outs.rs`).
    fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, BackendError> {
        let mut textures = self.atlas.render_beams(scene, jobs)?;
        self.see_through_cut_outs(scene, jobs, &mut textures);
        Ok(textures)
    }

    /// Kept where the composite will shade the tree (exact shading, the level within one texture),
    /// unless [`GpuBeams::reading_levels_back`] asked otherwise; located by the candidates the
    /// frame's eye view kept, where it did.
    fn render_level(
        &mut self,
        scene: &Scene,
        jobs: &[BeamJob<'_>],
        keep: &KeepLevel<'_>,
        frame: &mut KeptFrame,
    ) -> Result<(Vec<BeamTexture>, Option<KeptTotals>), BackendError> {
        let locate = frame.get::<GpuKept>().and_then(|k| k.eye_hits.as_ref()).map(|e| &e.locate);
        let (mut textures, kept) = self.atlas.render_level(scene, jobs, keep, locate)?;
        let Some(level) = kept else {
            // Every hit came back (a level with cut-outs is never kept: the host shades it).
            self.see_through_cut_outs(scene, jobs, &mut textures);
            return Ok((textures, None));
        };
        // A level rendered again replaces the frame's.
        let state = frame.get_or_default::<GpuKept>();
        state.child_levels.retain(|(l, _)| *l < keep.level);
        if let Some(lookups) = level.lookups {
            state.child_levels.push((keep.level, lookups));
        }
        state.levels.retain(|l| l.level < keep.level);
        state.levels.push(level.kept);
        Ok((textures, Some(level.totals)))
    }

    fn kept_level_points(&self, level: usize, frame: &KeptFrame) -> Result<Vec<Vec<TexelPoint>>, BackendError> {
        let levels = frame.get::<GpuKept>().map_or(&[][..], |k| &k.levels);
        let Some(kept) = levels.iter().find(|l| l.level == level && l.fits) else {
            return Ok(Vec::new());
        };
        Ok(checked(self.gpu, || kept.host_points(self.gpu))?)
    }

    fn take_kept_levels(&self, frame: &mut KeptFrame) -> Result<Vec<(usize, Vec<TexelRadiance>)>, BackendError> {
        let levels = frame.get_mut::<GpuKept>().map(|k| std::mem::take(&mut k.levels)).unwrap_or_default();
        let read = |l: &super::level::KeptLevel| Ok((l.level, l.read_back(self.gpu)?));
        Ok(checked(self.gpu, || levels.iter().map(read).collect())?)
    }
}
