//! Malformed glTF files are clear errors naming the file and the element, never a panic or a hang;
//! and a seeded mutation run over valid `.gltf` and `.glb` files finds no panic.

mod common;

use beam_scene::scene;
use common::{Doc, cornell, primitive, refused, write};
use rand::{Rng, SeedableRng};

/// A one-triangle document whose positions are `p` and indices `i`.
fn triangle(p: &[[f32; 3]], i: Option<&[u32]>) -> Doc {
    let mut d = Doc::default();
    let p = d.positions(p);
    let i = i.map(|i| d.indices(i, 4));
    let m = d.mesh(&[primitive(p, i, None, "")]);
    d.roots = vec![d.node(&format!(r#"{{"mesh": {m}}}"#))];
    d
}

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// Load `dir/name` holding `data`: the error, which must name the file and hold each of `words`.
#[track_caller]
#[test]
fn malformed_files_name_the_file_and_element() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = cornell().gltf();
    refused(d, "truncated.gltf", &good[..good.len() / 2], &["line", "column"]);
    refused(d, "truncated.glb", &cornell().glb()[..600], &["GLB header", "length"]);
    refused(d, "empty.glb", b"glTF\x02\0\0\0", &["GLB header", "truncated"]);
    refused(d, "index.gltf", triangle(&TRI, Some(&[0, 1, 9])).gltf(), &["mesh 0 primitive 0", "index 9 out of range"]);
    let nan = [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]];
    refused(d, "nan.gltf", triangle(&nan, None).gltf(), &["mesh 0 primitive 0", "POSITION 1 is not finite"]);
    let mut short = triangle(&TRI, None);
    short.byte_length = Some(64);
    refused(d, "short.gltf", short.gltf(), &["buffer 0", "36 bytes, fewer than its byteLength 64"]);
    let mut past = triangle(&TRI, None);
    past.views[0] = r#"{"buffer": 0, "byteOffset": 24, "byteLength": 36}"#.into();
    refused(d, "past.gltf", past.gltf(), &["buffer view 0", "outside buffer 0"]);
    let mut long = triangle(&TRI, None);
    long.accessors[0] = long.accessors[0].replace(r#""count": 3"#, r#""count": 4000000000"#);
    refused(d, "count.gltf", long.gltf(), &["mesh 0 primitive 0", "accessor 0", "do not fit in buffer view 0"]);
    let tri = triangle(&TRI, None);
    refused(d, "missing.gltf", tri.json(Some("gone.bin")), &["buffer 0", "gone.bin"]);
    // The buffer file's own error is kept whole, with the system's.
    match scene::load_file(&d.join("missing.gltf")) {
        Err(beam_scene::SceneError::InMesh { element, source, .. }) => {
            assert_eq!(element, "buffer 0");
            assert!(matches!(*source, beam_scene::SceneError::Read { .. }), "{source:?}");
        }
        other => panic!("expected InMesh(Read): {:?}", other.err()),
    }
    refused(d, "outside.gltf", tri.json(Some("../x.bin")), &["buffer 0", "outside", "--allow-outside-paths"]);
    refused(d, "http.gltf", tri.json(Some("https://example.invalid/x.bin")), &["buffer 0", "`https:`"]);
    refused(d, "nobin.gltf", tri.json(None), &["buffer 0", "GLB binary chunk"]);
    let mut no_position = triangle(&TRI, None);
    no_position.meshes[0] = r#"{"primitives": [{"attributes": {"NORMAL": 0}}]}"#.into();
    refused(d, "nopos.gltf", no_position.gltf(), &["meshes[0].primitives[0]", "POSITION", "missing"]);
    let mut bad_ref = triangle(&TRI, None);
    bad_ref.meshes[0] = primitive(7, None, None, "").replace("{\"attributes", "{\"primitives\": [{\"attributes") + "]}";
    refused(d, "ref.gltf", bad_ref.gltf(), &["meshes[0].primitives[0].attributes", "out of bounds"]);
    let mut cycle = triangle(&TRI, None);
    cycle.nodes[0] = r#"{"mesh": 0, "children": [1]}"#.into();
    cycle.nodes.push(r#"{"children": [0]}"#.into());
    refused(d, "cycle.gltf", cycle.gltf(), &["node 0", "reached twice"]);
    let mut inf = triangle(&TRI, None);
    inf.nodes[0] = r#"{"mesh": 0, "scale": [1e39, 1, 1]}"#.into();
    refused(d, "inf.gltf", inf.gltf(), &["node 0", "finite"]);
    let mut black_hole = triangle(&TRI, None);
    black_hole.materials.push(r#"{"pbrMetallicRoughness": {"baseColorFactor": [1, -1, 1, 1]}}"#.into());
    black_hole.meshes[0] = black_hole.meshes[0].replace(r#""POSITION": 0}"#, r#""POSITION": 0}, "material": 0"#);
    refused(d, "colour.gltf", black_hole.gltf(), &["material 0", "baseColorFactor"]);
    let mut lines = triangle(&TRI, None);
    lines.meshes[0] = r#"{"primitives": [{"attributes": {"POSITION": 0}, "mode": 1}]}"#.into();
    refused(d, "lines.gltf", lines.gltf(), &["no valid triangle"]);
    let mut no_lights = cornell();
    no_lights.lights.clear();
    refused(d, "nolights.gltf", no_lights.gltf(), &["nodes[7].extensions", "light: index out of bounds"]);
    let deep =
        format!(r#"{{"asset": {{"version": "2.0"}}, "extras": {}1{}}}"#, "[".repeat(100_000), "]".repeat(100_000));
    refused(d, "deep.gltf", deep, &["line 1"]);
}

#[test]
fn outside_buffers_load_when_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("in");
    std::fs::create_dir(&inner).unwrap();
    let tri = triangle(&TRI, None);
    write(dir.path(), "x.bin", &tri.bin);
    let p = write(&inner, "t.gltf", tri.json(Some("../x.bin")));
    let options = scene::LoadOptions { allow_outside_paths: true };
    assert_eq!(scene::load_file_with(&p, &options).unwrap().stats.triangles, 1);
}

/// Flip, overwrite, drop or repeat a few bytes of `data`.
fn mutate(rng: &mut rand_pcg::Pcg64, data: &[u8]) -> Vec<u8> {
    let mut out = data.to_vec();
    for _ in 0..rng.random_range(1..4) {
        if out.is_empty() {
            break;
        }
        let at = rng.random_range(0..out.len());
        match rng.random_range(0..4) {
            0 => out[at] ^= 1 << rng.random_range(0..8),
            1 => out[at] = b"0123456789-.e,[]{}\"\xff\0"[rng.random_range(0..21)],
            2 => {
                out.remove(at);
            }
            _ => {
                let end = (at + rng.random_range(1..16)).min(out.len());
                let copy = out[at..end].to_vec();
                out.splice(at..at, copy);
            }
        }
    }
    out
}

#[test]
fn mutated_files_never_panic_and_errors_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = cornell();
    let seeds = [(d.gltf().into_bytes(), "m.gltf"), (d.glb(), "m.glb")];
    let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
    let (mut loaded, mut refused) = (0, 0);
    for k in 0..1500 {
        let (seed, name) = &seeds[k % 2];
        let data = mutate(&mut rng, seed);
        let path = write(dir.path(), name, &data);
        let result = std::panic::catch_unwind(|| scene::load_file(&path));
        match result {
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(e)) => {
                assert!(e.to_string().contains(name), "case {k}: {e}");
                refused += 1;
            }
            Err(_) => {
                let keep = write(&std::env::temp_dir(), &format!("beam-gltf-panic-{k}-{name}"), &data);
                panic!("case {k} panicked; input kept in {}", keep.display());
            }
        }
    }
    assert!(loaded > 0 && refused > 0, "{loaded} loaded, {refused} refused");
}
