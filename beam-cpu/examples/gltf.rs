//! Load a glTF 2.0 model and render it with exact soft shadows (001): each shade point's shadow
//! beam to every area light (the model's emissive triangles) split exactly at the occluders.
//!
//! `cargo run --release -p beam-cpu --example gltf -- model.gltf` (or `.glb`; writes `gltf.png`).
//! Without an argument it first writes a small Cornell-like box (`box.gltf` and its buffer
//! `box.bin`: an emissive ceiling quad, a white box and a mirror cube turned by node rotations, a red
//! and a green wall, a camera on a node) to a temporary folder, so it runs without files.

use beam_cpu::render::render;
use beam_render::options::RenderOptions;
use beam_scene::scene;
use std::path::{Path, PathBuf};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = tempfile::tempdir()?;
    let model = match std::env::args_os().nth(1) {
        Some(p) => PathBuf::from(p),
        None => write_box(dir.path())?,
    };
    let scene = scene::load_file(&model)?;
    let (w, h) = (scene.camera.width.min(512), scene.camera.height.min(512));
    println!(
        "{}: {} triangles ({} degenerate filtered), {} materials, {} lights",
        model.display(),
        scene.stats.triangles,
        scene.stats.degenerate,
        scene.materials.len(),
        scene.lights.len()
    );
    let (image, stats) = render(&scene, &RenderOptions::exact(w, h), || {});
    image.save_png(Path::new("gltf.png"))?;
    println!(
        "exact soft shadows, {w}×{h}: {:.3} s, {} shadow beams; wrote gltf.png",
        stats.seconds, stats.shadow_beams
    );
    Ok(())
}

/// A glTF document being written: one buffer (`box.bin`), a view and an accessor per array.
#[derive(Default)]
struct Model {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Model {
    /// Add a triangle mesh's positions (with their bounds, as glTF asks) and indices; the
    /// primitive's JSON with `material`.
    fn primitive(&mut self, positions: &[[f32; 3]], indices: &[u32], material: usize) -> String {
        let (min, max) = positions.iter().fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
            (std::array::from_fn(|k| lo[k].min(p[k])), std::array::from_fn(|k| hi[k].max(p[k])))
        });
        let p = self.array(positions.iter().flatten().flat_map(|x| x.to_le_bytes()).collect());
        self.accessors.push(format!(
            r#"{{"bufferView": {p}, "componentType": 5126, "count": {}, "type": "VEC3", "min": {min:?}, "max": {max:?}}}"#,
            positions.len()
        ));
        let i = self.array(indices.iter().flat_map(|i| i.to_le_bytes()).collect());
        self.accessors.push(format!(
            r#"{{"bufferView": {i}, "componentType": 5125, "count": {}, "type": "SCALAR"}}"#,
            indices.len()
        ));
        let n = self.accessors.len();
        format!(r#"{{"attributes": {{"POSITION": {}}}, "indices": {}, "material": {material}}}"#, n - 2, n - 1)
    }

    /// Append `bytes` as a buffer view; its index.
    fn array(&mut self, bytes: Vec<u8>) -> usize {
        self.views.push(format!(r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, self.bin.len(), bytes.len()));
        self.bin.extend(bytes);
        self.views.len() - 1
    }
}

/// The indices of quads `0123`, `4567`, … (two triangles each, counter-clockwise as given).
fn quads(n: u32) -> Vec<u32> {
    (0..n).flat_map(|q| [0, 1, 2, 0, 2, 3].map(|k| 4 * q + k)).collect()
}

/// The 24 corners (6 faces × 4, outward) of the cube [−1, 1]³.
fn cube() -> Vec<[f32; 3]> {
    let c = |i: usize| [(i & 1) as f32 * 2.0 - 1.0, (i >> 1 & 1) as f32 * 2.0 - 1.0, (i >> 2 & 1) as f32 * 2.0 - 1.0];
    [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
        .iter()
        .flatten()
        .map(|&i| c(i))
        .collect()
}

/// Write the Cornell-like box to `dir/box.gltf` and `dir/box.bin`; the model's path.
fn write_box(dir: &Path) -> Result<PathBuf, std::io::Error> {
    let mut m = Model::default();
    #[rustfmt::skip]
    let white = [
        [-1.0, 0.0, -1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], // floor
        [-1.0, 2.0, -1.0], [1.0, 2.0, -1.0], [1.0, 2.0, 1.0], [-1.0, 2.0, 1.0], // ceiling
        [-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 2.0, -1.0], [-1.0, 2.0, -1.0], // back
    ];
    let room = [
        m.primitive(&white, &quads(3), 0),
        m.primitive(&[[-1.0, 0.0, -1.0], [-1.0, 2.0, -1.0], [-1.0, 2.0, 1.0], [-1.0, 0.0, 1.0]], &quads(1), 1),
        m.primitive(&[[1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [1.0, 2.0, 1.0], [1.0, 2.0, -1.0]], &quads(1), 2),
    ];
    // Facing down, just under the ceiling.
    let lamp = m.primitive(&[[-0.3, 1.99, -0.3], [0.3, 1.99, -0.3], [0.3, 1.99, 0.3], [-0.3, 1.99, 0.3]], &quads(1), 3);
    let white_box = m.primitive(&cube(), &quads(6), 0);
    let mirror_box = m.primitive(&cube(), &quads(6), 4);
    std::fs::write(dir.join("box.bin"), &m.bin)?;
    // Turns of 20° and −40° about y: the quaternions (0, sin θ/2, 0, cos θ/2).
    let (s, c) = 10f32.to_radians().sin_cos();
    let (s2, c2) = (-20f32).to_radians().sin_cos();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}},
 "extensionsUsed": ["KHR_materials_emissive_strength"],
 "scene": 0, "scenes": [{{"nodes": [0, 1, 2, 3, 4]}}],
 "nodes": [
  {{"mesh": 0}}, {{"mesh": 1}},
  {{"mesh": 2, "translation": [-0.35, 0.6, -0.3], "rotation": [0, {s}, 0, {c}], "scale": [0.3, 0.6, 0.3]}},
  {{"mesh": 3, "translation": [0.4, 0.3, 0.35], "rotation": [0, {s2}, 0, {c2}], "scale": [0.3, 0.3, 0.3]}},
  {{"camera": 0, "translation": [0, 1, 3.4]}}],
 "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.75, "aspectRatio": 1.0, "znear": 0.1}}}}],
 "materials": [
  {{"pbrMetallicRoughness": {{"baseColorFactor": [0.73, 0.73, 0.73, 1], "metallicFactor": 0}}}},
  {{"pbrMetallicRoughness": {{"baseColorFactor": [0.65, 0.05, 0.05, 1], "metallicFactor": 0}}}},
  {{"pbrMetallicRoughness": {{"baseColorFactor": [0.12, 0.45, 0.15, 1], "metallicFactor": 0}}}},
  {{"emissiveFactor": [1, 1, 1], "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": 12}}}}}},
  {{"pbrMetallicRoughness": {{"baseColorFactor": [0.95, 0.95, 0.95, 1], "metallicFactor": 1, "roughnessFactor": 0}}}}],
 "meshes": [{{"primitives": [{}]}}, {{"primitives": [{lamp}]}}, {{"primitives": [{white_box}]}}, {{"primitives": [{mirror_box}]}}],
 "accessors": [{}],
 "bufferViews": [{}],
 "buffers": [{{"uri": "box.bin", "byteLength": {}}}]}}"#,
        room.join(", "),
        m.accessors.join(",\n  "),
        m.views.join(",\n  "),
        m.bin.len()
    );
    let path = dir.join("box.gltf");
    std::fs::write(&path, json)?;
    Ok(path)
}
