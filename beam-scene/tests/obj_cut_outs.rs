//! A bare OBJ's alpha maps (`map_d`) cut its diffuse faces out as a glTF `MASK` does: the scene's
//! own ray queries pass where the map's alpha (or, without alpha, its grey level) is below ½.

use beam_scene::beam_math::Ray;
use beam_scene::beam_math::glam::Vec3;
use beam_scene::scene;
use std::path::Path;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn an_alpha_map_cuts_its_faces_out() {
    let dir = tempfile::tempdir().unwrap();
    // Left texel kept, right one cut: by alpha, and by grey level in an image without alpha.
    image::RgbaImage::from_raw(2, 1, vec![9, 9, 9, 255, 9, 9, 9, 0]).unwrap().save(dir.path().join("a.png")).unwrap();
    image::RgbImage::from_raw(2, 1, vec![255, 255, 255, 0, 0, 0]).unwrap().save(dir.path().join("g.png")).unwrap();
    write(
        dir.path(),
        "m.mtl",
        "newmtl alpha\nKd 1 1 1\nmap_d a.png\nnewmtl grey\nKd 1 1 1\nmap_d -imfchan m g.png\n\
         newmtl gone\nKd 1 1 1\nmap_d none.png\n",
    );
    // Three quads, x ∈ [10k, 10k + 2], y ∈ [0, 2], u along x.
    let mut obj = String::from("mtllib m.mtl\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n");
    for (k, material) in ["alpha", "grey", "gone"].iter().enumerate() {
        let x = 10.0 * k as f32;
        obj += &format!("v {x} 0 0\nv {} 0 0\nv {} 2 0\nv {x} 2 0\n", x + 2.0, x + 2.0);
        let i = 4 * k + 1;
        obj += &format!("usemtl {material}\nf {i}/1 {}/2 {}/3 {}/4\n", i + 1, i + 2, i + 3);
    }
    let s = scene::load_file(&write(dir.path(), "q.obj", &obj)).unwrap();
    let there = |x: f32| s.closest_hit(Ray::new(Vec3::new(x, 1.0, 1.0), -Vec3::Z), f32::INFINITY).is_some();
    assert!(there(0.5) && !there(1.5), "by alpha");
    assert!(there(10.5) && !there(11.5), "by grey level");
    assert!(there(20.5) && there(21.5), "a missing map: the faces whole");
    let noticed = |what: &str| s.notices.iter().find(|n| n.what.contains(what)).map(|n| n.count);
    assert_eq!(noticed("alpha map image(s) (map_d) not found"), Some(1));
    assert_eq!(noticed("texture option(s)"), Some(1), "{:?}", s.notices);
}
