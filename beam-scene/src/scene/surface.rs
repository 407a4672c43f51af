//! What a triangle's surface looks like beyond its material's constants: texture coordinates and
//! vertex colours per triangle corner, and per material its base-colour and emissive textures and
//! its coverage (alpha, glTF 2.0 §3.9.4), evaluated at a point of the triangle by its barycentric
//! coordinates.

use super::texture::Texture;
use beam_math::glam::{Affine2, Vec2, Vec3, Vec4};

/// Where a material reads one texture: which texture, which set of texture coordinates
/// (`TEXCOORD_0` or `_1`), and the `KHR_texture_transform` applied to them first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`Surfaces::textures`].
    pub texture: u32,
    /// Texture-coordinate set, 0 or 1.
    pub tex_coord: u8,
    /// `offset · rotation · scale` of `KHR_texture_transform` (the identity without it).
    pub transform: Affine2,
}

/// How a material's coverage α cuts its surface (glTF `alphaMode` other than `OPAQUE`). α is the
/// base colour's alpha: `baseColorFactor`'s times its texture's times the vertex colours'.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaCut {
    /// The alpha of `baseColorFactor`.
    pub factor: f32,
    /// The texture whose alpha multiplies it (`baseColorTexture`).
    pub texture: Option<TextureRef>,
    /// `MASK`: the surface is there where `α ≥ cutoff` (`alphaCutoff`, ½ by default). `None` for
    /// `BLEND`: there with probability α, decided for each ray by a hash of the ray
    /// (`Scene::closest_hit`), so that many rays see `α` of the surface and `1 − α` of what lies
    /// behind it (stochastic transparency).
    pub cutoff: Option<f32>,
}

/// A tangent-space normal texture (glTF `normalTexture`): RGB `(x, y, z)` from `[0, 1]` to
/// `[−1, 1]`, `x` along increasing `u`, `y` towards decreasing `v` (up in the image), `z` along the
/// triangle's normal; `x` and `y` scaled by `scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalMap {
    /// Where it is read (its channels are data: not decoded from sRGB).
    pub texture: TextureRef,
    /// `normalTexture.scale`.
    pub scale: f32,
}

/// The textures of one material. Each multiplies the material's constant (base colour, emitted
/// radiance).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaterialMaps {
    /// `baseColorTexture` (RGB decoded from sRGB).
    pub base_color: Option<TextureRef>,
    /// `emissiveTexture` (RGB decoded from sRGB).
    pub emissive: Option<TextureRef>,
    /// Its cut-out, for `alphaMode` `MASK` and `BLEND`.
    pub alpha: Option<AlphaCut>,
    /// Its normal texture.
    pub normal: Option<NormalMap>,
}

impl MaterialMaps {
    /// Whether the material is the constant it says: no texture and no cut-out.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.base_color.is_none() && self.emissive.is_none() && self.alpha.is_none() && self.normal.is_none()
    }
}

/// Texture coordinates, vertex colours and textures of a scene's triangles; empty for a scene
/// whose materials are constants (then every lookup is one branch).
#[derive(Clone, Debug, Default)]
pub struct Surfaces {
    /// Per triangle, the texture coordinates of its corners in sets 0 and 1 (each empty when no
    /// triangle has that set; a triangle without it has zeros).
    pub uv: [Vec<[Vec2; 3]>; 2],
    /// Per triangle, the linear RGBA colour of its corners (`COLOR_0`; empty when none has one,
    /// white for a triangle without one).
    pub color: Vec<[Vec4; 3]>,
    /// Per triangle, the unit shading normals of its corners (glTF `NORMAL`, OBJ `vn`; empty when
    /// none has any, zeros for a triangle without them): diffuse and glossy surfaces are shaded
    /// with their interpolation ([`Surfaces::smooth_normal`]).
    pub normals: Vec<[Vec3; 3]>,
    /// Textures.
    pub textures: Vec<Texture>,
    /// Per material, its textures; empty when no material has any.
    pub maps: Vec<MaterialMaps>,
}

impl Surfaces {
    /// Whether nothing varies over a triangle: no vertex colours and no textures.
    #[must_use]
    pub fn is_plain(&self) -> bool {
        self.color.is_empty() && self.maps.is_empty()
    }

    /// Keep the per-triangle attributes of the triangles whose `keep` is true (as the scene
    /// drops degenerate triangles).
    pub(super) fn retain(&mut self, keep: &[bool]) {
        retain_by(&mut self.uv[0], keep);
        retain_by(&mut self.uv[1], keep);
        retain_by(&mut self.color, keep);
        retain_by(&mut self.normals, keep);
    }

    /// The shading normal of triangle `prim` (geometric unit normal `n`) at barycentric coordinates
    /// `w`: its corners' normals interpolated (Phong), turned to `n`'s side where the file winds the
    /// triangle against them; `None` without them (a corner without one: all zeros) or where they
    /// cancel.
    #[must_use]
    pub fn smooth_normal(&self, prim: u32, n: Vec3, w: Vec3) -> Option<Vec3> {
        let c = self.normals.get(prim as usize).filter(|c| !c.contains(&Vec3::ZERO))?;
        let s = (w.x * c[0] + w.y * c[1] + w.z * c[2]).try_normalize()?;
        Some(if s.dot(n) < 0.0 { -s } else { s })
    }

    /// What multiplies the base colour of triangle `prim` (material `material`) at barycentric
    /// coordinates `w`: its base-colour texture's RGB times its vertex colour's RGB (1 without).
    #[must_use]
    pub fn base_factor(&self, prim: u32, material: u32, w: Vec3) -> Vec3 {
        let mut f = Vec3::ONE;
        if let Some(c) = self.color.get(prim as usize) {
            f *= (w.x * c[0] + w.y * c[1] + w.z * c[2]).truncate();
        }
        if let Some(t) = self.maps.get(material as usize).and_then(|m| m.base_color) {
            f *= self.read(t, prim, w).truncate();
        }
        f
    }

    /// What multiplies the emitted radiance of triangle `prim` (material `material`) at
    /// barycentric coordinates `w`: its emissive texture's RGB (1 without).
    #[must_use]
    pub fn emissive_factor(&self, prim: u32, material: u32, w: Vec3) -> Vec3 {
        match self.maps.get(material as usize).and_then(|m| m.emissive) {
            Some(t) => self.read(t, prim, w).truncate(),
            None => Vec3::ONE,
        }
    }

    /// The mean of [`Self::emissive_factor`] over triangle `prim`: the average of a 6-level
    /// triangular grid of 28 points (exact for a factor linear over the triangle).
    #[must_use]
    pub fn mean_emissive_factor(&self, prim: u32, material: u32) -> Vec3 {
        const N: u32 = 6;
        let mut sum = Vec3::ZERO;
        let mut count = 0;
        for i in 0..=N {
            for j in 0..=N - i {
                let w = Vec3::new(i as f32, j as f32, (N - i - j) as f32) / N as f32;
                sum += self.emissive_factor(prim, material, w);
                count += 1;
            }
        }
        sum / count as f32
    }

    /// The cut-out of material `material`, if it has one.
    #[must_use]
    pub fn cut_out(&self, material: u32) -> Option<AlphaCut> {
        self.maps.get(material as usize).and_then(|m| m.alpha)
    }

    /// Whether some material has a cut-out.
    #[must_use]
    pub fn has_cut_outs(&self) -> bool {
        self.maps.iter().any(|m| m.alpha.is_some())
    }

    /// Coverage α of triangle `prim` (cut-out `cut`) at barycentric coordinates `w`.
    #[must_use]
    pub fn alpha(&self, cut: AlphaCut, prim: u32, w: Vec3) -> f32 {
        let mut a = cut.factor;
        if let Some(c) = self.color.get(prim as usize) {
            a *= w.x * c[0].w + w.y * c[1].w + w.z * c[2].w;
        }
        if let Some(t) = cut.texture {
            a *= self.read(t, prim, w).w;
        }
        a
    }

    /// The shading normal of triangle `prim` (corners `corners`, material `material`) at
    /// barycentric coordinates `w` by its material's normal texture, on the side of its geometric
    /// unit normal `n`; `None` without a normal texture, or where the texture coordinates give the
    /// triangle no tangent frame. The frame is the triangle's own: tangent `∂p/∂u`, bitangent
    /// `−∂p/∂v` (glTF's `v` runs down the image), made orthonormal to `n` (Gram–Schmidt).
    #[must_use]
    pub fn mapped_normal(&self, prim: u32, material: u32, corners: &[Vec3; 3], n: Vec3, w: Vec3) -> Option<Vec3> {
        let map = self.maps.get(material as usize)?.normal?;
        let uv = self.uv[usize::from(map.texture.tex_coord.min(1))].get(prim as usize)?;
        let (e1, e2) = (corners[1] - corners[0], corners[2] - corners[0]);
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        let det = d1.x * d2.y - d1.y * d2.x;
        if det.abs() < 1e-12 {
            return None;
        }
        let dp_du = (e1 * d2.y - e2 * d1.y) / det;
        let dp_dv = (e2 * d1.x - e1 * d2.x) / det;
        let t = (dp_du - n * n.dot(dp_du)).try_normalize()?;
        // The bitangent keeps the side `−∂p/∂v` lies on (mirrored texture coordinates flip it).
        let b = n.cross(t);
        let b = if b.dot(dp_dv) > 0.0 { -b } else { b };
        let c = self.read_data(map.texture, prim, w) * 2.0 - Vec3::ONE;
        (t * (c.x * map.scale) + b * (c.y * map.scale) + n * c.z.max(0.0)).try_normalize()
    }

    /// Texture `t` read at the point of barycentric coordinates `w` of triangle `prim`.
    fn read(&self, t: TextureRef, prim: u32, w: Vec3) -> Vec4 {
        self.textures.get(t.texture as usize).map_or(Vec4::ONE, |tex| tex.sample(self.coordinates(t, prim, w)))
    }

    /// [`Surfaces::read`] of a data texture (RGB not decoded from sRGB).
    fn read_data(&self, t: TextureRef, prim: u32, w: Vec3) -> Vec3 {
        self.textures
            .get(t.texture as usize)
            .map_or(Vec3::new(0.5, 0.5, 1.0), |tex| tex.sample_data(self.coordinates(t, prim, w)).truncate())
    }

    /// Where texture `t` is read at the point of barycentric coordinates `w` of triangle `prim`.
    fn coordinates(&self, t: TextureRef, prim: u32, w: Vec3) -> Vec2 {
        let uv = self.uv[usize::from(t.tex_coord.min(1))]
            .get(prim as usize)
            .map_or(Vec2::ZERO, |uv| w.x * uv[0] + w.y * uv[1] + w.z * uv[2]);
        t.transform.transform_point2(uv)
    }
}

/// Keep the elements of `v` whose `keep` is true (all of an empty `v`).
fn retain_by<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut k = keep.iter();
    v.retain(|_| *k.next().unwrap_or(&true));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::texture::{Filter, Wrap};

    fn checker() -> Texture {
        let texels = std::sync::Arc::new([[255, 0, 0, 255], [0, 0, 255, 255]]);
        Texture { width: 2, height: 1, texels, wrap: [Wrap::Repeat; 2], filter: Filter::Nearest }
    }

    fn textured(transform: Affine2) -> Surfaces {
        let uv = vec![[Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]];
        let t = TextureRef { texture: 0, tex_coord: 0, transform };
        Surfaces {
            uv: [uv, Vec::new()],
            textures: vec![checker()],
            maps: vec![MaterialMaps { base_color: Some(t), emissive: Some(t), ..MaterialMaps::default() }],
            ..Surfaces::default()
        }
    }

    #[test]
    fn textures_are_read_at_the_interpolated_coordinates() {
        let s = textured(Affine2::IDENTITY);
        assert!(!s.is_plain());
        assert_eq!(s.base_factor(0, 0, Vec3::new(1.0, 0.0, 0.0)), Vec3::X, "u = 0: red");
        assert_eq!(s.base_factor(0, 0, Vec3::new(0.2, 0.8, 0.0)), Vec3::Z, "u = 0.8: blue");
        // A material without maps and a triangle without colours read 1.
        assert_eq!(s.base_factor(0, 1, Vec3::X), Vec3::ONE);
        let mean = s.mean_emissive_factor(0, 0);
        assert!(mean.x > 0.4 && mean.z > 0.2 && mean.y == 0.0, "{mean}");
    }

    #[test]
    fn the_texture_transform_moves_the_coordinates() {
        let s = textured(Affine2::from_translation(Vec2::new(0.5, 0.0)));
        assert_eq!(s.base_factor(0, 0, Vec3::new(1.0, 0.0, 0.0)), Vec3::Z, "u = 0 + 0.5: blue");
    }

    #[test]
    fn vertex_colours_interpolate_and_retain_follows_the_triangles() {
        let mut s = Surfaces {
            color: vec![[Vec4::ONE; 3], [Vec4::new(1.0, 0.0, 0.0, 1.0), Vec4::ZERO, Vec4::ZERO]],
            ..Surfaces::default()
        };
        assert_eq!(s.base_factor(1, 0, Vec3::new(0.5, 0.25, 0.25)), Vec3::new(0.5, 0.0, 0.0));
        s.retain(&[false, true]);
        assert_eq!(s.color.len(), 1);
        assert_eq!(s.base_factor(0, 0, Vec3::X), Vec3::X);
    }
}
