//! The beams of the nonlinear beam tree (000 §4, §6.3): S1, S3 or bump-mapped, over one S-mesh
//! face, and what a backend needs of one to render it into texels ([`TexelBeam`], 000 Algs. 1–4).

use super::face::SFace;
use crate::specular::{dielectric, reflect};
use beam_math::collide::Cone;
use beam_math::glam::Vec3;
use beam_math::nonlinear::{
    BeamBounds, BoundingTriangle, BumpBeam, Interpolant, NonlinearBeam, Polish, Projection, S1, S3,
};
use beam_math::{Ray, Triangle};
use beam_scene::scene::{Bump, Material, Scene};

/// How far a lookup's projection is polished ([`Beam::project_in`]; the shaders' twin is
/// `lib/lookup.wgsl`). A lookup needs `ω` to a fraction of a texel (1/32 of the base at most), far
/// above a residual of 10⁻⁶ of the base's size. Started from a guess ([`reproject`](super::reproject)), on
/// the mirror teapot under an S mesh of 850 faces, 98.5% of the projections that converge within
/// 10 steps do so within 5 (93% within 3), and 11% do not converge (points no ray of the beam
/// reaches), which spent more than half of all steps; with 5 the radiance flow takes half the time
/// of the corner rays' start with 10 steps (1280×1024: 0.60 → 0.29 s on 2 cores) and the image
/// keeps its PSNR against the ray-traced reference (32.96 → 33.00 dB at 256²).
pub const LOOKUP: Polish = Polish { steps: 5, tolerance: 1e-6 };

/// How many texels outside a child beam's base a coarse face's lookup may fall ([`reproject`](super::reproject))
/// before its point is traced by rays instead: the one-texel margin its region
/// renders. (On the mirror teapot with 850 S faces, before folded faces were traced by rays, 0.5,
/// 1 and 2 texels traced 6,938, 6,080 and 4,921 points, and the image was 33.00, 32.81 and
/// 32.46 dB from the reference without caustics.)
pub const OUTSIDE_TEXELS: f32 = 1.0;

/// How much less outside its child beam's base (barycentric units) another candidate face's
/// lookup must lie than the best so far to be taken instead (the located face is tried first).
pub const LOOKUP_PREFERENCE: f32 = 1e-4;

/// The S^n parameterization of the beams (000 §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Degree {
    /// Linear (eq. 3): C⁰ across S-mesh edges, so reflections show kinks (000 Fig. 4).
    S1,
    /// Cubic over the vertex normals (eq. 6): C¹ at the S-mesh vertices.
    S3,
}

/// A nonlinear beam of either parameterization.
#[derive(Clone, Copy, Debug)]
pub enum Beam {
    /// Linear (eq. 3).
    S1(NonlinearBeam<S1>),
    /// Cubic (eq. 6).
    S3(NonlinearBeam<S3>),
    /// Off a bumpy mirror: S1 rays tilted by its bump map (000 §6.3).
    Bumped(BumpedBeam),
}

impl Beam {
    /// The beam off face `f` with boundary directions `dirs`; `None` when degenerate.
    pub fn new(degree: Degree, f: &SFace, dirs: [Vec3; 3]) -> Option<Self> {
        match degree {
            Degree::S1 => NonlinearBeam::s1(f.v, dirs).map(Self::S1),
            Degree::S3 => NonlinearBeam::new(f.v, dirs, S3 { normals: f.n }).map(Self::S3),
        }
    }

    /// The ray at barycentric point `w` of the base.
    #[must_use]
    pub fn ray_at(&self, w: Vec3) -> Ray {
        self.texel_beam().texel_ray(w)
    }

    /// What a renderer needs of it.
    #[must_use]
    pub fn texel_beam(&self) -> &dyn TexelBeam {
        match self {
            Self::S1(b) => b,
            Self::S3(b) => b,
            Self::Bumped(b) => b,
        }
    }

    /// Unit direction of the beam's ray through `q` (its nearest projection, 000 §5; for a bumped
    /// beam, that of its unperturbed S1 beam).
    pub fn direction_through(&self, q: Vec3) -> Option<Vec3> {
        self.ray_at(self.project(q)?).direction.try_normalize()
    }

    /// Barycentric coordinates of the base point whose ray passes through `q`: its projection
    /// (000 §5) least outside the base, in front of it (for a bumped beam, its unperturbed S1
    /// beam's).
    pub fn project(&self, q: Vec3) -> Option<Vec3> {
        self.project_in(q, Polish::FULL, None).map(|p| p.bary)
    }

    /// [`Beam::project`] with its ray parameter, polished as `polish` says for S^n beams and
    /// started from `guess` where given ([`NonlinearBeam::project_nearest_from`], else
    /// [`NonlinearBeam::project_nearest_in`]): for lookups, which need the coordinates to a
    /// fraction of a texel.
    pub fn project_in(&self, q: Vec3, polish: Polish, guess: Option<Projection>) -> Option<Projection> {
        fn nearest<L: Interpolant>(
            b: &NonlinearBeam<L>,
            q: Vec3,
            p: Polish,
            g: Option<Projection>,
        ) -> Option<Projection> {
            g.map_or_else(|| b.project_nearest_in(q, p), |g| b.project_nearest_from(q, g, p))
        }
        match self {
            Self::S1(b) => nearest(b, q, polish, guess),
            Self::S3(b) => nearest(b, q, polish, guess),
            Self::Bumped(b) => nearest(&b.beam.beam, q, polish, guess),
        }
    }
}

/// The beams off S-mesh face `f` for light arriving along the unit directions `incoming` at its
/// vertices (000 §7.2): the mirror reflection about the vertex normals, and for glass the
/// refraction by Snell's law (`Some(None)` when that beam is degenerate). Under total internal
/// reflection a boundary direction grazes the surface (the beam clamps it to the transmitted side,
/// 000 §4); such texels take reflection only. `None` when the reflection beam is degenerate.
pub fn child_beams(
    scene: &Scene,
    f: &SFace,
    incoming: [Vec3; 3],
    degree: Degree,
) -> Option<(Beam, Option<Option<Beam>>)> {
    // Vertex normals turned against the incoming light.
    let entering = (incoming[0] + incoming[1] + incoming[2]).dot(f.normal) < 0.0;
    let n = f.n.map(|n| if entering { n } else { -n });
    let dirs = [0, 1, 2].map(|i| reflect(incoming[i], n[i]));
    let reflected = match scene.material(f.prim) {
        // Bump beams are S1 beams perturbed by at most δ (000 §6.3).
        Material::Mirror { bump, .. } if bump.delta > 0.0 => {
            Beam::Bumped(BumpedBeam { beam: BumpBeam { beam: NonlinearBeam::s1(f.v, dirs)?, delta: bump.delta }, bump })
        }
        _ => Beam::new(degree, f, dirs)?,
    };
    let refracted = match scene.material(f.prim) {
        Material::Glass { ior } => Some(Beam::new(
            degree,
            f,
            [0, 1, 2].map(|i| {
                let d = incoming[i];
                dielectric(d, n[i], ior, entering).1.unwrap_or(d - d.dot(n[i]) * n[i])
            }),
        )),
        _ => None,
    };
    Some((reflected, refracted))
}

/// Distance along `ray` (a ray of `beam`) below which a hit on a triangle sharing a vertex with the
/// base is the surface meeting itself: S^n ray origins leave the flat base by up to μ_b (eq. 4), and
/// on a concave surface they start behind the neighbouring S-mesh faces, so hits nearer than 2μ_b
/// over the ray's rise above the base are skipped (1e-4 of the scene's diagonal `extent` for S1).
#[must_use]
pub fn self_hit_distance(beam: &(impl TexelBeam + ?Sized), ray: Ray, extent: f32) -> f32 {
    self_hit_at(beam.lift(), beam.base_normal(), ray, extent)
}

/// [`self_hit_distance`] for a beam of lift `lift` and unit base normal `normal`.
pub fn self_hit_at(lift: f32, normal: Vec3, ray: Ray, extent: f32) -> f32 {
    self_hit_at_rise(lift, ray.direction.normalize_or_zero().dot(normal), extent)
}

/// [`self_hit_at`] for a ray of rise `rise` (its unit direction's dot with the base normal).
pub(crate) fn self_hit_at_rise(lift: f32, rise: f32, extent: f32) -> f32 {
    (TEXEL_EPS * extent).max(2.0 * lift / rise.max(MIN_RISE))
}

/// The nearest a texel ray's hit may be, as a fraction of the scene's diagonal (WGSL twin in
/// `beam_gpu::interface`).
pub const TEXEL_EPS: f32 = 1e-4;

/// The least rise above the base [`self_hit_distance`] divides by (WGSL twin in
/// `beam_gpu::interface`).
pub const MIN_RISE: f32 = 0.05;

/// What a renderer needs of a beam ([`render_beam`](super::render_beam), beam-gpu's atlas): its texel rays and their bounds (000 Algs. 1–4).
pub trait TexelBeam {
    /// The bounds the bounding triangles are computed from (Alg. 3's `B`).
    fn s1_or_sn_bounds(&self) -> BeamBounds;
    /// A cone containing every ray (App. A).
    fn culling_cone(&self, bounds: &BeamBounds) -> Cone;
    /// Bounding triangle of `tri` on the base (Algs. 3–4, eq. 5 for bump beams), its vertices
    /// classified by `inside` (as [`Self::contains_s1`]).
    fn bounding_triangle_of(
        &self,
        bounds: &BeamBounds,
        tri: &Triangle,
        inside: &mut dyn FnMut(Vec3) -> bool,
    ) -> Option<BoundingTriangle>;
    /// True when `q` lies in the S1 beam through the boundary rays (the classification of Algs.
    /// 3–4's brute-force case).
    fn contains_s1(&self, q: Vec3) -> bool;
    /// The ray at barycentric point `w` of the base.
    fn texel_ray(&self, w: Vec3) -> Ray;
    /// Base vertices.
    fn base(&self) -> [Vec3; 3];
    /// Unit base normal on the rays' side.
    fn base_normal(&self) -> Vec3;
    /// Largest distance of a ray origin from the flat base (μ_b of eq. 4).
    fn lift(&self) -> f32;
}

impl<L: Interpolant> TexelBeam for NonlinearBeam<L> {
    fn s1_or_sn_bounds(&self) -> BeamBounds {
        self.bounds()
    }
    fn culling_cone(&self, bounds: &BeamBounds) -> Cone {
        self.bounding_cone(&bounds.extremal, 0.0)
    }
    fn bounding_triangle_of(
        &self,
        bounds: &BeamBounds,
        tri: &Triangle,
        inside: &mut dyn FnMut(Vec3) -> bool,
    ) -> Option<BoundingTriangle> {
        self.bounding_triangle_with(bounds, tri, inside)
    }
    fn contains_s1(&self, q: Vec3) -> bool {
        NonlinearBeam::contains_s1(self, q)
    }
    fn texel_ray(&self, w: Vec3) -> Ray {
        self.ray_at(w)
    }
    fn base(&self) -> [Vec3; 3] {
        self.base
    }
    fn base_normal(&self) -> Vec3 {
        self.normal
    }
    fn lift(&self) -> f32 {
        self.max_offsets().0
    }
}

/// A bump-mapped (perturbed) beam off a bumpy mirror (000 §6.3): S1 rays tilted by the mirror's
/// bump map, bounded by the D-expanded bounding triangles (eq. 5) and the δ-widened cone.
#[derive(Clone, Copy, Debug)]
pub struct BumpedBeam {
    /// The perturbed beam of beam-math.
    pub beam: BumpBeam,
    /// The bump map that tilts its rays.
    pub bump: Bump,
}

impl TexelBeam for BumpedBeam {
    fn s1_or_sn_bounds(&self) -> BeamBounds {
        self.beam.beam.bounds()
    }
    fn culling_cone(&self, _: &BeamBounds) -> Cone {
        self.beam.bounding_cone()
    }
    fn bounding_triangle_of(
        &self,
        bounds: &BeamBounds,
        tri: &Triangle,
        inside: &mut dyn FnMut(Vec3) -> bool,
    ) -> Option<BoundingTriangle> {
        self.beam.bounding_triangle_with(bounds, tri, inside)
    }
    fn contains_s1(&self, q: Vec3) -> bool {
        self.beam.beam.contains_s1(q)
    }
    fn texel_ray(&self, w: Vec3) -> Ray {
        let base = Triangle { v: self.beam.beam.base };
        self.beam.ray_at(w, self.bump.tilt(&base, self.beam.beam.normal, base.point(w)))
    }
    fn base(&self) -> [Vec3; 3] {
        self.beam.beam.base
    }
    fn base_normal(&self) -> Vec3 {
        self.beam.beam.normal
    }
    fn lift(&self) -> f32 {
        0.0
    }
}
