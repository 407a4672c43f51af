//! Irradiance maps: the gather of a two-pass caustic method (000 §9.2 after Wyman and Davis), in
//! receiver space rather than image space. Every receiving plane of the scene gets a grid of square
//! texels; flux carriers (beam texels or photons) are splatted into it with a tent kernel, and a
//! shade point reads the irradiance back bilinearly.

use beam_math::glam::{Vec2, Vec3};
use beam_scene::scene::{Material, Scene};
use std::collections::HashMap;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

/// One receiving plane's texels.
#[derive(Clone, Debug)]
struct PlaneMap {
    origin: Vec3,
    axes: [Vec3; 2],
    size: [u32; 2],
    flux: Vec<Vec3>,
}

impl PlaneMap {
    /// Continuous texel coordinates of `p` (texel centres at integers).
    fn coords(&self, p: Vec3) -> Vec2 {
        let q = p - self.origin;
        Vec2::new(q.dot(self.axes[0]), q.dot(self.axes[1]))
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

/// Irradiance over the scene's diffuse and glossy triangles, grouped by plane.
#[derive(Clone, Debug)]
pub struct IrradianceMap {
    /// World size of a texel's side.
    pub texel: f32,
    maps: Vec<PlaneMap>,
    /// Per scene triangle, its plane's index in `maps`, or [`NO_PLANE`] (a dense table: every
    /// splat and every shade point looks one up; SipHash cost more than the splat itself).
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
            .map(|(origin, [u, v], lo, hi)| {
                // One texel of margin each side; texel centres at integer coordinates.
                let corner = origin + (lo.x - texel) * u + (lo.y - texel) * v;
                let size = ((hi - lo) / texel).ceil().as_uvec2() + 3;
                let size = [size.x.min(4096), size.y.min(4096)];
                PlaneMap {
                    origin: corner,
                    axes: [u / texel, v / texel],
                    size,
                    flux: vec![Vec3::ZERO; (size[0] * size[1]) as usize],
                }
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

    /// Deposit `flux` (watts) arriving at point `p` of triangle `prim`; false when `prim` has no map.
    pub fn splat(&mut self, prim: u32, p: Vec3, flux: Vec3) -> bool {
        let Some(m) = self.plane_of(prim) else { return false };
        self.id = OnceLock::new();
        let map = &mut self.maps[m];
        for (k, w) in taps(map.size, map.coords(p)) {
            map.flux[k] += w * flux;
        }
        true
    }

    /// Add `flux` to texel `at` (column, row) of plane `plane` (an index in [`IrradianceMap::grids`]);
    /// outside the grid it is dropped.
    pub fn add_texel(&mut self, plane: usize, at: [usize; 2], flux: Vec3) {
        self.id = OnceLock::new();
        if let Some(map) = self.maps.get_mut(plane)
            && at[0] < map.size[0] as usize
            && at[1] < map.size[1] as usize
        {
            map.flux[at[1] * map.size[0] as usize + at[0]] += flux;
        }
    }

    /// Irradiance (watts per unit area) at point `p` of triangle `prim`: the splatted flux over the
    /// texel area, read bilinearly; zero where there is no map.
    #[must_use]
    pub fn irradiance(&self, prim: u32, p: Vec3) -> Vec3 {
        let Some(m) = self.plane_of(prim) else { return Vec3::ZERO };
        let map = &self.maps[m];
        let sum: Vec3 = taps(map.size, map.coords(p)).map(|(k, w)| w * map.flux[k]).sum();
        sum / (self.texel * self.texel)
    }

    /// Add another map of the same scene and texel size.
    pub fn merge(&mut self, other: &Self) {
        self.id = OnceLock::new();
        for (a, b) in self.maps.iter_mut().zip(&other.maps) {
            for (x, y) in a.flux.iter_mut().zip(&b.flux) {
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
            for (x, y) in a.flux.iter().zip(&b.flux) {
                diff += f64::from((*x - *y).length_squared());
                norm += f64::from(y.length_squared());
            }
        }
        (diff / norm.max(f64::MIN_POSITIVE)).sqrt()
    }

    /// The planes' grids in order, for upload to a GPU: texel-centre origin, axes scaled to texels
    /// (so `(p − origin)·axis` is a continuous texel coordinate), size, and flux per texel (row-major).
    pub fn grids(&self) -> impl Iterator<Item = (Vec3, [Vec3; 2], [u32; 2], &[Vec3])> {
        self.maps.iter().map(|m| (m.origin, m.axes, m.size, m.flux.as_slice()))
    }

    /// The index (in [`IrradianceMap::grids`]) of the plane of triangle `prim`, if it has one.
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
        let first = map.content_id();
        assert_eq!(map.content_id(), first);
        let clone = map.clone();
        assert_eq!(clone.content_id(), first);
        assert!(map.splat(prim, scene.triangles[prim as usize].v[0], Vec3::ONE));
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
}
