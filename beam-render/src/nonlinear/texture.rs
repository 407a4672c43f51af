//! What a backend is given and returns for the beams of one tree level: jobs, texel regions and
//! their nearest hits (000 Alg. 1), and the points it shades.

use super::beam_tree::Beam;
use super::face::Exclude;
use super::fit::Fit;
use beam_math::glam::Vec3;

/// What a texel's ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelHit {
    /// The scene triangle.
    pub prim: u32,
    /// Ray parameter of the hit (the ray's direction is not normalised).
    pub t: f32,
}

/// A texel's hit handed back with its ray's hit point and unit direction, found where the backend
/// rendered the texel (the host then evaluates no texel ray for it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelPoint {
    /// The texel in the region's square (`y · size + x`).
    pub texel: u32,
    /// The scene triangle hit.
    pub prim: u32,
    /// The hit point.
    pub p: Vec3,
    /// Unit direction of the texel's ray.
    pub d: Vec3,
    /// The S-mesh face the backend located its point on among its triangle's candidates (beam-gpu,
    /// under a coarse S mesh: the nearest, as [`SMesh::locate`](super::SMesh::locate) chooses),
    /// [`u32::MAX`] where it did not (the caller locates it, [`SMesh::locate_on`](super::SMesh::locate_on)).
    pub face: u32,
}

/// A beam's texel region: `size × size` texels over the base's barycentric square, of which those
/// with `u + v ≤ 1 + 1/size` (the base triangle and a one-texel margin for filtering) are rendered.
/// Texel `(x, y)` has centre `(u, v) = ((x + ½)/size, (y + ½)/size)` and barycentric coordinates
/// `(1 − u − v, u, v)` (clamped to the base in the margin).
#[derive(Clone, Debug)]
pub struct BeamTexture {
    /// Texels per side.
    pub size: u32,
    /// Nearest hit per texel (row-major), `None` where the ray leaves the scene; of a level the
    /// backend kept, only the hits handed back (empty where they are in `points`).
    pub hits: Vec<Option<TexelHit>>,
    /// The hits a backend that kept the level handed back with their points, in texel order:
    /// where not empty, the host's texel hits (empty: the host finds them in `hits`).
    pub points: Vec<TexelPoint>,
    /// Where the backend summed them itself ([`KeptTotals::fits`](super::KeptTotals::fits)), the
    /// fits of the texels from which the tree goes on, per S-mesh face they lie on, ascending by
    /// face (the host's requests of the next level; `points` is then empty).
    pub fits: Vec<(u32, Fit)>,
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
        region_texels(self.size)
    }
}

/// Texels rendered in a region of side `size`: row 0 holds `size`, row `y ≥ 1` holds `size + 1 − y`
/// (the texels with `x + y ≤ size`), `size + size(size + 1)/2 − 1` in all.
#[must_use]
pub fn region_texels(size: u32) -> u64 {
    let s = u64::from(size);
    (s + s * (s + 1) / 2).saturating_sub(1)
}

/// Texels a beam's region gives each pixel its face covers (directly, or through the parent beams):
/// 4, two per side, so that bilinear lookups interpolate rather than extrapolate.
pub const TEXELS_PER_SAMPLE: u32 = 4;

/// The texels per side a beam's region may have: 2 (a base's three corners and its centre) to 4096.
pub const TEXELS: core::ops::RangeInclusive<u32> = 2..=4096;

/// Texels per side of the region of a beam standing for `pixels` pixels, at most `most` (clamped
/// to [`TEXELS`]): the smallest power of two whose `size²/2` texels over the base give
/// [`TEXELS_PER_SAMPLE`] per pixel, and at least 4 unless `most` is smaller.
#[must_use]
pub fn region_size(pixels: f32, most: u32) -> u32 {
    let most = most.clamp(*TEXELS.start(), *TEXELS.end());
    let size = (2.0 * TEXELS_PER_SAMPLE as f32 * pixels.max(0.0)).sqrt().ceil();
    // `as` saturates: a NaN or huge count gives 0 or u32::MAX, both clamped below.
    (size as u32).checked_next_power_of_two().unwrap_or(most).clamp(4.min(most), most)
}

/// A point to shade (beam-cpu's `shade_point`, beam-gpu's shading pass): the radiance leaving point `p` of triangle `prim` towards `−d`
/// (`d` unit), shadow-ray samples seeded by `seed`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadePoint {
    /// The scene triangle.
    pub prim: u32,
    /// The point.
    pub p: Vec3,
    /// Unit direction of the arriving ray.
    pub d: Vec3,
    /// Seed of its samples.
    pub seed: u64,
}

/// One beam to render: `size × size` texels, skipping the surface under its base (`exclude`).
#[derive(Clone, Copy)]
pub struct BeamJob<'a> {
    /// The beam.
    pub beam: &'a Beam,
    /// Texels per side of its region.
    pub size: u32,
    /// The surface it leaves (never hit by its own rays).
    pub exclude: Exclude<'a>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn region_texels_counts_the_rows() {
        for size in 0..200u32 {
            let rows: u64 = (0..size).map(|y| u64::from((size + 1 - y).min(size))).sum();
            let in_region = (0..size).flat_map(|y| (0..size).map(move |x| (x, y))).filter(|&(x, y)| x + y < size + 1);
            assert_eq!(region_texels(size), rows, "{size}");
            assert_eq!(rows, in_region.count() as u64, "{size}");
        }
    }
}
