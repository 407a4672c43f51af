//! What every stage of the renderer shares: the shading context of a render ([`Context`]), what a
//! thread keeps between shade points ([`Thread`]), the surface points a tile shades ([`Surface`])
//! and which lights they gather ([`Lights`]), and the seeds of a pixel's samples.

use super::emitters::Emitter;
use super::rounds::Partial;
use super::stats::Counters;
use crate::render::clear_shafts::ClearShafts;
use crate::render::cut_outs::CutOuts;
use crate::render::shadow_beam::{ShadowScratch, WindingScratch};
use crate::render::tile_shadows::TileShadows;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::irradiance_map::IrradianceMap;
use beam_render::options::{Method, RenderOptions};
use beam_render::queries::AnyHit;
use beam_render::tolerance::shading_eps;
use beam_scene::scene::{Light, Scene};

/// What a primary ray's shade point's seed (of its shadow-ray samples) is its pixel's seed
/// ([`pixel_seed`]) xor.
pub(super) const SHADE_SEED: u64 = 0x5EED;

/// The seed of pixel `(x, y)`'s primary rays for the render's seed `seed`.
pub(super) fn pixel_seed(seed: u64, x: u32, y: u32) -> u64 {
    seed ^ (u64::from(y) << 32 | u64::from(x)).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// What a thread keeps from one shade point to the next: its counters, its shadow-beam buffers and
/// the candidate occluders of the tile it is shading.
#[derive(Default)]
pub(super) struct Thread {
    pub(super) c: Counters,
    pub(super) scratch: ShadowScratch,
    pub(super) tile: TileShadows,
    /// Where beams do not pay: which blocks of the tile see which lights whole.
    pub(super) clear: ClearShafts,
    /// Block of the tile the current pixel lies in.
    pub(super) block: usize,
    /// The buffers of a winding pass.
    pub(super) winding: WindingScratch,
    /// The lights that face the tile being shaded (`None`: every light).
    pub(super) facing: Option<Vec<u32>>,
    /// The geometric normal of the shade point being lit, while a normal texture bends the normal
    /// its lights are integrated with: shadow beams then also clip each light to the half-space
    /// above the surface itself (what lies below it the surface hides, as it hides it from rays).
    pub(super) surface: Option<Vec3>,
    /// Which lights the last point sampled had partly hidden (the order of the next one's rays).
    pub(super) partial: Partial,
}

pub(super) struct Context<'a> {
    pub(super) scene: &'a Scene,
    pub(super) options: RenderOptions,
    pub(super) eps: f32,
    /// A peer's shadow-ray tracer, asked instead of the scene's own BVH (benchmarks).
    pub(super) peer: Option<&'a AnyHit<'a>>,
    /// Irradiance arriving at diffuse surfaces by paths the direct light does not follow (caustics).
    pub(super) caustics: Option<&'a IrradianceMap>,
    /// The lights shaded: the scene's (in the order of `scene.lights`, so that their indices are
    /// the scene's), then, with beams, a constant environment's ([`Environment::lights`], the sky
    /// as the six faces of a cube about the scene).
    pub(super) lights: Vec<Light>,
    /// The lights' geometry, in the order of `lights`.
    pub(super) emitters: Vec<Emitter>,
    /// The scene's cut-out triangles, when it has any.
    pub(super) cut_outs: Option<CutOuts<'a>>,
    /// Whether a shade point may gather light other than point lights' (an area light, the sky).
    area_or_sky: bool,
}

impl<'a> Context<'a> {
    pub(super) fn new(
        scene: &'a Scene,
        options: &RenderOptions,
        peer: Option<&'a AnyHit<'a>>,
        caustics: Option<&'a IrradianceMap>,
    ) -> Self {
        let mut lights = scene.lights.clone();
        if options.method == Method::Beam {
            lights.extend(scene.environment.lights(scene.bounds()));
        }
        let emitters = lights.iter().map(Emitter::of).collect();
        let cut_outs = CutOuts::of(scene);
        let area_or_sky = lights.iter().any(|l| !matches!(l, Light::Point { .. })) || !scene.environment.is_black();
        let eps = shading_eps(scene);
        Self { scene, options: *options, eps, peer, caustics, lights, emitters, cut_outs, area_or_sky }
    }

    /// Whether a shade point gathering `lights` has any light to gather: not where only point
    /// lights remain and those come from lit fragments.
    pub(super) fn gathers(&self, lights: Lights) -> bool {
        lights == Lights::All || self.area_or_sky
    }

    /// Whether the shadow ray from `origin` along `direction` meets a surface below `t_max`;
    /// `last` carries the occluder of the previous ray from the same point, tested first
    /// ([`Scene::occluded_after`]; a peer's tracer is asked as it is). Each arm builds its own
    /// ray: one built once and copied into the peer's argument was written in parts that the
    /// peer read across, a stalled store forwarding that cost Embree 12% of its render time.
    pub(super) fn occluded(&self, (origin, direction): (Vec3, Vec3), t_max: f32, last: &mut Option<u32>) -> bool {
        match self.peer {
            Some(occluded) => occluded(Ray::new(origin, direction), t_max),
            None => self.scene.occluded_after(Ray::new(origin, direction), t_max, last),
        }
    }
}

/// A visible surface point of a tile to shade: pixel, weight in it, triangle, point, unit view
/// direction and the seed of its shadow-ray samples, and the weights it also has in the pixel to
/// its right and the one below ([`lend_slivers`](super::shade_points::lend_slivers)).
#[derive(Clone, Copy, Debug)]
pub(super) struct Surface {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) weight: f32,
    pub(super) prim: u32,
    pub(super) q: Vec3,
    pub(super) d: Vec3,
    pub(super) seed: u64,
    pub(super) lent: [f32; 2],
}

impl Surface {
    /// The pixels this point is shaded into, with its weight in each: its own, then the ones it
    /// lends to (the pixel to its right, the one below).
    pub(super) fn targets(&self) -> impl Iterator<Item = ((u32, u32), f32)> + use<> {
        let (x, y) = (self.x, self.y);
        let lent = [((x + 1, y), self.lent[0]), ((x, y + 1), self.lent[1])];
        core::iter::once(((x, y), self.weight)).chain(lent.into_iter().filter(|&(_, w)| w > 0.0))
    }
}

/// Which lights a shade point gathers directly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Lights {
    /// Every light.
    All,
    /// Area lights only: point lights come from lit fragments (001 §4.2).
    AreaOnly,
}
