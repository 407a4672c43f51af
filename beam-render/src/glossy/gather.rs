//! Gathering (002 §3.1, §4.2–4.3): at a receiver point, for every light beam, the flux plane through
//! the point, the flux triangle and the in-beam test; the irradiance of specular beams by eq. 1, of
//! glossy ones by eq. 3 with the Gaussian volume over the scatter-angle domain; shadow beams mark the
//! lights whose direct irradiance they remove. Linear over all beams, or through the cone hierarchy
//! (identical results: the hierarchy culls only beams that add nothing).

use super::beams::{GlossyBeam, trace_light_beams};
use super::cones::ConeTree;
use super::emitters::{Emitter, emitters};
use crate::queries::AnyHit;
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_math::glossy::{LightBeam, VolumeMethod, in_beam};
use beam_scene::scene::Scene;

/// What the beams give a receiver point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Gathered {
    /// Irradiance of the scattered beams.
    pub irradiance: Vec3,
    /// Bit `l` set: a shadow beam of emitter `l` covers the point.
    pub shadowed: u64,
    /// Beams evaluated.
    pub tested: u32,
}

/// The light volumes of a scene: its beams, ordered as the leaves of their cone hierarchy.
#[derive(Clone, Debug)]
pub struct LightVolumes {
    /// The beams.
    pub beams: Vec<GlossyBeam>,
    /// Their cone hierarchy.
    pub tree: ConeTree,
    /// The scene's emitters' positions and intensities (along their normals), indexed by
    /// [`GlossyBeam::light`].
    pub lights: Vec<(Vec3, Vec3)>,
    /// The scene's emitters (point lights, and area lights' strata), indexed likewise.
    pub emitters: Vec<Emitter>,
    /// Scatterer triangles skipped as degenerate (per light).
    pub degenerate: u64,
    /// How glossy volumes are integrated.
    pub method: VolumeMethod,
}

/// True when `p` lies downstream of `b`'s scatterer and in its flux triangle (the in-beam test of
/// 002 §3.1).
#[must_use]
pub fn covers(b: &LightBeam, p: Vec3) -> bool {
    let Some(plane) = b.flux_plane(p) else { return false };
    b.in_front(p) && b.flux_triangle(plane).is_some_and(|t| in_beam(&t, p))
}

/// Whether the light from a scatterer's point to a receiver point is blocked, asked as the segment
/// from the receiver (ray origin) to the source (parameter 1): second-order shadows, which 002
/// leaves out (its §3.2); `None` leaves them out too.
pub type Occluded<'a> = Option<&'a AnyHit<'a>>;

/// True when `occluded` says the light from `b`'s source point does not reach `p`.
pub fn blocked(b: &LightBeam, p: Vec3, occluded: Occluded<'_>) -> bool {
    occluded.is_some_and(|o| b.source_point(p).is_some_and(|s| o(Ray::new(p, s - p), 1.0)))
}

impl LightVolumes {
    /// Trace the beams of `scene` (002 §3.1; scatterers split into `subdivide²` sub-triangles) and
    /// build their cone hierarchy.
    #[must_use]
    pub fn new(scene: &Scene, method: VolumeMethod, subdivide: u32) -> Self {
        let (mut beams, degenerate) = trace_light_beams(scene, subdivide);
        let tree = ConeTree::build(&mut beams);
        let emitters = emitters(scene);
        let lights = emitters.iter().map(|e| (e.position, e.intensity)).collect();
        Self { beams, tree, lights, emitters, degenerate, method }
    }

    /// The same lights' negative shadow beams alone, with their own cone hierarchy (for a gather that
    /// takes the scattered beams elsewhere, as `beam_cpu`'s `PhotonKernel::splat` does).
    #[must_use]
    pub fn shadows(&self) -> Self {
        let mut beams: Vec<GlossyBeam> = self.beams.iter().filter(|b| b.shadow).copied().collect();
        let tree = ConeTree::build(&mut beams);
        let (lights, emitters) = (self.lights.clone(), self.emitters.clone());
        Self { beams, tree, lights, emitters, degenerate: self.degenerate, method: self.method }
    }

    /// Add beam `i`'s share at point `p` with unit normal `n` to `g`; a scattered beam adds nothing
    /// where `occluded(p, source)` says its light is blocked on the way from its source point
    /// ([`LightBeam::source_point`]).
    pub fn add(&self, i: usize, p: Vec3, n: Vec3, occluded: Occluded<'_>, g: &mut Gathered) {
        let b = &self.beams[i];
        g.tested += 1;
        if b.shadow {
            let bit = 1 << b.light.min(63);
            if g.shadowed & bit == 0 && self.tree.cones[i].contains(p) && covers(&b.beam, p) {
                g.shadowed |= bit;
            }
            return;
        }
        let e = self.scattered(i, p, n);
        if e != Vec3::ZERO && !blocked(&b.beam, p, occluded) {
            g.irradiance += e;
        }
    }

    /// Scattered beam `i`'s irradiance at `p` (unit normal `n`), second-order shadows left out: eq. 1
    /// or eq. 3 inside its support, zero outside: its own bounding cone (widened by `GLOSSY_REACH·σ`
    /// for glossy beams; see cones.rs), which holds its whole warped volume.
    pub fn scattered(&self, i: usize, p: Vec3, n: Vec3) -> Vec3 {
        let b = &self.beams[i];
        if !self.tree.cones[i].contains(p) {
            return Vec3::ZERO;
        }
        b.power
            * if b.sigma > 0.0 {
                b.beam.glossy_irradiance(p, n, b.sigma, self.method)
            } else {
                b.beam.specular_irradiance(p, n)
            }
    }

    /// The gather at `p` (unit normal `n`) through the cone hierarchy, with second-order shadows
    /// where `occluded` is given.
    #[must_use]
    pub fn gather(&self, p: Vec3, n: Vec3, occluded: Occluded<'_>) -> Gathered {
        let mut g = Gathered::default();
        self.tree.for_each_near(p, 0.0, |i| self.add(i, p, n, occluded, &mut g));
        g
    }

    /// The gather at `p` over every beam, in the same order (the hierarchy's reference).
    #[must_use]
    pub fn gather_linear(&self, p: Vec3, n: Vec3, occluded: Occluded<'_>) -> Gathered {
        let mut g = Gathered::default();
        for i in 0..self.beams.len() {
            self.add(i, p, n, occluded, &mut g);
        }
        g
    }
}
