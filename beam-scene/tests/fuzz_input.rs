//! Seeded mutation fuzzer over scene files (TOML), meshes (OBJ) and their material libraries (MTL):
//! valid seeds mutated by bytes,
//! lines and tokens (deletions, duplicates, swaps, `nan`, `inf`, `1e39`, `-0`, huge integers, deep
//! brackets, odd Unicode, invalid UTF-8) go to the library loaders. Every case must load or fail
//! with a short error naming the file; none may panic, and each must finish within a time limit
//! (a watchdog fails the test on a hang). Counts are printed; `BEAM_FUZZ_SHOW=1` prints every error.
//!
//! Reproducible: case `k`'s two inputs are mutated by generators seeded from the run's seed and `k`
//! alone (`BEAM_FUZZ_SEED`, default [`SEED`]), from fixed seed texts: the TOML ones and, for even
//! `k`, the built-in meshes; odd `k` mutate the shared scenes' meshes where they are found (their
//! names are printed: without them the odd cases are built-in ones too). Every path a case may
//! reach outside its folder is one the test made. A failure names its cases and the command that
//! reruns one (`BEAM_FUZZ_CASE=k`). (Before, one generator ran through all cases, TOML and OBJ in
//! turn, over `k mod` the number of OBJ seeds, so that a checkout without the shared scenes beside
//! it fuzzed another case set: 2,455 OBJ cases accepted there against 2,137 here.)
//! `.ci/run` runs it in the `fuzz` profile too (optimized, with debug assertions and overflow checks).
//! It needs beam-scene alone, so it lives here, not in the conformance suite: that build of the
//! fuzz profile is a third of one that takes in the GPU crates.

use beam_scene::SceneError;
use beam_scene::mesh;
use beam_scene::scene::{self, LoadOptions};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Cases per kind (TOML, OBJ).
const CASES: usize = 6000;
/// The run's seed without `BEAM_FUZZ_SEED`.
const SEED: u64 = 0x18_2024;
/// Longest a single case may take.
const CASE_LIMIT: Duration = Duration::from_secs(10);
/// Longest error message accepted, in characters.
const MESSAGE_LIMIT: usize = 1000;

const TOKENS: &[&str] = &[
    "nan",
    "-nan",
    "NaN",
    "inf",
    "-inf",
    "+inf",
    "1e39",
    "-1e39",
    "1e-46",
    "-0",
    "0",
    "-1",
    "0.5",
    "1_000",
    "4294967295",
    "4294967296",
    "-2147483649",
    "18446744073709551616",
    "99999999999999999999999999999",
    "9223372036854775807",
    "0x10",
    "1e",
    ".",
    "..",
    "=",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    ",",
    "\"",
    "'",
    "\"\"\"",
    "'''",
    "#",
    "\\",
    "/",
    "//",
    "f",
    "v",
    "l",
    "p",
    "vt",
    "vn",
    "o",
    "g",
    "s off",
    "mtllib /dev/zero",
    "mtllib x.mtl",
    "f 1 2",
    "f 0 0 0",
    "f -1 -2 -3",
    "f 1/2/3 4//5 -7",
    "l 1 2 3",
    "v 1 2",
    "v 1 2 3 4 5 6",
    "true",
    "\"m.obj\"",
    "\"../m.obj\"",
    "\"/dev/zero\"",
    "\"/\"",
    "\"\"",
    "\"m.OBJ\"",
    "type = \"point\"",
    "type = \"quad\"",
    "type = \"emissive\"",
    "[[meshes]]",
    "[[lights]]",
    "[camera]",
    "[materials.x]",
    "albedo = [nan, 1, 1]",
    "radiance = [-1, 1, 1]",
    "scale = 0",
    "scale = 1e38",
    "rotate = [90, 0, 0]",
    "width = 0",
    "fov = 180",
    "up = [0, 0, 0]",
];

const NUMBERS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e39",
    "-1e39",
    "1e-46",
    "-0",
    "0",
    "0.0",
    "-1",
    "-0.5",
    "1e30",
    "3.4028235e38",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "-9223372036854775808",
    "2",
    "1e5",
    "7",
];

const UNICODE: &[&str] =
    &["é", "\u{feff}", "\u{202e}", "\u{0}", "\r", "\r\n", "\t", "𝕏", "\u{fffd}", "\u{85}", "\u{2028}", "ｖ", "１"];

/// `text` with one to four random mutations (one half the time).
fn mutate(rng: &mut Pcg64, text: &[u8]) -> Vec<u8> {
    let mut t = text.to_vec();
    for _ in 0..[1, 1, 1, 1, 2, 2, 3, 4][rng.random_range(0..8)] {
        let at = |rng: &mut Pcg64, t: &Vec<u8>| rng.random_range(0..=t.len());
        match rng.random_range(0..14) {
            // Lines: delete, duplicate, swap, truncate.
            0..=3 => {
                let mut lines: Vec<Vec<u8>> = t.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
                let i = rng.random_range(0..lines.len());
                let j = rng.random_range(0..lines.len());
                match rng.random_range(0..4) {
                    0 => drop(lines.remove(i)),
                    1 => lines.insert(i, lines[j].clone()),
                    2 => lines.swap(i, j),
                    _ => lines.truncate(i),
                }
                t = lines.join(&b'\n');
            }
            // Tokens: replace one, or insert one anywhere.
            4..=6 => {
                let token = TOKENS[rng.random_range(0..TOKENS.len())].as_bytes();
                let starts: Vec<usize> = (0..t.len())
                    .filter(|&k| !t[k].is_ascii_whitespace() && (k == 0 || t[k - 1].is_ascii_whitespace()))
                    .collect();
                if starts.is_empty() || rng.random_bool(0.3) {
                    let k = at(rng, &t);
                    t.splice(k..k, token.iter().copied().chain([b' ']));
                } else {
                    let s = starts[rng.random_range(0..starts.len())];
                    let e = (s..t.len())
                        .find(|&k| t[k].is_ascii_whitespace() || t[k] == b',' || t[k] == b']')
                        .unwrap_or(t.len());
                    t.splice(s..e.max(s + 1).min(t.len()), token.iter().copied());
                }
            }
            // Bytes: set one (maybe making invalid UTF-8), delete or duplicate a range.
            7 | 8 => {
                if !t.is_empty() {
                    let k = rng.random_range(0..t.len());
                    let n = rng.random_range(1..=16).min(t.len() - k);
                    match rng.random_range(0..3) {
                        0 => t[k] = rng.random(),
                        1 => drop(t.drain(k..k + n)),
                        _ => {
                            let copy = t[k..k + n].to_vec();
                            t.splice(k..k, copy);
                        }
                    }
                }
            }
            // Deep brackets or inline tables.
            9 => {
                let depth = [8, 63, 64, 65, 1000, 100_000][rng.random_range(0..6)];
                let (open, close) = if rng.random_bool(0.5) { ("[", "]") } else { ("{a=", "}") };
                let k = at(rng, &t);
                let deep = format!("{}1{}", open.repeat(depth), close.repeat(rng.random_range(0..=depth)));
                t.splice(k..k, deep.into_bytes());
            }
            // A number replaced by another (often still valid TOML or OBJ: reaches the value checks).
            12 | 13 => {
                let digits: Vec<usize> = (0..t.len())
                    .filter(|&k| {
                        t[k].is_ascii_digit() && (k == 0 || !t[k - 1].is_ascii_alphanumeric() && t[k - 1] != b'.')
                    })
                    .collect();
                if !digits.is_empty() {
                    let s = digits[rng.random_range(0..digits.len())];
                    let e = (s..t.len()).find(|&k| !(t[k].is_ascii_digit() || t[k] == b'.')).unwrap_or(t.len());
                    t.splice(s..e, NUMBERS[rng.random_range(0..NUMBERS.len())].bytes());
                }
            }
            // Odd Unicode.
            10 => {
                let k = at(rng, &t);
                t.splice(k..k, UNICODE[rng.random_range(0..UNICODE.len())].bytes());
            }
            // A long run of one token (long lines, many corners).
            _ => {
                let token = TOKENS[rng.random_range(0..TOKENS.len())];
                let k = at(rng, &t);
                t.splice(k..k, format!("{token} ").repeat(rng.random_range(2..2000)).into_bytes());
            }
        }
    }
    t
}

const MESH: &str = "# a box corner and a non-convex face\nmtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n\
    v 2 0 0\nv 2 1 0\nv 1 1 0.5\nvn 0 0 1\nvt 0 0\no part\ng side\nusemtl white\nf 1 2 3 4\nf 1//1 5//1 2//1\n\
    f 2/1/1 6/1/1 7/1/1 8/1/1 # non-convex\nf -1 -2 -3\nl 1 2\n";

const SCENE: &str = "[camera]\nposition = [0, 1, 4]\ntarget = [0, 0.5, 0]\nup = [0, 1, 0]\nfov = 45\nwidth = 64\n\
    height = 48\n\n[materials.white]\ntype = \"diffuse\"\nalbedo = [0.7, 0.7, 0.7]\n\n[materials.m]\n\
    type = \"mirror\"\ntint = [0.9, 0.9, 0.9]\nbump = 0.1\nbump_wavelength = 2\n\n[materials.g]\ntype = \"glass\"\n\
    ior = 1.5\n\n[materials.s]\ntype = \"glossy\"\nalbedo = [0.5, 0.5, 0.5]\nvariance = 0.05\n\n[materials.t]\n\
    type = \"thin-glass\"\ntint = [1, 0.5, 0.5]\nsigma = 0.01\n\n[materials.e]\ntype = \"emissive\"\n\
    radiance = [5, 5, 5]\n\n[[meshes]]\nfile = \"m.obj\"\nmaterial = \"white\"\ntranslate = [0, 0, 0]\n\
    rotate = [0, 90, 0]\nscale = 1.0\n\n[[meshes]]\nfile = \"sub/t.obj\"\nmaterial = \"m\"\nscale = [1, 2, 1]\n\n\
    [[lights]]\ntype = \"quad\"\ncorner = [-0.5, 2, -0.5]\nedge_u = [1, 0, 0]\nedge_v = [0, 0, 1]\n\
    radiance = [10, 10, 10]\n\n[[lights]]\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = [1, 1, 1]\n\n\
    [[lights]]\ntype = \"triangle\"\nvertices = [[0, 2, 0], [1, 2, 0], [0, 2, 1]]\nradiance = [1, 1, 1]\n";

/// The MTL seed: a diffuse, an emissive, a glossy and a textured material (its images missing).
const MTL: &str = "# materials\nnewmtl white\n  Kd 0.7 0.7 0.7\n  Ka 0 0 0\n  illum 2\nnewmtl light\nKe 17 12 4\n\
    Kd 0.78\nnewmtl shiny\nKd 0 0 0\nKs 0.7 0.7 0.7\nNs 200\nd 0.5\nnewmtl tex\nKd 1 1 1\n\
    map_Kd -s 1 1 1 textures\\t.png\nbump -bm 0.5 b.png\nnorm -s 1 1 1 n.png\nmap_d -imfchan m a.png\n";

/// The built-in OBJ seeds: [`MESH`] and one triangle.
const MESHES: [&str; 2] = [MESH, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"];

/// A scene with every material, light and transform kind of the scene-file format, and a minimal one.
const SCENES: [&str; 2] = [
    SCENE,
    "[materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\n[[meshes]]\nfile = \"m.obj\"\nmaterial = \"w\"\n",
];

/// Up to 300 vertices and the faces among them of each shared scene mesh, as extra OBJ seeds, and
/// the meshes' file names.
fn shared_seeds() -> (Vec<String>, Vec<String>) {
    let Ok(paths) = beam_scene::scenes::shared_meshes() else { return (Vec::new(), Vec::new()) };
    let mut seeds = Vec::new();
    let mut names = Vec::new();
    for p in paths {
        let Ok(text) = std::fs::read_to_string(&p) else { continue };
        names.push(p.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned()));
        let v: Vec<&str> = text.lines().filter(|l| l.starts_with("v ")).take(300).collect();
        let f = text.lines().filter(|l| {
            l.starts_with("f ")
                && l[2..]
                    .split_whitespace()
                    .all(|c| c.split('/').next().and_then(|i| i.parse::<usize>().ok()).is_some_and(|i| i <= v.len()))
        });
        seeds.push(v.iter().copied().chain(f.take(300)).collect::<Vec<_>>().join("\n"));
    }
    (seeds, names)
}

#[derive(Default, Debug)]
struct Counts {
    cases: usize,
    ok: usize,
    errors: usize,
    panics: usize,
    longest: Duration,
}

impl Counts {
    /// Count one case's outcome; a panic or a vague error is remembered in `bad`.
    fn add(
        &mut self,
        k: usize,
        name: &str,
        input: &[u8],
        took: Duration,
        r: std::thread::Result<Result<(), SceneError>>,
        bad: &mut Vec<String>,
    ) {
        self.cases += 1;
        self.longest = self.longest.max(took);
        let shown = || String::from_utf8_lossy(&input[..input.len().min(300)]).into_owned();
        match r {
            Ok(Ok(())) => self.ok += 1,
            Ok(Err(e)) => {
                let e = e.to_string();
                self.errors += 1;
                if std::env::var_os("BEAM_FUZZ_SHOW").is_some() {
                    eprintln!("ERR {}", e.chars().take(160).collect::<String>());
                }
                if !e.contains(name) || e.chars().count() > MESSAGE_LIMIT {
                    let e = e.chars().take(300).collect::<String>();
                    bad.push(format!("case {k}: unclear error {e:?} for {name} {:?}", shown()));
                }
            }
            Err(p) => {
                self.panics += 1;
                let why = p.downcast_ref::<String>().map(String::as_str).or(p.downcast_ref::<&str>().copied());
                bad.push(format!("case {k}: panic {:?} on {name} {:?}", why.unwrap_or("?"), shown()));
            }
        }
    }
}

/// The generator of input `kind` (0: TOML, 1: OBJ) of case `k` of the run seeded `seed`: each case
/// on its own, so that one reruns alone and a change to one case's mutations moves no other.
fn case_rng(seed: u64, k: usize, kind: u64) -> Pcg64 {
    Pcg64::seed_from_u64(seed ^ (2 * k as u64 + kind + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// Run the cases `cases` (every one, or the one of `BEAM_FUZZ_CASE`) of the run seeded `seed` in a
/// worker thread, reporting each finished case to `progress`.
fn run(
    dir: PathBuf,
    seed: u64,
    cases: std::ops::Range<usize>,
    shared: Vec<String>,
    progress: mpsc::Sender<()>,
) -> (Counts, Counts, Counts, Vec<String>) {
    let (mut toml, mut obj, mut mtl, mut bad) = (Counts::default(), Counts::default(), Counts::default(), Vec::new());
    let scene_path = dir.join("case.toml");
    let obj_path = dir.join("case.obj");
    let show = cases.len() == 1;
    for k in cases {
        let input = mutate(&mut case_rng(seed, k, 0), SCENES[k % SCENES.len()].as_bytes());
        if show {
            println!("case {k} case.toml ({} bytes): {:?}", input.len(), String::from_utf8_lossy(&input));
        }
        std::fs::write(&scene_path, &input).unwrap();
        let options = LoadOptions { allow_outside_paths: k % 2 == 1 };
        let start = Instant::now();
        let r = catch_unwind(AssertUnwindSafe(|| scene::load_file_with(&scene_path, &options).map(drop)));
        toml.add(k, "case.toml", &input, start.elapsed(), r, &mut bad);
        let _ = progress.send(());

        // Even cases mutate a built-in mesh, odd ones a shared scene's where there are any: the
        // even half of the case set is the same wherever the test runs.
        let obj_seed = match shared.len() {
            n if k % 2 == 1 && n > 0 => shared[(k / 2) % n].as_str(),
            _ => MESHES[(k / 2) % MESHES.len()],
        };
        let input = mutate(&mut case_rng(seed, k, 1), obj_seed.as_bytes());
        if show {
            println!("case {k} case.obj ({} bytes): {:?}", input.len(), String::from_utf8_lossy(&input));
        }
        let start = Instant::now();
        let r = catch_unwind(AssertUnwindSafe(|| mesh::parse_obj(Path::new("case.obj"), &input, true).map(drop)));
        // Every fourth goes through the file loader too (bounded read, degenerate filter, BVH).
        let r = match r {
            Ok(Ok(())) if k % 4 == 0 => {
                std::fs::write(&obj_path, &input).unwrap();
                catch_unwind(AssertUnwindSafe(|| scene::load_file(&obj_path).map(drop)))
            }
            r => r,
        };
        obj.add(k, "case.obj", &input, start.elapsed(), r, &mut bad);

        let input = mutate(&mut case_rng(seed, k, 2), MTL.as_bytes());
        let start = Instant::now();
        let r = catch_unwind(AssertUnwindSafe(|| mesh::parse_mtl(Path::new("case.mtl"), &input, true).map(drop)));
        mtl.add(k, "case.mtl", &input, start.elapsed(), r, &mut bad);
        let _ = progress.send(());
    }
    (toml, obj, mtl, bad)
}

#[test]
fn mutated_scene_files_and_meshes_never_panic_or_hang() {
    let var = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<u64>().ok());
    let seed = var("BEAM_FUZZ_SEED").unwrap_or(SEED);
    let only = var("BEAM_FUZZ_CASE").map(|k| k as usize);
    let cases = only.map_or(0..CASES, |k| k..k + 1);
    // The cases run in `cases/`, in a folder of their own: a path a mutation sends outside
    // (`../m.obj`, allowed every other case) finds what this test wrote, not what another left.
    let root = std::env::temp_dir().join(format!("beam-fuzz-input-{}", std::process::id()));
    let dir = root.join("cases");
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(dir.join("m.obj"), MESH).unwrap();
    std::fs::write(dir.join("m.mtl"), MTL).unwrap();
    std::fs::write(root.join("m.obj"), MESH).unwrap();
    std::fs::write(dir.join("sub/t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let (shared, names) = shared_seeds();
    println!("fuzz_input: seed {seed}; OBJ seeds: 2 built in and {} shared meshes {names:?}", names.len());
    let start = Instant::now();
    let (tx, rx) = mpsc::channel();
    let worker = {
        let dir = dir.clone();
        let cases = cases.clone();
        std::thread::spawn(move || run(dir, seed, cases, shared, tx))
    };
    let mut done = 0;
    loop {
        match rx.recv_timeout(CASE_LIMIT) {
            Ok(()) => done += 1,
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                let k = cases.start + done / 2;
                panic!(
                    "case {k} took over {CASE_LIMIT:?} (hangs); inputs in {}; rerun it alone with \
                     BEAM_FUZZ_SEED={seed} BEAM_FUZZ_CASE={k} cargo test -p beam-scene --test fuzz_input",
                    dir.display()
                )
            }
        }
    }
    let (toml, obj, mtl, bad) = worker.join().unwrap();
    let _ = std::fs::remove_dir_all(&root);
    let all = toml.cases + obj.cases + mtl.cases;
    println!("fuzz_input: {all} cases in {:.1} s", start.elapsed().as_secs_f64());
    for (kind, c) in [("toml", &toml), ("obj", &obj), ("mtl", &mtl)] {
        println!(
            "  {kind}: {} cases, {} ok, {} clear errors, {} panics, longest case {:.1} ms",
            c.cases,
            c.ok,
            c.errors,
            c.panics,
            c.longest.as_secs_f64() * 1e3
        );
    }
    assert!(only.is_some() || all >= 10_000);
    assert!(
        bad.is_empty(),
        "{} bad cases of seed {seed}, first: {:#?}\nrerun case k alone (its inputs printed) with \
         BEAM_FUZZ_SEED={seed} BEAM_FUZZ_CASE=k cargo test -p beam-scene --test fuzz_input -- --nocapture",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    assert_eq!(toml.panics + obj.panics + mtl.panics, 0);
}
