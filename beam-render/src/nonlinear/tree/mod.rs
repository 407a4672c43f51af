//! The beam tree's data (000 §7.3): its beams ([`TreeBeam`], [`Node`]), the child beams of a face
//! ([`Scattered`]), one frame's tree ([`Tree`]) and the memos of beams the frames share
//! ([`TreeMemos`]). Data
//! only, below the stages that build the tree (`trace`) and composite into it (`lookup`).

use crate::irradiance_map::IrradianceMap;
use crate::memo::FrameMemo;
use crate::nonlinear::beam_tree::Beam;
use crate::nonlinear::settings::NonlinearOptions;
use crate::nonlinear::smesh::SMesh;
use crate::nonlinear::texture::{BeamTexture, TexelPoint};
use beam_math::glam::Vec3;
use beam_scene::scene::Scene;
use std::sync::Arc;

pub(super) mod lookup;
pub(super) mod radiance_flow;
mod source;
pub(super) mod trace;

/// A map keyed by S-mesh face, hashed by rustc's `FxHasher` (one multiplication): the maps below
/// are looked up once per texel (with the default SipHash: glass-lens radiance flow 192–194 →
/// 182–192 ms, next level's faces 7 → 5 ms). Face indices come from the scene, not from an
/// adversary.
pub(super) type FaceMap<V> = rustc_hash::FxHashMap<usize, V>;

/// The child beams of one S-mesh face: indices of its reflection and, for glass, its refraction in
/// the next level.
#[derive(Clone, Copy)]
pub(super) struct Scattered {
    pub(super) reflected: usize,
    pub(super) refracted: Option<usize>,
}

/// One of a face's beams as [`BeamMemo`] holds them: shared, not copied (a beam is ~0.9 KB, and
/// a level of the glass lens holds 5,592 of them).
#[derive(Clone)]
pub(super) struct TreeBeam {
    pub(super) beams: Arc<(Beam, Option<Beam>)>,
    pub(super) refracted: bool,
    /// What the beams are made of (`trace`'s `children_key`).
    pub(super) key: [u32; 11],
}

impl std::ops::Deref for TreeBeam {
    type Target = Beam;
    fn deref(&self) -> &Beam {
        match (&self.beams.1, self.refracted) {
            (Some(refracted), true) => refracted,
            _ => &self.beams.0,
        }
    }
}

/// A rendered beam of the tree.
pub(super) struct Node {
    pub(super) beam: TreeBeam,
    /// Whether it is bump-mapped (a composite into it reads the face's own coordinates): known
    /// here, so that a lookup per point does not follow the beam's pointer to find out.
    pub(super) bumped: bool,
    /// Its base: the S-mesh face it leaves.
    pub(super) face: usize,
    /// Pixels it covers (directly, or through its parents).
    pub(super) pixels: f32,
    pub(super) tex: BeamTexture,
    /// Per texel that hit: its index, hit triangle, hit point and unit ray direction (the
    /// texture's `points`, moved here, where the backend handed them back).
    pub(super) hits: Vec<TexelPoint>,
    /// Per hit, its S-mesh face and barycentric coordinates there ([`SMesh::locate`]), found once
    /// for the next level's requests and the composite; empty on the last level, whose hits no
    /// child beam composites.
    pub(super) located: Vec<Option<(usize, Vec3)>>,
    /// Its children per S-mesh face its texels hit.
    pub(super) children: FaceMap<Scattered>,
}

/// One render's beam tree.
pub(super) struct Tree<'a> {
    pub(super) scene: &'a Scene,
    pub(super) smesh: &'a SMesh,
    pub(super) options: NonlinearOptions,
    pub(super) eye: Vec3,
    /// Irradiance through the specular surfaces from the lights (caustics, nonlinear shadows).
    pub(super) caustics: Option<&'a IrradianceMap>,
    /// Points under coarse faces traced by rays: no child beam holds their scattered ray.
    pub(super) by_rays: std::sync::atomic::AtomicU64,
    /// The scene's diagonal: the depth where a texel's ray leaves the scene ([`reproject`](super::lookup::reproject)),
    /// found once (a lookup and a composite a point read it).
    pub(super) far: f32,
}

/// What one frame's tree leaves for the next frame's (found again where the next one asks with the
/// same bits): held by the frames' caller ([`super::NonlinearPrecomputed`]) and lent to one frame
/// at a time.
#[derive(Debug, Default)]
pub(super) struct TreeMemos {
    /// The beams of this frame's tree and of the last one's, by face and incoming light.
    pub(super) beams: BeamMemo,
    /// The parents' rays through their children's faces' vertices, of this frame's tree and of
    /// the last one's.
    pub(super) through: ThroughMemo,
}

/// A face's beams (reflected, and refracted through glass; `None` where degenerate) by what they
/// are made of (`trace`'s `children_key`), kept from one frame's tree to the next: on the wavy lake's 2,146
/// beams, 1.6 of the 21 host ms a frame went to their S3 patches.
pub(super) type BeamMemo = FrameMemo<[u32; 11], Option<Arc<(Beam, Option<Beam>)>>>;

/// The unit directions of a parent beam's rays through the vertices of a face its texels hit
/// where they do not span it ([`through`](super::source::through): three Newton projections), by the parent
/// (`trace`'s `through_key`), kept from one frame's tree to the next: on the mirror teapot under 850
/// coarse faces, 6 of the 28 host ms a frame with the eye still.
pub(super) type ThroughMemo = FrameMemo<[u32; 13], Option<[Vec3; 3]>>;
