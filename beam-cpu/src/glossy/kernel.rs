//! The beams through a photon map's kernel, so that beams and photons estimate the very same image.
//! A photon map reads irradiance at `p` as `Σⱼ tentⱼ(p)·Fⱼ/t²` with texel sums `Fⱼ = Σ tentⱼ(x)·Φ`
//! over the photons landing at `x`, in expectation `Fⱼ = ∫ tentⱼ(x)·E(x) dA` over the receivers. The
//! beams' `Fⱼ` are that integral, splatted once a frame and read back like the photons'.
//!
//! A specular beam spreads its flux `Φ` evenly over its footprint on the receiver's plane (the
//! triangle where its three rays meet it: eq. 1 read on that plane), so its share is
//! `Fⱼ = Φ/A·∫ tentⱼ dA` over the footprint's part on the receiver triangles, exactly: the footprint
//! is clipped against each kernel cell (and against the receiver triangles where they cover a cell
//! in part) and the bilinear tents integrated on the pieces by the midpoint rule (exact for degree
//! 2). Glossy beams, smooth at the scale of their lobe, are sampled at each cell's centre:
//! `∫_cell tentⱼ·E dA ≈ E(centre)·∫_cell tentⱼ dA`. Second-order shadows are tested once per beam and
//! cell. The cells are visited in blocks, each taking the beams whose cones reach it from the cone
//! hierarchy; negative shadow beams stay per receiver point ([`LightVolumes::shadows`]).

use beam_math::glam::{Vec2, Vec3};
use beam_render::glossy::{LightVolumes, Occluded, blocked};
use beam_render::irradiance_map::IrradianceMap;
use beam_render::tolerance::shading_eps;
use beam_scene::scene::Scene;
use rayon::prelude::*;

/// Cells per side of a block: the unit of parallel work and of the cone-hierarchy query.
const BLOCK: usize = 16;

/// Glossy beams are sampled on a lattice no coarser than their lobe's width (`σ·distance`) over this.
const LATTICE: f32 = 2.0;

/// Footprints smaller than this (texels²) are splatted as a point mass at their centroid.
const SLIVER: f32 = 1e-3;

/// A convex polygon of at most 8 vertices: a triangle or cell clipped by a few lines (the kernel's
/// inner loop: lines as `m·p ≤ d`, and no capacity error to carry, unlike `ConvexPolygon::clip`).
#[derive(Clone, Copy)]
struct Piece {
    v: [Vec2; 8],
    n: usize,
}

impl Piece {
    fn new(points: &[Vec2]) -> Self {
        let mut v = [Vec2::ZERO; 8];
        v[..points.len()].copy_from_slice(points);
        Self { v, n: points.len() }
    }

    /// The unit cell with lower corner `c`.
    fn cell(c: Vec2) -> Self {
        Self::new(&[c, c + Vec2::X, c + Vec2::ONE, c + Vec2::Y])
    }

    /// The part where `m·p ≤ d` (Sutherland–Hodgman against one line).
    fn clip(&self, m: Vec2, d: f32) -> Self {
        let mut out = Self { v: [Vec2::ZERO; 8], n: 0 };
        for i in 0..self.n {
            let (a, b) = (self.v[i], self.v[(i + 1) % self.n]);
            let (da, db) = (m.dot(a) - d, m.dot(b) - d);
            if da <= 0.0 && out.n < 8 {
                out.v[out.n] = a;
                out.n += 1;
            }
            if (da <= 0.0) != (db <= 0.0) && out.n < 8 {
                out.v[out.n] = a + (b - a) * (da / (da - db));
                out.n += 1;
            }
        }
        out
    }

    /// The part inside triangle `t` (counter-clockwise).
    fn inside(&self, t: &[Vec2; 3]) -> Self {
        (0..3).fold(*self, |p, k| {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let m = -(b - a).perp();
            if p.n < 3 { p } else { p.clip(m, m.dot(a)) }
        })
    }

    /// `∫ tentₖ dA` over the piece for the four corners `cₖ` of the unit cell with lower corner
    /// `cell` (`tentₖ(x) = (1 − |x − cₖ|)(1 − |y − cₖ|)`, bilinear on the cell): fan triangles,
    /// midpoint rule (exact for degree 2).
    fn tents(&self, cell: Vec2) -> [f32; 4] {
        let at = |x: Vec2| tents_at(x - cell);
        let p = &self.v[..self.n];
        let mut sum = [0.0; 4];
        for k in 1..p.len().saturating_sub(1) {
            let (a, b, c) = (p[0], p[k], p[k + 1]);
            let third = (b - a).perp_dot(c - a).abs() / 6.0;
            let (u, v, w) = (at(0.5 * (a + b)), at(0.5 * (b + c)), at(0.5 * (c + a)));
            for j in 0..4 {
                sum[j] += third * (u[j] + v[j] + w[j]);
            }
        }
        sum
    }

    /// The mean of its vertices (a point inside it).
    fn centre(&self) -> Vec2 {
        self.v[..self.n].iter().sum::<Vec2>() / self.n.max(1) as f32
    }
}

/// The four tents of a unit cell's corners (lower left, lower right, upper left, upper right) at
/// `f`, relative to its lower corner.
fn tents_at(f: Vec2) -> [f32; 4] {
    [(1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y]
}

/// Continuous texel coordinates of world point `x` on the plane with texel (0, 0) at `origin` and
/// axes scaled to texels `axes`.
fn texel_coords(origin: Vec3, axes: [Vec3; 2], x: Vec3) -> Vec2 {
    Vec2::new((x - origin).dot(axes[0]), (x - origin).dot(axes[1]))
}

/// True when `p` lies in triangle `t` (counter-clockwise), edges included.
fn contains(t: &[Vec2; 3], p: Vec2) -> bool {
    (0..3).all(|k| (t[(k + 1) % 3] - t[k]).perp_dot(p - t[k]) >= 0.0)
}

/// `∫ tentₖ dA` over a whole unit cell, for each corner.
const WHOLE: [f32; 4] = [0.25; 4];

/// One receiving plane of the map: its grid and how its receiver triangles cover the grid's cells
/// (cell `(x, y)` spans texel centres `x ..= x + 1`, `y ..= y + 1`).
#[derive(Clone, Debug)]
struct Receivers {
    /// World position of texel (0, 0), in-plane axes scaled to texels (world to texels) and their
    /// inverses (a texel step in the world), unit normal.
    origin: Vec3,
    axes: [Vec3; 2],
    steps: [Vec3; 2],
    normal: Vec3,
    /// Texels per side.
    size: [usize; 2],
    /// The receiver triangles in texel coordinates, counter-clockwise.
    triangles: Vec<[Vec2; 3]>,
    /// Per cell: inside one receiver triangle whole.
    full: Vec<bool>,
    /// Per cell, `partial[start[c]..start[c + 1]]`: the triangles that cover part of it.
    start: Vec<u32>,
    partial: Vec<u32>,
}

impl Receivers {
    /// The plane of grid `(origin, axes, size)` and its receiver triangles `triangles` (world).
    fn new((origin, axes, size): (Vec3, [Vec3; 2], [u32; 2]), world: &[[Vec3; 3]]) -> Self {
        let size = [size[0] as usize, size[1] as usize];
        let triangles: Vec<[Vec2; 3]> = world
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|x| texel_coords(origin, axes, x));
                if (b - a).perp_dot(c - a) < 0.0 { [a, c, b] } else { [a, b, c] }
            })
            .collect();
        let cells = size[0].saturating_sub(1) * size[1].saturating_sub(1);
        let mut full = vec![false; cells];
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for (i, t) in triangles.iter().enumerate() {
            let lo = t[0].min(t[1]).min(t[2]).floor().max(Vec2::ZERO);
            let hi = t[0].max(t[1]).max(t[2]).floor();
            for y in lo.y as usize..=(hi.y as usize).min(size[1].saturating_sub(2)) {
                for x in lo.x as usize..=(hi.x as usize).min(size[0].saturating_sub(2)) {
                    let c = Vec2::new(x as f32, y as f32);
                    let cell = y * (size[0] - 1) + x;
                    if [c, c + Vec2::X, c + Vec2::Y, c + Vec2::ONE].into_iter().all(|p| contains(t, p)) {
                        full[cell] = true;
                    } else if Piece::cell(c).inside(t).tents(c).iter().sum::<f32>() > 1e-9 {
                        pairs.push((cell as u32, i as u32));
                    }
                }
            }
        }
        pairs.sort_unstable();
        let mut start = vec![0u32; cells + 1];
        for &(c, _) in &pairs {
            start[c as usize + 1] += 1;
        }
        for c in 0..cells {
            start[c + 1] += start[c];
        }
        let partial = pairs.into_iter().map(|p| p.1).collect();
        let (normal, steps) = (axes[0].cross(axes[1]).normalize_or_zero(), axes.map(|a| a / a.length_squared()));
        Self { origin, axes, steps, normal, size, triangles, full, start, partial }
    }

    /// Cells per side.
    fn cells(&self) -> [usize; 2] {
        [self.size[0].saturating_sub(1), self.size[1].saturating_sub(1)]
    }

    fn to_texels(&self, x: Vec3) -> Vec2 {
        texel_coords(self.origin, self.axes, x)
    }

    /// The world point at texel coordinates `c`.
    fn world(&self, c: Vec2) -> Vec3 {
        self.origin + c.x * self.steps[0] + c.y * self.steps[1]
    }

    /// The triangles covering part of cell `c` (an index), none when it is whole.
    fn partial(&self, c: usize) -> &[u32] {
        &self.partial[self.start[c] as usize..self.start[c + 1] as usize]
    }

    /// True when cell `c` has receivers.
    fn covered(&self, c: usize) -> bool {
        self.full[c] || self.start[c] != self.start[c + 1]
    }

    /// `∫ tentₖ dA` over `piece`'s part on the receivers, in cell `c` (an index) with lower corner
    /// `corner`.
    fn tents(&self, piece: &Piece, c: usize, corner: Vec2) -> [f32; 4] {
        if self.full[c] {
            return piece.tents(corner);
        }
        let mut sum = [0.0; 4];
        for &t in self.partial(c) {
            let part = piece.inside(&self.triangles[t as usize]);
            if part.n >= 3 {
                let w = part.tents(corner);
                for k in 0..4 {
                    sum[k] += w[k];
                }
            }
        }
        sum
    }

    /// True when point `m` (texel coordinates) of cell `c` lies on a receiver.
    fn receives(&self, c: usize, m: Vec2) -> bool {
        self.full[c] || self.partial(c).iter().any(|&t| contains(&self.triangles[t as usize], m))
    }
}

/// The texel sums of one block of cells, per side, row by row (`BLOCK + 1` texels a row at most).
struct Block {
    plane: usize,
    first: [usize; 2],
    width: usize,
    flux: [Vec<Vec3>; 2],
    tested: u64,
}

impl Block {
    /// Add `f·w[k]` to the four corners of the cell at `(x, y)` (block-relative) on `side`.
    fn add(&mut self, side: usize, (x, y): (usize, usize), f: Vec3, w: [f32; 4]) {
        let i = y * self.width + x;
        for (k, at) in [i, i + 1, i + self.width, i + self.width + 1].into_iter().enumerate() {
            self.flux[side][at] += f * w[k];
        }
    }
}

/// A photon map's layout (its planes' grids, which plane each receiver triangle reads) and the
/// receiver triangles' cover of its cells.
#[derive(Clone, Debug)]
pub struct PhotonKernel {
    map: IrradianceMap,
    planes: Vec<Receivers>,
    /// The blocks (plane, first cell) that hold receivers.
    blocks: Vec<(usize, [usize; 2])>,
    /// Offset of shade points off their surface.
    eps: f32,
}

impl PhotonKernel {
    /// The layout of a photon map of `scene` with texels of side `texel`.
    #[must_use]
    pub fn new(scene: &Scene, texel: f32) -> Self {
        let map = IrradianceMap::new(scene, texel);
        // Per plane (its front grid's layout: both sides share it), its receiver triangles.
        let mut world: Vec<Vec<[Vec3; 3]>> = vec![Vec::new(); map.grids().count() / 2];
        for (i, t) in scene.triangles.iter().enumerate() {
            if let Some(k) = map.plane_of(i as u32) {
                world[k].push(t.v);
            }
        }
        let grids: Vec<_> = map.grids().step_by(2).map(|(origin, axes, size, _)| (origin, axes, size)).collect();
        let planes: Vec<Receivers> =
            grids.into_par_iter().zip(world.par_iter()).map(|(grid, tris)| Receivers::new(grid, tris)).collect();
        let mut blocks = Vec::new();
        for (k, r) in planes.iter().enumerate() {
            let [cx, cy] = r.cells();
            for y in (0..cy).step_by(BLOCK) {
                for x in (0..cx).step_by(BLOCK) {
                    let any = (y..(y + BLOCK).min(cy)).any(|y| (x..(x + BLOCK).min(cx)).any(|x| r.covered(y * cx + x)));
                    if any {
                        blocks.push((k, [x, y]));
                    }
                }
            }
        }
        Self { map, planes, blocks, eps: shading_eps(scene) }
    }

    /// The scattered beams of `volumes` splatted into photon maps of this layout (one per side of
    /// the receivers, as [`super::glossy_photons`]'s), second-order shadows by `occluded`; and the
    /// beam–block pairs evaluated. Shadow beams are left out.
    #[must_use]
    pub fn splat(&self, volumes: &LightVolumes, occluded: Occluded<'_>) -> (IrradianceMap, u64) {
        let done: Vec<Block> =
            self.blocks.par_iter().map(|&(k, first)| self.splat_block(volumes, k, first, occluded)).collect();
        let mut map = self.map.clone();
        let mut tested = 0;
        for b in done {
            tested += b.tested;
            for (side, flux) in b.flux.iter().enumerate() {
                for (i, f) in flux.iter().enumerate() {
                    if *f != Vec3::ZERO {
                        map.add_texel(2 * b.plane + side, [b.first[0] + i % b.width, b.first[1] + i / b.width], *f);
                    }
                }
            }
        }
        (map, tested)
    }

    /// The texel sums of the cells `first ..< first + BLOCK` of plane `k`.
    fn splat_block(&self, volumes: &LightVolumes, k: usize, first: [usize; 2], occluded: Occluded<'_>) -> Block {
        let r = &self.planes[k];
        let [cx, cy] = r.cells();
        let last = [(first[0] + BLOCK).min(cx), (first[1] + BLOCK).min(cy)];
        let width = last[0] - first[0] + 1;
        let texels = width * (last[1] - first[1] + 1);
        let mut out =
            Block { plane: k, first, width, flux: [vec![Vec3::ZERO; texels], vec![Vec3::ZERO; texels]], tested: 0 };
        let (lo, hi) = (Vec2::new(first[0] as f32, first[1] as f32), Vec2::new(last[0] as f32, last[1] as f32));
        let reach = 0.5 * (hi - lo).length() * self.map.texel + self.eps;
        volumes.tree.for_each_near(r.world(0.5 * (lo + hi)), reach, |i| {
            let b = &volumes.beams[i];
            if b.shadow {
                return;
            }
            out.tested += 1;
            let l = &b.beam;
            // The side the light arrives on: the scatterer's.
            let above = ((l.origins[0] + l.origins[1] + l.origins[2]) / 3.0 - r.origin).dot(r.normal);
            if above == 0.0 {
                return;
            }
            let (side, n) = if above > 0.0 { (0, r.normal) } else { (1, -r.normal) };
            let lift = |c: Vec2| r.world(c) + n * self.eps;
            if b.sigma > 0.0 {
                self.splat_glossy(volumes, i, (r, side, n), (first, last), occluded, &mut out);
                return;
            }
            // The footprint on the receiver's plane: each ray at or past its origin.
            let mut foot = [Vec2::ZERO; 3];
            for k in 0..3 {
                let (height, along) = ((l.origins[k] - r.origin).dot(n), l.dirs[k].dot(n));
                let t = if height.abs() <= self.eps { 0.0 } else { -height / along };
                if !(t >= 0.0 && t.is_finite()) {
                    return;
                }
                foot[k] = r.to_texels(l.origins[k] + l.dirs[k] * t);
            }
            let area = 0.5 * (foot[1] - foot[0]).perp_dot(foot[2] - foot[0]).abs();
            let flux = b.power * l.flux;
            if !area.is_finite() {
                return;
            }
            if area < SLIVER {
                // A sliver (near a caustic): its flux as a point mass at its centroid.
                let m = (foot[0] + foot[1] + foot[2]) / 3.0;
                let cell = m.floor();
                if cell.cmpge(lo).all() && cell.cmplt(hi).all() {
                    let (x, y) = (cell.x as usize, cell.y as usize);
                    if r.receives(y * cx + x, m) && !blocked(l, lift(m), occluded) {
                        out.add(side, (x - first[0], y - first[1]), flux, tents_at(m - cell));
                    }
                }
                return;
            }
            // The block's cells the footprint's bounds meet, column strips first, each clipped only
            // where it crosses.
            let (flo, fhi) = (foot[0].min(foot[1]).min(foot[2]), foot[0].max(foot[1]).max(foot[2]));
            let (from, to) = (flo.floor().max(lo), fhi.floor().min(hi - Vec2::ONE));
            let tri = Piece::new(&foot);
            let per_area = flux / area;
            let mut x = from.x;
            while x <= to.x {
                let mut strip = tri;
                if flo.x < x {
                    strip = strip.clip(-Vec2::X, -x);
                }
                if fhi.x > x + 1.0 {
                    strip = strip.clip(Vec2::X, x + 1.0);
                }
                let mut y = from.y;
                while y <= to.y && strip.n >= 3 {
                    let (corner, c) = (Vec2::new(x, y), y as usize * cx + x as usize);
                    if r.covered(c) {
                        let mut piece = strip;
                        if flo.y < y {
                            piece = piece.clip(-Vec2::Y, -y);
                        }
                        if fhi.y > y + 1.0 {
                            piece = piece.clip(Vec2::Y, y + 1.0);
                        }
                        if piece.n >= 3 {
                            let w = r.tents(&piece, c, corner);
                            if w.iter().any(|w| *w > 0.0) && !blocked(l, lift(piece.centre()), occluded) {
                                out.add(side, (x as usize - first[0], y as usize - first[1]), per_area, w);
                            }
                        }
                    }
                    y += 1.0;
                }
                x += 1.0;
            }
        });
        out
    }

    /// Glossy beam `i`'s share of the cells `first ..< last` of plane `r` (its light arriving on
    /// `side`, against `n`): eq. 3 at the cells' centres, read off a lattice of every `s`-th centre
    /// (bilinearly) where the lobe is wide enough, `s ≤` its width over [`LATTICE`]; second-order
    /// shadows tested on the lattice and, between lattice points that disagree, at each cell.
    fn splat_glossy(
        &self,
        volumes: &LightVolumes,
        i: usize,
        (r, side, n): (&Receivers, usize, Vec3),
        (first, last): ([usize; 2], [usize; 2]),
        occluded: Occluded<'_>,
        out: &mut Block,
    ) {
        let b = &volumes.beams[i];
        let lift = |c: Vec2| r.world(c) + n * self.eps;
        let at = |x: usize, y: usize| Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        // The lobe's width here: σ times the distance from the scatterer.
        let centre = (b.beam.origins[0] + b.beam.origins[1] + b.beam.origins[2]) / 3.0;
        let middle = lift(0.5 * (at(first[0], first[1]) + at(last[0] - 1, last[1] - 1)));
        let width = b.sigma * (middle - centre).length() / self.map.texel;
        let mut s = 1;
        while 2 * s <= BLOCK && (2 * s) as f32 <= width / LATTICE {
            s *= 2;
        }
        // Lattice point (u, v) at the centre of cell first + s·(u, v): irradiance and, where it has
        // some, whether its light is blocked.
        let span = [(last[0] - first[0] - 1).div_ceil(s) + 1, (last[1] - first[1] - 1).div_ceil(s) + 1];
        let mut lattice = [(Vec3::ZERO, false); (BLOCK + 1) * (BLOCK + 1)];
        for v in 0..span[1] {
            for u in 0..span[0] {
                let q = lift(at(first[0] + s * u, first[1] + s * v));
                let e = volumes.scattered(i, q, n);
                lattice[v * span[0] + u] = (e, e != Vec3::ZERO && blocked(&b.beam, q, occluded));
            }
        }
        let t2 = self.map.texel * self.map.texel;
        let cx = r.cells()[0];
        for y in first[1]..last[1] {
            let (v, fy) = ((y - first[1]) / s, ((y - first[1]) % s) as f32 / s as f32);
            for x in first[0]..last[0] {
                let (c, corner) = (y * cx + x, Vec2::new(x as f32, y as f32));
                if !r.covered(c) {
                    continue;
                }
                let (u, fx) = ((x - first[0]) / s, ((x - first[0]) % s) as f32 / s as f32);
                let (u1, v1) = ((u + 1).min(span[0] - 1), (v + 1).min(span[1] - 1));
                let k = [
                    (u, v, (1.0 - fx) * (1.0 - fy)),
                    (u1, v, fx * (1.0 - fy)),
                    (u, v1, (1.0 - fx) * fy),
                    (u1, v1, fx * fy),
                ];
                let (mut e, mut lit, mut dark) = (Vec3::ZERO, false, false);
                for (u, v, w) in k {
                    let (le, shadowed) = lattice[v * span[0] + u];
                    if w > 0.0 && le != Vec3::ZERO {
                        e += w * le;
                        lit |= !shadowed;
                        dark |= shadowed;
                    }
                }
                if e == Vec3::ZERO || (dark && (!lit || blocked(&b.beam, lift(corner + 0.5), occluded))) {
                    continue;
                }
                let w = if r.full[c] { WHOLE } else { r.tents(&Piece::cell(corner), c, corner) };
                out.add(side, (x - first[0], y - first[1]), e * t2, w);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tents_of_a_whole_cell_are_a_quarter_each() {
        let c = Vec2::new(3.0, -2.0);
        for w in Piece::cell(c).tents(c) {
            assert!((w - 0.25).abs() < 1e-6, "{w}");
        }
    }

    #[test]
    fn tents_of_a_half_cell_lean_to_its_corners() {
        // The left half of the unit cell: ∫ (1 − x)(1 − y) over [0, ½] × [0, 1] = 3/16, and x(1 − y): 1/16.
        let half = Piece::cell(Vec2::ZERO).clip(Vec2::X, 0.5);
        let w = half.tents(Vec2::ZERO);
        for (got, want) in w.iter().zip([3.0 / 16.0, 1.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0]) {
            assert!((got - want).abs() < 1e-6, "{w:?}");
        }
    }

    #[test]
    fn a_cell_inside_a_triangle_keeps_only_its_part() {
        // The triangle (0,0), (1,0), (0,1) covers half the unit cell.
        let t = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let part = Piece::cell(Vec2::ZERO).inside(&t);
        let area: f32 = part.tents(Vec2::ZERO).iter().sum();
        assert!((area - 0.5).abs() < 1e-6, "{area}");
    }
}
