//! Rendering one nonlinear beam into its texel region (000 Algs. 1–2): every scene triangle that
//! survives bounding-cone culling (App. A) gets its bounding triangle on the beam base; the texels
//! inside it rebuild their ray from the S^n parameterization, intersect the scene triangle, discard
//! misses and keep the nearest hit (the depth test). Where a GPU's fragment shader evaluates the
//! ray for every fragment, the CPU keeps each texel's ray once evaluated (regions up to
//! [`RAY_CACHE_SIZE`] texels a side): the same rays, evaluated once instead of once per covering
//! triangle. A texel's hit on a cut-out (glTF `MASK`, `BLEND`) counts where the surface is there
//! at it ([`Scene::is_there`], as rays decide): a rasterizer's alpha test.

use super::beam_tree::{TEXEL_EPS, TexelBeam, self_hit_at};
use super::cull::cone_candidates;
use super::face::Exclude;
use super::texture::{BeamTexture, TexelHit};
use beam_bvh::Hit;
use beam_math::Ray;
use beam_math::collide::WatertightRay;
use beam_math::glam::Vec3;
use beam_scene::scene::Scene;

/// Regions at most this many texels a side keep their texels' rays (about 100 bytes per texel).
pub(super) const RAY_CACHE_SIZE: u32 = 512;

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
/// triangles): nearest hits of the texels' rays, skipping the surface under the beam's base
/// (`exclude`: its own scene triangle, or a coarse S-mesh face's patch), and hits on the triangles
/// that share a vertex with the base or lie in `exclude`'s ring nearer than the self-hit distance.
#[must_use]
pub fn render_beam(scene: &Scene, beam: &(impl TexelBeam + ?Sized), size: u32, exclude: Exclude<'_>) -> BeamTexture {
    let n = size as usize;
    let mut tex = BeamTexture {
        size,
        hits: vec![None; n * n],
        points: Vec::new(),
        fits: Vec::new(),
        triangles_after_culling: 0,
        texels_tested: 0,
    };
    let bounds = beam.s1_or_sn_bounds();
    let extent = scene.bounds().extent().length();
    // Half a texel of slack around the bounding triangle, in barycentric units.
    let slack = 0.5 / size as f32;
    // Under a coarse face the fine surface strays from the S^n origins by up to its thickness.
    let (lift, normal) = (beam.lift().max(exclude.thickness), beam.base_normal());
    let mut memo = InsideMemo::new();
    let mut rays: Vec<Option<TexelRay>> = vec![None; if size <= RAY_CACHE_SIZE { n * n } else { 0 }];
    for i in cone_candidates(scene, beam, &bounds, exclude) {
        let tri = &scene.triangles[i as usize];
        let inside = &mut |q| memo.get(q, |q| beam.contains_s1(q));
        let Some(bt) = beam.bounding_triangle_of(&bounds, tri, inside) else { continue };
        let neighbour = tri.v.iter().any(|v| beam.base().contains(v)) || exclude.near(i);
        let cut_out = scene.cut_out(i).is_some();
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
                let t_min =
                    if neighbour { self_hit_at(lift, normal, r.ray, extent) } else { TEXEL_EPS * extent } / r.len;
                let t_max = tex.hits[k].map_or(f32::INFINITY, |h| h.t);
                let Some(hit) = r.watertight.intersect(tri, t_min, t_max) else { continue };
                if !cut_out || scene.is_there(&r.ray, &Hit { prim: i, t: hit.t, u: hit.u, v: hit.v }) {
                    tex.hits[k] = Some(TexelHit { prim: i, t: hit.t });
                }
            }
        }
    }
    tex
}
