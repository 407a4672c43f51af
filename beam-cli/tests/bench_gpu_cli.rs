//! `beam bench softshadow --backend gpu` and `beam bench primary --backend gpu` at tiny sizes: they
//! run and print their GPU tables (skipped, saying SKIPPED, where there is no adapter; a failure
//! instead under `BEAM_REQUIRE_GPU=1`, as in CI), and a `--backend` other than cpu or gpu is refused.

use std::process::{Command, Output};

fn beam(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_beam")).args(args).env_remove("BEAM_MAX_MEMORY").output().expect("run beam")
}

fn text(o: &Output) -> (String, String) {
    (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// Whether there is an adapter; `false` after printing SKIPPED past the test harness's capture (a
/// failure instead under `BEAM_REQUIRE_GPU=1`).
fn adapter() -> bool {
    match beam_gpu::Gpu::new() {
        Ok(_) => true,
        Err(e) => {
            assert!(std::env::var("BEAM_REQUIRE_GPU").as_deref() != Ok("1"), "BEAM_REQUIRE_GPU=1 but {e}");
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "SKIPPED: {e}");
            false
        }
    }
}

#[test]
fn other_backends_are_refused() {
    for args in [
        &["bench", "softshadow", "--backend", "tpu"][..],
        &["bench", "softshadow", "--suite", "--backend", "cuda"],
        &["bench", "primary", "--backend", "vulkan"],
    ] {
        let o = beam(args);
        let (_, e) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(e.contains("--backend") && e.contains("expected cpu or gpu") && !e.contains("panicked"), "{e}");
    }
    let o = beam(&["bench", "primary", "--sweep", "--backend", "gpu"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("--sweep"), "{}", text(&o).1);
}

#[test]
fn softshadow_runs_on_the_gpu() {
    if !adapter() {
        return;
    }
    let o = beam(&["bench", "softshadow", "--backend", "gpu", "--size", "8", "--reference-spp", "4"]);
    let (out, e) = text(&o);
    assert!(o.status.success(), "{:?}: {e}", o.status);
    // A row for each walk of the GPU's shadow beams, in both tables.
    for walk in ["alone", "together"] {
        assert!(out.contains(&format!("gpu {walk}")), "{out}");
        let name = format!("cornell-{walk} ");
        let row = out.lines().find(|l| l.starts_with(&name)).unwrap_or_else(|| panic!("no GPU row: {out}"));
        // GPU ms, rays ms, host ms, beams, …: a number or n/a each; the PSNR against the CPU's last but one.
        let fields: Vec<&str> = row.split_whitespace().collect();
        assert_eq!(fields.len(), 13, "{row}");
        assert!(fields[4].parse::<u64>().is_ok_and(|b| b > 0), "no shadow beams: {row}");
        assert!(fields[11] == "equal" || fields[11].parse::<f64>().is_ok_and(|p| p > 40.0), "GPU ≠ CPU: {row}");
    }
}

#[test]
fn softshadow_suite_runs_on_the_gpu() {
    if !adapter() {
        return;
    }
    let args = ["bench", "softshadow", "--cases", "spheres", "--size", "8", "--runs", "1", "--reference-spp", "4"];
    let o = beam(&[&args[..], &["--backend", "gpu"]].concat());
    let (out, e) = text(&o);
    assert!(o.status.success(), "{:?}: {e}", o.status);
    assert!(out.contains("  gpu: spheres "), "{out}");
}

#[test]
fn primary_runs_on_the_gpu() {
    if !adapter() {
        return;
    }
    let o = beam(&["bench", "primary", "--backend", "gpu", "--scenes", "cornell", "--size", "8"]);
    let (out, e) = text(&o);
    assert!(o.status.success(), "{:?}: {e}", o.status);
    for spp in [1, 4, 16] {
        let row = format!("gpu rays {spp} spp");
        let line = out.lines().rfind(|l| l.starts_with(&row)).unwrap_or_else(|| panic!("no `{row}`: {out}"));
        // The PSNR against the CPU rays' image of the same rays, last.
        let psnr = line.split_whitespace().last().unwrap_or_default();
        assert!(psnr == "equal" || psnr.parse::<f64>().is_ok_and(|p| p > 40.0), "GPU ≠ CPU: {line}");
    }
}
