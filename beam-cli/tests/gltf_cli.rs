//! `beam render --scene model.gltf`: a glTF file with its buffer beside it renders, lit by its
//! emissive quad; a malformed one is a clear error naming the file and element.

use std::path::Path;
use std::process::{Command, Output};

fn beam(args: &[&str]) -> Output {
    let bin = std::env::var("BEAM_TEST_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_beam").into());
    Command::new(bin).args(args).env_remove("BEAM_MAX_MEMORY").output().expect("run beam")
}

/// A floor (x, z ∈ [−1, 1], y = 0, white) under a 0.5 × 0.5 emissive quad at y = 1 facing down,
/// seen by a camera at (0, 2, 3) pitched down to look at the origin; the buffer in `box.bin`.
/// `indices` replaces the floor's indices.
fn write_model(dir: &Path, indices: [u32; 6]) -> std::path::PathBuf {
    #[rustfmt::skip]
    let positions: [[f32; 3]; 8] = [
        [-1.0, 0.0, -1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0],
        [-0.25, 1.0, -0.25], [0.25, 1.0, -0.25], [0.25, 1.0, 0.25], [-0.25, 1.0, 0.25],
    ];
    let mut bin: Vec<u8> = positions.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    bin.extend(indices.iter().chain(&[0, 1, 2, 0, 2, 3]).flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("box.bin"), &bin).unwrap();
    // Pitched down by atan(2/3) about x: the quaternion (sin(−θ/2), 0, 0, cos(θ/2)).
    let half = (2.0f32 / 3.0).atan() / 2.0;
    let (qx, qw) = (-half.sin(), half.cos());
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}},
 "extensionsUsed": ["KHR_materials_emissive_strength"],
 "scene": 0, "scenes": [{{"nodes": [0, 1, 2]}}],
 "nodes": [{{"mesh": 0}}, {{"mesh": 1}}, {{"camera": 0, "translation": [0, 2, 3], "rotation": [{qx}, 0, 0, {qw}]}}],
 "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.8, "znear": 0.1}}}}],
 "materials": [
   {{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0}}}},
   {{"emissiveFactor": [1, 1, 1], "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": 10}}}}}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 2, "material": 0}}]}},
            {{"primitives": [{{"attributes": {{"POSITION": 1}}, "indices": 3, "material": 1}}]}}],
 "accessors": [
   {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]}},
   {{"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.25, 1, -0.25], "max": [0.25, 1, 0.25]}},
   {{"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"}},
   {{"bufferView": 1, "byteOffset": 24, "componentType": 5125, "count": 6, "type": "SCALAR"}}],
 "bufferViews": [{{"buffer": 0, "byteLength": 96}}, {{"buffer": 0, "byteOffset": 96, "byteLength": 48}}],
 "buffers": [{{"uri": "box.bin", "byteLength": {}}}]}}"#,
        bin.len()
    );
    let path = dir.join("box.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn a_gltf_model_renders_lit_by_its_emissive_quad() {
    let dir = tempfile::tempdir().unwrap();
    let model = write_model(dir.path(), [0, 1, 2, 0, 2, 3]);
    let out = dir.path().join("y.png");
    let o = beam(&["render", "--scene", model.to_str().unwrap(), "--width", "32", "--out", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{:?}: {}", o.status, String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("box.gltf: 4 triangles"), "{stdout}");
    let image = image::open(&out).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (32, 32), "square: the camera has no aspect ratio");
    // The camera looks at the floor's centre, under the light: lit. The corners above the floor's
    // far edge see nothing: black.
    let centre = image.get_pixel(16, 16);
    assert!(centre.0.iter().all(|&c| c > 40), "centre {centre:?}");
    assert_eq!(image.get_pixel(0, 0).0, [0, 0, 0]);
}

#[test]
fn a_malformed_gltf_model_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let model = write_model(dir.path(), [0, 1, 2, 0, 2, 7]);
    let out = dir.path().join("y.png");
    let o = beam(&["render", "--scene", model.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("box.gltf: mesh 0 primitive 0: index 7 out of range (4 vertices)"), "{e}");
    assert!(!out.exists());
}
