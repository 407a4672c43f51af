//! Irradiance maps: the gather of a two-pass caustic method (000 §9.2 after Wyman and Davis), in
//! receiver space rather than image space. Every receiving plane of the scene gets a grid of square
//! texels on each of its two sides (a thin wall lit on one side stays dark on the other); flux
//! carriers (beam texels or photons) are splatted into the side they arrive on with a tent kernel,
//! and a shade point reads the irradiance of the side it is seen from back bilinearly.

use beam_math::glam::{Vec2, Vec3};
use beam_scene::scene::{Material, Scene};
use std::collections::HashMap;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

/// One side of a receiving plane: its texels.
#[derive(Clone, Debug)]
struct PlaneMap {
    origin: Vec3,
    axes: [Vec3; 2],
    size: [u32; 2],
    /// Row-major; empty until flux is first deposited (most sides receive none).
    flux: Vec<Vec3>,
}

impl PlaneMap {
    /// Continuous texel coordinates of `p` (texel centres at integers).
    fn coords(&self, p: Vec3) -> Vec2 {
        let q = p - self.origin;
        Vec2::new(q.dot(self.axes[0]), q.dot(self.axes[1]))
    }

    /// Its texels, allocated on first use.
    fn flux_mut(&mut self) -> &mut [Vec3] {
        if self.flux.is_empty() {
            self.flux = vec![Vec3::ZERO; self.size[0] as usize * self.size[1] as usize];
        }
        &mut self.flux
    }

    /// A normal of its plane (not unit: its sign is what [`IrradianceMap::grid`] asks):
    /// `axes[0] × axes[1]`, which [`IrradianceMap::new`] makes along the first triangle's normal.
    fn normal(&self) -> Vec3 {
        self.axes[0].cross(self.axes[1])
    }
}

/// The texels of a `size[0] × size[1]` grid around continuous coordinates `c`, with their bilinear
/// (tent) weights.
fn taps(size: [u32; 2], c: Vec2) -> impl Iterator<Item = (usize, f32)> {
    let (x0, y0) = (c.x.floor(), c.y.floor());
    let (ax, ay) = (c.x - x0, c.y - y0);
    [(0, 0, (1.0 - ax) * (1.0 - ay)), (1, 0, ax * (1.0 - ay)), (0, 1, (1.0 - ax) * ay), (1, 1, ax * ay)]
        .into_iter()
        .filter_map(move |(dx, dy, k)| {
            let (x, y) = (x0 as i64 + dx, y0 as i64 + dy);
            let inside = x >= 0 && y >= 0 && x < i64::from(size[0]) && y < i64::from(size[1]);
            (inside && k > 0.0).then(|| ((y as u64 * u64::from(size[0]) + x as u64) as usize, k))
        })
}

/// Irradiance over the scene's diffuse and glossy triangles, grouped by plane, on both sides of
/// each: grid `2k` of plane `k` holds the flux that arrives travelling against the plane's normal
/// (on its front), grid `2k + 1` the flux travelling along it ([`IrradianceMap::grid`]).
#[derive(Clone, Debug)]
pub struct IrradianceMap {
    /// World size of a texel's side.
    pub texel: f32,
    maps: Vec<PlaneMap>,
    /// Per scene triangle, its plane's index (its front grid's in `maps` over two), or
    /// [`NO_PLANE`] (a dense table: every splat and every shade point looks one up; SipHash cost
    /// more than the splat itself).
    plane_of: Vec<u32>,
    /// Which texels these are ([`IrradianceMap::content_id`]): assigned on first asking, forgotten
    /// by every change of the texels.
    id: OnceLock<u64>,
}

/// "No map" in [`IrradianceMap`]'s table of planes.
const NO_PLANE: u32 = u32::MAX;

impl IrradianceMap {
    /// Empty maps over every diffuse and glossy triangle of `scene`, texels of side `texel` (world
    /// units); coplanar triangles (normals within 1e-3, offsets within a tenth of a texel) share one
    /// map, so that splats cross their shared edges.
    #[must_use]
    pub fn new(scene: &Scene, texel: f32) -> Self {
        let texel = texel.max(f32::MIN_POSITIVE);
        let mut key_of: HashMap<(i32, i32, i32, i64), usize> = HashMap::new();
        // Per plane: origin, in-plane axes, and the bounds of its triangles in those axes.
        let mut bounds: Vec<(Vec3, [Vec3; 2], Vec2, Vec2)> = Vec::new();
        let mut plane_of = vec![NO_PLANE; scene.triangles.len()];
        for (i, tri) in scene.triangles.iter().enumerate() {
            if !matches!(scene.material(i as u32), Material::Diffuse { .. } | Material::Glossy { .. }) {
                continue;
            }
            let n = scene.normal(i as u32);
            let q = |x: f32| (x * 1000.0).round() as i32;
            let key = (q(n.x), q(n.y), q(n.z), (n.dot(tri.v[0]) / (0.1 * texel)).round() as i64);
            let m = *key_of.entry(key).or_insert_with(|| {
                let axes = [n.any_orthonormal_vector(), n.cross(n.any_orthonormal_vector())];
                bounds.push((tri.v[0], axes, Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)));
                bounds.len() - 1
            });
            let (origin, [u, v], lo, hi) = &mut bounds[m];
            let (u, v) = (*u, *v);
            for p in tri.v {
                let c = Vec2::new((p - *origin).dot(u), (p - *origin).dot(v));
                *lo = lo.min(c);
                *hi = hi.max(c);
            }
            plane_of[i] = m as u32;
        }
        let maps = bounds
            .into_iter()
            .flat_map(|(origin, [u, v], lo, hi)| {
                // One texel of margin each side; texel centres at integer coordinates.
                let corner = origin + (lo.x - texel) * u + (lo.y - texel) * v;
                let size = ((hi - lo) / texel).ceil().as_uvec2() + 3;
                let size = [size.x.min(4096), size.y.min(4096)];
                let side = PlaneMap { origin: corner, axes: [u / texel, v / texel], size, flux: Vec::new() };
                [side.clone(), side]
            })
            .collect();
        Self { texel, maps, plane_of, id: OnceLock::new() }
    }

    /// A number that names these texels: two maps with the same number hold the same texels (a
    /// clone keeps its original's; every change of the texels forgets it, and the next asking
    /// draws a number never given before). A GPU keeps the maps it uploaded under it and uploads
    /// them again only for another number.
    #[must_use]
    pub fn content_id(&self) -> u64 {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        *self.id.get_or_init(|| NEXT.fetch_add(1, Ordering::Relaxed))
    }

    /// The grid (an index in [`IrradianceMap::grids`]) of the side of triangle `prim`'s plane that
    /// a ray travelling along `d` arrives on, if the triangle has a plane.
    #[must_use]
    pub fn grid(&self, prim: u32, d: Vec3) -> Option<usize> {
        let front = 2 * self.plane_of(prim)?;
        Some(front + usize::from(self.maps[front].normal().dot(d) > 0.0))
    }

    /// Deposit `flux` (watts) travelling along `d` to point `p` of triangle `prim`, on the side it
    /// arrives on; false when `prim` has no map.
    pub fn splat(&mut self, prim: u32, p: Vec3, d: Vec3, flux: Vec3) -> bool {
        let Some(m) = self.grid(prim, d) else { return false };
        self.id = OnceLock::new();
        let map = &mut self.maps[m];
        let taps = taps(map.size, map.coords(p));
        let texels = map.flux_mut();
        for (k, w) in taps {
            texels[k] += w * flux;
        }
        true
    }

    /// Add `flux` to texel `at` (column, row) of grid `grid` (an index in [`IrradianceMap::grids`]);
    /// outside the grid it is dropped.
    pub fn add_texel(&mut self, grid: usize, at: [usize; 2], flux: Vec3) {
        self.id = OnceLock::new();
        if let Some(map) = self.maps.get_mut(grid)
            && at[0] < map.size[0] as usize
            && at[1] < map.size[1] as usize
        {
            let width = map.size[0] as usize;
            map.flux_mut()[at[1] * width + at[0]] += flux;
        }
    }

    /// Irradiance (watts per unit area) at point `p` of triangle `prim` on the side a ray along `d`
    /// (the eye's, arriving there) sees: the splatted flux over the texel area, read bilinearly;
    /// zero where there is no map.
    #[must_use]
    pub fn irradiance(&self, prim: u32, p: Vec3, d: Vec3) -> Vec3 {
        let Some(m) = self.grid(prim, d) else { return Vec3::ZERO };
        let map = &self.maps[m];
        if map.flux.is_empty() {
            return Vec3::ZERO;
        }
        let sum: Vec3 = taps(map.size, map.coords(p)).map(|(k, w)| w * map.flux[k]).sum();
        sum / (self.texel * self.texel)
    }

    /// Add another map of the same scene and texel size.
    pub fn merge(&mut self, other: &Self) {
        self.id = OnceLock::new();
        for (a, b) in self.maps.iter_mut().zip(&other.maps).filter(|(_, b)| !b.flux.is_empty()) {
            for (x, y) in a.flux_mut().iter_mut().zip(&b.flux) {
                *x += *y;
            }
        }
    }

    /// Relative RMS difference `√(Σ|a − b|² / Σ|b|²)` of the texels of `self` (a) and `other` (b),
    /// maps of the same scene and texel size.
    #[must_use]
    pub fn relative_rms(&self, other: &Self) -> f64 {
        let (mut diff, mut norm) = (0.0f64, 0.0f64);
        for (a, b) in self.maps.iter().zip(&other.maps) {
            // A side without texels holds zeros.
            let at = |flux: &[Vec3], k: usize| flux.get(k).copied().unwrap_or_default();
            for k in 0..a.flux.len().max(b.flux.len()) {
                let (x, y) = (at(&a.flux, k), at(&b.flux, k));
                diff += f64::from((x - y).length_squared());
                norm += f64::from(y.length_squared());
            }
        }
        (diff / norm.max(f64::MIN_POSITIVE)).sqrt()
    }

    /// The grids in order (each plane's front, then its back), for upload to a GPU: texel-centre
    /// origin, axes scaled to texels (so `(p − origin)·axis` is a continuous texel coordinate;
    /// `axes[0] × axes[1]` along the plane's normal), size, and flux per texel (row-major; empty
    /// where none was deposited: zeros).
    pub fn grids(&self) -> impl Iterator<Item = (Vec3, [Vec3; 2], [u32; 2], &[Vec3])> {
        self.maps.iter().map(|m| (m.origin, m.axes, m.size, m.flux.as_slice()))
    }

    /// The index of the plane of triangle `prim` (its front grid is `2 ×` it in
    /// [`IrradianceMap::grids`], its back grid the next), if it has one.
    #[must_use]
    pub fn plane_of(&self, prim: u32) -> Option<usize> {
        let m = *self.plane_of.get(prim as usize)?;
        (m != NO_PLANE).then_some(m as usize)
    }

    /// Total flux deposited.
    #[must_use]
    pub fn total_flux(&self) -> Vec3 {
        self.maps.iter().flat_map(|m| &m.flux).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_scene::scene::builtin;

    /// Equal numbers name equal texels: a clone keeps its original's number until either changes,
    /// and every change (a splat, a texel added, a merge) draws a new one.
    #[test]
    fn content_ids_name_the_texels() {
        let scene = builtin("wavy-lake").unwrap();
        let mut map = IrradianceMap::new(&scene, 0.1);
        let prim = (0..scene.triangles.len() as u32).find(|&p| map.plane_of(p).is_some()).unwrap();
        let down = Vec3::NEG_Y;
        let first = map.content_id();
        assert_eq!(map.content_id(), first);
        let clone = map.clone();
        assert_eq!(clone.content_id(), first);
        assert!(map.splat(prim, scene.triangles[prim as usize].v[0], down, Vec3::ONE));
        let splatted = map.content_id();
        assert_ne!(splatted, first);
        assert_eq!(clone.content_id(), first);
        map.add_texel(0, [0, 0], Vec3::ONE);
        assert_ne!(map.content_id(), splatted);
        let added = map.content_id();
        map.merge(&clone);
        assert_ne!(map.content_id(), added);
        assert_ne!(IrradianceMap::new(&scene, 0.1).content_id(), first);
    }

    /// Flux arriving on one side of a plane is read on that side only: a thin wall lit from the
    /// front stays dark behind, and the other way round; a side nothing reached holds no texels.
    #[test]
    fn each_side_keeps_its_own_flux() {
        let scene = builtin("cornell").unwrap();
        let mut map = IrradianceMap::new(&scene, 10.0);
        let prim = (0..scene.triangles.len() as u32).find(|&p| map.plane_of(p).is_some()).unwrap();
        let n = scene.normal(prim);
        let t = scene.triangles[prim as usize];
        let p = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
        assert!(map.splat(prim, p, -n, Vec3::ONE));
        let (front, back) = (map.irradiance(prim, p, -n), map.irradiance(prim, p, n));
        assert!(front.x > 0.0 && back == Vec3::ZERO, "front {front}, back {back}");
        assert_eq!(map.grids().filter(|g| !g.3.is_empty()).count(), 1);
        assert!(map.splat(prim, p, n, Vec3::splat(2.0)));
        assert!((map.irradiance(prim, p, n) - 2.0 * front).abs().max_element() < 1e-6);
        assert_eq!(map.irradiance(prim, p, -n), front);
        assert!((map.total_flux() - Vec3::splat(3.0)).abs().max_element() < 1e-5);
    }
}
