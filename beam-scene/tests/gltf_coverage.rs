//! The rest of glTF 2.0 that changes a picture: `EXT_mesh_gpu_instancing` places a mesh once per
//! instance; morph targets take their default weights; an orthographic camera, skins and
//! animations load with one notice each; scenes without nodes, accessors without a buffer view and sparse accessors load; optional
//! extensions are ignored and required ones we do not read are refused by name (`docs/gltf.md`).

mod common;

use beam_scene::beam_math::glam::Vec3;
use beam_scene::scene::{self, Scene};
use common::{Doc, primitive, refused, write};

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// A document with one triangle mesh (mesh 0, POSITION accessor 0) placed by node 0 (`node`, a
/// JSON object without its closing brace and without `mesh`, e.g. `{"translation": [0, 1, 0]`).
fn triangle(node: &str) -> Doc {
    let mut d = Doc::default();
    let p = d.positions(&TRI);
    let m = d.mesh(&[primitive(p, None, None, "")]);
    let sep = if node.trim_end().ends_with('{') { "" } else { ", " };
    d.roots = vec![d.node(&format!(r#"{node}{sep}"mesh": {m}}}"#))];
    d
}

/// Append the float values `v` as an accessor of `kind` (`"VEC4"`) with extra JSON `more`; its index.
fn floats(d: &mut Doc, v: &[f32], kind: &str, more: &str) -> usize {
    let components = match kind {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        _ => 4,
    };
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    raw_accessor(
        d,
        &bytes,
        &format!(r#""componentType": 5126, "count": {}, "type": "{kind}"{more}"#, v.len() / components),
    )
}

/// Append `bytes` as a buffer view and an accessor of the JSON members `members` on it; its index.
fn raw_accessor(d: &mut Doc, bytes: &[u8], members: &str) -> usize {
    while d.bin.len() % 4 != 0 {
        d.bin.push(0);
    }
    d.views.push(format!(r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, d.bin.len(), bytes.len()));
    d.bin.extend_from_slice(bytes);
    d.accessors.push(format!(r#"{{"bufferView": {}, {members}}}"#, d.views.len() - 1));
    d.accessors.len() - 1
}

/// The document's `.gltf` text with the top-level JSON members `members` added.
fn with_members(d: &Doc, members: &str) -> String {
    let json = d.gltf();
    format!("{{{members},\n{}", &json[1..])
}

/// `json` with `names` (JSON strings, comma-separated) added to its `extensionsUsed`.
fn using(json: &str, names: &str) -> String {
    json.replacen(r#""extensionsUsed": ["#, &format!(r#""extensionsUsed": [{names}, "#), 1)
}

/// Whether `s` carries a notice that starts with `what`, and its count.
fn notice(s: &Scene, what: &str) -> Option<usize> {
    s.notices.iter().find(|n| n.what.starts_with(what)).map(|n| n.count)
}

fn near(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-4
}

/// Every corner of every triangle of `s`.
fn corners(s: &Scene) -> Vec<Vec3> {
    s.triangles.iter().flat_map(|t| t.v).collect()
}

#[test]
fn an_instanced_mesh_is_placed_once_per_instance() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = triangle("{");
    let t = floats(&mut d, &[0.0, 0.0, 0.0, 5.0, 0.0, 0.0, 0.0, 0.0, -5.0], "VEC3", "");
    let h = std::f32::consts::FRAC_1_SQRT_2;
    // The third instance turned 90° about y (x → −z) and scaled by 2.
    let r = floats(&mut d, &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, h, 0.0, h], "VEC4", "");
    let s = floats(&mut d, &[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0], "VEC3", "");
    let instancing = format!(
        r#""extensions": {{"EXT_mesh_gpu_instancing": {{"attributes": {{"TRANSLATION": {t}, "ROTATION": {r}, "SCALE": {s}}}}}}}"#
    );
    // Composed after the node's own translation by (0, 1, 0).
    d.nodes[0] = format!(r#"{{"mesh": 0, "translation": [0, 1, 0], {instancing}}}"#);
    let json = with_members(&d, r#""extensionsRequired": ["EXT_mesh_gpu_instancing"]"#);
    let scene = scene::load_file(&write(dir.path(), "instanced.gltf", json)).unwrap();
    assert_eq!(scene.stats.triangles, 3, "3 instances of 1 triangle");
    let v = corners(&scene);
    for p in [Vec3::new(0.0, 2.0, 0.0), Vec3::new(6.0, 1.0, 0.0), Vec3::new(0.0, 1.0, -7.0), Vec3::new(0.0, 3.0, -5.0)]
    {
        assert!(v.iter().any(|&c| near(c, p)), "{p} not among {v:?}");
    }
    // The framing camera and light see the instances, not only the mesh at the origin.
    let min = v.iter().fold(Vec3::MAX, |a, &b| a.min(b));
    let max = v.iter().fold(Vec3::MIN, |a, &b| a.max(b));
    assert!(near(min, Vec3::new(0.0, 1.0, -7.0)) && near(max, Vec3::new(6.0, 3.0, 0.0)), "{min} {max}");
    assert!(scene.notices.is_empty(), "{:?}", scene.notices);

    // Only TRANSLATION: two copies; attributes of different counts are an error naming the node.
    let mut one = triangle("{");
    let t = floats(&mut one, &[0.0, 0.0, 0.0, 0.0, 0.0, 3.0], "VEC3", "");
    one.nodes[0] = format!(
        r#"{{"mesh": 0, "extensions": {{"EXT_mesh_gpu_instancing": {{"attributes": {{"TRANSLATION": {t}}}}}}}}}"#
    );
    let scene = scene::load_file(&write(dir.path(), "two.gltf", one.gltf())).unwrap();
    assert_eq!(scene.stats.triangles, 2);
    let s = floats(&mut one, &[1.0; 9], "VEC3", "");
    one.nodes[0] =
        one.nodes[0].replace(&format!(r#""TRANSLATION": {t}"#), &format!(r#""TRANSLATION": {t}, "SCALE": {s}"#));
    refused(dir.path(), "counts.gltf", one.gltf(), &["node 0", "EXT_mesh_gpu_instancing", "different counts"]);
}

#[test]
fn an_orthographic_camera_becomes_a_distant_narrow_perspective_one() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = triangle("{");
    d.cameras
        .push(r#"{"type": "orthographic", "orthographic": {"xmag": 2, "ymag": 1, "znear": 0.1, "zfar": 100}}"#.into());
    let c = d.node(r#"{"camera": 0, "translation": [0, 0, 5]}"#);
    d.roots.push(c);
    let s = scene::load_file(&write(dir.path(), "ortho.gltf", d.gltf())).unwrap();
    let cam = s.camera;
    let back = 1.0 / 1f32.to_radians().tan();
    assert!(near(cam.position, Vec3::new(0.0, 0.0, 5.0 + back)), "{cam:?}");
    assert!(near((cam.target - cam.position).normalize(), Vec3::NEG_Z), "{cam:?}");
    assert!((cam.fov_y - 2.0).abs() < 1e-6 && (cam.width, cam.height) == (1024, 512), "{cam:?}");
    // At the orthographic camera's position the view is ymag = 1 high either side of its axis.
    let half = (cam.fov_y / 2.0).to_radians().tan() * (cam.position.z - 5.0);
    assert!((half - 1.0).abs() < 1e-4, "{half}");
    assert_eq!(notice(&s, "orthographic camera(s) approximated"), Some(1), "{:?}", s.notices);
}

#[test]
fn skins_and_animations_load_in_one_pose_with_a_notice_each_and_morph_weights_apply() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = triangle("{");
    let offsets = floats(&mut d, &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC3", "");
    let times = floats(&mut d, &[0.0, 1.0], "SCALAR", r#", "min": [0], "max": [1]"#);
    let values = floats(&mut d, &[0.0, 1.0], "SCALAR", "");
    let ibm = floats(&mut d, &IDENTITY, "MAT4", "");
    d.meshes[0] = format!(
        r#"{{"primitives": [{}], "weights": [0.5]}}"#,
        primitive(0, None, None, &format!(r#", "targets": [{{"POSITION": {offsets}}}]"#))
    );
    d.nodes[0] = r#"{"mesh": 0, "skin": 0}"#.into();
    let joint = d.node(r#"{"translation": [0, 0, 0]}"#);
    d.roots.push(joint);
    let members = format!(
        r#""skins": [{{"joints": [{joint}], "inverseBindMatrices": {ibm}}}],
 "animations": [{{"samplers": [{{"input": {times}, "output": {values}}}],
   "channels": [{{"sampler": 0, "target": {{"path": "weights"}}}}, {{"sampler": 0, "target": {{"node": 0, "path": "weights"}}}}]}}]"#
    );
    let s = scene::load_file(&write(dir.path(), "posed.gltf", with_members(&d, &members))).unwrap();
    // The default pose: the base plus half the morph offset, the mesh where its node puts it.
    assert_eq!(s.stats.triangles, 1);
    assert!(corners(&s).iter().all(|v| v.z == 0.5), "{:?}", corners(&s));
    assert_eq!(notice(&s, "skin(s) ignored: meshes are drawn in their bind pose"), Some(1), "{:?}", s.notices);
    assert_eq!(notice(&s, "animation(s) ignored: beam renders one pose"), Some(1), "{:?}", s.notices);
    assert_eq!(s.notices.len(), 2, "{:?}", s.notices);

    // A node's weights win over its mesh's; zero weights are the base shape; two nodes of the
    // same mesh under different weights get their own shapes.
    let mut two = d;
    two.nodes[0] = r#"{"mesh": 0, "weights": [2]}"#.into();
    two.roots = vec![0, two.node(r#"{"mesh": 0, "weights": [0], "translation": [5, 0, 0]}"#)];
    let s = scene::load_file(&write(dir.path(), "two.gltf", two.gltf())).unwrap();
    let z: Vec<f32> = corners(&s).iter().map(|v| v.z).collect();
    assert_eq!(z, [2.0, 2.0, 2.0, 0.0, 0.0, 0.0], "{:?}", corners(&s));
    assert!(s.notices.is_empty(), "{:?}", s.notices);

    // A weight past f32 and a target with the wrong number of elements are refused, naming them.
    let mut huge = two.clone();
    huge.nodes[0] = r#"{"mesh": 0, "weights": [1e39]}"#.into();
    refused(dir.path(), "huge.gltf", huge.gltf(), &["node 0", "morph weight inf is not finite"]);
    let mut bad = two;
    let short = floats(&mut bad, &[0.0, 0.0, 1.0], "VEC3", "");
    bad.meshes[0] =
        bad.meshes[0].replace(&format!(r#""POSITION": {offsets}}}]"#), &format!(r#""POSITION": {short}}}]"#));
    refused(
        dir.path(),
        "bad.gltf",
        bad.gltf(),
        &["mesh 0 primitive 0", "morph target 0 Position", "one element per vertex"],
    );
}

#[test]
fn morph_targets_move_normals_too() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = triangle("{");
    // Normals along +z, and a target tilting them towards +x under weight 1: (1, 0, 1) unnormalized.
    let normals = floats(&mut d, &[0.0, 0.0, 1.0].repeat(3), "VEC3", "");
    let turn = floats(&mut d, &[1.0, 0.0, 0.0].repeat(3), "VEC3", "");
    let targets = format!(r#", "targets": [{{"NORMAL": {turn}}}]"#);
    let prim = format!(r#"{{"attributes": {{"POSITION": 0, "NORMAL": {normals}}}{targets}}}"#);
    d.meshes[0] = format!(r#"{{"primitives": [{prim}], "weights": [1]}}"#);
    let s = scene::load_file(&write(dir.path(), "normals.gltf", d.gltf())).unwrap();
    let n = s.surfaces.normals[0];
    let want = Vec3::new(1.0, 0.0, 1.0).normalize();
    assert!(n.iter().all(|n| (*n - want).length() < 1e-5), "{n:?}");
}

/// The identity matrix (an inverse bind matrix).
const IDENTITY: [f32; 16] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];

#[test]
fn scenes_without_nodes_and_accessors_without_views_load() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = triangle("{");
    // An unused accessor without a buffer view (its elements are zeros).
    d.accessors.push(r#"{"componentType": 5126, "count": 4, "type": "VEC3"}"#.into());
    let json = d.gltf().replace(r#""scenes": [{"nodes": [0]}]"#, r#""scenes": [{"nodes": [0]}, {"name": "empty"}]"#);
    assert!(json.contains(r#"{"name": "empty"}"#));
    let s = scene::load_file(&write(dir.path(), "scenes.gltf", json)).unwrap();
    assert_eq!(s.stats.triangles, 1);

    // Sparse POSITION accessors: over a buffer view (vertex 1 moved to (2, 0, 0)), and over zeros
    // (vertices 1 and 2 set; vertex 0 stays at the origin).
    let mut d = triangle("{");
    let index_bytes: Vec<u8> = [1u16, 2].iter().flat_map(|i| i.to_le_bytes()).collect();
    let value_bytes: Vec<u8> = [2.0f32, 0.0, 0.0, 0.0, 3.0, 0.0].iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut view = |bytes: &[u8]| {
        while d.bin.len() % 4 != 0 {
            d.bin.push(0);
        }
        d.views.push(format!(r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, d.bin.len(), bytes.len()));
        d.bin.extend_from_slice(bytes);
        d.views.len() - 1
    };
    let (iv, vv) = (view(&index_bytes), view(&value_bytes));
    let one = |n: usize, offset: usize| {
        format!(
            r#""sparse": {{"count": {n}, "indices": {{"bufferView": {iv}, "componentType": 5123}}, "values": {{"bufferView": {vv}, "byteOffset": {offset}}}}}"#
        )
    };
    d.accessors[0] =
        d.accessors[0].replace(r#""type": "VEC3""#, &format!(r#""type": "VEC3", "max": [2, 1, 0], {}"#, one(1, 0)));
    d.accessors[0] = d.accessors[0].replacen(r#", "max": [1, 1, 0]"#, "", 1);
    d.accessors.push(format!(
        r#"{{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [2, 3, 0], {}}}"#,
        one(2, 0)
    ));
    let zeros = d.mesh(&[primitive(1, None, None, "")]);
    let n = d.node(&format!(r#"{{"mesh": {zeros}, "translation": [0, 0, -1]}}"#));
    d.roots.push(n);
    let s = scene::load_file(&write(dir.path(), "sparse.gltf", d.gltf())).unwrap();
    let v = corners(&s);
    assert_eq!(s.stats.triangles, 2, "{v:?}");
    for p in [Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 3.0, -1.0), Vec3::new(0.0, 0.0, -1.0)]
    {
        assert!(v.iter().any(|&c| near(c, p)), "{p} not among {v:?}");
    }
    assert!(!v.iter().any(|&c| near(c, Vec3::X)), "vertex 1 was replaced: {v:?}");
}

#[test]
fn optional_and_supported_required_extensions_load() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = triangle(r#"{"extensions": {"EXT_future_thing": {"x": 1}}"#);
    d.materials.push(r#"{"extensions": {"KHR_materials_unlit": {}, "EXT_future_material": {}}}"#.into());
    d.meshes[0] = d.meshes[0].replace(r#""POSITION": 0}"#, r#""POSITION": 0}, "material": 0"#);
    let optional = using(&d.gltf(), r#""KHR_materials_unlit", "EXT_future_thing", "EXT_future_material""#);
    let s = scene::load_file(&write(dir.path(), "optional.gltf", &optional)).unwrap();
    assert_eq!(s.stats.triangles, 1);

    // Required: unlit, and quantized positions (normalized shorts, KHR_mesh_quantization).
    let quantized: Vec<u8> = [0i16, 0, 0, 32767, 0, 0, 0, 32767, 0].iter().flat_map(|x| x.to_le_bytes()).collect();
    let q = raw_accessor(
        &mut d,
        &quantized,
        r#""componentType": 5122, "normalized": true, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [32767, 32767, 0]"#,
    );
    let m = d.mesh(&[primitive(q, None, None, "")]);
    let n = d.node(&format!(r#"{{"mesh": {m}, "translation": [0, 0, -2]}}"#));
    d.roots.push(n);
    let required = with_members(
        &d,
        r#""extensionsRequired": ["KHR_materials_unlit", "KHR_mesh_quantization", "KHR_texture_transform", "KHR_lights_punctual"]"#,
    );
    let s = scene::load_file(&write(dir.path(), "required.gltf", &required)).unwrap();
    assert_eq!(s.stats.triangles, 2);
    assert!(corners(&s).iter().any(|&c| near(c, Vec3::new(1.0, 0.0, -2.0))), "{:?}", corners(&s));
}

/// Load `dir/name` holding `data`: the error, which must name the file and hold each of `words`.
#[track_caller]
#[test]
fn unsupported_required_extensions_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    // A Draco file: its accessors have no buffer views; the extension is named, not the accessors.
    let mut draco = Doc::default();
    for _ in 0..3 {
        draco
            .accessors
            .push(r#"{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}"#.into());
    }
    draco.bin = vec![0; 16];
    let ext = r#", "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}"#;
    draco.views.push(r#"{"buffer": 0, "byteLength": 16}"#.into());
    let m = draco.mesh(&[primitive(0, None, None, ext)]);
    draco.roots = vec![draco.node(&format!(r#"{{"mesh": {m}}}"#))];
    let required =
        |d: &Doc, names: &str| using(&with_members(d, &format!(r#""extensionsRequired": [{names}]"#)), names);
    let e = refused(dir, "model.gltf", required(&draco, r#""KHR_draco_mesh_compression""#), &[]);
    assert!(
        e.ends_with(
            "model.gltf: extensionsRequired: KHR_draco_mesh_compression (Draco mesh compression) is not supported"
        ),
        "{e}"
    );
    // Used but not required, without the uncompressed data the extension then demands.
    let used = using(&draco.gltf(), r#""KHR_draco_mesh_compression""#);
    refused(dir, "draco.gltf", used, &["meshes[0].primitives[0]", "Draco", "no uncompressed"]);

    let tri = triangle("{");
    for (name, what) in [
        ("EXT_meshopt_compression", "meshopt"),
        ("KHR_meshopt_compression", "meshopt"),
        ("KHR_texture_basisu", "KTX2"),
        ("EXT_texture_webp", "WebP"),
        ("EXT_future_geometry", "EXT_future_geometry is not supported"),
    ] {
        let file = format!("{name}.gltf");
        refused(dir, &file, required(&tri, &format!("\"{name}\"")), &["extensionsRequired", name, what]);
    }
    // Several: each named, the supported one not.
    let two = required(&tri, r#""KHR_lights_punctual", "KHR_draco_mesh_compression", "EXT_texture_webp""#);
    let e = refused(dir, "two.gltf", two, &["Draco", "WebP", "are not supported"]);
    assert!(!e.contains("KHR_lights_punctual"), "{e}");
    // A meshopt fallback buffer (no data of its own) used without the extension being required.
    let fallback = using(&tri.gltf(), r#""EXT_meshopt_compression""#).replace(
        r#""buffers": [{"#,
        r#""buffers": [{"byteLength": 8, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}, {"#,
    );
    refused(dir, "fallback.gltf", fallback, &["buffers[0]", "meshopt", "fallback"]);
}

#[test]
fn a_document_of_the_wrong_types_names_the_element() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = triangle("{");
    d.nodes[0] = r#"{"mesh": "zero"}"#.into();
    refused(dir.path(), "types.gltf", d.gltf(), &["nodes[0]", "invalid type"]);
}

#[test]
fn spot_and_directional_lights_are_noticed() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene::load_file(&write(dir.path(), "box.gltf", common::cornell().gltf())).unwrap();
    assert_eq!(notice(&s, "spot light(s) drawn as point lights"), Some(1), "{:?}", s.notices);
    assert_eq!(notice(&s, "directional light(s) skipped"), Some(1), "{:?}", s.notices);
}
