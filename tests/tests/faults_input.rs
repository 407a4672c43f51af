//! Fault cases of issue 18 for input files: scene files (TOML) and meshes (OBJ). Each case is one
//! defect: unbounded reads and hangs, silent wrong scenes, misleading messages, paths outside the
//! scene's folder, degenerate geometry. Cases that hung before run under a time limit.

use beam_scene::mesh;
use beam_scene::read::{self, QUOTE_CHARS};
use beam_scene::scene::{self, LoadOptions, Scene};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

/// A folder under the system's temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let p = std::env::temp_dir().join(format!("beam-faults-input-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        Self(p)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `f()`'s result, or a test failure when it takes more than 20 s (a hang).
fn within<T: Send + 'static>(what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || tx.send(f()));
    rx.recv_timeout(Duration::from_secs(20)).unwrap_or_else(|_| panic!("{what}: no answer in 20 s (hangs)"))
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// A scene file naming the mesh `file`, with `extra` TOML appended.
fn scene_text(file: &str, extra: &str) -> String {
    format!(
        "[materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\n[[meshes]]\nfile = \"{file}\"\nmaterial = \"w\"\n{extra}"
    )
}

fn load(path: &Path) -> Result<Scene, String> {
    let path = path.to_path_buf();
    within(&path.display().to_string(), move || scene::load_file(&path)).map_err(|e| e.to_string())
}

fn load_with(path: &Path, allow_outside_paths: bool) -> Result<Scene, String> {
    let path = path.to_path_buf();
    within(&path.display().to_string(), move || scene::load_file_with(&path, &LoadOptions { allow_outside_paths }))
        .map_err(|e| e.to_string())
}

fn err(r: Result<Scene, String>) -> String {
    match r {
        Ok(_) => panic!("loaded, expected an error"),
        Err(e) => e,
    }
}

fn has_mkfifo() -> bool {
    std::process::Command::new("mkfifo").arg("--version").output().is_ok_and(|o| o.status.success())
}

fn mkfifo(p: &Path) {
    assert!(std::process::Command::new("mkfifo").arg(p).status().unwrap().success());
}

// 1. Unbounded reads and hangs.

#[test]
#[cfg(unix)]
fn devices_and_fifos_are_refused_not_read() {
    let dir = TempDir::new("devices");
    std::os::unix::fs::symlink("/dev/zero", dir.0.join("zero.obj")).unwrap();
    std::os::unix::fs::symlink("/dev/urandom", dir.0.join("random.toml")).unwrap();
    for name in ["zero.obj", "random.toml"] {
        let e = err(load(&dir.0.join(name)));
        assert!(e.contains(name) && e.contains("not a regular file"), "{e}");
    }
    let e = within("/dev/zero", || mesh::load_obj(Path::new("/dev/zero"))).unwrap_err().to_string();
    assert!(e.contains("/dev/zero: not a regular file (a device)"), "{e}");
    // Named by a scene (allowed outside its folder): still refused.
    let s = dir.write("s.toml", &scene_text("/dev/zero", ""));
    let e = err(load_with(&s, true));
    assert!(e.contains("meshes[0]") && e.contains("not a regular file"), "{e}");
    if has_mkfifo() {
        mkfifo(&dir.0.join("fifo.obj"));
        let e = err(load(&dir.0.join("fifo.obj")));
        assert!(e.contains("not a regular file (a FIFO)"), "{e}");
        let s = dir.write("f.toml", &scene_text("fifo.obj", ""));
        assert!(err(load(&s)).contains("not a regular file (a FIFO)"));
    }
}

#[test]
#[cfg(unix)]
fn material_libraries_that_are_not_files_are_refused_unread() {
    let dir = TempDir::new("mtllib");
    std::os::unix::fs::symlink("/dev/zero", dir.0.join("zero.mtl")).unwrap();
    let zero = dir.write("z.obj", &format!("mtllib zero.mtl\nusemtl x\n{TRI}"));
    let e = err(load(&zero));
    assert!(e.contains("z.obj: mtllib on line 1") && e.contains("--allow-outside-paths"), "{e}");
    let absolute = dir.write("a.obj", &format!("mtllib /dev/zero\nusemtl x\n{TRI}"));
    assert!(err(load(&absolute)).contains("a.obj: mtllib on line 1"));
    if has_mkfifo() {
        mkfifo(&dir.0.join("fifo.mtl"));
        let fifo = dir.write("f.obj", &format!("mtllib fifo.mtl\nusemtl x\n{TRI}"));
        let e = err(load(&fifo));
        assert!(e.contains("f.obj: mtllib on line 1") && e.contains("not a regular file (a FIFO)"), "{e}");
    }
    // A library that is not there is a notice: the model loads grey.
    let missing = dir.write("m.obj", &format!("mtllib gone.mtl\nusemtl x\n{TRI}"));
    assert_eq!(load(&missing).unwrap().stats.triangles, 1);
}

#[test]
fn oversized_inputs_are_refused_with_the_limit() {
    let dir = TempDir::new("big");
    let big = dir.write("big.toml", &"# padding padding padding padding padding padding padding\n".repeat(80_000));
    let e = err(load(&big));
    assert!(e.contains("big.toml: larger than the 4 MiB limit"), "{e}");
    let small = dir.write("small.obj", TRI);
    let e = read::read_bounded(&small, 10).unwrap_err().to_string();
    assert!(e.contains("small.obj: larger than the 10 bytes limit"), "{e}");
}

// 2. Silent wrong images.

#[test]
fn non_finite_and_negative_colours_and_positions_are_refused() {
    let dir = TempDir::new("colours");
    dir.write("t.obj", TRI);
    let cases = [
        ("albedo = [nan, 0.5, 0.5]", "materials.w.albedo"),
        ("albedo = [-1, 0.5, 0.5]", "materials.w.albedo"),
        ("albedo = [1e39, 0.5, 0.5]", "materials.w.albedo"),
    ];
    for (k, (albedo, element)) in cases.iter().enumerate() {
        let text = scene_text("t.obj", "").replace("albedo = [0.5, 0.5, 0.5]", albedo);
        let e = err(load(&dir.write(&format!("a{k}.toml"), &text)));
        assert!(e.contains(&format!("a{k}.toml")) && e.contains(element) && e.contains("finite and ≥ 0"), "{e}");
    }
    let extra = [
        ("[materials.e]\ntype = \"emissive\"\nradiance = [1, inf, 1]\n", "materials.e.radiance"),
        ("[materials.e]\ntype = \"emissive\"\nradiance = [1, -2, 1]\n", "materials.e.radiance"),
        ("[materials.m]\ntype = \"mirror\"\ntint = [nan, 1, 1]\n", "materials.m.tint"),
        ("[materials.g]\ntype = \"glossy\"\nalbedo = [-0.1, 1, 1]\nvariance = 0.1\n", "materials.g.albedo"),
        ("[materials.t]\ntype = \"thin-glass\"\ntint = [1, 1, -1]\n", "materials.t.tint"),
        ("[[lights]]\ntype = \"point\"\nposition = [nan, 1, 0]\nintensity = [1, 1, 1]\n", "lights[0].position"),
        ("[[lights]]\ntype = \"point\"\nposition = [0, 1e39, 0]\nintensity = [1, 1, 1]\n", "lights[0].position"),
        ("[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [-1, 1, 1]\n", "lights[0].intensity"),
        (
            "[[lights]]\ntype = \"quad\"\ncorner = [0, 2, 0]\nedge_u = [1, 0, 0]\nedge_v = [0, 0, 1]\nradiance = [nan, 1, 1]\n",
            "lights[0].radiance",
        ),
        (
            "[[lights]]\ntype = \"triangle\"\nvertices = [[0, 2, 0], [1, 2, 0], [0, 2, 1]]\nradiance = [1, -1, 1]\n",
            "lights[0].radiance",
        ),
        ("[camera]\nposition = [0, 5, 0]\ntarget = [0, 0, 0]\n", "camera"),
    ];
    for (k, (toml, element)) in extra.iter().enumerate() {
        let e = err(load(&dir.write(&format!("b{k}.toml"), &scene_text("t.obj", toml))));
        assert!(e.contains(&format!("b{k}.toml")) && e.contains(element), "{toml}: {e}");
    }
}

/// Sum of the triangles' signed areas in the xy plane, and whether each is counter-clockwise.
fn xy_area(m: &mesh::Mesh) -> (f32, bool) {
    let areas: Vec<f32> = m.triangles().iter().map(|t| 0.5 * (t.v[1] - t.v[0]).cross(t.v[2] - t.v[0]).z).collect();
    (areas.iter().sum(), areas.iter().all(|&a| a > 0.0))
}

#[test]
fn non_convex_faces_are_triangulated_in_their_plane() {
    let dir = TempDir::new("nonconvex");
    // An L of area 3; a fan from its second corner covers area outside it.
    let l = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n";
    let obj = dir.write("l.obj", &format!("{l}f 2 3 4 5 6 1\n"));
    let m = mesh::load_obj(&obj).unwrap();
    let (area, ccw) = xy_area(&m);
    assert!((area - 3.0).abs() < 1e-5 && ccw, "area {area}, all counter-clockwise: {ccw}");
    // A tilted copy (the plane x = z), as an arrow with two reflex corners.
    let arrow = "v 0 0 0\nv 4 0 4\nv 2 2 2\nv 4 4 4\nv 0 4 0\nv 1 2 1\nf 1 2 3 4 5 6\n";
    let m = mesh::load_obj(&dir.write("arrow.obj", arrow)).unwrap();
    let area: f32 = m.triangles().iter().map(|t| t.area()).sum();
    assert!((area - 10.0 * 2f32.sqrt()).abs() < 1e-4, "area {area}");
    let bow = dir.write("bow.obj", "v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\n# bow tie\nf 1 2 3 4\n");
    let e = mesh::load_obj(&bow).unwrap_err().to_string();
    assert!(e.contains("bow.obj:6:") && e.contains("crosses itself"), "{e}");
}

#[test]
fn polylines_and_points_are_skipped_and_counted() {
    let dir = TempDir::new("lines");
    let obj = dir.write("l.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nl 1 2 3 4\np 1\nf 1 2 3\n");
    let s = load(&obj).unwrap();
    assert_eq!((s.stats.triangles, s.stats.skipped_elements), (1, 2));
    let only = dir.write("only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n");
    let e = err(load(&only));
    assert!(e.contains("only.obj: no triangles (1 line or point elements skipped)"), "{e}");
}

// 3. Misleading messages.

#[test]
fn comments_after_data_and_upper_case_extensions_are_accepted() {
    let dir = TempDir::new("comments");
    let obj = dir.write("CUBE.OBJ", "v 0 0 0 # origin\nv 1 0 0#x\nv 0 1 0\nf 1 2 3 # the face\n");
    assert_eq!(load(&obj).unwrap().stats.triangles, 1);
    let s = dir.write("S.TOML", &scene_text("CUBE.OBJ", ""));
    assert_eq!(load(&s).unwrap().stats.triangles, 1);
}

#[test]
fn deep_nesting_gets_a_short_error_with_the_line() {
    let dir = TempDir::new("deep");
    let deep = format!("[camera]\nposition = {}0{}\n", "[".repeat(100_000), "]".repeat(100_000));
    let e = err(load(&dir.write("deep.toml", &deep)));
    assert!(e.contains("deep.toml:2:") && e.contains("deeper than 64") && e.len() < 300, "{e}");
    let inline = format!("a = {}1{}\n", "{b = ".repeat(100_000), "}".repeat(100_000));
    let e = err(load(&dir.write("inline.toml", &inline)));
    assert!(e.contains("inline.toml:1:") && e.len() < 300, "{e}");
    let long = format!("[camera]\nposition = [0, 0, {}\n", "1, ".repeat(50_000));
    let e = err(load(&dir.write("long.toml", &long)));
    assert!(e.contains("long.toml:2:") && e.len() < 400, "{}", &e[..e.len().min(1000)]);
}

#[test]
fn every_obj_error_names_the_file_and_line() {
    let dir = TempDir::new("objerrors");
    let cases = [
        ("v 0 0 0\nv 1 0\n", 2, "three numbers"),
        ("v 0 0 0\nv 1 x 0\n", 2, "must be a number"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2\n", 5, "at least three"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", 4, "past the last vertex (3)"),
        ("v 0 0 0\nv 1 0 0\nf 1 2 -3\nv 0 1 0\n", 3, "not a vertex index"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 2\n", 4, "not a vertex index"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2//3 99999999999999999999\n", 4, "corner 3 is not a vertex index"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/x/3 3\n", 4, "corner 2 is not v, v/vt, v//vn or v/vt/vn"),
        ("v 0 0 \\\n 0\nv 1 0 0\nv 0 1\n", 4, "three numbers"),
    ];
    for (k, (text, line, what)) in cases.iter().enumerate() {
        let e = mesh::load_obj(&dir.write(&format!("e{k}.obj"), text)).unwrap_err().to_string();
        assert!(e.contains(&format!("e{k}.obj:{line}: ")) && e.contains(what), "{text:?}: {e}");
    }
    let long = format!("v 0 0 0\nv 1 0 {}\n", "9".repeat(10_000) + "x");
    let e = mesh::load_obj(&dir.write("long.obj", &long)).unwrap_err().to_string();
    assert!(e.contains("long.obj:2:") && e.chars().count() < 2 * QUOTE_CHARS + 120, "{e}");
}

// 4. Paths a scene file names.

#[test]
fn mesh_paths_stay_inside_the_scene_folder() {
    let root = TempDir::new("paths");
    let scene_dir = root.0.join("scene");
    std::fs::create_dir_all(scene_dir.join("meshes")).unwrap();
    std::fs::write(scene_dir.join("meshes/t.obj"), TRI).unwrap();
    let secret = root.write("secret.obj", "v 0 0 0\nv 1 0 TOP-SECRET\n");
    root.write("out.obj", TRI);
    let write = |name: &str, mesh: &str| {
        let p = scene_dir.join(name);
        std::fs::write(&p, scene_text(mesh, "")).unwrap();
        p
    };
    assert_eq!(load(&write("in.toml", "meshes/../meshes/t.obj")).unwrap().stats.triangles, 1);
    let outside = [
        ("up.toml", "../out.obj".to_string()),
        ("abs.toml", root.0.join("out.obj").display().to_string()),
        ("missing.toml", "../nothing/here.obj".to_string()),
    ];
    for (name, mesh) in &outside {
        let e = err(load(&write(name, mesh)));
        assert!(e.contains(name) && e.contains("meshes[0]") && e.contains("--allow-outside-paths"), "{e}");
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(root.0.join("out.obj"), scene_dir.join("link.obj")).unwrap();
        let e = err(load(&write("link.toml", "link.obj")));
        assert!(e.contains("resolves outside"), "{e}");
        assert_eq!(load_with(&scene_dir.join("link.toml"), true).unwrap().stats.triangles, 1);
    }
    assert_eq!(load_with(&scene_dir.join("up.toml"), true).unwrap().stats.triangles, 1);
    // Allowed outside, a malformed file's lines are still not quoted.
    let e = err(load_with(&write("secret.toml", &secret.display().to_string()), true));
    assert!(e.contains("secret.obj:2:") && !e.contains("TOP-SECRET"), "{e}");
    // Inside, they are, clipped.
    std::fs::write(scene_dir.join("meshes/bad.obj"), format!("v 1 0 x{}\n", " 7".repeat(500))).unwrap();
    let e = err(load(&write("bad.toml", "meshes/bad.obj")));
    assert!(e.contains("bad.obj:1:") && e.contains("`v 1 0 x 7 7") && e.contains('…'), "{e}");
    assert!(e.chars().count() < 400, "{e}");
}

// 5. Degenerate geometry.

#[test]
fn degenerate_and_non_finite_triangles_are_filtered_and_counted() {
    let dir = TempDir::new("degenerate");
    let obj = dir.write(
        "d.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nv inf 1 1\nv 1e39 2 2\nv 2 0 0\n\
         f 1 2 3\nf 1 2 4\nf 1 5 6\nf 1 2 7\nf 4 5 6 1\nf 1 1 1\n",
    );
    let s = load(&obj).unwrap();
    assert_eq!(s.stats.triangles, 1);
    assert_eq!(s.stats.degenerate, 6, "{:?}", s.stats);
    let none = dir.write("none.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv nan 1 1\nf 1 2 3\nf 1 2 4\n");
    let e = err(load(&none));
    assert!(e.contains("none.obj: no valid triangle"), "{e}");
    // A transform that overflows every vertex to infinity.
    dir.write("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\nf 4 4 4\n");
    let s = dir.write("s.toml", &scene_text("t.obj", "scale = 1e38\ntranslate = [1e38, 0, 0]\n"));
    let e = err(load(&s));
    assert!(e.contains("s.toml: no valid triangle"), "{e}");
}

// 6. Cameras and beam trees no renderer can handle (issue 67).

/// A camera at z = 3·10³⁸ (its image plane at distance 1 is lost in rounding) panicked in the eye
/// beams: now the scene file is refused naming the camera and why, and a library render of such
/// a camera (set after loading) returns an image.
#[test]
fn a_camera_too_far_for_its_image_plane_is_refused_not_a_panic() {
    let dir = TempDir::new("far-camera");
    dir.write("t.obj", TRI);
    let far = "[camera]\nposition = [0, 0, 3e38]\ntarget = [0, 0, 0]\nwidth = 8\nheight = 8\n";
    let e = err(load(&dir.write("far.toml", &scene_text("t.obj", far))));
    assert!(e.contains("far.toml") && e.contains("camera") && e.contains("too far from the origin"), "{e}");
    // A key of an animated camera too.
    let keys = "[camera]\nwidth = 8\nheight = 8\n[[camera.keys]]\nframe = 0\nposition = [0, 0, 3]\ntarget = [0, 0, 0]\n\
                [[camera.keys]]\nframe = 4\nposition = [0, 0, 3e38]\ntarget = [0, 0, 0]\n";
    let e = err(load(&dir.write("keys.toml", &scene_text("t.obj", keys))));
    assert!(e.contains("keys.toml") && e.contains("camera.keys[1]") && e.contains("too far"), "{e}");
    // Position and target whose difference overflows.
    let huge = "[camera]\nposition = [0, 0, 3e38]\ntarget = [0, 0, -3e38]\n";
    let e = err(load(&dir.write("huge.toml", &scene_text("t.obj", huge))));
    assert!(e.contains("huge.toml") && e.contains("camera") && e.contains("overflows"), "{e}");

    let near = dir.write("near.toml", &scene_text("t.obj", ""));
    for primary_beams in [true, false] {
        let mut scene = load(&near).unwrap();
        assert!(scene.camera.has_view());
        scene.camera.position.z = 3e38;
        let why = scene.camera.check_view().unwrap_err();
        assert!(why.contains("too far from the origin"), "{why}");
        let options =
            beam_render::options::RenderOptions { primary_beams, ..beam_render::options::RenderOptions::exact(8, 8) };
        let (image, _) = within("render", move || beam_cpu::render::render(&scene, &options, || {}));
        assert_eq!(image.pixels.len(), 64);
    }
    // The nonlinear renderer too.
    let mut scene = scene::builtin("mirror-glass").unwrap();
    scene.camera.position.z = 3e38;
    let shading = beam_render::options::RenderOptions::exact(8, 8);
    let options = beam_render::nonlinear::NonlinearOptions {
        degree: beam_render::nonlinear::Degree::S1,
        texels: 8,
        bounces: 1,
        caustic_strata: 0,
        shading,
    };
    within("nonlinear", move || beam_cpu::nonlinear::render_nonlinear(&scene, &options).map(drop)).unwrap();
}

/// `--bounces 16` on the bumpy mirror built a beam tree growing about tenfold a level, for hours:
/// now it is refused, naming the bounces, the estimate and the limit, after its first levels.
#[test]
fn a_beam_tree_too_large_to_build_is_refused_promptly() {
    use beam_cpu::nonlinear::render_nonlinear;
    use beam_render::nonlinear::Degree;
    use beam_render::nonlinear::{MAX_TREE_BEAMS, NonlinearOptions};
    let scene = scene::builtin("bumpy-mirror").unwrap();
    let shading = beam_render::options::RenderOptions::exact(16, 16);
    let options = NonlinearOptions { degree: Degree::S3, texels: 32, bounces: 16, caustic_strata: 0, shading };
    let start = std::time::Instant::now();
    let r = within("bounces 16", move || render_nonlinear(&scene, &options).map(|_| ()));
    let e = match r {
        Err(e @ beam_render::nonlinear::NonlinearError::BeamTree { .. }) => e.to_string(),
        other => panic!("expected a refused beam tree, got {other:?}"),
    };
    assert!(start.elapsed() < Duration::from_secs(15), "refused only after {:?}", start.elapsed());
    assert!(e.contains("--bounces 16") && e.contains(&format!("limit of {MAX_TREE_BEAMS} beams")), "{e}");
    assert!(e.contains("bounces fit"), "{e}");
    // Four levels (3,665 beams) fit and render.
    let (scene, options) = (scene::builtin("bumpy-mirror").unwrap(), NonlinearOptions { bounces: 4, ..options });
    let (_, stats) = within("bounces 4", move || render_nonlinear(&scene, &options)).unwrap();
    assert_eq!(stats.beams_per_level.len(), 4, "{:?}", stats.beams_per_level);
}
