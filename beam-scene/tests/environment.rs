//! Environment maps read from `.hdr` (Radiance RGBE) and `.exr` (OpenEXR) files, and the scene
//! file's `[environment]` table: the texels come back where the convention puts them, and bad
//! files and values are clear errors naming the file (and the key).

use beam_scene::beam_math::glam::Vec3;
use beam_scene::region::Placement;
use beam_scene::scene::{self, Environment, EnvironmentMap};
use std::path::{Path, PathBuf};

fn write(dir: &Path, name: &str, data: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, data).unwrap();
    p
}

/// A 4 × 2 map: the top row red, green, blue, white; the bottom row a quarter of each.
fn texels() -> Vec<Vec3> {
    let top = [Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 0.5), Vec3::splat(4.0)];
    top.iter().copied().chain(top.iter().map(|c| 0.25 * *c)).collect()
}

fn hdr_bytes(width: usize, height: usize, texels: &[Vec3]) -> Vec<u8> {
    let rgb: Vec<image::Rgb<f32>> = texels.iter().map(|t| image::Rgb(t.to_array())).collect();
    let mut out = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut out).encode(&rgb, width, height).unwrap();
    out
}

/// Each texel of a written map is seen at its centre's direction, after the file's round trip
/// (RGBE keeps about 1% of each value; EXR's 32-bit floats all of it).
fn sees_each_texel(map: &EnvironmentMap, tolerance: f32) {
    assert_eq!((map.width(), map.height()), (4, 2));
    for (i, t) in texels().iter().enumerate() {
        let (x, y) = (i % 4, i / 4);
        let d = EnvironmentMap::direction((x as f32 + 0.5) / 4.0, (y as f32 + 0.5) / 2.0);
        let got = map.radiance(d);
        assert!(got.abs_diff_eq(*t, tolerance * t.max_element()), "texel ({x}, {y}): {got}, written {t}");
    }
}

#[test]
fn reads_hdr_and_exr_maps() {
    let dir = tempfile::tempdir().unwrap();
    let hdr = write(dir.path(), "sky.hdr", hdr_bytes(4, 2, &texels()));
    sees_each_texel(&EnvironmentMap::load(&hdr).unwrap(), 0.01);
    let exr = write(dir.path(), "sky.EXR", scene_exr(&texels()));
    sees_each_texel(&EnvironmentMap::load(&exr).unwrap(), 1e-5);
}

fn scene_exr(texels: &[Vec3]) -> Vec<u8> {
    beam_scene::io::encode_exr(texels, Placement::whole(4, 2)).unwrap()
}

/// Bad files are refused with the file named: not an image, a truncated one, a wrong extension,
/// a missing file, a folder, a non-finite texel.
#[test]
fn bad_maps_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let err = |p: &Path| EnvironmentMap::load(p).unwrap_err().to_string();
    let cases = [
        write(dir.path(), "junk.hdr", b"not a radiance file"),
        write(dir.path(), "junk.exr", b"not an exr file at all"),
        write(dir.path(), "cut.hdr", &hdr_bytes(4, 2, &texels())[..60]),
        write(dir.path(), "sky.png", b"\x89PNG"),
        dir.path().join("missing.hdr"),
    ];
    for p in &cases {
        let e = err(p);
        let name = p.file_name().unwrap().to_str().unwrap();
        assert!(e.contains(name), "{e}");
    }
    assert!(err(&cases[3]).contains(".hdr") && err(&cases[3]).contains(".exr"));
    std::fs::create_dir(dir.path().join("folder.exr")).unwrap();
    assert!(err(&dir.path().join("folder.exr")).contains("not a regular file"));
    let mut nan = texels();
    nan[5].y = f32::NAN;
    let e = err(&write(dir.path(), "nan.exr", scene_exr(&nan)));
    assert!(e.contains("nan.exr") && e.contains("texel (1, 1) is not finite"), "{e}");
    // Sizes are checked before any texel is decoded.
    let e = EnvironmentMap::new(20000, 1, Vec::new()).unwrap_err().to_string();
    assert!(e.contains("20000×1") && e.contains("16384"), "{e}");
}

/// `[environment]` in a scene file: a colour (times the intensity), or a map beside the scene
/// file; errors name the scene file and the key.
#[test]
fn scene_files_give_an_environment() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write(dir.path(), "sky.hdr", hdr_bytes(4, 2, &texels()));
    let body =
        "[materials.w]\ntype = \"diffuse\"\nalbedo = [1, 1, 1]\n[[meshes]]\nfile = \"t.obj\"\nmaterial = \"w\"\n";
    let load = |name: &str, env: &str| scene::load_file(&write(dir.path(), name, format!("{body}{env}")));
    assert_eq!(load("a.toml", "").unwrap().environment, Environment::Black);
    let s = load("b.toml", "[environment]\ncolor = [0.1, 0.2, 0.3]\nintensity = 2\n").unwrap();
    assert_eq!(s.environment, Environment::Constant(Vec3::new(0.2, 0.4, 0.6)));
    let s = load("c.toml", "[environment]\nmap = \"sky.hdr\"\nrotation = 90\nintensity = 0.5\n").unwrap();
    let Environment::Map(map) = &s.environment else { panic!("{:?}", s.environment) };
    // Turned by 90° about +Y, the texel the map's +X saw (the top row's second and third) is seen
    // along −Z.
    let plain = EnvironmentMap::load(&dir.path().join("sky.hdr")).unwrap();
    assert!(map.radiance(-Vec3::Z).abs_diff_eq(0.5 * plain.radiance(Vec3::X), 1e-4));
    let err = |name: &str, env: &str| load(name, env).err().unwrap().to_string();
    let e = err("d.toml", "[environment]\ncolor = [1, 1, 1]\nmap = \"sky.hdr\"\n");
    assert!(e.contains("d.toml") && e.contains("environment") && e.contains("not both"), "{e}");
    let e = err("e.toml", "[environment]\nintensity = 2\n");
    assert!(e.contains("e.toml") && e.contains("needs color"), "{e}");
    let e = err("f.toml", "[environment]\ncolor = [1, -1, 1]\n");
    assert!(e.contains("environment.color") && e.contains("≥ 0"), "{e}");
    let e = err("g.toml", "[environment]\nmap = \"none.hdr\"\n");
    assert!(e.contains("g.toml") && e.contains("environment.map") && e.contains("none.hdr"), "{e}");
    let e = err("h.toml", "[environment]\nmap = \"../outside.hdr\"\n");
    assert!(e.contains("environment.map") && e.contains("--allow-outside-paths"), "{e}");
    let e = err("i.toml", "[environment]\ncolor = [1, 1, 1]\nrotation = 10\n");
    assert!(e.contains("rotation applies to a map"), "{e}");
    let e = err("j.toml", "[environment]\ncolor = [1, 1, 1]\nintensity = -1\n");
    assert!(e.contains("environment.intensity"), "{e}");
    let e = err("k.toml", "[environment]\ncolour = [1, 1, 1]\n");
    assert!(e.contains("k.toml:") && e.contains("colour"), "{e}");
    write(dir.path(), "bad.hdr", b"#?RADIANCE\nnonsense");
    let e = err("l.toml", "[environment]\nmap = \"bad.hdr\"\n");
    assert!(e.contains("l.toml") && e.contains("environment.map") && e.contains("bad.hdr"), "{e}");
}
