//! The narrow interfaces a nonlinear backend implements, each named for what it does: ray queries
//! (nearest hits with barycentric weights, any hits), the eye's view, a beam rasterizer (beams and
//! scene triangles to texels, 000 Alg. 1), point shading (hit to radiance, where the backend
//! can) and a coarse S mesh's lookups (where it can). A renderer is their composition
//! ([`BeamRenderer`]): beam-cpu's `CpuBeams` and beam-gpu's `GpuBeams` are two. A backend that can
//! fail returns a [`BackendError`] (the CPU's never fails); its message is the backend's own.
//!
//! A frame's stages hand what a backend keeps on its device from one to the next as a value the
//! caller holds, [`KeptFrame`]: the eye's view starts it, each level of the tree adds to it, and
//! the composite consumes it (or hands it back, for a frame the caller shades after all). What a
//! backend keeps across frames (work the next frame can skip, never a frame's results) it holds
//! itself: frames use a renderer in turn, so the stages that read or write it take `&mut self`,
//! and nothing of a frame sits behind a lock.

use super::beam_tree::Beam;
use super::radiance::{LevelRadiance, TexelRadiance};
use super::smesh::SMesh;
use super::texture::{BeamJob, BeamTexture, ShadePoint, TexelPoint};
use crate::error::BackendError;
use crate::irradiance_map::IrradianceMap;
use crate::options::RenderOptions;
use crate::queries::RayQueries;
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_scene::scene::{Camera, Scene};
use rayon::prelude::*;
use std::any::Any;
use std::fmt;

/// Renders a tree level's beams into their texel regions: the nearest scene hit of every texel's
/// ray (000 Alg. 1; beam-cpu: each beam in parallel; beam-gpu: per-level atlases, 000 §3).
pub trait BeamRasterizer: Sync {
    /// The textures of `jobs`, in order.
    fn render_beams(&self, scene: &Scene, jobs: &[BeamJob<'_>]) -> Result<Vec<BeamTexture>, BackendError>;

    /// [`render_beams`](Self::render_beams) for a level of the beam tree whose texels the backend
    /// may keep in the frame's `frame` (the value its eye's view returned), where its
    /// [`PointShading::shade_tree`] shades the tree with `keep.options`: every texel that hits a
    /// triangle from which the tree does not go on (`keep.continues`) becomes a shading point on
    /// the backend, at its place in the level's radiance (`keep.layout`), and is not handed back;
    /// the textures hold the others' hits (all of them `keep.with_hits`, for lookups into the
    /// level). A level rendered again replaces what `frame` kept of it. Returns the textures, and
    /// what was kept where it was. The default keeps nothing.
    fn render_level(
        &mut self,
        scene: &Scene,
        jobs: &[BeamJob<'_>],
        keep: &KeepLevel<'_>,
        frame: &mut KeptFrame,
    ) -> Result<(Vec<BeamTexture>, Option<KeptTotals>), BackendError> {
        let _ = (keep, frame);
        Ok((self.render_beams(scene, jobs)?, None))
    }

    /// The points that [`render_level`](Self::render_level) kept in `frame`, per level as texels
    /// of the level's radiance (for a frame that the caller shades after all), taken out of it.
    fn take_kept_levels(&self, frame: &mut KeptFrame) -> Result<Vec<(usize, Vec<TexelRadiance>)>, BackendError> {
        let _ = frame;
        Ok(Vec::new())
    }

    /// The texels of tree level `level` whose fits [`render_level`](Self::render_level) summed in
    /// `frame` ([`KeptTotals::fits`]), per beam of the level, in texel order, with their points
    /// (each beam's [`BeamTexture::points`] as they would have been handed back), for a frame that
    /// the caller shades after all; empty where there are none.
    fn kept_level_points(&self, level: usize, frame: &KeptFrame) -> Result<Vec<Vec<TexelPoint>>, BackendError> {
        let _ = (level, frame);
        Ok(Vec::new())
    }
}

/// What a backend keeps of one frame on its device between the frame's stages (the eye's view,
/// each level of the beam tree, the composite), opaque to the caller, which holds it for the frame
/// and hands it from stage to stage: [`EyeView::eye_view`] and [`EyeView::eye_faces`] return it,
/// [`BeamRasterizer::render_level`] adds each level to it, [`PointShading::shade_tree`] consumes
/// it (or hands it back, and the `take_kept_*` methods read what it holds for a frame the caller
/// shades after all). It lives for one frame; a backend that keeps nothing leaves it empty (the
/// default). Each backend holds its own type in it (beam-gpu: `GpuBeams`' kept points, hits and
/// levels).
#[derive(Default)]
pub struct KeptFrame(Option<Box<dyn Any + Send>>);

impl KeptFrame {
    /// A frame holding a backend's `state`.
    #[must_use]
    pub fn new<T: Any + Send>(state: T) -> Self {
        Self(Some(Box::new(state)))
    }

    /// Whether it holds nothing.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_none()
    }

    /// The backend's state, where it is a `T`.
    #[must_use]
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.0.as_ref()?.downcast_ref()
    }

    /// The backend's state, where it is a `T`.
    pub fn get_mut<T: Any>(&mut self) -> Option<&mut T> {
        self.0.as_mut()?.downcast_mut()
    }

    /// The backend's state as a `T`, a new one where it holds none (or another backend's, which
    /// goes).
    pub fn get_or_default<T: Any + Send + Default>(&mut self) -> &mut T {
        if self.get::<T>().is_none() {
            self.0 = Some(Box::new(T::default()));
        }
        self.0.as_mut().and_then(|b| b.downcast_mut()).expect("a `T` was just put in")
    }

    /// The backend's state, where it is a `T`; `None` where it holds none or another type.
    #[must_use]
    pub fn into_inner<T: Any>(self) -> Option<T> {
        self.0?.downcast().ok().map(|b| *b)
    }
}

impl fmt::Debug for KeptFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.is_empty() { "KeptFrame(empty)" } else { "KeptFrame(..)" })
    }
}

/// A frame's pixels a backend left on its device for display ([`FramePixels::Kept`]), opaque to
/// the caller, which hands it to the code that shows it: that code knows the backend's type
/// (beam-gpu's `GpuFrame`, by [`DeviceImage::downcast`]). One frame's; it owns the pixels.
pub struct DeviceImage(Box<dyn Any + Send>);

impl DeviceImage {
    /// The pixels `image` as a backend keeps them.
    #[must_use]
    pub fn new<T: Any + Send>(image: T) -> Self {
        Self(Box::new(image))
    }

    /// The pixels as the backend's `T`, or this image back where they are not one.
    pub fn downcast<T: Any>(self) -> Result<T, Self> {
        self.0.downcast().map(|b| *b).map_err(Self)
    }
}

impl fmt::Debug for DeviceImage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("DeviceImage(..)")
    }
}

/// Where a tree level's texels lie in its radiance ([`LevelRadiance`]'s layout): per beam, its
/// first texel (its region's texels follow row by row, `size²` of them) and the scene triangle of
/// its S-mesh face (with the texel, the seed of its points' shading: `triangle << 32 | texel`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LevelLayout {
    /// Per beam, its first texel in the level.
    pub firsts: Vec<u32>,
    /// Per beam, its face's scene triangle.
    pub prims: Vec<u32>,
    /// Texels of the level.
    pub len: usize,
}

/// A level of the beam tree that a backend may keep ([`BeamRasterizer::render_level`]).
#[derive(Clone, Copy, Debug)]
pub struct KeepLevel<'a> {
    /// Which level (1 for the beams off the faces the eye sees).
    pub level: usize,
    /// Where its texels lie in its radiance.
    pub layout: &'a LevelLayout,
    /// How the frame is shaded.
    pub options: &'a RenderOptions,
    /// Whether the textures must hold every hit all the same.
    pub with_hits: bool,
    /// Faces of the S mesh (a backend that composites the texels it hands back indexes them).
    pub faces: usize,
    /// Per scene triangle, whether the tree goes on from a texel that hits it (it has an S-mesh
    /// face, and the level is not the last): such texels are handed back. None past its end.
    pub continues: &'a [bool],
}

/// What a backend kept of a level ([`BeamRasterizer::render_level`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KeptTotals {
    /// Texels that hit: the level's points.
    pub points: u64,
    /// Of them, points on curved (smooth-normal) triangles.
    pub curved: u64,
    /// Whether the backend composites the texels it handed back itself, given the level's
    /// [`super::LevelRadiance::node_children`] (on an S mesh of fine faces, from the hits it holds).
    pub records: bool,
    /// Whether the backend summed the fits of the texels it would hand back, on the faces they lie
    /// on ([`BeamTexture::fits`]), and handed none back ([`BeamRasterizer::kept_level_points`]
    /// reads them for a frame the caller shades after all); the backend then counts them among
    /// `points`, and those on curved triangles without child beams at their face among
    /// [`CoarseByRays::curved`].
    pub fits: bool,
}

/// Where [`PointShading::shade_tree`] left a frame's pixels.
#[derive(Debug)]
pub enum FramePixels {
    /// Read back: the eye's pixels, row-major.
    Read(Vec<Vec3>),
    /// Kept on the backend's device for display and not read back (000 §7.3 draws its frame where
    /// it is shown).
    Kept(DeviceImage),
}

/// What [`PointShading::shade_tree`] did with a frame.
#[derive(Debug)]
pub enum TreeShading {
    /// Shaded by the backend, which consumed the frame's [`KeptFrame`].
    Shaded {
        /// The frame's pixels.
        pixels: FramePixels,
        /// Of the mirror and glass points under coarse S-mesh faces that the backend composited
        /// itself, those it sent to the rays.
        coarse_by_rays: CoarseByRays,
    },
    /// Not shaded by the backend: the caller shades the frame, with what the backend kept, handed
    /// back (the `take_kept_*` methods read it).
    HandedBack(KeptFrame),
}

/// Shades points where a backend can; `Ok(None)` hands the work back to the caller, which shades on
/// the CPU (both methods' default).
pub trait PointShading: Sync {
    /// The radiance of every point as beam-cpu's `shade_point` computes it, or `Ok(None)` when this
    /// backend does not shade with `options`.
    fn shade_points(
        &mut self,
        scene: &Scene,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        points: &[ShadePoint],
    ) -> Result<Option<Vec<Vec3>>, BackendError> {
        let _ = (scene, options, caustics, points);
        Ok(None)
    }

    /// The radiance flow of a built tree (`levels[0]` the eye's view), with what the backend kept
    /// of the frame (`frame`, from its eye's view and levels): the eye's pixels
    /// ([`TreeShading::Shaded`]), or `frame` handed back when this backend does not run it
    /// ([`composite_levels`](super::composite_levels) then does, on the host; the default).
    fn shade_tree(
        &mut self,
        scene: &Scene,
        smesh: &SMesh,
        options: &RenderOptions,
        caustics: Option<&IrradianceMap>,
        levels: &[LevelRadiance],
        frame: KeptFrame,
    ) -> Result<TreeShading, BackendError> {
        let _ = (scene, smesh, options, caustics, levels);
        Ok(TreeShading::HandedBack(frame))
    }
}

/// The eye's view of a frame (000 §7.3): the roots of the beam tree and the eye's level of the
/// radiance flow.
pub trait EyeView: RayQueries {
    /// The nearest hit of the primary ray through every pixel centre of `camera` (row-major) that
    /// hits, as `(pixel, ray, hit)` in pixel order, and what the backend kept of the frame, which
    /// the caller hands to the frame's later stages. A backend whose [`PointShading::shade_tree`]
    /// shades the eye's diffuse, glossy and emissive pixels itself may keep those of `options`'
    /// region and leave them out ([`take_kept_eye`](Self::take_kept_eye) hands them back); every
    /// mirror and glass hit of the frame is returned. The default keeps nothing.
    fn eye_view(
        &self,
        scene: &Scene,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Result<(PixelHits, KeptFrame), BackendError> {
        let _ = options;
        Ok((eye_by_rays(self, scene, camera)?, KeptFrame::default()))
    }

    /// [`eye_view`](Self::eye_view) as the roots of the beam tree over `smesh`: the hits handed
    /// back, and per S-mesh face the pixels the backend kept that see it. A backend whose
    /// [`PointShading::shade_tree`] composites the eye's pixels itself may keep the mirror and glass
    /// hits on S-mesh faces, each counted at its face ([`EyeFaces`]; under a coarse face, the one
    /// [`SMesh::locate`] chooses); the default keeps none of them. With it, what the backend kept
    /// of the frame, as [`eye_view`](Self::eye_view)'s.
    fn eye_faces(
        &self,
        scene: &Scene,
        smesh: &SMesh,
        camera: &Camera,
        options: &RenderOptions,
    ) -> Result<(EyeFaces, KeptFrame), BackendError> {
        let (hits, frame) = self.eye_view(scene, camera, options)?;
        Ok((EyeFaces::handed_back(hits, smesh), frame))
    }

    /// The mirror and glass hits that [`eye_faces`](Self::eye_faces) kept in `frame`, as
    /// `(pixel, ray, hit)` (for a frame that the caller shades after all), taken out of it.
    fn take_kept_eye_hits(&self, scene: &Scene, frame: &mut KeptFrame) -> Result<Vec<(usize, Ray, Hit)>, BackendError> {
        let _ = (scene, frame);
        Ok(Vec::new())
    }

    /// The eye's pixels that [`eye_view`](Self::eye_view) kept in `frame`, as texels of the eye's
    /// level of the radiance flow (for a frame that the caller shades after all), taken out of it.
    fn take_kept_eye(&self, frame: &mut KeptFrame) -> Result<Vec<TexelRadiance>, BackendError> {
        let _ = frame;
        Ok(Vec::new())
    }
}

/// The eye's hits of a frame's pixels, `(pixel, ray, hit)` in pixel order ([`EyeView::eye_view`]).
pub type PixelHits = Vec<(usize, Ray, Hit)>;

/// Mirror and glass points under coarse S-mesh faces that a backend's composite traced by rays
/// ([`TreeShading::Shaded`]): of the hits [`EyeView::eye_faces`] kept and the texels of levels
/// whose [`KeptTotals::records`] it makes, as the host's composite counts its own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoarseByRays {
    /// Under a face with child beams, none of which holds the point's scattered rays.
    pub uncovered: u64,
    /// On a triangle with interpolated normals (a curved mirror or glass), but for a level's
    /// texels without child beams at the face the caller located them on (the caller counts
    /// those).
    pub curved: u64,
}

/// The eye's view as the roots of the beam tree ([`EyeView::eye_faces`]).
#[derive(Clone, Debug, Default)]
pub struct EyeFaces {
    /// The hits handed back, `(pixel, ray, hit)` in pixel order.
    pub hits: Vec<(usize, Ray, Hit)>,
    /// Per S-mesh face: the pixels the backend kept that see it, of the frame and of the region.
    pub seen: Vec<[u32; 2]>,
    /// Mirror and glass pixels the backend kept.
    pub kept: u64,
}

impl EyeFaces {
    /// Every hit handed back (`hits`), none kept or located, over the faces of `smesh`.
    #[must_use]
    pub fn handed_back(hits: Vec<(usize, Ray, Hit)>, smesh: &SMesh) -> Self {
        Self { hits, seen: vec![[0, 0]; smesh.faces.len()], kept: 0 }
    }
}

/// [`EyeView::eye_view`] by `queries`' nearest hits of the pixels' primary rays, keeping none.
pub fn eye_by_rays(
    queries: &(impl RayQueries + ?Sized),
    scene: &Scene,
    camera: &Camera,
) -> Result<Vec<(usize, Ray, Hit)>, BackendError> {
    let frame = camera.frame();
    let rays: Vec<Ray> = (0..camera.width as usize * camera.height as usize)
        .into_par_iter()
        .map(|i| camera.pixel_ray(&frame, i))
        .collect();
    let hits = queries.closest_hits(scene, &rays)?;
    Ok(hits.into_par_iter().zip(rays).enumerate().filter_map(|(i, (h, ray))| Some((i, ray, h?))).collect())
}

/// How long a backend has blocked on a device, so that a frame's host work (000 Table 2's CPU
/// share) is its wall time less these waits. A backend on the CPU has none (the default).
pub trait DeviceWaits: Sync {
    /// Seconds spent blocked on the device so far.
    fn waited_seconds(&self) -> f64 {
        0.0
    }
}

/// One lookup of a point of a fine surface under a coarse S-mesh face (000 §7.1) in a child beam
/// of the face: [`reproject`](super::reproject) of `p`, at `w` on the face, for its scattered unit
/// direction `truth`, in beam `beam` of the next level (`far`: the scene's diagonal, the depth
/// where a texel's ray leaves the scene).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookupJob {
    /// The child beam, an index into the next level's beams.
    pub beam: u32,
    /// The point.
    pub p: Vec3,
    /// Its scattered unit direction.
    pub truth: Vec3,
    /// Its barycentric coordinates on the face.
    pub w: Vec3,
    /// The depth where a texel's ray leaves the scene.
    pub far: f32,
}

/// Lookups on a backend (the GPU's `lookups.wgsl`); by default none, and the host looks the
/// points up itself.
pub trait ChildLookups: Sync {
    /// Whether [`Self::child_lookups`] looks up (else the frame gathers no jobs for it).
    fn looks_up(&self) -> bool {
        false
    }

    /// Each job's coordinates on its beam's base and how far outside the base its last projection
    /// lay, the beams `beams` (the next level's, with their textures); `None` where the backend
    /// does not look up.
    fn child_lookups(
        &self,
        _beams: &[(&Beam, &BeamTexture)],
        _jobs: &[LookupJob],
    ) -> Result<Option<Vec<(Vec3, f32)>>, BackendError> {
        Ok(None)
    }
}

/// What the nonlinear renderer needs of a backend: ray queries, the eye's view, a beam rasterizer,
/// (optional) point shading and lookups, and its device waits. Implemented for every type that has
/// the six.
pub trait BeamRenderer: RayQueries + EyeView + BeamRasterizer + PointShading + ChildLookups + DeviceWaits {}

impl<T: RayQueries + EyeView + BeamRasterizer + PointShading + ChildLookups + DeviceWaits> BeamRenderer for T {}
