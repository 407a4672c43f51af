//! Seeded mutation fuzzing of the OBJ and scene-file loaders: thousands of corrupted versions of
//! the shared scenes' OBJ files (their first 400 lines) and of a scene file must each load or fail
//! with an error that names the file, and never panic.

use beam_scene::scene;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::panic::{AssertUnwindSafe, catch_unwind};

const TOKENS: [&str; 14] =
    ["nan", "inf", "-1", "0", "1e39", "f", "v", "f 1 2", "f 0 0 0", "v 1 2", "/", "//", "-99999999", "f 1/2/3 4//5 -7"];

fn mutate(rng: &mut Pcg64, text: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for _ in 0..rng.random_range(1..6) {
        if lines.is_empty() {
            lines.push(String::new());
        }
        let i = rng.random_range(0..lines.len());
        match rng.random_range(0..6) {
            0 => {
                lines.remove(i);
            }
            1 => {
                let l = lines[i].clone();
                lines.insert(i, l);
            }
            2 => lines[i] = TOKENS[rng.random_range(0..TOKENS.len())].to_string(),
            3 => {
                let mut words: Vec<&str> = lines[i].split_whitespace().collect();
                if !words.is_empty() {
                    let k = rng.random_range(0..words.len());
                    words[k] = TOKENS[rng.random_range(0..TOKENS.len())];
                }
                lines[i] = words.join(" ");
            }
            4 => {
                let mut bytes = lines[i].clone().into_bytes();
                if !bytes.is_empty() {
                    let k = rng.random_range(0..bytes.len());
                    bytes[k] = rng.random_range(32..127);
                }
                lines[i] = String::from_utf8_lossy(&bytes).into_owned();
            }
            _ => lines.truncate(i),
        }
    }
    lines.join("\n")
}

#[test]
fn mutated_inputs_never_panic() {
    let mut sources: Vec<(&str, String)> = Vec::new();
    match beam_scene::scenes::shared_meshes() {
        Ok(paths) => {
            for p in paths {
                let text = std::fs::read_to_string(&p).unwrap();
                sources.push(("obj", text.lines().take(400).collect::<Vec<_>>().join("\n")));
            }
        }
        Err(reason) => println!("shared scenes skipped: {reason}"),
    }
    sources.push(("obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n".into()));
    let toml = "[camera]\nposition = [0, 1, 3]\ntarget = [0, 0, 0]\nfov = 40\n\n[materials.w]\ntype = \"diffuse\"\nalbedo = [0.7, 0.7, 0.7]\n\n[[meshes]]\nfile = \"m.obj\"\nmaterial = \"w\"\nscale = 2\n\n[[lights]]\ntype = \"quad\"\ncorner = [0, 2, 0]\nedge_u = [1, 0, 0]\nedge_v = [0, 0, 1]\nradiance = [5, 5, 5]\n";
    sources.push(("toml", toml.into()));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let mut rng = Pcg64::seed_from_u64(2024);
    let (mut inputs, mut loaded, mut errors) = (0, 0, 0);
    for round in 0..250 {
        for (k, (ext, text)) in sources.iter().enumerate() {
            let path = dir.path().join(format!("case{round}_{k}.{ext}"));
            std::fs::write(&path, mutate(&mut rng, text)).unwrap();
            let result = catch_unwind(AssertUnwindSafe(|| scene::load_file(&path).map(|_| ())));
            inputs += 1;
            match result {
                Ok(Ok(())) => loaded += 1,
                Ok(Err(e)) => {
                    assert!(e.to_string().contains(&format!("case{round}_{k}")), "error does not name the file: {e}");
                    errors += 1;
                }
                Err(_) => panic!("loading {} panicked", path.display()),
            }
            std::fs::remove_file(&path).unwrap();
        }
    }
    println!("{inputs} mutated inputs: {loaded} loaded, {errors} clear errors, 0 panics");
    assert_eq!(loaded + errors, inputs);
}
