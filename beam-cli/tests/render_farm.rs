//! Render farms: `beam render --tile I/N` and `--crop` in separate processes, joined by `beam merge`,
//! give the one-process render byte for byte (PNG and EXR); the merge's checks; HDR output and
//! exposure; `--frame` of an animated camera.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary under test.
fn bin() -> String {
    std::env::var("BEAM_TEST_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_beam").into())
}

fn command(args: &[String]) -> Command {
    let mut cmd = Command::new(bin());
    cmd.args(args).env_remove("BEAM_MAX_MEMORY");
    cmd
}

fn beam(args: &[&str]) -> Output {
    command(&args.iter().map(|a| a.to_string()).collect::<Vec<_>>()).output().expect("run beam")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[track_caller]
fn ok(o: &Output) {
    assert!(o.status.success(), "{:?}: {}", o.status, stderr(o));
}

/// Exit status 2 and a message containing every one of `words`.
#[track_caller]
fn refused(o: &Output, words: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "expected a clear error, got {:?}: {e}", o.status);
    assert!(!e.contains("panicked"), "{e}");
    for w in words {
        assert!(e.contains(w), "`{w}` missing from: {e}");
    }
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `beam render` with `args`, then `--out out` and `extra`, as a command line.
fn render_args(args: &[&str], out: &Path, extra: &[String]) -> Vec<String> {
    let mut v: Vec<String> = ["render"].iter().chain(args).map(|a| a.to_string()).collect();
    v.extend(["--out".to_string(), s(out).to_string()]);
    v.extend_from_slice(extra);
    v
}

/// Each of `parts` (extra arguments, output file) rendered by its own process, all at once.
fn render_in_processes(args: &[&str], parts: &[(Vec<String>, PathBuf)]) {
    use std::process::Stdio;
    let children: Vec<_> = parts
        .iter()
        .map(|(extra, out)| {
            let mut cmd = command(&render_args(args, out, extra));
            cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("start beam")
        })
        .collect();
    for child in children {
        ok(&child.wait_with_output().expect("wait for beam"));
    }
}

/// `beam merge tiles… --out out`.
fn merge(tiles: &[PathBuf], out: &Path) -> Output {
    let mut args: Vec<&str> = vec!["merge"];
    args.extend(tiles.iter().map(|t| s(t)));
    args.extend(["--out", s(out)]);
    beam(&args)
}

/// The tiles `--tile i/4` of `dir`, as (extra arguments, file).
fn tiles(dir: &Path, ext: &str) -> Vec<(Vec<String>, PathBuf)> {
    (0..4).map(|i| (vec!["--tile".into(), format!("{i}/4")], dir.join(format!("tile{i}.{ext}")))).collect()
}

#[test]
fn four_tiles_in_four_processes_merge_to_the_one_process_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let size = ["--width", "64", "--height", "48"];
    let methods: [&[&str]; 2] = [&[], &["--method", "ray", "--spp", "4", "--primary-spp", "4"]];
    for (m, method) in methods.iter().enumerate() {
        let args: Vec<&str> = size.iter().chain(method.iter()).copied().collect();
        for ext in ["png", "exr"] {
            let full = d.join(format!("full{m}.{ext}"));
            ok(&command(&render_args(&args, &full, &[])).output().unwrap());
            let parts = tiles(d, ext);
            render_in_processes(&args, &parts);
            let merged = d.join(format!("merged{m}.{ext}"));
            let files: Vec<PathBuf> = parts.iter().map(|p| p.1.clone()).rev().collect();
            ok(&merge(&files, &merged));
            assert!(
                std::fs::read(&full).unwrap() == std::fs::read(&merged).unwrap(),
                "{method:?} {ext}: merged differs"
            );
            // Each tile holds its band only: 12 rows of 48.
            if ext == "png" {
                let tile = image::open(&parts[1].1).unwrap();
                assert_eq!((tile.width(), tile.height()), (64, 12));
            }
        }
        // Crops across the renderers' 16-pixel tiles and one another's edges cover the frame too.
        let crops = ["0,0,40,20", "40,0,64,20", "0,20,17,48", "17,20,64,48"];
        let parts: Vec<(Vec<String>, PathBuf)> = crops
            .iter()
            .enumerate()
            .map(|(i, c)| (vec!["--crop".into(), c.to_string()], d.join(format!("crop{i}.png"))))
            .collect();
        render_in_processes(&args, &parts);
        let merged = d.join(format!("crops{m}.png"));
        ok(&merge(&parts.iter().map(|p| p.1.clone()).collect::<Vec<_>>(), &merged));
        let full = d.join(format!("full{m}.png"));
        assert!(std::fs::read(&full).unwrap() == std::fs::read(&merged).unwrap(), "{method:?}: merged crops differ");
    }
}

#[test]
fn a_tile_computes_its_own_rows_only() {
    let dir = tempfile::tempdir().unwrap();
    let rays = |extra: &[&str]| {
        let (out, stats) = (dir.path().join("r.png"), dir.path().join("r.json"));
        let mut args = vec!["render", "--method", "ray", "--spp", "1", "--width", "64", "--height", "256"];
        args.extend_from_slice(extra);
        args.extend(["--out", s(&out), "--stats", s(&stats)]);
        ok(&beam(&args));
        let json = std::fs::read_to_string(&stats).unwrap();
        let line = json.lines().find(|l| l.contains("\"camera_rays\"")).unwrap().to_string();
        line.trim().trim_start_matches("\"camera_rays\": ").trim_end_matches(',').parse::<u64>().unwrap()
    };
    // Band 1 of 4 is rows 64..128: whole 16-row shading tiles, so exactly a quarter of the rays.
    assert_eq!(rays(&["--tile", "1/4"]) * 4, rays(&[]));
    assert_eq!(rays(&["--crop", "0,0,64,16"]) * 16, rays(&[]));
}

#[test]
fn merges_and_regions_that_do_not_fit_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = ["--width", "32", "--height", "24"];
    let parts = tiles(d, "png");
    render_in_processes(&args, &parts);
    let t: Vec<PathBuf> = parts.iter().map(|p| p.1.clone()).collect();
    let out = d.join("full.png");
    refused(&merge(&[t[0].clone(), t[1].clone(), t[3].clone()], &out), &["do not cover", "0..32 × 12..18", "missing"]);
    refused(&merge(&[t[0].clone(), t[1].clone(), t[1].clone(), t[2].clone(), t[3].clone()], &out), &["overlap"]);
    let crop = d.join("crop.png");
    ok(&command(&render_args(&args, &crop, &["--crop".into(), "0,10,5,14".into()])).output().unwrap());
    refused(&merge(&[t[0].clone(), crop, t[1].clone(), t[2].clone(), t[3].clone()], &out), &["overlap", "crop.png"]);
    let small = d.join("small.png");
    ok(&beam(&["render", "--width", "16", "--height", "12", "--tile", "0/2", "--out", s(&small)]));
    refused(&merge(&[t[0].clone(), small], &out), &["different frames", "32×24", "16×12"]);
    // The same frame and tiling, but another render: another exposure, or another method.
    for (name, other) in [("bright.png", &["--exposure", "1"][..]), ("rays.png", &["--method", "ray"][..])] {
        let tile = d.join(name);
        let mut a = vec!["render", "--width", "32", "--height", "24", "--tile", "2/4", "--out", s(&tile)];
        a.extend_from_slice(other);
        ok(&beam(&a));
        refused(
            &merge(&[t[0].clone(), t[1].clone(), tile, t[3].clone()], &out),
            &["tiles of different renders", name, "tile0.png"],
        );
    }
    refused(&merge(&[t[0].clone()], &t[0]), &["would replace the tile"]);
    refused(&merge(&[t[0].clone()], &d.join("full.exr")), &["PNG", "OpenEXR"]);
    refused(&merge(&[t[0].clone()], &d.join("full.jpg")), &["--out", "*.png"]);
    assert!(!out.exists());
    let bad = |extra: &[&str], words: &[&str]| {
        let mut a = vec!["render", "--width", "32", "--height", "24", "--out", s(&out)];
        a.extend_from_slice(extra);
        refused(&beam(&a), words);
    };
    bad(&["--tile", "4/4"], &["--tile 4/4", "0 to 3"]);
    bad(&["--tile", "0/25"], &["--tile 0/25", "at most 24"]);
    bad(&["--tile", "one"], &["--tile one", "I/N"]);
    bad(&["--crop", "0,0,33,24"], &["--crop 0,0,33,24", "32×24"]);
    bad(&["--crop", "0,0,0,24"], &["--crop", "empty"]);
    bad(&["--exposure", "nan"], &["--exposure"]);
    bad(&["--exposure", "65"], &["--exposure 65", "64"]);
    bad(&["--frame", "1"], &["--frame 1", "still camera"]);
    assert!(!out.exists());
    assert_eq!(beam(&["render", "--tile", "0/2", "--crop", "0,0,1,1", "--out", s(&out)]).status.code(), Some(2));
}

/// The pixels of an EXR file read by the `exr` crate, as `f32` bits.
fn exr_bits(path: &Path) -> (usize, usize, Vec<u32>) {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| (size.width(), size.height(), vec![0u32; size.area() * 3]),
        |(w, _, px): &mut (usize, usize, Vec<u32>), p, (r, g, b, _): (f32, f32, f32, f32)| {
            let i = 3 * (p.y() * *w + p.x());
            px[i..i + 3].copy_from_slice(&[r.to_bits(), g.to_bits(), b.to_bits()]);
        },
    )
    .unwrap();
    image.layer_data.channel_data.pixels
}

#[test]
fn exr_holds_the_linear_pixels_and_exposure_scales_both_formats() {
    use beam_cpu::render::render;
    use beam_render::image::srgb_encode;
    use beam_render::options::RenderOptions;
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (24, 18);
    let args = ["--width", "24", "--height", "18", "--method", "ray", "--spp", "4"];
    let exr = dir.path().join("a.exr");
    ok(&command(&render_args(&args, &exr, &[])).output().unwrap());
    // The library's render with the options `beam render` builds.
    let scene = beam_scene::scene::builtin("cornell").unwrap();
    let options = RenderOptions { method: beam_render::options::Method::Ray, spp: 4, ..RenderOptions::exact(w, h) };
    let (image, _) = render(&scene, &options, || {});
    let linear: Vec<u32> = image.pixels.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect();
    assert_eq!(exr_bits(&exr), (w as usize, h as usize, linear), "the EXR holds the linear pixels bit for bit");
    assert!(image.pixels.iter().any(|c| c.max_element() > 1.0), "the light is brighter than white");
    // --exposure 3 multiplies by exactly 8 in the EXR, and before the sRGB encoding in the PNG.
    let brighter = dir.path().join("b.exr");
    ok(&command(&render_args(&args, &brighter, &["--exposure".into(), "3".into()])).output().unwrap());
    let eight: Vec<u32> = image.pixels.iter().flat_map(|c| (*c * 8.0).to_array().map(f32::to_bits)).collect();
    assert_eq!(exr_bits(&brighter).2, eight);
    let png = dir.path().join("b.png");
    ok(&command(&render_args(&args, &png, &["--exposure".into(), "-1.5".into()])).output().unwrap());
    let srgb: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|c| (*c * (-1.5f32).exp2()).to_array().map(|v| (srgb_encode(v) * 255.0 + 0.5) as u8))
        .collect();
    assert_eq!(image::open(&png).unwrap().to_rgb8().into_raw(), srgb);
    // A tile's EXR sits in its frame through the data and display windows.
    let tile = dir.path().join("t.exr");
    ok(&command(&render_args(&args, &tile, &["--crop".into(), "3,4,10,9".into()])).output().unwrap());
    let meta = exr::meta::MetaData::read_from_file(&tile, false).unwrap();
    let header = &meta.headers[0];
    assert_eq!(header.shared_attributes.display_window.size.0, w as usize);
    assert_eq!(header.data_window().position.0, 3);
    assert_eq!(header.data_window().size.1, 5);
}

/// A scene file with an animated camera (keys at frames 0 and 4), and the same scene with a still
/// camera at the first key.
fn animated_scene(dir: &Path) -> (PathBuf, PathBuf) {
    // A floor and a box-ish wall.
    std::fs::write(
        dir.join("m.obj"),
        "v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nv -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0.5 1 -0.5\nv -0.5 1 -0.5\n\
         f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n",
    )
    .unwrap();
    let body = "[materials.w]\ntype = \"diffuse\"\nalbedo = [0.7, 0.7, 0.7]\n\
                [[meshes]]\nfile = \"m.obj\"\nmaterial = \"w\"\n\
                [[lights]]\ntype = \"point\"\nposition = [1, 3, 2]\nintensity = [8, 8, 8]\n";
    let animated = dir.join("walk.toml");
    std::fs::write(
        &animated,
        format!(
            "{body}[camera]\nfov = 50\n\
             [[camera.keys]]\nframe = 0\nposition = [0, 1, 4]\ntarget = [0, 0.5, 0]\n\
             [[camera.keys]]\nframe = 4\nposition = [3, 2, 2]\ntarget = [0, 0.5, 0]\n"
        ),
    )
    .unwrap();
    let still = dir.join("still.toml");
    std::fs::write(&still, format!("{body}[camera]\nfov = 50\nposition = [0, 1, 4]\ntarget = [0, 0.5, 0]\n")).unwrap();
    (animated, still)
}

#[test]
fn frames_of_an_animated_camera() {
    let dir = tempfile::tempdir().unwrap();
    let (animated, still) = animated_scene(dir.path());
    let out = |name: &str| dir.path().join(name);
    let frame = |scene: &Path, k: Option<&str>, file: &str| {
        let mut args = vec!["render", "--scene", s(scene), "--width", "32", "--height", "24", "--out"];
        let path = out(file);
        args.push(s(&path));
        if let Some(k) = k {
            args.extend(["--frame", k]);
        }
        ok(&beam(&args));
        std::fs::read(&path).unwrap()
    };
    let first = frame(&animated, Some("0"), "f0.png");
    let third = frame(&animated, Some("3"), "f3.png");
    assert!(first != third, "the camera moves");
    assert!(first == frame(&still, None, "still.png"), "frame 0 is the first key's still camera");
    assert!(first == frame(&animated, None, "default.png"), "without --frame, frame 0");
    let mut args = vec!["render", "--scene", s(&animated), "--width", "32", "--height", "24", "--out"];
    let path = out("f5.png");
    args.extend([s(&path), "--frame", "5"]);
    refused(&beam(&args), &["--frame 5", "frames 0 to 4"]);
    let path = out("s1.png");
    refused(&beam(&["render", "--scene", s(&still), "--frame", "1", "--out", s(&path)]), &["still camera"]);
}
