//! The CLI and output half of issue 18's fault suite: each case ran to a silent wrong image, a
//! clobbered file or a misleading message before, and is a clear error (or a right result) now.
//! Renders are 8 × 8 on the small built-ins, so the suite runs in seconds.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary under test: this build's, or `$BEAM_TEST_BIN` (to show a case failing on an older one).
fn bin() -> String {
    std::env::var("BEAM_TEST_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_beam").into())
}

fn beam(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(bin());
    cmd.args(args).env_remove("BEAM_MAX_MEMORY");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("run beam")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit status 2 and a message containing every one of `words`.
#[track_caller]
fn refused(o: &Output, words: &[&str]) -> String {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "expected a clear error, got {:?}: {e}", o.status);
    assert!(!e.contains("panicked"), "{e}");
    for w in words {
        assert!(e.contains(w), "`{w}` missing from: {e}");
    }
    e
}

#[track_caller]
fn ok(o: &Output) {
    assert!(o.status.success(), "{:?}: {}", o.status, stderr(o));
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// No `.NAME.beam-tmp-*` file left in `dir`.
#[track_caller]
fn no_temporaries(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name();
        assert!(!name.to_string_lossy().contains(".beam-tmp-"), "left behind: {name:?}");
    }
}

/// A small valid render: `beam render --width 8 --out OUT` plus `extra`.
fn render(out: &Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let mut args = vec!["render", "--width", "8", "--height", "8", "--out", s(out)];
    args.extend_from_slice(extra);
    beam(&args, env)
}

#[test]
fn sample_counts_are_exact_or_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    // Wrapped to zero samples (a black image) before.
    refused(
        &render(&out, &["--primary-rays", "--primary-spp", "4294967295"], &[]),
        &["--primary-spp", "perfect square"],
    );
    // Rounded down to 4 without a word before.
    refused(&render(&out, &["--primary-rays", "--primary-spp", "5"], &[]), &["--primary-spp 5", "perfect square"]);
    refused(&render(&out, &["--method", "ray", "--spp", "0"], &[]), &["--spp 0"]);
    assert!(!out.exists());
    ok(&render(&out, &["--primary-rays", "--primary-spp", "4"], &[]));
    assert!(out.exists());
}

#[test]
fn image_sizes_are_checked_without_wrapping() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scene = dir.path().join("tall.toml");
    std::fs::write(
        &scene,
        "[camera]\nposition = [0, 0, 3]\ntarget = [0, 0, 0]\nwidth = 1\nheight = 2147483649\n\
         [materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
         [[meshes]]\nfile = \"t.obj\"\nmaterial = \"w\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 0, 2]\nintensity = [1, 1, 1]\n",
    )
    .unwrap();
    let out = dir.path().join("o.png");
    // A 2 × 2 image before (2 · (2³¹ + 1) wrapped).
    let o = beam(&["render", "--scene", s(&scene), "--width", "2", "--out", s(&out)], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!out.exists());
    refused(&beam(&["render", "--width", "0", "--out", s(&out)], &[]), &["out of range"]);
    refused(&beam(&["render", "--width", "16385", "--height", "1", "--out", s(&out)], &[]), &["out of range"]);
    refused(&beam(&["bench", "softshadow", "--size", "0"], &[]), &["--size 0"]);
}

#[test]
fn only_png_is_written_under_a_png_name() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["x.jpg", "x.png.tmp", "x", "x.exr"] {
        let out = dir.path().join(name);
        refused(&render(&out, &[], &[]), &["--out", name, "PNG"]);
        assert!(!out.exists());
    }
    let upper = dir.path().join("X.PNG");
    ok(&render(&upper, &[], &[]));
    assert_eq!(&std::fs::read(&upper).unwrap()[1..4], b"PNG");
}

#[test]
fn stats_are_written_by_every_method() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    for (method, scene) in [("nonlinear-reference", "mirror-glass"), ("glossy-reference", "cardioid-ring")] {
        let stats = dir.path().join(format!("{method}.json"));
        let extra = ["--scene", scene, "--method", method, "--photons", "2000", "--stats", s(&stats)];
        ok(&render(&out, &extra, &[]));
        let json = std::fs::read_to_string(&stats).unwrap();
        assert!(json.contains(method) && json.contains("\"width\": 8"), "{json}");
    }
}

#[test]
fn options_that_do_not_apply_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    refused(&render(&out, &["--texels", "8"], &[]), &["--texels", "--method beam", "nonlinear"]);
    refused(&render(&out, &["--method", "glossy", "--spp", "4"], &[]), &["--spp", "--method glossy"]);
    refused(&render(&out, &["--method", "ray", "--primary-rays"], &[]), &["--primary-rays", "--method ray"]);
    refused(&render(&out, &["--primary-spp", "4"], &[]), &["--primary-spp"]);
    refused(&render(&out, &["--photons", "10"], &[]), &["--photons", "--method beam"]);
    refused(&render(&out, &["--method", "glossy-reference", "--backend", "gpu"], &[]), &["--backend gpu"]);
    // Defaults are not "given": a plain render of every kind still runs.
    ok(&render(&out, &["--method", "ray", "--spp", "4", "--primary-spp", "1", "--shading", "exact"], &[]));
}

#[test]
fn texels_below_the_smallest_region_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    for t in ["2", "3", "0", "4097"] {
        let extra = ["--scene", "facing-mirrors", "--method", "nonlinear", "--texels", t];
        refused(&render(&out, &extra, &[]), &["--texels", "4 to 4096"]);
    }
}

#[test]
fn messages_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    let e = refused(&render(&out, &["--method", "nonlinear", "--backend", "cuda"], &[]), &["unknown backend `cuda`"]);
    assert!(!e.contains("nonlinear only"), "{e}");
    let bogus = [("WGPU_BACKEND", "bogus")];
    let e = refused(
        &render(&out, &["--scene", "facing-mirrors", "--method", "nonlinear", "--backend", "gpu"], &bogus),
        &["WGPU_BACKEND", "bogus"],
    );
    assert!(!e.contains("mesa-vulkan-drivers"), "{e}");
    refused(
        &beam(&["conformance", "--only", "NOPE"], &[]),
        &["NOPE", "no such property", "bvh_hits_equal_brute_force"],
    );
}

#[test]
fn out_and_stats_must_differ() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    std::fs::write(&out, b"precious").unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    let dotted = sub.join("..").join("o.png");
    for stats in [out.clone(), dir.path().join(".").join("o.png"), dotted] {
        refused(&render(&out, &["--stats", s(&stats)], &[]), &["same file"]);
    }
    #[cfg(unix)]
    {
        let link_dir = dir.path().join("link");
        std::os::unix::fs::symlink(dir.path(), &link_dir).unwrap();
        refused(&render(&out, &["--stats", s(&link_dir.join("o.png"))], &[]), &["same file"]);
        let hard = dir.path().join("hard.png");
        std::fs::hard_link(&out, &hard).unwrap();
        refused(&render(&out, &["--stats", s(&hard)], &[]), &["same file"]);
    }
    assert_eq!(std::fs::read(&out).unwrap(), b"precious");
}

#[cfg(unix)]
#[test]
fn only_regular_files_are_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("target.png");
    std::fs::write(&target, b"precious").unwrap();
    let link = dir.path().join("link.png");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    refused(&render(&link, &[], &[]), &["link.png", "symbolic link"]);
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert_eq!(std::fs::read(&target).unwrap(), b"precious");
    let fifo = dir.path().join("fifo.png");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    refused(&render(&fifo, &[], &[]), &["fifo.png", "FIFO"]);
    refused(&render(&dir.path().join("d.png"), &["--stats", "/dev/null"], &[]), &["/dev/null", "device node"]);
    std::fs::create_dir(dir.path().join("dir.png")).unwrap();
    refused(&render(&dir.path().join("dir.png"), &[], &[]), &["dir.png", "directory"]);
    no_temporaries(dir.path());
}

#[cfg(unix)]
#[test]
fn modes_follow_the_umask_and_the_old_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let out = dir.path().join("o.png");
    let stats = dir.path().join("o.json");
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "umask 077 && exec \"$0\" render --width 8 --height 8 --out '{}' --stats '{}'",
            s(&out),
            s(&stats)
        ))
        .arg(bin())
        .output()
        .unwrap();
    ok(&o);
    assert_eq!((mode(&out), mode(&stats)), (0o600, 0o600), "always 0644 before");
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o640)).unwrap();
    ok(&render(&out, &[], &[]));
    assert_eq!(mode(&out), 0o640, "an existing file keeps its mode");
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o444)).unwrap();
    let before = std::fs::read(&out).unwrap();
    refused(&render(&out, &[], &[]), &["o.png", "read-only"]);
    assert_eq!(std::fs::read(&out).unwrap(), before);
    no_temporaries(dir.path());
}

/// Outputs are checked before the render: a render that would take hours fails at once, and a
/// `--stats` that cannot be written leaves the old image in place.
#[cfg(unix)]
#[test]
fn outputs_are_checked_before_rendering() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    std::fs::write(&out, b"old image").unwrap();
    let slow = ["render", "--method", "ray", "--spp", "65536", "--primary-spp", "1024", "--width", "4096"];
    let start = std::time::Instant::now();
    let mut args = slow.to_vec();
    args.extend(["--out", "/no/such/folder/o.png"]);
    refused(&beam(&args, &[]), &["--out /no/such/folder/o.png"]);
    let mut args = slow.to_vec();
    args.extend(["--out", s(&out), "--stats", "/no/such/folder/s.json"]);
    refused(&beam(&args, &[]), &["--stats /no/such/folder/s.json"]);
    // A folder that takes no new files, even for root.
    let mut args = slow.to_vec();
    args.extend(["--out", "/proc/beam-fault-test.png"]);
    let e = refused(&beam(&args, &[]), &["--out /proc/beam-fault-test.png", "cannot create"]);
    assert!(!e.contains(".beam-tmp-"), "the temporary's name, not the user's: {e}");
    let ro = dir.path().join("ro");
    std::fs::create_dir(&ro).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    // Root writes to a 0555 folder anyway: then only /proc above shows the check.
    if std::fs::write(ro.join("probe"), b"").is_err() {
        let mut args = slow.to_vec();
        let in_ro = ro.join("o.png");
        args.extend(["--out", s(&in_ro)]);
        refused(&beam(&args, &[]), &["ro/o.png"]);
    }
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    assert!(start.elapsed().as_secs() < 60, "refused only after rendering");
    assert_eq!(std::fs::read(&out).unwrap(), b"old image");
    no_temporaries(dir.path());
    no_temporaries(&ro);
}

fn write_png(path: &PathBuf, w: u32, h: u32, seed: u8) {
    let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i as u8).wrapping_mul(seed)).collect();
    image::save_buffer(path, &rgb, w, h, image::ExtendedColorType::Rgb8).unwrap();
}

#[test]
fn memory_is_estimated_and_limited() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    let e = refused(
        &beam(&["render", "--width", "16384", "--height", "16384", "--out", s(&out)], &[("BEAM_MAX_MEMORY", "8G")]),
        &["16384×16384", "GiB", "8.0 GiB", "BEAM_MAX_MEMORY"],
    );
    assert!(e.contains("memory"), "{e}");
    refused(&render(&out, &[], &[("BEAM_MAX_MEMORY", "lots")]), &["BEAM_MAX_MEMORY"]);
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    write_png(&a, 300, 200, 3);
    write_png(&b, 300, 200, 5);
    let diff = dir.path().join("d.png");
    refused(&beam(&["compare", s(&a), s(&b), "--out", s(&diff)], &[("BEAM_MAX_MEMORY", "1M")]), &["memory", "300×200"]);
    assert!(!diff.exists());
    let o = beam(&["compare", s(&a), s(&b), "--out", s(&diff)], &[]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("RMSE"));
    assert_eq!(image::image_dimensions(&diff).unwrap(), (900, 200));
    // The output may not replace an input, and inputs must be regular files.
    refused(&beam(&["compare", s(&a), s(&b), "--out", s(&a)], &[]), &["would replace the input"]);
    refused(&beam(&["compare", "/dev/zero", s(&b), "--out", s(&diff)], &[]), &["/dev/zero", "not a regular file"]);
    let c = dir.path().join("c.png");
    write_png(&c, 30, 20, 5);
    refused(&beam(&["compare", s(&a), s(&c), "--out", s(&diff)], &[]), &["sizes differ"]);
}
