//! The beams through a photon map's kernel, so that beams and photons estimate the very same image.
//! A photon map reads irradiance at `p` as `Σⱼ tentⱼ(p)·Fⱼ/t²` with `Fⱼ = Σ tentⱼ(x)·Φ` over the
//! photons: its expectation is `∫ E(x)·K(p, x) dA` with `K = Σⱼ tentⱼ(p)·tentⱼ(x)/t²`, bilinear in `x`
//! on each texel cell. A specular beam spreads its flux `Φ` evenly over its footprint on the
//! receiver's plane (the triangle where its three rays meet it: eq. 1 read on that plane), so its
//! share is `Φ/A·∫_footprint K dA`, exactly: the footprint is clipped against each cell of the
//! kernel's support and the bilinear kernel integrated on the pieces by the midpoint rule (exact for
//! degree 2). Glossy beams, smooth already, are sampled at `p`.

use super::gather::{Gathered, LightVolumes, Occluded, blocked};
use crate::render::IrradianceMap;
use crate::scene::Scene;
use beam_math::glam::{Vec2, Vec3};

/// A photon map's layout: its planes' grids and which plane each receiver triangle reads.
#[derive(Clone, Debug)]
pub struct PhotonKernel {
    map: IrradianceMap,
    /// Per plane: texel-centre origin, axes scaled to texels, size.
    grids: Vec<(Vec3, [Vec3; 2], [u32; 2])>,
}

/// The corners of a unit cell, from its lower one.
const CORNERS: [Vec2; 4] = [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE];

/// A convex polygon of at most 7 vertices: a triangle clipped by up to four axis-aligned lines (the
/// kernel's inner loop; `ConvexPolygon::clip` is general and keeps both halves).
#[derive(Clone, Copy)]
struct Piece {
    v: [Vec2; 8],
    n: usize,
}

impl Piece {
    fn triangle(t: [Vec2; 3]) -> Self {
        let mut v = [Vec2::ZERO; 8];
        v[..3].copy_from_slice(&t);
        Self { v, n: 3 }
    }

    /// The part where coordinate `axis` is at most `bound` (`below`), or at least it
    /// (Sutherland–Hodgman against one line).
    fn clip(&self, axis: usize, bound: f32, below: bool) -> Self {
        let inside = |p: Vec2| if below { p[axis] <= bound } else { p[axis] >= bound };
        let mut out = Self { v: [Vec2::ZERO; 8], n: 0 };
        for i in 0..self.n {
            let (a, b) = (self.v[i], self.v[(i + 1) % self.n]);
            let (ia, ib) = (inside(a), inside(b));
            if ia && out.n < 8 {
                out.v[out.n] = a;
                out.n += 1;
            }
            if ia != ib && out.n < 8 {
                out.v[out.n] = a + (b - a) * ((bound - a[axis]) / (b[axis] - a[axis]));
                out.n += 1;
            }
        }
        out
    }

    /// `∫ (Σ wₖ·(1 − |x − cₖ|)(1 − |y − cₖ|)) dA` over the piece, inside one unit cell whose
    /// corners `cₖ` carry weights `wₖ`: fan triangles, midpoint rule (exact for degree 2).
    fn integrate(&self, corners: &[(Vec2, f32); 4]) -> f32 {
        let f = |x: Vec2| {
            corners.iter().map(|&(c, w)| w * (1.0 - (x.x - c.x).abs()) * (1.0 - (x.y - c.y).abs())).sum::<f32>()
        };
        let p = &self.v[..self.n];
        let mut sum = 0.0;
        for k in 1..p.len().saturating_sub(1) {
            let (a, b, c) = (p[0], p[k], p[k + 1]);
            let area = 0.5 * (b - a).perp_dot(c - a).abs();
            sum += area * (f(0.5 * (a + b)) + f(0.5 * (b + c)) + f(0.5 * (c + a))) / 3.0;
        }
        sum
    }
}

impl PhotonKernel {
    /// The layout of a photon map of `scene` with texels of side `texel`.
    #[must_use]
    pub fn new(scene: &Scene, texel: f32) -> Self {
        let map = IrradianceMap::new(scene, texel);
        let grids = map.grids().map(|(origin, axes, size, _)| (origin, axes, size)).collect();
        Self { map, grids }
    }

    /// What the beams of `volumes` give point `p` of receiver triangle `prim` (unit normal `n`, on
    /// the viewer's side) through the kernel: specular beams integrated over it, glossy beams and
    /// shadow beams at `p` (offset to `q` off the surface).
    #[must_use]
    pub fn gather(
        &self,
        volumes: &LightVolumes,
        prim: u32,
        (p, q, n): (Vec3, Vec3, Vec3),
        occluded: Occluded<'_>,
    ) -> Gathered {
        let Some(&(origin, axes, size)) = self.map.plane_of(prim).and_then(|k| self.grids.get(k)) else {
            return volumes.gather(q, n, occluded);
        };
        let to_texels = |x: Vec3| Vec2::new((x - origin).dot(axes[0]), (x - origin).dot(axes[1]));
        let t2 = self.map.texel * self.map.texel;
        let c = to_texels(p);
        let j0 = c.floor();
        // Bilinear weights of the four texels about p (zero outside the grid, as the map's taps).
        let weight = |j: Vec2| {
            let inside = j.x >= 0.0 && j.y >= 0.0 && j.x < size[0] as f32 && j.y < size[1] as f32;
            if inside { (1.0 - (c.x - j.x).abs()).max(0.0) * (1.0 - (c.y - j.y).abs()).max(0.0) } else { 0.0 }
        };
        // The kernel's support, cells j0 − 1 ..= j0 + 1 (cell i spans [i, i + 1]), each with its
        // corners' weights, once per point.
        let cells: [[[(Vec2, f32); 4]; 3]; 3] = core::array::from_fn(|dy| {
            core::array::from_fn(|dx| {
                let cell = j0 + Vec2::new(dx as f32 - 1.0, dy as f32 - 1.0);
                CORNERS.map(|o| (cell + o, weight(cell + o)))
            })
        });
        let mut g = Gathered::default();
        let reach = 2.0 * core::f32::consts::SQRT_2 * self.map.texel;
        volumes.tree.for_each_near(q, reach, |i| {
            let b = &volumes.beams[i];
            if b.shadow || b.sigma > 0.0 {
                volumes.add(i, q, n, occluded, &mut g);
                return;
            }
            g.tested += 1;
            // The footprint on the receiver's plane, light arriving on the viewer's side.
            let l = &b.beam;
            if (l.dirs[0] + l.dirs[1] + l.dirs[2]).dot(n) >= 0.0 {
                return;
            }
            let mut foot = [Vec2::ZERO; 3];
            for k in 0..3 {
                let to = (p - l.origins[k]).dot(n);
                let along = l.dirs[k].dot(n);
                // Origins on the receiver's plane (a scatterer touching it) are footprint corners.
                if along == 0.0 || to / along < -1e-4 * (p - l.origins[k]).length() / along.abs() {
                    return;
                }
                foot[k] = to_texels(l.origins[k] + l.dirs[k] * (to / along).max(0.0));
            }
            let area = 0.5 * (foot[1] - foot[0]).perp_dot(foot[2] - foot[0]).abs();
            if !area.is_finite() {
                return;
            }
            if area < 1e-3 {
                // A sliver (near a caustic): its flux as a point mass at its centroid.
                let m = (foot[0] + foot[1] + foot[2]) / 3.0;
                let k: f32 = cells[1][1]
                    .iter()
                    .map(|&(j, w)| w * (1.0 - (m.x - j.x).abs()).max(0.0) * (1.0 - (m.y - j.y).abs()).max(0.0))
                    .sum();
                if k > 0.0 && !blocked(l, q, occluded) {
                    g.irradiance += b.power * (l.flux * k / t2);
                }
                return;
            }
            // The kernel's cells the footprint's bounds meet, column strips first, each clipped only
            // where it crosses.
            let (lo, hi) = (foot[0].min(foot[1]).min(foot[2]), foot[0].max(foot[1]).max(foot[2]));
            let (first, last) = (lo.floor().max(j0 - Vec2::ONE), hi.floor().min(j0 + Vec2::ONE));
            let tri = Piece::triangle(foot);
            let mut sum = 0.0;
            let mut x = first.x;
            while x <= last.x {
                let mut strip = tri;
                if lo.x < x {
                    strip = strip.clip(0, x, false);
                }
                if hi.x > x + 1.0 {
                    strip = strip.clip(0, x + 1.0, true);
                }
                let mut y = first.y;
                while y <= last.y && strip.n >= 3 {
                    let corners = &cells[(y - j0.y + 1.0) as usize][(x - j0.x + 1.0) as usize];
                    if corners.iter().any(|k| k.1 > 0.0) {
                        let mut piece = strip;
                        if lo.y < y {
                            piece = piece.clip(1, y, false);
                        }
                        if hi.y > y + 1.0 {
                            piece = piece.clip(1, y + 1.0, true);
                        }
                        if piece.n >= 3 {
                            sum += piece.integrate(corners);
                        }
                    }
                    y += 1.0;
                }
                x += 1.0;
            }
            if sum > 0.0 && !blocked(l, q, occluded) {
                g.irradiance += b.power * (l.flux * sum / (area * t2));
            }
        });
        g
    }
}
