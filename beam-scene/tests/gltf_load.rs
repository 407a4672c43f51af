//! glTF 2.0 scenes load with their node transforms, camera, lights and materials, the same from a
//! `.gltf` with a base64 buffer, a `.gltf` with a buffer file beside it, and a `.glb`.

mod common;

use beam_scene::beam_math::glam::Vec3;
use beam_scene::scene::{self, Light, Material, Scene};
use common::{Doc, cornell, primitive, write};

/// The Cornell-like box of [`cornell`] as each of the three containers.
fn each_container() -> Vec<Scene> {
    let dir = tempfile::tempdir().unwrap();
    let d = cornell();
    // With a byte-order mark, which readers may ignore.
    let embedded = write(dir.path(), "box.gltf", format!("\u{feff}{}", d.gltf()));
    write(dir.path(), "box data.bin", &d.bin);
    let external = write(dir.path(), "external.GLTF", d.json(Some("box%20data.bin")));
    let binary = write(dir.path(), "box.glb", d.glb());
    [embedded, external, binary].iter().map(|p| scene::load_file(p).unwrap()).collect()
}

fn near(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn cornell_box_counts_transforms_and_camera() {
    for s in each_container() {
        let name = &s.name;
        assert_eq!((s.stats.triangles, s.stats.degenerate), (28, 1), "{name}");
        assert_eq!((s.stats.skipped_elements, s.stats.skipped_lights), (1, 1), "{name}: points, directional");
        // The cube: corner (1, 1, 1) scaled by ¼, turned 90° about y (x, z → z, −x), lifted by ¼, then
        // moved by its parent's (0.4, 0, −0.3).
        let mirror = |m: &Material| matches!(m, Material::Mirror { .. });
        let cube: Vec<_> = (0..s.triangles.len()).filter(|&i| mirror(&s.material(i as u32))).collect();
        assert_eq!(cube.len(), 12, "{name}");
        let corners: Vec<Vec3> = cube.iter().flat_map(|&i| s.triangles[i].v).collect();
        assert!(corners.iter().any(|&v| near(v, Vec3::new(0.65, 0.5, -0.55))), "{name}: {corners:?}");
        assert!(corners.iter().all(|v| (0.15 - 1e-5..=0.65 + 1e-5).contains(&v.x)), "{name}");
        // The glossy pane is placed by a matrix: scale ½, then translated by (−0.2, 0.1, −0.8).
        let glossy = (0..s.triangles.len()).filter(|&i| matches!(s.material(i as u32), Material::Glossy { .. }));
        let v: Vec<Vec3> = glossy.flat_map(|i| s.triangles[i].v).collect();
        assert!(v.len() == 6 && v.iter().any(|&p| near(p, Vec3::new(-0.05, 0.25, -0.8))), "{name}: {v:?}");
        // The camera's node: at (0, 1, 3.4), looking down −z, 1.5 times wider than high.
        let c = s.camera;
        assert!(near(c.position, Vec3::new(0.0, 1.0, 3.4)), "{name}: {c:?}");
        assert!(near((c.target - c.position).normalize(), Vec3::NEG_Z), "{name}: {c:?}");
        assert!((c.fov_y - 0.7f32.to_degrees()).abs() < 1e-4 && (c.width, c.height) == (768, 512), "{name}: {c:?}");
    }
}

#[test]
fn materials_and_lights_are_mapped() {
    for s in each_container() {
        let name = &s.name;
        let has = |f: &dyn Fn(&Material) -> bool| s.materials.iter().any(f);
        assert!(has(&|m| *m == Material::Diffuse { albedo: Vec3::new(0.65, 0.05, 0.05) }), "{name}: red");
        assert!(has(&|m| *m == Material::Emissive { radiance: Vec3::splat(15.0) }), "{name}: emissive × strength");
        assert!(has(&|m| matches!(m, Material::Mirror { tint, .. } if near(*tint, Vec3::splat(0.9)))), "{name}");
        assert!(has(&|m| *m == Material::Glass { ior: 1.4 }), "{name}: transmission + ior");
        let glossy = Material::Glossy { albedo: Vec3::new(0.8, 0.6, 0.2), variance: 0.0625 };
        assert!(has(&|m| *m == glossy), "{name}: rough metal, variance roughness⁴");
        // The emissive quad's two triangles joined into one quad light, facing down at y = 1.98; the
        // point light; the spot light as a point light; the directional light skipped.
        assert_eq!(s.lights.len(), 3, "{name}: {:?}", s.lights);
        assert_eq!(s.stats.merged_lights, 1, "{name}");
        let quads: Vec<&Light> = s.lights.iter().filter(|l| matches!(l, Light::Quad { .. })).collect();
        assert_eq!(quads.len(), 1, "{name}");
        for l in quads {
            assert!(near(l.normal(), Vec3::NEG_Y) && (l.center().y - 1.98).abs() < 1e-5, "{name}: {l:?}");
            assert_eq!(l.power(), Vec3::splat(15.0));
        }
        let point = Light::Point { position: Vec3::new(0.0, 1.5, 0.0), intensity: Vec3::new(4.0, 2.0, 1.0) };
        assert!(s.lights.contains(&point), "{name}: {:?}", s.lights);
        let spot = Light::Point { position: Vec3::new(0.5, 1.9, 0.0), intensity: Vec3::splat(3.0) };
        assert!(s.lights.contains(&spot), "{name}: {:?}", s.lights);
    }
}

#[test]
fn a_model_without_camera_or_light_gets_the_defaults_of_a_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let m = d.mesh(&[primitive(p, None, None, "")]);
    d.roots = vec![d.node(&format!(r#"{{"mesh": {m}}}"#))];
    let gltf = scene::load_file(&write(dir.path(), "t.gltf", d.gltf())).unwrap();
    let obj = scene::load_file(&write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).unwrap();
    assert_eq!(gltf.camera, obj.camera);
    assert_eq!(gltf.lights, obj.lights);
    assert_eq!(gltf.materials.last(), obj.materials.first(), "no material: the grey of a bare OBJ");
}

#[test]
fn a_mirroring_transform_keeps_emitters_facing_the_same_side() {
    // An emissive triangle facing +y, mirrored by scale (1, 1, −1): it still faces +y (the winding
    // is flipped with the determinant), and its light with it.
    let dir = tempfile::tempdir().unwrap();
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]);
    let m = d.mesh(&[primitive(p, None, Some(0), "")]);
    d.materials.push(r#"{"emissiveFactor": [1, 1, 1]}"#.into());
    d.roots = vec![d.node(&format!(r#"{{"mesh": {m}, "scale": [1, 1, -1]}}"#))];
    let s = scene::load_file(&write(dir.path(), "m.gltf", d.gltf())).unwrap();
    assert_eq!(s.lights.len(), 1);
    assert!(near(s.lights[0].normal(), Vec3::Y), "{:?}", s.lights);
    assert!(near(s.normal(0), Vec3::Y));
}

#[test]
fn gltf_files_load_through_the_scene_name_dispatch() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "box.glb", cornell().glb());
    let s = scene::load_with(p.to_str().unwrap(), &scene::LoadOptions::default()).unwrap();
    assert_eq!(s.stats.triangles, 28);
}

/// The Cornell-like box without its camera node is a room open towards +z: its default camera
/// stands on that side looking in at the box's centre, and its own lights stay.
#[test]
fn a_room_without_a_camera_is_seen_from_its_open_side() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = cornell();
    d.roots.retain(|&r| r != 6);
    let s = scene::load_file(&write(dir.path(), "room.gltf", d.gltf())).unwrap();
    let c = s.camera;
    assert!(c.position.z > 1.0 && c.position.x.abs() < 1e-5, "{c:?}");
    assert!(near(c.target, s.bounds().center()), "{c:?}");
    assert_eq!(s.lights.len(), 3, "the emissive quad and two point lights: {:?}", s.lights);
}
