//! Small glTF files written in the tests: [`Doc`] gathers binary data (positions, indices) into one
//! buffer with a view and an accessor each, and JSON for the rest; [`cornell`] is a Cornell-like box
//! using every mapped feature.

#![allow(dead_code, reason = "shared by several test binaries, each of which uses a part")]

use base64::Engine as _;
use std::path::{Path, PathBuf};

/// A glTF document being written: one buffer, and the JSON of its other arrays.
#[derive(Clone, Default)]
pub(crate) struct Doc {
    pub bin: Vec<u8>,
    pub views: Vec<String>,
    pub accessors: Vec<String>,
    pub meshes: Vec<String>,
    pub materials: Vec<String>,
    pub nodes: Vec<String>,
    pub cameras: Vec<String>,
    pub lights: Vec<String>,
    /// The default scene's root nodes.
    pub roots: Vec<usize>,
    /// What `byteLength` says; the data's length when `None`.
    pub byte_length: Option<usize>,
}

impl Doc {
    /// Append `bytes` (4-aligned) as a new buffer view; its index.
    fn view(&mut self, bytes: &[u8]) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(format!(r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, self.bin.len(), bytes.len()));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A float accessor of `values`, `kind` (`"VEC2"`, `"VEC3"`) each `width` of them; its index.
    pub(crate) fn floats(&mut self, values: &[f32], kind: &str, width: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let count = values.len() / width;
        self.accessors
            .push(format!(r#"{{"bufferView": {view}, "componentType": 5126, "count": {count}, "type": "{kind}"}}"#));
        self.accessors.len() - 1
    }

    /// A VEC3 float accessor of `p`; its index.
    pub(crate) fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let bytes: Vec<u8> = p.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        // POSITION accessors must say their bounds.
        let bound = |f: fn(f32, f32) -> f32, start: f32| {
            let b = p.iter().fold([start; 3], |b, v| [f(b[0], v[0]), f(b[1], v[1]), f(b[2], v[2])]);
            format!("[{}, {}, {}]", b[0], b[1], b[2])
        };
        let (min, max) = (bound(f32::min, f32::MAX), bound(f32::max, f32::MIN));
        self.accessors.push(format!(
            r#"{{"bufferView": {view}, "componentType": 5126, "count": {}, "type": "VEC3", "min": {min}, "max": {max}}}"#,
            p.len()
        ));
        self.accessors.len() - 1
    }

    /// A scalar index accessor of `i` stored as `bytes` per index (1, 2 or 4); its index.
    pub(crate) fn indices(&mut self, i: &[u32], bytes: usize) -> usize {
        let data: Vec<u8> = i
            .iter()
            .flat_map(|&x| match bytes {
                1 => vec![x as u8],
                2 => (x as u16).to_le_bytes().to_vec(),
                _ => x.to_le_bytes().to_vec(),
            })
            .collect();
        let view = self.view(&data);
        let kind = match bytes {
            1 => 5121,
            2 => 5123,
            _ => 5125,
        };
        self.accessors.push(format!(
            r#"{{"bufferView": {view}, "componentType": {kind}, "count": {}, "type": "SCALAR"}}"#,
            i.len()
        ));
        self.accessors.len() - 1
    }

    /// A mesh of `primitives` (JSON objects); its index.
    pub(crate) fn mesh(&mut self, primitives: &[String]) -> usize {
        self.meshes.push(format!(r#"{{"primitives": [{}]}}"#, primitives.join(", ")));
        self.meshes.len() - 1
    }

    /// A node (JSON object); its index.
    pub(crate) fn node(&mut self, json: &str) -> usize {
        self.nodes.push(json.to_string());
        self.nodes.len() - 1
    }

    /// The JSON, its buffer at `uri` (the GLB chunk when `None`).
    pub(crate) fn json(&self, uri: Option<&str>) -> String {
        let uri = uri.map_or(String::new(), |u| format!(r#""uri": "{u}", "#));
        let list = |v: &[String]| v.join(",\n  ");
        let lights = if self.lights.is_empty() {
            String::new()
        } else {
            format!(r#", "extensions": {{"KHR_lights_punctual": {{"lights": [{}]}}}}"#, list(&self.lights))
        };
        let roots: Vec<String> = self.roots.iter().map(|r| r.to_string()).collect();
        format!(
            r#"{{"asset": {{"version": "2.0"}},
 "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior"],
 "scene": 0, "scenes": [{{"nodes": [{}]}}],
 "nodes": [{}], "meshes": [{}], "materials": [{}], "cameras": [{}],
 "accessors": [{}], "bufferViews": [{}],
 "buffers": [{{{uri}"byteLength": {}}}]{lights}}}"#,
            roots.join(", "),
            list(&self.nodes),
            list(&self.meshes),
            list(&self.materials),
            list(&self.cameras),
            list(&self.accessors),
            list(&self.views),
            self.byte_length.unwrap_or(self.bin.len()),
        )
    }

    /// The `.gltf` text with the buffer as a base64 data URI.
    pub(crate) fn gltf(&self) -> String {
        let data = base64::engine::general_purpose::STANDARD.encode(&self.bin);
        self.json(Some(&format!("data:application/octet-stream;base64,{data}")))
    }

    /// The `.glb` bytes: header, JSON chunk, BIN chunk.
    pub(crate) fn glb(&self) -> Vec<u8> {
        let mut json = self.json(None).into_bytes();
        while json.len() % 4 != 0 {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend((total as u32).to_le_bytes());
        out.extend((json.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(json);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }
}

/// Load `data` written as `dir/name` and expect a refusal that names the file and holds every one of
/// `words`; the message.
pub(crate) fn refused(dir: &Path, name: &str, data: impl AsRef<[u8]>, words: &[&str]) -> String {
    let e = match beam_scene::scene::load_file(&write(dir, name, data)) {
        Ok(_) => panic!("{name} loaded"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains(name), "the file is not named: {e}");
    for w in words {
        assert!(e.contains(w), "`{w}` missing from: {e}");
    }
    e
}

/// Write `data` to `dir/name`; its path.
pub(crate) fn write(dir: &Path, name: &str, data: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, data).unwrap();
    p
}

/// A quad's two triangles, as indices from `base`.
fn quad(base: u32) -> [u32; 6] {
    [base, base + 1, base + 2, base, base + 2, base + 3]
}

/// A primitive of `positions`, `indices` and `material` (JSON), with extra JSON `more`.
pub(crate) fn primitive(positions: usize, indices: Option<usize>, material: Option<usize>, more: &str) -> String {
    let mut s = format!(r#"{{"attributes": {{"POSITION": {positions}}}"#);
    if let Some(i) = indices {
        s += &format!(r#", "indices": {i}"#);
    }
    if let Some(m) = material {
        s += &format!(r#", "material": {m}"#);
    }
    s + more + "}"
}

/// A Cornell-like box (x, z ∈ [−1, 1], y ∈ [0, 2], open towards +z) with:
/// - room mesh 0: floor (with one degenerate triangle), ceiling and back wall white, left wall red,
///   right wall green, and a POINTS primitive (skipped);
/// - an emissive 0.6 × 0.6 quad (strength 15) translated to y = 1.98, facing down;
/// - a mirror cube (local ±1, 16-bit indices) scaled by ¼, turned 90° about y and lifted by ¼,
///   under a parent node translated by (0.4, 0, −0.3);
/// - a glass pane as a triangle fan, a glossy metal pane as a triangle strip (8-bit indices) placed
///   by a matrix;
/// - a perspective camera (yfov 0.7, aspect 1.5) at (0, 1, 3.4);
/// - a point light, a directional light (skipped) and a spot light (a point light here).
///
/// 28 valid triangles, 1 degenerate; 4 lights (2 from the emissive quad).
pub(crate) fn cornell() -> Doc {
    let mut d = Doc::default();
    #[rustfmt::skip]
    let room = d.positions(&[
        [-1.0, 0.0, -1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0], // floor, +y
        [-1.0, 2.0, -1.0], [1.0, 2.0, -1.0], [1.0, 2.0, 1.0], [-1.0, 2.0, 1.0], // ceiling, −y
        [-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 2.0, -1.0], [-1.0, 2.0, -1.0], // back, +z
        [-1.0, 0.0, -1.0], [-1.0, 2.0, -1.0], [-1.0, 2.0, 1.0], [-1.0, 0.0, 1.0], // left, +x
        [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [1.0, 2.0, 1.0], [1.0, 2.0, -1.0], // right, −x
    ]);
    let mut floor = quad(0).to_vec();
    floor.extend([0, 0, 1]);
    let floor = d.indices(&floor, 4);
    let walls: Vec<usize> = (1..5).map(|k| d.indices(&quad(4 * k), 4)).collect();
    let mut prims = vec![primitive(room, Some(floor), Some(0), "")];
    for (w, m) in walls.iter().zip([0, 0, 1, 2]) {
        prims.push(primitive(room, Some(*w), Some(m), ""));
    }
    prims.push(primitive(room, None, Some(0), r#", "mode": 0"#));
    let room = d.mesh(&prims);

    let light = d.positions(&[[-0.3, 0.0, -0.3], [0.3, 0.0, -0.3], [0.3, 0.0, 0.3], [-0.3, 0.0, 0.3]]);
    let light_idx = d.indices(&quad(0), 4);
    let light = d.mesh(&[primitive(light, Some(light_idx), Some(3), "")]);

    let corners: Vec<[f32; 3]> = (0..8)
        .map(|i| [(i & 1) as f32 * 2.0 - 1.0, (i >> 1 & 1) as f32 * 2.0 - 1.0, (i >> 2 & 1) as f32 * 2.0 - 1.0])
        .collect();
    let cube = d.positions(&corners);
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let cube_idx: Vec<u32> = faces.iter().flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]]).collect();
    let cube_idx = d.indices(&cube_idx, 2);
    let cube = d.mesh(&[primitive(cube, Some(cube_idx), Some(4), "")]);

    let pane = d.positions(&[[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.3, 0.3, 0.0], [0.0, 0.3, 0.0]]);
    let glass = d.mesh(&[primitive(pane, None, Some(5), r#", "mode": 6"#)]);
    let strip = d.indices(&[0, 1, 3, 2], 1);
    let glossy = d.mesh(&[primitive(pane, Some(strip), Some(6), r#", "mode": 5"#)]);

    d.materials = [
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.73, 0.73, 0.73, 1], "metallicFactor": 0}}"#,
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.65, 0.05, 0.05, 1], "metallicFactor": 0}}"#,
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.12, 0.45, 0.15, 1], "metallicFactor": 0}}"#,
        r#"{"emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 15}}}"#,
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 1, "roughnessFactor": 0}}"#,
        r#"{"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.4}}}"#,
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.2, 1], "metallicFactor": 1, "roughnessFactor": 0.5}}"#,
    ]
    .map(String::from)
    .to_vec();
    d.cameras.push(r#"{"type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 1.5, "znear": 0.1}}"#.into());
    d.lights = [
        r#"{"type": "point", "color": [1, 0.5, 0.25], "intensity": 4}"#,
        r#"{"type": "directional", "intensity": 2}"#,
        r#"{"type": "spot", "intensity": 3, "spot": {"outerConeAngle": 0.5}}"#,
    ]
    .map(String::from)
    .to_vec();

    let s = std::f32::consts::FRAC_1_SQRT_2;
    let roots = [
        d.node(&format!(r#"{{"mesh": {room}}}"#)),
        d.node(&format!(r#"{{"mesh": {light}, "translation": [0, 1.98, 0]}}"#)),
        d.node(r#"{"translation": [0.4, 0, -0.3], "children": [3]}"#),
        d.node(&format!(
            r#"{{"mesh": {cube}, "scale": [0.25, 0.25, 0.25], "rotation": [0, {s}, 0, {s}], "translation": [0, 0.25, 0]}}"#
        )),
        d.node(&format!(r#"{{"mesh": {glass}, "translation": [-0.6, 0.2, 0.2]}}"#)),
        d.node(&format!(r#"{{"mesh": {glossy}, "matrix": [0.5,0,0,0, 0,0.5,0,0, 0,0,0.5,0, -0.2,0.1,-0.8,1]}}"#)),
        d.node(r#"{"camera": 0, "translation": [0, 1, 3.4]}"#),
        d.node(r#"{"translation": [0, 1.5, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}"#),
        d.node(r#"{"rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 1}}}"#),
        d.node(r#"{"translation": [0.5, 1.9, 0], "extensions": {"KHR_lights_punctual": {"light": 2}}}"#),
    ];
    d.roots = roots.into_iter().filter(|&r| r != 3).collect();
    d
}
