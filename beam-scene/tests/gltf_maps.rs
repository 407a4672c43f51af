//! Textures that change what a surface is, not its colour. `alphaMode` `MASK` and `BLEND`: a cut-out's coverage is its base colour's alpha (factor ×
//! texture × vertex colour), and the scene's own ray queries see through it where that alpha says
//! (`MASK`: below `alphaCutoff`; `BLEND`: with probability `1 − α` per ray). A normal texture
//! bends the shading normal.

mod common;

use base64::Engine as _;
use beam_scene::beam_math::Ray;
use beam_scene::beam_math::glam::Vec3;
use beam_scene::scene::{self, Scene};
use common::{Doc, primitive, refused, write};

/// A 2 × 1 RGBA PNG: opaque white on the left (u < ½), transparent white on the right.
fn half_transparent_png() -> String {
    let image = image::RgbaImage::from_raw(2, 1, vec![255, 255, 255, 255, 255, 255, 255, 0]).unwrap();
    let mut png = std::io::Cursor::new(Vec::new());
    image.write_to(&mut png, image::ImageFormat::Png).unwrap();
    base64::engine::general_purpose::STANDARD.encode(png.into_inner())
}

/// Three triangles in planes `z = 0, −1, −2`, spanning x, y ∈ [0, 4] with texture coordinates
/// `(x, y) / 4`: a `MASK` cut-out (cutoff 0.3) of the half-transparent texture, a `BLEND` one of
/// alpha 0.25, and an opaque one that reads the texture as its normal texture (scale ½); and at
/// x ∈ [10, 14], two `BLEND` layers of alpha ½ in planes `z = 0, −1`.
fn layers(dir: &std::path::Path) -> Scene {
    let mut d = Doc::default();
    let mut meshes = Vec::new();
    for (x, z, material) in [(0.0, 0.0, 0), (0.0, -1.0, 1), (0.0, -2.0, 2), (10.0, 0.0, 3), (10.0, -1.0, 3)] {
        let p = d.positions(&[[x, 0.0, z], [x + 4.0, 0.0, z], [x, 4.0, z]]);
        let uv = d.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 2);
        let prim = primitive(p, None, Some(material), "").replacen('}', &format!(r#", "TEXCOORD_0": {uv}}}"#), 1);
        meshes.push(d.mesh(&[prim]));
    }
    d.roots = meshes.iter().map(|m| d.node(&format!(r#"{{"mesh": {m}}}"#))).collect();
    d.materials = vec![
        r#"{"alphaMode": "MASK", "alphaCutoff": 0.3, "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}"#.into(),
        r#"{"alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.25], "metallicFactor": 0}}"#.into(),
        r#"{"normalTexture": {"index": 0, "scale": 0.5}, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.25], "metallicFactor": 0}}"#.into(),
        r#"{"alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5], "metallicFactor": 0}}"#.into(),
    ];
    let json = d.gltf();
    let images = format!(
        r#""images": [{{"uri": "data:image/png;base64,{}"}}], "samplers": [{{"magFilter": 9728}}], "textures": [{{"source": 0, "sampler": 0}}]"#,
        half_transparent_png()
    );
    let json = format!("{{{images},\n{}", &json[1..]);
    scene::load_file(&write(dir, "layers.gltf", json)).unwrap()
}

/// The plane (z) a ray down −z from `(x, y)` stops at, if any.
fn stops_at(s: &Scene, x: f32, y: f32) -> Option<f32> {
    let ray = Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z);
    s.closest_hit(ray, f32::INFINITY).map(|h| 1.0 - h.t)
}

#[test]
fn a_mask_is_there_where_its_alpha_reaches_the_cutoff() {
    let dir = tempfile::tempdir().unwrap();
    let s = layers(dir.path());
    assert!(s.has_cut_outs());
    let mask = s.surfaces.cut_out(0).expect("material 0 is a cut-out");
    assert_eq!((mask.cutoff, mask.factor), (Some(0.3), 1.0));
    assert!(s.surfaces.cut_out(2).is_none(), "the opaque material ignores its factor's alpha");
    // u = x / 4 < ½: the opaque texel stops the ray at z = 0.
    let z = stops_at(&s, 1.0, 0.5).unwrap();
    assert!(z.abs() < 1e-5, "{z}");
    // u > ½: through the mask; the blend layer stops a quarter of the rays, the rest reach z = −2.
    let z = stops_at(&s, 2.5, 0.5).unwrap();
    assert!((z + 1.0).abs() < 1e-5 || (z + 2.0).abs() < 1e-5, "{z}");
    assert!(s.occluded(Ray::new(Vec3::new(2.5, 0.5, 1.0), -Vec3::Z), 4.0), "the opaque layer is there");
}

/// The share of 4,000 rays down −z (slightly slanted), from `(x, y, 1)` with `x` from `x0` in
/// steps of `dx`, that a surface stops before `t_max`; and its standard deviation were `p` the
/// chance that one stops.
fn stopped_share(s: &Scene, (x0, dx): (f32, f32), t_max: f32, p: f64) -> (f64, f64) {
    let n = 4000;
    let stopped = (0..n)
        .filter(|&i| {
            let (x, y) = (x0 + dx * i as f32, 0.1 + 0.00011 * (i % 97) as f32);
            s.occluded(Ray::new(Vec3::new(x, y, 1.0), Vec3::new(0.01, 0.0, -1.0)), t_max)
        })
        .count();
    (stopped as f64 / f64::from(n), (p * (1.0 - p) / f64::from(n)).sqrt())
}

#[test]
fn a_blend_stops_alpha_of_the_rays() {
    let dir = tempfile::tempdir().unwrap();
    let s = layers(dir.path());
    // Rays through the right half of the mask, between z = 1 and z = −1.5 (the blend layer only).
    let (share, sigma) = stopped_share(&s, (2.1, 0.0003), 2.5, 0.25);
    assert!((share - 0.25).abs() < 3.0 * sigma, "{share} of the rays stopped, α = 0.25 (σ {sigma:.4})");
    // Two layers of alpha ½ pass a ray independently: 1 − ½ · ½ of the rays stop.
    let (share, sigma) = stopped_share(&s, (10.1, 0.0005), 3.0, 0.75);
    assert!((share - 0.75).abs() < 3.0 * sigma, "{share} of the rays stopped by two layers of α = ½ (σ {sigma:.4})");
}

#[test]
fn an_eye_ray_blends_what_it_sees() {
    let dir = tempfile::tempdir().unwrap();
    let s = layers(dir.path());
    let layers_seen = |x: f32| {
        let mut seen = Vec::new();
        let beyond = s.blended_hits(Ray::new(Vec3::new(x, 0.5, 1.0), -Vec3::Z), f32::INFINITY, |hit, share| {
            seen.push((1.0 - hit.t, share));
        });
        (seen, beyond)
    };
    // Through the mask's cut half: a quarter of the blend layer, three quarters of the opaque one.
    let (seen, beyond) = layers_seen(2.5);
    assert_eq!(seen.len(), 2, "{seen:?}");
    assert!((seen[0].0 + 1.0).abs() < 1e-5 && (seen[0].1 - 0.25).abs() < 1e-6, "{seen:?}");
    assert!((seen[1].0 + 2.0).abs() < 1e-5 && (seen[1].1 - 0.75).abs() < 1e-6, "{seen:?}");
    assert_eq!(beyond, 0.0);
    // The mask's solid half ends the ray; past the triangles' reach the ray sees the environment.
    assert_eq!(layers_seen(1.0).0.len(), 1);
    let (seen, beyond) = layers_seen(5.0);
    assert!(seen.is_empty() && beyond == 1.0);
}

#[test]
fn a_normal_texture_is_read_as_data() {
    let dir = tempfile::tempdir().unwrap();
    let s = layers(dir.path());
    let map = s.surfaces.maps[2].normal.expect("material 2 has a normal texture");
    assert_eq!(map.scale, 0.5);
    let prim = (0..s.triangles.len() as u32).find(|&i| s.material_of[i as usize] == 2).unwrap();
    // The white texel is (1, 1, 1) as data: x and y halved by the scale, along u (+x) and up the
    // image (−v: −y here, where v grows with y).
    let n = s.mapped_normal(prim, Vec3::new(0.5, 0.5, -2.0), Vec3::Z);
    let want = Vec3::new(0.5, -0.5, 1.0).normalize();
    assert!((n - want).length() < 1e-5, "{n} against {want}");
    // Seen from behind, the bent normal is reversed.
    assert!((s.mapped_normal(prim, Vec3::new(0.5, 0.5, -2.0), -Vec3::Z) + want).length() < 1e-5);
}

/// `NORMAL` shades a diffuse triangle smoothly: its corners' normals, taken to world space by the
/// inverse transpose of the node's matrix (a scale of 2 along x halves their x), interpolated.
#[test]
fn vertex_normals_shade_through_the_node_transform() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let n = d.floats(&[1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC3", 3);
    let prim = primitive(p, None, None, "").replacen('}', &format!(r#", "NORMAL": {n}}}"#), 1);
    let mesh = d.mesh(&[prim]);
    d.roots = vec![d.node(&format!(r#"{{"mesh": {mesh}, "scale": [2, 1, 1]}}"#))];
    let s = scene::load_file(&write(dir.path(), "smooth.gltf", d.gltf())).unwrap();
    let corner = s.mapped_normal(0, Vec3::ZERO, Vec3::Z);
    let want = Vec3::new(0.5, 0.0, 1.0).normalize();
    assert!((corner - want).length() < 1e-5, "{corner} against {want}");
    // Half-way along the edge to the corner whose normal is +z, and seen from behind.
    let mid = s.mapped_normal(0, Vec3::new(1.0, 0.0, 0.0), -Vec3::Z);
    let want = -(want + Vec3::Z).normalize();
    assert!((mid - want).length() < 1e-5, "{mid} against {want}");
}

/// A triangle spanning x, y ∈ [0, 4] at z = 0 with texture coordinates `(x, y) / 4`, whose normal
/// texture (a 2 × 1 PNG, nearest: tilted towards +x on the left half, −x on the right) is read
/// through the `KHR_texture_transform` `transform` (JSON members, or none): the `.gltf` text.
fn tilted(transform: Option<&str>) -> String {
    let image = image::RgbImage::from_raw(2, 1, vec![255, 128, 255, 0, 128, 255]).unwrap();
    let mut png = std::io::Cursor::new(Vec::new());
    image.write_to(&mut png, image::ImageFormat::Png).unwrap();
    let png = base64::engine::general_purpose::STANDARD.encode(png.into_inner());
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]);
    let uv = d.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 2);
    let prim = primitive(p, None, Some(0), "").replacen('}', &format!(r#", "TEXCOORD_0": {uv}}}"#), 1);
    let m = d.mesh(&[prim]);
    d.roots = vec![d.node(&format!(r#"{{"mesh": {m}}}"#))];
    let extension =
        transform.map_or(String::new(), |t| format!(r#", "extensions": {{"KHR_texture_transform": {{{t}}}}}"#));
    d.materials = vec![format!(
        r#"{{"normalTexture": {{"index": 0{extension}}}, "pbrMetallicRoughness": {{"metallicFactor": 0}}}}"#
    )];
    let images = format!(
        r#""images": [{{"uri": "data:image/png;base64,{png}"}}], "samplers": [{{"magFilter": 9728}}], "textures": [{{"source": 0, "sampler": 0}}]"#
    );
    let json = d.gltf();
    format!("{{{images},\n{}", &json[1..])
}

#[test]
fn a_normal_texture_is_read_through_its_texture_transform() {
    let dir = tempfile::tempdir().unwrap();
    // At x = 0.5 the coordinates are u = 0.125: the left texel, tilted towards +x.
    let x_of = |name: &str, transform| {
        let s = scene::load_file(&write(dir.path(), name, tilted(transform))).unwrap();
        s.mapped_normal(0, Vec3::new(0.5, 0.5, 0.0), Vec3::Z).x
    };
    assert!(x_of("plain.gltf", None) > 0.5);
    // Offset by half the image, the same point reads the right texel; scaled by 5, too (u = 0.625).
    assert!(x_of("offset.gltf", Some(r#""offset": [0.5, 0]"#)) < -0.5);
    assert!(x_of("scaled.gltf", Some(r#""scale": [5, 1]"#)) < -0.5);
    // A transform that does not fit the extension's schema is refused, naming it.
    let bad = tilted(Some(r#""offset": "left""#));
    refused(dir.path(), "bad.gltf", bad, &["materials[0].normalTexture.extensions.KHR_texture_transform"]);
}
