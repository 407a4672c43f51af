//! glTF materials mapped to ours, from their factors, with the textures that multiply them
//! ([`MaterialMaps`]: `baseColorTexture` and `emissiveTexture`, their `texCoord` set and
//! `KHR_texture_transform`; the normal texture's too):
//!
//! - an emissive factor (times `KHR_materials_emissive_strength`) above zero → [`Material::Emissive`]
//!   (its triangles also become area lights);
//! - `KHR_materials_transmission` factor ≥ ½ → [`Material::Glass`] with the `KHR_materials_ior`
//!   index (1.5 without it);
//! - metallic factor ≥ ½: roughness ≤ [`MIRROR_ROUGHNESS`] → [`Material::Mirror`] tinted by the
//!   base colour, rougher → [`Material::Glossy`] of that albedo with micro-facet variance
//!   `roughness⁴` (a facet standard deviation of GGX's α = roughness²);
//! - anything else → [`Material::Diffuse`] of the base colour.
//!
//! A diffuse or glossy material's `normalTexture` bends its shading normals ([`NormalMap`]), and
//! its `alphaMode` `MASK` or `BLEND` makes it a cut-out ([`AlphaCut`]): its coverage is the base
//! colour's alpha (factor × texture × vertex colour). Other materials stay opaque (noticed).
//!
//! A primitive without a material gets the diffuse grey of a bare OBJ file.

use super::errors::error;
use crate::error::SceneError;
use crate::scene::material::{Bump, Material};
use crate::scene::surface::{AlphaCut, MaterialMaps, NormalMap, TextureRef};
use beam_math::glam::{Affine2, Vec2, Vec3};
use gltf::json::extensions::texture::TextureTransform;
use std::collections::HashMap;
use std::path::Path;

/// Roughest metal that is still a mirror.
const MIRROR_ROUGHNESS: f32 = 0.1;

/// What a primitive without a material gets (the grey of a bare OBJ file).
pub(super) const DEFAULT: Material = Material::Diffuse { albedo: Vec3::splat(0.7) };

/// Our material for each of `document`'s materials, in order, then [`DEFAULT`] (the material of
/// primitives that name none, at index `document.materials().len()`); and the textures of each
/// (their indices glTF texture indices); `normal_transforms` the normal textures'
/// `KHR_texture_transform` by material.
pub(super) fn map_all(
    path: &Path,
    document: &gltf::Document,
    normal_transforms: &HashMap<usize, TextureTransform>,
) -> Result<(Vec<Material>, Vec<MaterialMaps>), SceneError> {
    let mut out = Vec::with_capacity(document.materials().len() + 1);
    let mut maps = Vec::with_capacity(document.materials().len() + 1);
    for m in document.materials() {
        let material = map(path, &m)?;
        let pbr = m.pbr_metallic_roughness();
        // What the base colour's texture and alpha, and the normal texture, apply to.
        let reflecting = matches!(material, Material::Diffuse { .. } | Material::Glossy { .. });
        let base_color = pbr.base_color_texture().filter(|_| reflecting).map(|t| reference(&t));
        let emissive = match material {
            Material::Emissive { .. } => m.emissive_texture().map(|t| reference(&t)),
            _ => None,
        };
        let factor = pbr.base_color_factor()[3];
        let factor = if factor.is_finite() { factor.clamp(0.0, 1.0) } else { 1.0 };
        let cut = |cutoff| Some(AlphaCut { factor, texture: base_color, cutoff });
        let alpha = match m.alpha_mode() {
            _ if !reflecting => None,
            gltf::material::AlphaMode::Opaque => None,
            gltf::material::AlphaMode::Mask => cut(Some(m.alpha_cutoff().filter(|c| c.is_finite()).unwrap_or(0.5))),
            gltf::material::AlphaMode::Blend => cut(None),
        };
        let normal = m.normal_texture().filter(|_| reflecting).map(|t| {
            let transform = m.index().and_then(|i| normal_transforms.get(&i));
            let transform = transform.map(|t| (t.offset.0, t.rotation.0, t.scale.0, t.tex_coord));
            NormalMap {
                texture: texture_ref(t.texture().index(), t.tex_coord(), transform),
                scale: if t.scale().is_finite() { t.scale() } else { 1.0 },
            }
        });
        out.push(material);
        maps.push(MaterialMaps { base_color, emissive, alpha, normal });
    }
    out.push(DEFAULT);
    maps.push(MaterialMaps::default());
    Ok((out, maps))
}

/// Where the texture `info` is read: its texture, coordinate set and `KHR_texture_transform`
/// (`offset · rotation · scale`, whose `texCoord` overrides the info's).
fn reference(info: &gltf::texture::Info) -> TextureRef {
    let transform = info.texture_transform().map(|t| (t.offset(), t.rotation(), t.scale(), t.tex_coord()));
    texture_ref(info.texture().index(), info.tex_coord(), transform)
}

/// A `KHR_texture_transform`: offset, rotation, scale and the `texCoord` that overrides the set.
type Transform = ([f32; 2], f32, [f32; 2], Option<u32>);

/// Texture `texture` read through coordinate set `tex_coord` and `transform` (`offset · rotation ·
/// scale`; non-finite parts left out).
fn texture_ref(texture: usize, tex_coord: u32, transform: Option<Transform>) -> TextureRef {
    let Some((offset, rotation, scale, set)) = transform else {
        return TextureRef { texture: texture as u32, tex_coord: tex_coord.min(1) as u8, transform: Affine2::IDENTITY };
    };
    let finite = |v: [f32; 2]| Vec2::from_array(v).is_finite().then(|| Vec2::from_array(v));
    let (scale, offset) = (finite(scale).unwrap_or(Vec2::ONE), finite(offset).unwrap_or(Vec2::ZERO));
    let rotation = if rotation.is_finite() { rotation } else { 0.0 };
    TextureRef {
        texture: texture as u32,
        tex_coord: set.unwrap_or(tex_coord).min(1) as u8,
        transform: Affine2::from_scale_angle_translation(scale, rotation, offset),
    }
}

/// Our material for the glTF material `m`, its factors checked (colours finite and ≥ 0, the
/// index of refraction positive).
fn map(path: &Path, m: &gltf::Material) -> Result<Material, SceneError> {
    let element = format!("material {}", m.index().unwrap_or_default());
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let base = colour(path, &element, "baseColorFactor", [r, g, b])?;
    let strength = m.emissive_strength().unwrap_or(1.0);
    let emitted = colour(path, &element, "emissiveFactor", m.emissive_factor())?;
    let radiance = colour(path, &element, "emissive strength × factor", (emitted * strength).to_array())?;
    let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
    let transmission = m.transmission().map_or(0.0, |t| t.transmission_factor());
    if ![metallic, roughness, transmission].iter().all(|x| x.is_finite()) {
        return Err(error(path, element, "metallic, roughness and transmission factors must be finite"));
    }
    Ok(if radiance.max_element() > 0.0 {
        Material::Emissive { radiance }
    } else if transmission >= 0.5 {
        let ior = m.ior().unwrap_or(1.5);
        if !(ior > 0.0 && ior.is_finite()) {
            return Err(error(path, element, format!("KHR_materials_ior: ior must be a positive number, not {ior}")));
        }
        Material::Glass { ior }
    } else if metallic >= 0.5 && roughness <= MIRROR_ROUGHNESS {
        Material::Mirror { tint: base, bump: Bump::NONE }
    } else if metallic >= 0.5 {
        Material::Glossy { albedo: base, variance: roughness.clamp(0.0, 1.0).powi(4) }
    } else {
        Material::Diffuse { albedo: base }
    })
}

/// The colour `field` of material `element`, checked finite and ≥ 0.
fn colour(path: &Path, element: &str, field: &str, rgb: [f32; 3]) -> Result<Vec3, SceneError> {
    if rgb.iter().all(|v| v.is_finite() && *v >= 0.0) {
        Ok(Vec3::from_array(rgb))
    } else {
        Err(error(path, element, format!("{field}: each channel must be finite and ≥ 0, not {rgb:?}")))
    }
}
