//! Rendering one nonlinear beam into its texel region (000 Algs. 1–2): every scene triangle that
//! survives bounding-cone culling (App. A) gets its bounding triangle on the beam base; the texels
//! inside it rebuild their ray from the S^n parameterization, intersect the scene triangle, discard
//! misses and keep the nearest hit (the depth test). Where a GPU's fragment shader evaluates the
//! ray for every fragment, the CPU keeps each texel's ray once evaluated (regions up to
//! [`RAY_CACHE_SIZE`] texels a side): the same rays, evaluated once instead of once per covering
//! triangle.

use beam_bvh::{Control, NodeVisitor};
use beam_math::collide::{Cone, WatertightRay, cone_sphere};
use beam_math::glam::Vec3;
use beam_math::nonlinear::{BeamBounds, BoundingTriangle, BumpBeam};
use beam_math::nonlinear::{Interpolant, NonlinearBeam};
use beam_math::{Aabb, Ray, Triangle};
use beam_scene::scene::Bump;
use beam_scene::scene::Scene;

/// What a texel's ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelHit {
    /// The scene triangle.
    pub prim: u32,
    /// Ray parameter of the hit (the ray's direction is not normalised).
    pub t: f32,
}

/// A beam's texel region: `size × size` texels over the base's barycentric square, of which those
/// with `u + v ≤ 1 + 1/size` (the base triangle and a one-texel margin for filtering) are rendered.
/// Texel `(x, y)` has centre `(u, v) = ((x + ½)/size, (y + ½)/size)` and barycentric coordinates
/// `(1 − u − v, u, v)` (clamped to the base in the margin).
#[derive(Clone, Debug)]
pub struct BeamTexture {
    /// Texels per side.
    pub size: u32,
    /// Nearest hit per texel (row-major), `None` where the ray leaves the scene.
    pub hits: Vec<Option<TexelHit>>,
    /// Scene triangles left after bounding-cone culling.
    pub triangles_after_culling: u32,
    /// Texels inside bounding triangles (rays intersected); overdraw is this over the texels rendered.
    pub texels_tested: u64,
}

impl BeamTexture {
    /// Barycentric coordinates of texel `(x, y)`; margin texels (outside the base) take the nearest
    /// point of the base's edge, where bounding triangles still hold.
    #[must_use]
    pub fn barycentric(&self, x: u32, y: u32) -> Vec3 {
        let (u, v) = ((x as f32 + 0.5) / self.size as f32, (y as f32 + 0.5) / self.size as f32);
        if u + v <= 1.0 {
            return Vec3::new(1.0 - u - v, u, v);
        }
        let excess = 0.5 * (u + v - 1.0);
        let (u, v) = ((u - excess).clamp(0.0, 1.0), (v - excess).clamp(0.0, 1.0));
        Vec3::new(1.0 - u - v, u, v).max(Vec3::ZERO)
    }

    /// True when texel `(x, y)` is rendered.
    #[must_use]
    pub fn in_region(&self, x: u32, y: u32) -> bool {
        x + y < self.size + 1
    }

    /// Texels rendered.
    #[must_use]
    pub fn texels(&self) -> u64 {
        (0..self.size).map(|y| u64::from((self.size + 1 - y).min(self.size))).sum()
    }
}

/// Regions at most this many texels a side keep their texels' rays (about 100 bytes per texel).
pub const RAY_CACHE_SIZE: u32 = 512;

/// A texel's ray, prepared for intersection.
#[derive(Clone, Copy)]
struct TexelRay {
    ray: Ray,
    watertight: WatertightRay,
    /// Length of the ray's direction (not normalised).
    len: f32,
}

impl TexelRay {
    fn new(ray: Ray) -> Self {
        Self { ray, watertight: WatertightRay::new(ray), len: ray.direction.length().max(f32::MIN_POSITIVE) }
    }
}

/// A memo of a beam's [`TexelBeam::contains_s1`] over the vertices of its candidate triangles: a
/// mesh's triangles share their vertices (about six each), and each answer costs a cubic. Direct
/// mapped by the position's bits, a slot overwritten on a collision; the answers are the function's
/// own, so the bounding triangles are the same with or without it.
struct InsideMemo {
    keys: [[u32; 3]; MEMO_SLOTS],
    /// 0: empty, 1: outside, 2: inside.
    values: [u8; MEMO_SLOTS],
}

/// Slots of an [`InsideMemo`] (a power of two).
const MEMO_SLOTS: usize = 512;

impl InsideMemo {
    fn new() -> Self {
        Self { keys: [[0; 3]; MEMO_SLOTS], values: [0; MEMO_SLOTS] }
    }

    /// `inside(q)`, remembered.
    fn get(&mut self, q: Vec3, inside: impl FnOnce(Vec3) -> bool) -> bool {
        let key = q.to_array().map(f32::to_bits);
        let h = key[0].wrapping_mul(0x9E37_79B1) ^ key[1].wrapping_mul(0x85EB_CA77) ^ key[2].wrapping_mul(0xC2B2_AE3D);
        let slot = (h >> (32 - MEMO_SLOTS.trailing_zeros())) as usize;
        if self.values[slot] != 0 && self.keys[slot] == key {
            return self.values[slot] == 2;
        }
        let answer = inside(q);
        (self.keys[slot], self.values[slot]) = (key, 1 + u8::from(answer));
        answer
    }
}

/// Render `beam` into a `size × size` texel region (000 Alg. 1 with Alg. 3 or 4 for the bounding
/// triangles): nearest hits of the texels' rays, skipping triangle `exclude` (the beam's own base).
#[must_use]
pub fn render_beam(scene: &Scene, beam: &(impl TexelBeam + ?Sized), size: u32, exclude: u32) -> BeamTexture {
    let n = size as usize;
    let mut tex = BeamTexture { size, hits: vec![None; n * n], triangles_after_culling: 0, texels_tested: 0 };
    let bounds = beam.s1_or_sn_bounds();
    let cone = beam.culling_cone(&bounds);
    let extent = scene.bounds().extent().length();
    // Half a texel of slack around the bounding triangle, in barycentric units.
    let slack = 0.5 / size as f32;
    let (lift, normal) = (beam.lift(), beam.base_normal());
    let mut memo = InsideMemo::new();
    let mut rays: Vec<Option<TexelRay>> = vec![None; if size <= RAY_CACHE_SIZE { n * n } else { 0 }];
    for i in cone_candidates(scene, &cone, exclude) {
        let tri = &scene.triangles[i as usize];
        let inside = &mut |q| memo.get(q, |q| beam.contains_s1(q));
        let Some(bt) = beam.bounding_triangle_of(&bounds, tri, inside) else { continue };
        let neighbour = tri.v.iter().any(|v| beam.base().contains(v));
        tex.triangles_after_culling += 1;
        let m = bt.lower - Vec3::splat(slack);
        // Texels with u ≥ m.y, v ≥ m.z, u + v ≤ 1 − m.x.
        let x_lo = ((m.y * size as f32 - 0.5).floor().max(0.0)) as u32;
        let y_lo = ((m.z * size as f32 - 0.5).floor().max(0.0)) as u32;
        let hi = ((1.0 - m.x) * size as f32).ceil().min(size as f32) as u32;
        for y in y_lo..hi.min(size) {
            for x in x_lo..hi.min(size) {
                if !tex.in_region(x, y) {
                    break;
                }
                let w = tex.barycentric(x, y);
                if !bt.contains(w, slack) {
                    continue;
                }
                tex.texels_tested += 1;
                let k = y as usize * n + x as usize;
                let r = match rays.get_mut(k) {
                    Some(cached) => *cached.get_or_insert_with(|| TexelRay::new(beam.texel_ray(w))),
                    None => TexelRay::new(beam.texel_ray(w)),
                };
                let t_min = if neighbour { self_hit_at(lift, normal, r.ray, extent) } else { 1e-4 * extent } / r.len;
                let t_max = tex.hits[k].map_or(f32::INFINITY, |h| h.t);
                if let Some(hit) = r.watertight.intersect(tri, t_min, t_max) {
                    tex.hits[k] = Some(TexelHit { prim: i, t: hit.t });
                }
            }
        }
    }
    tex
}

/// The scene triangles other than `exclude` that may meet a beam with bounding cone `cone`:
/// bounding-cone culling (000 App. A) of the BVH's boxes, then of each triangle's bounding sphere.
#[must_use]
pub fn cone_candidates(scene: &Scene, cone: &Cone, exclude: u32) -> Vec<u32> {
    let mut cull = ConeCull { cone: *cone, prims: Vec::new() };
    scene.bvh.traverse(&mut cull);
    cull.prims.retain(|&i| {
        let tri = &scene.triangles[i as usize];
        let centre = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
        let radius = tri.v.iter().fold(0.0f32, |m, v| m.max(v.distance(centre)));
        i != exclude && cone_sphere(cone, centre, radius)
    });
    cull.prims
}

/// Collects the triangles of the BVH leaves whose boxes' bounding spheres meet a beam's bounding
/// cone.
struct ConeCull {
    cone: Cone,
    prims: Vec<u32>,
}

impl NodeVisitor for ConeCull {
    fn enter(&mut self, bounds: &Aabb) -> Option<f32> {
        cone_sphere(&self.cone, bounds.center(), 0.5 * bounds.extent().length()).then_some(0.0)
    }

    fn leaf(&mut self, prims: &[u32]) -> Control {
        self.prims.extend_from_slice(prims);
        Control::Continue
    }
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
fn self_hit_at(lift: f32, normal: Vec3, ray: Ray, extent: f32) -> f32 {
    let rise = (ray.direction.normalize_or_zero().dot(normal)).max(0.05);
    (1e-4 * extent).max(2.0 * lift / rise)
}

/// What [`render_beam`] needs of a beam: its texel rays and their bounds (000 Algs. 1–4).
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
