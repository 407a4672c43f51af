//! The light arriving from beyond the scene, seen along every ray that leaves it: black, a
//! constant radiance (a uniform sky), or an equirectangular map of linear RGB radiance read from a
//! Radiance `.hdr` or an OpenEXR `.exr` file.
//!
//! # The map's convention
//!
//! That of glTF viewers (three.js's `equirectUv`, the Khronos sample viewer): +Y is up; a unit
//! direction `d` looks at
//!
//! - `u = 0.5 + atan2(d.z, d.x) / 2π` across the image, from its left edge (0) to its right (1);
//! - `v = acos(d.y) / π` down the image, from its top row (+Y, 0) to its bottom row (−Y, 1).
//!
//! So the image's centre column looks along +X, the column at three quarters along +Z, the one at a
//! quarter along −Z and its left and right edges along −X; seen from inside, looking at the centre
//! column with +Y up, the panorama is not mirrored. Texels are point samples at their centres
//! (`(i + ½) / width`, `(j + ½) / height`), filtered bilinearly, wrapping around in `u` and clamped at
//! the poles in `v`. A `rotation` turns the map about +Y (right-handed: by 90°, what was seen along
//! +X is seen along −Z).

use super::light::Light;
use crate::error::SceneError;
use crate::read::{has_extension, read_bounded};
use beam_math::Aabb;
use beam_math::glam::Vec3;
use std::f32::consts::{PI, TAU};
use std::io::Cursor;
use std::path::Path;
use std::sync::Arc;

/// Largest environment map file read (1 GiB).
pub const MAX_ENVIRONMENT_BYTES: u64 = 1 << 30;
/// Largest side of an environment map, texels.
pub const MAX_ENVIRONMENT_SIDE: u32 = 16384;
/// Most texels of an environment map (8192 × 4096, 384 MiB as `f32` RGB).
pub const MAX_ENVIRONMENT_TEXELS: u64 = 8192 * 4096;

/// What a ray that leaves the scene sees.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Environment {
    /// Nothing: black (the default; no light from beyond the scene).
    #[default]
    Black,
    /// The same linear RGB radiance from every direction (a uniform sky).
    Constant(Vec3),
    /// An equirectangular map of radiance.
    Map(Arc<EnvironmentMap>),
}

impl Environment {
    /// A neutral, slightly blue, uniform sky of modest radiance (about 0.3), for models that
    /// bring no light of their own (with a key light beside it).
    #[must_use]
    pub fn neutral_sky() -> Self {
        Self::Constant(Vec3::new(0.28, 0.31, 0.36))
    }

    /// The radiance arriving from direction `direction` (not necessarily unit): what a ray of that
    /// direction sees when it leaves the scene.
    #[must_use]
    pub fn radiance(&self, direction: Vec3) -> Vec3 {
        match self {
            Self::Black => Vec3::ZERO,
            Self::Constant(c) => *c,
            Self::Map(map) => map.radiance(direction),
        }
    }

    /// The largest channel of the radiance from any direction.
    #[must_use]
    pub fn max_radiance(&self) -> f32 {
        match self {
            Self::Black => 0.0,
            Self::Constant(c) => c.max_element(),
            Self::Map(map) => map.max_radiance(),
        }
    }

    /// Whether no light at all arrives from beyond the scene.
    #[must_use]
    pub fn is_black(&self) -> bool {
        match self {
            Self::Black => true,
            Self::Constant(c) => *c == Vec3::ZERO,
            Self::Map(map) => map.max_radiance() == 0.0,
        }
    }

    /// The environment in a few words, for statistics (`black`, `constant`, `map 2048×1024`).
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Self::Black => "black".into(),
            Self::Constant(_) => "constant".into(),
            Self::Map(m) => format!("map {}×{}", m.width, m.height),
        }
    }

    /// A constant environment as area lights: the six inward-facing faces of a cube about `bounds`
    /// (every point of `bounds` at least half the box's diagonal from every face), each of the
    /// environment's radiance `L`. Radiance is constant along a ray in empty space, so a point
    /// inside the cube receives from each direction either what the scene sends it or `L`, from
    /// the cube or from the sky alike: the cube's light is the sky's light exactly, and exact
    /// shadow beams to its faces give exact sky visibility. Empty for a black or mapped environment
    /// (a map is not constant over a face).
    #[must_use]
    pub fn lights(&self, bounds: Aabb) -> Vec<Light> {
        let Self::Constant(radiance) = *self else { return Vec::new() };
        if radiance == Vec3::ZERO || !bounds.is_valid() {
            return Vec::new();
        }
        let diagonal = bounds.extent().length();
        let half = if diagonal > 0.0 { diagonal } else { 1.0 };
        let (lo, hi) = (bounds.center() - Vec3::splat(half), bounds.center() + Vec3::splat(half));
        let side = hi - lo;
        let mut out = Vec::with_capacity(6);
        for axis in 0..3 {
            // `a × b` is along the axis: `Y × Z = X`, `Z × X = Y`, `X × Y = Z`.
            let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
            let (a, b) = (Vec3::AXES[i] * side[i], Vec3::AXES[j] * side[j]);
            // The face at the low end faces +axis (inwards), the one at the high end −axis.
            out.push(Light::Quad { corner: lo, edge_u: a, edge_v: b, radiance });
            let far = lo + Vec3::AXES[axis] * side[axis];
            out.push(Light::Quad { corner: far, edge_u: b, edge_v: a, radiance });
        }
        out
    }
}

/// An equirectangular map of linear RGB radiance (the module's convention), times an intensity,
/// turned about +Y by a rotation.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    width: u32,
    height: u32,
    /// Row-major, the top row (+Y) first.
    texels: Vec<Vec3>,
    intensity: f32,
    /// `(cos, sin)` of the rotation about +Y.
    rotation: (f32, f32),
    /// Largest channel of any texel.
    max: f32,
}

impl EnvironmentMap {
    /// A map of `width × height` texels, row-major from the top row. Errors for a size out of
    /// range ([`MAX_ENVIRONMENT_SIDE`], [`MAX_ENVIRONMENT_TEXELS`]), a texel count that does not
    /// match, or a texel that is not finite (negative channels are taken as 0).
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Result<Self, SceneError> {
        check_size(None, width, height)?;
        if texels.len() as u64 != u64::from(width) * u64::from(height) {
            let message = format!("{} texels for a {width}×{height} environment map", texels.len());
            return Err(SceneError::Image { path: None, message });
        }
        Self::checked(None, width, height, texels)
    }

    /// The `.hdr` (Radiance RGBE) or `.exr` (OpenEXR, its R, G and B channels; the first layer,
    /// at full resolution) environment map at `path`, read once through a bounded reader
    /// ([`MAX_ENVIRONMENT_BYTES`]); its size is checked before its texels are decoded. Errors name
    /// the file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let fail = |message: String| SceneError::Image { path: Some(path.to_path_buf()), message };
        let (hdr, exr) = (has_extension(path, "hdr"), has_extension(path, "exr"));
        if !hdr && !exr {
            return Err(fail("expected an environment map in .hdr (Radiance) or .exr (OpenEXR)".into()));
        }
        let bytes = read_bounded(path, MAX_ENVIRONMENT_BYTES)?;
        let (width, height, texels) = if hdr { decode_hdr(path, &bytes)? } else { decode_exr(path, &bytes)? };
        Self::checked(Some(path), width, height, texels)
    }

    /// The map with its radiance scaled by `intensity` (≥ 0 and finite; other values leave it
    /// as it is).
    #[must_use]
    pub fn with_intensity(mut self, intensity: f32) -> Self {
        if intensity >= 0.0 && intensity.is_finite() {
            self.intensity = intensity;
        }
        self
    }

    /// The map turned by `degrees` about +Y (right-handed: by 90°, what was seen along +X is seen
    /// along −Z); a non-finite angle leaves it as it is.
    #[must_use]
    pub fn with_rotation(mut self, degrees: f32) -> Self {
        if degrees.is_finite() {
            let (s, c) = degrees.to_radians().sin_cos();
            self.rotation = (c, s);
        }
        self
    }

    /// Width in texels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The largest channel of any texel, times the intensity: a bound on [`Self::radiance`].
    #[must_use]
    pub fn max_radiance(&self) -> f32 {
        self.max * self.intensity
    }

    /// The radiance arriving from direction `d` (not necessarily unit; zero for a zero or
    /// non-finite direction): the map's bilinear filter at `(u, v)` of the module's convention,
    /// after the rotation, times the intensity.
    #[must_use]
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let Some(d) = d.try_normalize() else { return Vec3::ZERO };
        // Into the map's own frame: turned back by the rotation.
        let (c, s) = self.rotation;
        let d = Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
        let u = 0.5 + d.z.atan2(d.x) / TAU;
        let v = d.y.clamp(-1.0, 1.0).acos() / PI;
        self.bilinear(u * self.width as f32 - 0.5, v * self.height as f32 - 0.5) * self.intensity
    }

    /// The unit direction the point `(u, v)` of the image looks along (`u` from the left edge, `v`
    /// from the top, both in `[0, 1]`), before the rotation: the inverse of [`Self::radiance`]'s
    /// mapping.
    #[must_use]
    pub fn direction(u: f32, v: f32) -> Vec3 {
        let (phi, theta) = ((u - 0.5) * TAU, v * PI);
        Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin())
    }

    /// The texels about `(x, y)` (texel coordinates, centres at integers) weighted bilinearly:
    /// columns wrap around, rows are clamped.
    fn bilinear(&self, x: f32, y: f32) -> Vec3 {
        let (w, h) = (self.width as i32, self.height as i32);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        // `x` lies in `[−½, w − ½]` and `y` in `[−½, h − ½]`: one wrap or clamp each way is enough.
        let (i, j) = (x0 as i32, y0 as i32);
        let c0 = if i < 0 {
            i + w
        } else if i >= w {
            i - w
        } else {
            i
        };
        let c1 = if c0 + 1 == w { 0 } else { c0 + 1 };
        let (r0, r1) = (j.clamp(0, h - 1), (j + 1).clamp(0, h - 1));
        let at = |c: i32, r: i32| self.texels[(r * w + c) as usize];
        let top = at(c0, r0) * (1.0 - fx) + at(c1, r0) * fx;
        let bottom = at(c0, r1) * (1.0 - fx) + at(c1, r1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// A map of the decoded `texels` of `path` (none: given in memory): each finite (negative
    /// channels taken as 0).
    fn checked(path: Option<&Path>, width: u32, height: u32, mut texels: Vec<Vec3>) -> Result<Self, SceneError> {
        let mut max = 0.0f32;
        for (i, t) in texels.iter_mut().enumerate() {
            if !t.is_finite() {
                let (x, y) = (i % width as usize, i / width as usize);
                let message = format!("texel ({x}, {y}) is not finite ({t})");
                return Err(SceneError::Image { path: path.map(Path::to_path_buf), message });
            }
            *t = t.max(Vec3::ZERO);
            max = max.max(t.max_element());
        }
        Ok(Self { width, height, texels, intensity: 1.0, rotation: (1.0, 0.0), max })
    }
}

/// Refuse a map size out of range, naming `path` where there is one.
fn check_size(path: Option<&Path>, width: u32, height: u32) -> Result<(), SceneError> {
    let texels = u64::from(width) * u64::from(height);
    if width == 0 || height == 0 || width > MAX_ENVIRONMENT_SIDE || height > MAX_ENVIRONMENT_SIDE {
        let message =
            format!("a {width}×{height} environment map: each side must be 1 to {MAX_ENVIRONMENT_SIDE} texels");
        return Err(SceneError::Image { path: path.map(Path::to_path_buf), message });
    }
    if texels > MAX_ENVIRONMENT_TEXELS {
        let message =
            format!("a {width}×{height} environment map has more than the {MAX_ENVIRONMENT_TEXELS} texels allowed");
        return Err(SceneError::Image { path: path.map(Path::to_path_buf), message });
    }
    Ok(())
}

/// The texels of the Radiance RGBE image `bytes` (of `path`), its size checked from its header
/// before it is decoded.
fn decode_hdr(path: &Path, bytes: &[u8]) -> Result<(u32, u32, Vec<Vec3>), SceneError> {
    use image::ImageDecoder;
    let fail = |e: image::ImageError| SceneError::Image {
        path: Some(path.to_path_buf()),
        message: format!("not a Radiance RGBE (.hdr) image: {e}"),
    };
    let decoder = image::codecs::hdr::HdrDecoder::new(Cursor::new(bytes)).map_err(fail)?;
    let (width, height) = decoder.dimensions();
    check_size(Some(path), width, height)?;
    let mut buf = vec![0u8; decoder.total_bytes() as usize];
    decoder.read_image(&mut buf).map_err(fail)?;
    let f = |b: &[u8]| f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
    let texels = buf.chunks_exact(12).map(|c| Vec3::new(f(&c[0..4]), f(&c[4..8]), f(&c[8..12]))).collect();
    Ok((width, height, texels))
}

/// The R, G and B texels of the OpenEXR image `bytes` (of `path`; its first layer, at full
/// resolution), its data window's size checked from its header before it is decoded; decoding
/// allocates at most that many texels, whatever the file says by then.
fn decode_exr(path: &Path, bytes: &[u8]) -> Result<(u32, u32, Vec<Vec3>), SceneError> {
    let fail = |e: &dyn std::fmt::Display| SceneError::Image {
        path: Some(path.to_path_buf()),
        message: format!("not an OpenEXR image of R, G and B: {e}"),
    };
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).map_err(|e| fail(&e))?;
    let Some(header) = meta.headers.first() else { return Err(fail(&"no layer")) };
    let size = header.layer_size;
    let (width, height) = (u32::try_from(size.width()), u32::try_from(size.height()));
    let (Ok(width), Ok(height)) = (width, height) else {
        return Err(fail(&format!("a {}×{} image is too large", size.width(), size.height())));
    };
    check_size(Some(path), width, height)?;
    let n = width as usize * height as usize;
    let (w, texels) = crate::io::read_rgb(Cursor::new(bytes), n).map_err(|e| fail(&e))?;
    if texels.len() != n || w != width as usize {
        return Err(fail(&"its pixels do not fill its first layer"));
    }
    Ok((width, height, texels))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mapping and its inverse agree, the poles and the seam are where the convention says,
    /// and a constant map is constant everywhere.
    #[test]
    fn directions_map_to_their_texels() {
        for (u, v) in [(0.5, 0.5), (0.75, 0.5), (0.25, 0.3), (0.1, 0.9), (0.99, 0.01)] {
            let d = EnvironmentMap::direction(u, v);
            let back = (0.5 + d.z.atan2(d.x) / TAU, d.y.acos() / PI);
            assert!((back.0 - u).abs() < 1e-5 && (back.1 - v).abs() < 1e-5, "{u} {v} {d} {back:?}");
        }
        assert!(EnvironmentMap::direction(0.5, 0.5).abs_diff_eq(Vec3::X, 1e-6));
        assert!(EnvironmentMap::direction(0.75, 0.5).abs_diff_eq(Vec3::Z, 1e-6));
        assert!(EnvironmentMap::direction(0.25, 0.5).abs_diff_eq(-Vec3::Z, 1e-6));
        assert!(EnvironmentMap::direction(0.3, 0.0).abs_diff_eq(Vec3::Y, 1e-6));
        let flat = EnvironmentMap::new(4, 2, vec![Vec3::splat(2.0); 8]).unwrap();
        for d in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::new(0.3, -0.2, 0.9)] {
            assert!(flat.radiance(d).abs_diff_eq(Vec3::splat(2.0), 1e-6));
        }
        assert_eq!(flat.radiance(Vec3::ZERO), Vec3::ZERO);
    }

    /// Each of four columns shows its own colour at its centre, columns blend bilinearly between
    /// centres and across the seam, and a rotation turns the map about +Y.
    #[test]
    fn bilinear_filter_wraps_and_rotates() {
        let colours = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE];
        let map = EnvironmentMap::new(4, 1, colours.to_vec()).unwrap();
        for (i, c) in colours.iter().enumerate() {
            let d = EnvironmentMap::direction((i as f32 + 0.5) / 4.0, 0.5);
            assert!(map.radiance(d).abs_diff_eq(*c, 1e-5), "column {i}: {}", map.radiance(d));
        }
        // The left edge (−X) lies halfway between the last column and the first.
        assert!(map.radiance(-Vec3::X).abs_diff_eq(0.5 * (colours[3] + colours[0]), 1e-5));
        assert!(map.radiance(Vec3::X).abs_diff_eq(0.5 * (colours[1] + colours[2]), 1e-5));
        let turned = map.clone().with_rotation(90.0).with_intensity(2.0);
        // Turned by 90° about +Y: what +X saw is seen along −Z.
        assert!(turned.radiance(-Vec3::Z).abs_diff_eq(2.0 * map.radiance(Vec3::X), 1e-5));
        assert_eq!(turned.max_radiance(), 2.0);
    }

    /// A constant sky's six faces enclose the box, face inwards and sum to the full sphere of
    /// solid angle seen from any point inside.
    #[test]
    fn sky_faces_enclose_the_scene() {
        let bounds = Aabb::new(Vec3::new(-1.0, 0.0, -2.0), Vec3::new(3.0, 0.5, 2.0));
        let lights = Environment::Constant(Vec3::ONE).lights(bounds);
        assert_eq!(lights.len(), 6);
        for p in bounds.corners().into_iter().chain([bounds.center()]) {
            let mut solid = 0.0;
            for l in &lights {
                assert!(l.normal().dot(p - l.center()) > 0.0, "{l:?} faces {p}");
                // Solid angle of the quad from `p` (two triangles, Van Oosterom–Strackee).
                let c = l.polygon();
                for t in [[c[0], c[1], c[2]], [c[0], c[2], c[3]]] {
                    let [a, b, c] = t.map(|v| v - p);
                    let (la, lb, lc) = (a.length(), b.length(), c.length());
                    let num = a.dot(b.cross(c));
                    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
                    solid += 2.0 * num.atan2(den).abs();
                }
            }
            assert!((solid - 4.0 * PI).abs() < 1e-3, "{solid}");
        }
        assert!(Environment::Black.lights(bounds).is_empty());
        assert!(Environment::Constant(Vec3::ZERO).is_black());
    }
}
