//! A seeded mutation fuzzer over `beam`'s argument vectors (issue 18): valid command lines with
//! arguments dropped, duplicated, swapped, inserted or replaced by hostile values (0, -1, huge
//! integers, NaN, empty, odd Unicode, /dev/zero, a FIFO, a symbolic link, a folder), run through
//! the parser and the checks of each command (`run(.., dry = true)`: nothing is rendered or
//! written), with a real 8 × 8 render for a small share of the accepted ones. Each case must end in
//! an acceptance or a clear error, never a panic, within a time bound.
//!
//! `cargo test -p beam-cli --release fuzz -- --nocapture` prints the counts;
//! `BEAM_FUZZ_CASES` and `BEAM_FUZZ_SEED` change the run.

use crate::{parse_from, run};
use beam_math::glam::Vec3;
use beam_scene::io::{encode_exr, encode_png_placed};
use beam_scene::region::{PixelRect, Placement};
use clap::error::ErrorKind;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// No case may take longer (a hang, or a render that escaped the size checks). A valid case takes
/// up to 18 s alone on the 2-core CI machine (`render --scene mirror-glass --smesh-target 40
/// --method nonlinear` at 8×8: its 26,496 caustic beams do not shrink with the image), and more
/// beside the other tests; 20 s failed CI once.
const CASE_LIMIT: Duration = Duration::from_secs(60);

/// Valid command lines; `{d}` is the fuzzer's scratch folder.
const BASES: &[&str] = &[
    "render --width 8 --height 8 --out {d}/o.png",
    "render --scene cornell-point --method ray --spp 4 --primary-spp 4 --width 8 --height 8 --out {d}/o.png",
    "render --scene cornell --primary-rays --shading fraction --width 8 --height 8 --out {d}/o.png --stats {d}/s.json",
    "render --scene mirror-glass --method nonlinear --texels 8 --bounces 1 --degree s1 --width 8 --height 8 --out {d}/o.png",
    "render --scene facing-mirrors --smesh 4 --method nonlinear --width 8 --height 8 --out {d}/o.png --stats {d}/s.json",
    "render --scene mirror-glass --smesh-target 40 --method nonlinear --texels 8 --width 8 --height 8 --out {d}/o.png",
    "render --scene cardioid-ring --method glossy --subdivide 1 --volume tessellated --width 8 --height 8 --out {d}/o.png",
    "render --scene cardioid-ring --method glossy-reference --photons 1000 --width 8 --height 8 --out {d}/o.png",
    "render --scene mirror-glass --method nonlinear-reference --photons 1000 --width 8 --height 8 --out {d}/o.png",
    "render --scene mirror-glass --method nonlinear --backend gpu --spp 4 --width 8 --out {d}/o.png",
    "render --width 8 --height 8 --tile 1/4 --exposure -1.5 --out {d}/o.exr",
    "render --scene mirror-glass --method nonlinear --texels 8 --width 8 --height 8 --crop 1,2,7,8 --out {d}/o.png",
    "render --scene cardioid-ring --method glossy --subdivide 1 --width 8 --height 8 --tile 0/2 --out {d}/o.png",
    "render --scene {d}/walk.toml --frame 1 --width 8 --height 8 --exposure 2 --out {d}/o.png",
    "merge {d}/t0.png {d}/t1.png --out {d}/m.png",
    "merge {d}/t0.exr {d}/t1.exr --out {d}/m.exr",
    "compare {d}/a.png {d}/b.png --out {d}/d.png --scale 0.5",
    "conformance --only bvh_hits_equal_brute_force --backend bvh --rays 10",
    "bench softshadow --size 8 --reference-spp 4 --light-size 0.1 --out-dir {d}",
    "bench softshadow --suite --cases spheres,plant --sweep light --runs 3 --size 8 --reference-spp 4 --out {d}",
    "bench primary --scenes cornell --size 8 --sweep-size 8 --cameras 2",
    "bench bvh --scene {d}/m.obj --size 8",
    "overdraw --points 4 --out {d}/p.png --csv {d}/p.csv",
];

/// Values put in place of others.
const VALUES: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "3",
    "5",
    "4097",
    "16385",
    "2147483649",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "99999999999999999999999",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e40",
    "0.0",
    "-0",
    "",
    " ",
    "é",
    "\u{202e}gnp.exe",
    "💥",
    "x\u{0}y",
    "🙂.png",
    "O.PNG",
    "x.jpg",
    "/dev/zero",
    "/dev/null",
    "/dev/urandom",
    "/",
    "..",
    "{d}",
    "{d}/fifo",
    "{d}/fifo.png",
    "{d}/fifo.toml",
    "{d}/link.png",
    "{d}/dir.png",
    "{d}/o.png",
    "{d}/a.png",
    "{d}/new.png",
    "{d}/no/such/x.png",
    "cornell",
    "mirror-glass",
    "cardioid-ring",
    "facing-mirrors",
    "nope",
    "s1",
    "s9",
    "gpu",
    "cpu",
    "cuda",
    "beam",
    "ray",
    "nonlinear",
    "glossy",
    "glossy-reference",
    "exact",
    "fraction",
    "tessellated",
    "0/1",
    "1/4",
    "4/4",
    "0/0",
    "1/0",
    "3/2",
    "/",
    "1/4294967295",
    "0,0,8,8",
    "1,2,7,8",
    "0,0,9,8",
    "8,8,8,8",
    "4294967295,0,4294967295,1",
    "1,2,3",
    "-64",
    "65",
    "1.5",
    "o.exr",
    "O.EXR",
    "{d}/o.exr",
    "{d}/t0.png",
    "{d}/t1.png",
    "{d}/t0.exr",
    "{d}/m.png",
    "{d}/walk.toml",
];

/// Options put in, with or without a value.
const OPTIONS: &[&str] = &[
    "--scene",
    "--method",
    "--backend",
    "--degree",
    "--texels",
    "--bounces",
    "--smesh",
    "--smesh-target",
    "--smesh-error",
    "--shading",
    "--spp",
    "--primary-spp",
    "--primary-rays",
    "--volume",
    "--linear-gather",
    "--subdivide",
    "--no-second-order",
    "--photon-kernel",
    "--photons",
    "--width",
    "--height",
    "--out",
    "--stats",
    "--exposure",
    "--tile",
    "--crop",
    "--frame",
    "--size",
    "--scale",
    "--only",
    "--rays",
    "--help",
    "--version",
    "--",
    "-x",
];

fn pick<'a>(rng: &mut Pcg64, xs: &[&'a str]) -> &'a str {
    xs[rng.random_range(0..xs.len())]
}

/// One mutated argument vector.
fn mutate(rng: &mut Pcg64, d: &str) -> Vec<String> {
    let mut args: Vec<String> = pick(rng, BASES).split(' ').map(String::from).collect();
    for _ in 0..rng.random_range(0..4) {
        let n = args.len();
        let i = rng.random_range(0..n.max(1));
        match rng.random_range(0..6) {
            0 if n > 1 => drop(args.remove(i)),
            1 => args.insert(i, args[i.min(n - 1)].clone()),
            2 => args.swap(i, rng.random_range(0..n)),
            3 => args.insert(i.max(1), pick(rng, OPTIONS).into()),
            4 => args.insert(i.max(1), pick(rng, VALUES).into()),
            _ => {
                // Replace a value (not the subcommand, not an option name) most of the time.
                let j = (i.max(1)..n).find(|&j| !args[j].starts_with("--")).unwrap_or(i);
                if j > 0 {
                    args[j] = pick(rng, VALUES).into();
                }
            }
        }
    }
    let mut argv = vec!["beam".to_string()];
    argv.extend(args.into_iter().map(|a| a.replace("{d}", d)));
    argv
}

/// What a case came to.
enum Verdict {
    Accepted { rendered: bool },
    Error(String),
    Panic(String),
}

fn case(argv: &[String], render: bool) -> Verdict {
    let outcome = std::panic::catch_unwind(|| {
        let (cli, given) = match parse_from(argv) {
            Ok(p) => p,
            // `--help` and `--version` end the parse with their text: accepted.
            Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => return Ok(false),
            Err(e) => return Err(e.to_string()),
        };
        // A real render only of small renders (the args name 8 × 8, CPU, no reference).
        let small = argv.windows(2).any(|w| w == ["--width", "8"])
            && argv.windows(2).any(|w| w == ["--height", "8"])
            && argv.get(1).is_some_and(|c| c == "render")
            && !argv.iter().any(|a| a == "gpu" || a.ends_with("reference") || a == "--photons")
            // Only into the case's folder: a relative `--stats NaN` would land in the crate.
            && argv.windows(2).all(|w| {
                !matches!(w[0].as_str(), "--out" | "--stats")
                    || w[1].starts_with(&*std::env::temp_dir().to_string_lossy())
            })
            && argv.iter().any(|a| a == "--out");
        match run(cli, &given, true) {
            Ok(_) if render && small => {
                let (cli, given) = parse_from(argv).map_err(|e| e.to_string())?;
                run(cli, &given, false).map(|_| true)
            }
            Ok(_) => Ok(false),
            Err(e) => Err(e),
        }
    });
    match outcome {
        Ok(Ok(rendered)) => Verdict::Accepted { rendered },
        Ok(Err(e)) => Verdict::Error(e),
        Err(p) => Verdict::Panic(
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default(),
        ),
    }
}

/// The scratch folder: two PNGs, an OBJ, a FIFO, a symbolic link, a folder named like a PNG.
fn scratch(dir: &Path) {
    let png = |name: &str, w: u32| {
        let rgb = vec![128u8; (w * w * 3) as usize];
        image::save_buffer(dir.join(name), &rgb, w, w, image::ExtendedColorType::Rgb8).unwrap();
    };
    png("a.png", 8);
    png("b.png", 8);
    // The two halves of an 8 × 8 frame, as `beam render --tile i/2` writes them.
    for (i, rect) in (0..2).filter_map(|i| Some((i, PixelRect::band(i, 2, 8, 8)?))) {
        let at = Placement::new(rect, 8, 8).unwrap();
        std::fs::write(dir.join(format!("t{i}.png")), encode_png_placed(&vec![99; rect.len() * 3], at).unwrap())
            .unwrap();
        std::fs::write(dir.join(format!("t{i}.exr")), encode_exr(&vec![Vec3::ONE; rect.len()], at).unwrap()).unwrap();
    }
    std::fs::write(
        dir.join("walk.toml"),
        "[camera]\n[[camera.keys]]\nframe = 0\nposition = [0, 0, 3]\ntarget = [0, 0, 0]\n\
         [[camera.keys]]\nframe = 2\nposition = [1, 0, 3]\ntarget = [0, 0, 0]\n\
         [materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n[[meshes]]\nfile = \"m.obj\"\nmaterial = \"w\"\n",
    )
    .unwrap();
    std::fs::write(dir.join("m.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::create_dir(dir.join("dir.png")).unwrap();
    std::fs::write(dir.join("target.dat"), b"keep").unwrap();
    #[cfg(unix)]
    {
        for f in ["fifo", "fifo.png", "fifo.toml"] {
            assert!(std::process::Command::new("mkfifo").arg(dir.join(f)).status().unwrap().success());
        }
        std::os::unix::fs::symlink(dir.join("target.dat"), dir.join("link.png")).unwrap();
    }
}

#[test]
fn fuzz_cli_arguments() {
    let cases: usize = std::env::var("BEAM_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(10_000);
    let seed: u64 = std::env::var("BEAM_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(18);
    let dir = tempfile::tempdir().unwrap();
    scratch(dir.path());
    let d = dir.path().to_str().unwrap().to_string();
    let start = Instant::now();
    let (tx, rx) = mpsc::channel();
    let worker = std::thread::spawn(move || {
        let mut rng = Pcg64::seed_from_u64(seed);
        for i in 0..cases {
            let argv = mutate(&mut rng, &d);
            let verdict = case(&argv, i % 64 == 0);
            if tx.send((argv, verdict)).is_err() {
                return;
            }
        }
    });
    let (mut accepted, mut rendered, mut errors, mut panics, mut unclear) = (0, 0, 0, Vec::new(), Vec::new());
    for _ in 0..cases {
        let (argv, verdict) = match rx.recv_timeout(CASE_LIMIT) {
            Ok(v) => v,
            Err(e) => panic!("a case ran over {CASE_LIMIT:?} (or the worker died): {e}"),
        };
        match verdict {
            Verdict::Accepted { rendered: r } => {
                accepted += 1;
                rendered += usize::from(r);
            }
            Verdict::Error(e) if e.trim().is_empty() || e.len() > 4000 => unclear.push((argv, e)),
            Verdict::Error(_) => errors += 1,
            Verdict::Panic(p) => panics.push((argv, p)),
        }
    }
    worker.join().unwrap();
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "CLI fuzzer (seed {seed}): {cases} cases in {seconds:.1} s: {accepted} accepted ({rendered} rendered at 8×8), \
         {errors} clear errors, {} unclear errors, {} panics",
        unclear.len(),
        panics.len()
    );
    assert!(panics.is_empty(), "panics: {panics:#?}");
    assert!(unclear.is_empty(), "empty or huge messages: {unclear:#?}");
    assert_eq!(std::fs::read(dir.path().join("target.dat")).unwrap(), b"keep", "written through a link");
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let meta = |f: &str| std::fs::symlink_metadata(dir.path().join(f)).unwrap().file_type();
        assert!(meta("fifo.png").is_fifo() && meta("link.png").is_symlink() && meta("dir.png").is_dir());
    }
    for e in std::fs::read_dir(dir.path()).unwrap() {
        let name = e.unwrap().file_name();
        assert!(!name.to_string_lossy().contains(beam_scene::io::TEMP_MARKER), "left behind: {name:?}");
    }
}
