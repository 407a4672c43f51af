//! The gallery of `docs/gallery.md`: six small glTF models written here, loaded with their
//! defaults (no camera and no light of their own: the framing camera, the key light and the
//! neutral sky), rendered by every method: beam, ray, nonlinear and glossy.
//!
//! `cargo run --release -p beam-cpu --example gallery -- [folder]` writes the models and
//! `gallery.png` (one column per model, a row per method in that order) to `folder` (default
//! `gallery`).
//!
//! 1. a box textured with a checker (`baseColorTexture`, nearest filtering);
//! 2. a box with a colour per face (`COLOR_0`);
//! 3. nine spheres placed by `EXT_mesh_gpu_instancing` on a ground plane 60 times wider;
//! 4. a mirror sphere beside the checker box under an equirectangular sky map (`--env`);
//! 5. a label sheet whose emissive factor scales an emissive texture, beside a white box;
//! 6. a lattice fence cut out of one quad by its texture's alpha (`alphaMode` `MASK`) and a glass
//!    pane of alpha ½ (`BLEND`), casting their shadows on a ground cobbled by a normal texture.

use beam_render::image::Image;

use beam_cpu::glossy::render_glossy;
use beam_cpu::nonlinear::CpuBeams;
use beam_cpu::render::render;
use beam_math::glam::Vec3;
use beam_render::glossy::GlossyOptions;
use beam_render::nonlinear::{CAUSTIC_STRATA, Degree, NonlinearOptions, render_nonlinear_with};
use beam_render::options::{Method, RenderOptions};
use beam_scene::scene::{self, Environment, EnvironmentMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Side of each picture, pixels.
const SIDE: u32 = 192;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(std::env::args_os().nth(1).unwrap_or_else(|| "gallery".into()));
    std::fs::create_dir_all(&dir)?;
    write_png(
        &dir.join("checker.png"),
        8,
        8,
        |x, y| if (x / 2 + y / 2) % 2 == 0 { [220, 40, 40] } else { [40, 60, 220] },
    )?;
    write_png(&dir.join("label.png"), 16, 16, |_, y| if y % 4 < 2 { [255, 230, 160] } else { [0, 0, 0] })?;
    // A lattice: opaque brown bars two texels wide every eight, transparent between.
    let lattice = image::RgbaImage::from_fn(16, 16, |x, y| {
        image::Rgba([150, 90, 40, if x % 8 < 2 || y % 8 < 2 { 255 } else { 0 }])
    });
    lattice.save(dir.join("lattice.png"))?;
    // Cobbles: a dome in each 16 × 16 cell, as a tangent-space normal texture (x right, y up the
    // image, z out of the surface; (n + 1) / 2 in 8 bits).
    let cobbles = image::RgbImage::from_fn(32, 32, |x, y| {
        let (dx, dy) = ((x % 16) as f32 - 7.5, 7.5 - (y % 16) as f32);
        let n = Vec3::new(dx, dy, (64.0 - dx * dx - dy * dy).max(4.0).sqrt()).normalize();
        image::Rgb(((n + Vec3::ONE) * 127.5).to_array().map(|c| c as u8))
    });
    cobbles.save(dir.join("cobbles.png"))?;
    let models = [
        box_model(&dir, "textured-box", Look::Textured)?,
        box_model(&dir, "coloured-box", Look::Coloured)?,
        instanced_spheres(&dir)?,
        mirror_sphere(&dir)?,
        label_sheet(&dir)?,
        fence(&dir)?,
    ];
    let mut sheet = Image { width: SIDE * models.len() as u32, height: 4 * SIDE, pixels: Vec::new() };
    sheet.pixels = vec![Vec3::ZERO; (sheet.width * sheet.height) as usize];
    for (column, model) in models.iter().enumerate() {
        let mut scene = scene::load_file(model)?;
        if model.ends_with("mirror-sphere.gltf") {
            scene.environment = sky_map();
        }
        scene.camera.width = SIDE;
        scene.camera.height = SIDE;
        for row in 0..4u32 {
            // The options of `beam render`: 64 rays' worth per shadow beam, eye beams.
            let options = RenderOptions {
                method: if row == 1 { Method::Ray } else { Method::Beam },
                spp: 64,
                primary_beams: true,
                exact: false,
                ..RenderOptions::exact(SIDE, SIDE)
            };
            let start = std::time::Instant::now();
            let (image, method) = match row {
                0 | 1 => (render(&scene, &options, || {}).0, ["beam", "ray"][row as usize]),
                2 => {
                    let nonlinear = NonlinearOptions {
                        degree: Degree::S3,
                        texels: 32,
                        bounces: 2,
                        caustic_strata: CAUSTIC_STRATA,
                        shading: options,
                    };
                    (render_nonlinear_with(&scene, &nonlinear, &mut CpuBeams, &CpuBeams)?.0, "nonlinear")
                }
                _ => (render_glossy(&scene, &GlossyOptions::new(SIDE, SIDE))?.0, "glossy"),
            };
            println!("{} {method}: {:.3} s", model.display(), start.elapsed().as_secs_f64());
            for y in 0..SIDE {
                for x in 0..SIDE {
                    let to = (row * SIDE + y) * sheet.width + column as u32 * SIDE + x;
                    sheet.pixels[to as usize] = image.pixels[(y * SIDE + x) as usize];
                }
            }
        }
        for n in &scene.notices {
            println!("  notice: {} {}", n.count, n.what);
        }
    }
    sheet.save_png(&dir.join("gallery.png"))?;
    println!("wrote {}", dir.join("gallery.png").display());
    Ok(())
}

/// A sky for the mirror: blue above the horizon brightening towards it, brown ground below, a
/// bright patch of sun, as a 64 × 32 equirectangular map.
fn sky_map() -> Environment {
    let (w, h) = (64, 32);
    let texels = (0..w * h)
        .map(|i| {
            let (u, v) = ((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let up = 1.0 - 2.0 * v / h as f32;
            let sun = if (u - 20.0).abs() < 3.0 && (v - 9.0).abs() < 2.0 { Vec3::splat(3.0) } else { Vec3::ZERO };
            if up > 0.0 { Vec3::new(0.25, 0.45, 0.9) * (1.0 - 0.6 * up) + sun } else { Vec3::new(0.3, 0.22, 0.12) }
        })
        .collect();
    Environment::Map(Arc::new(EnvironmentMap::new(w, h, texels).expect("a valid map")))
}

/// Write a `width × height` sRGB PNG of `rgb(x, y)` to `path`.
fn write_png(path: &Path, width: u32, height: u32, rgb: impl Fn(u32, u32) -> [u8; 3]) -> std::io::Result<()> {
    let bytes: Vec<u8> = (0..width * height).flat_map(|i| rgb(i % width, i / width)).collect();
    let png = beam_scene::io::encode_png(width, height, &bytes).map_err(std::io::Error::other)?;
    std::fs::write(path, png)
}

/// What a box's faces show.
#[derive(Clone, Copy, PartialEq)]
enum Look {
    Textured,
    Coloured,
}

/// A glTF document being written: one buffer, a view and an accessor per array.
#[derive(Default)]
struct Model {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Model {
    /// An accessor of `kind` (`VEC3`, …) over the floats `values`; its index.
    fn floats(&mut self, values: &[f32], kind: &str, bounds: bool) -> usize {
        let view = self.view(values.iter().flat_map(|x| x.to_le_bytes()).collect());
        let size = match kind {
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 4,
        };
        let count = values.len() / size;
        let extra = if bounds {
            let (lo, hi) = (0..size).fold((Vec::new(), Vec::new()), |(mut lo, mut hi), k| {
                let column = values.iter().skip(k).step_by(size);
                lo.push(column.clone().fold(f32::MAX, |a, &b| a.min(b)));
                hi.push(column.fold(f32::MIN, |a, &b| a.max(b)));
                (lo, hi)
            });
            format!(r#", "min": {lo:?}, "max": {hi:?}"#)
        } else {
            String::new()
        };
        self.accessors.push(format!(
            r#"{{"bufferView": {view}, "componentType": 5126, "count": {count}, "type": "{kind}"{extra}}}"#
        ));
        self.accessors.len() - 1
    }

    /// A primitive of `mesh` with `material`; its JSON.
    fn primitive(&mut self, mesh: &Mesh, material: usize) -> String {
        let p = self.floats(&mesh.positions, "VEC3", true);
        let mut attributes = format!(r#""POSITION": {p}"#);
        if !mesh.uv.is_empty() {
            attributes += &format!(r#", "TEXCOORD_0": {}"#, self.floats(&mesh.uv, "VEC2", false));
        }
        if !mesh.colours.is_empty() {
            attributes += &format!(r#", "COLOR_0": {}"#, self.floats(&mesh.colours, "VEC4", false));
        }
        let view = self.view(mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect());
        let count = mesh.indices.len();
        self.accessors
            .push(format!(r#"{{"bufferView": {view}, "componentType": 5125, "count": {count}, "type": "SCALAR"}}"#));
        format!(
            r#"{{"attributes": {{{attributes}}}, "indices": {}, "material": {material}}}"#,
            self.accessors.len() - 1
        )
    }

    /// Append `bytes` as a buffer view; its index.
    fn view(&mut self, bytes: Vec<u8>) -> usize {
        self.views.push(format!(r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, self.bin.len(), bytes.len()));
        self.bin.extend(bytes);
        self.views.len() - 1
    }

    /// Write `name.gltf` and `name.bin` to `dir` with these `meshes`, `nodes`, `materials` and
    /// extra top-level members `more`; the model's path.
    fn write(&self, dir: &Path, name: &str, parts: [&str; 4]) -> std::io::Result<PathBuf> {
        let [meshes, nodes, materials, more] = parts;
        std::fs::write(dir.join(format!("{name}.bin")), &self.bin)?;
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [{}]}}],
 "nodes": [{nodes}], "meshes": [{meshes}], "materials": [{materials}],
 "accessors": [{}], "bufferViews": [{}],
 "buffers": [{{"uri": "{name}.bin", "byteLength": {}}}]{more}}}"#,
            (0..nodes.matches("\"mesh\"").count()).map(|i| i.to_string()).collect::<Vec<_>>().join(", "),
            self.accessors.join(",\n  "),
            self.views.join(",\n  "),
            self.bin.len()
        );
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, json)?;
        Ok(path)
    }
}

/// Positions, texture coordinates, colours and triangle indices.
#[derive(Default)]
struct Mesh {
    positions: Vec<f32>,
    uv: Vec<f32>,
    colours: Vec<f32>,
    indices: Vec<u32>,
}

/// The cube [−½, ½]³ offset by `at`, each face's corners with texture coordinates over the whole
/// texture and a colour per face.
fn cube(at: Vec3, scale: f32) -> Mesh {
    const FACES: [[Vec3; 3]; 6] = [
        [Vec3::X, Vec3::Y, Vec3::Z],
        [Vec3::NEG_X, Vec3::Y, Vec3::NEG_Z],
        [Vec3::Y, Vec3::Z, Vec3::X],
        [Vec3::NEG_Y, Vec3::NEG_Z, Vec3::X],
        [Vec3::Z, Vec3::X, Vec3::Y],
        [Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y],
    ];
    let colours =
        [[0.9, 0.2, 0.2], [0.2, 0.8, 0.2], [0.2, 0.3, 0.9], [0.9, 0.8, 0.2], [0.2, 0.8, 0.8], [0.8, 0.2, 0.8]];
    let mut m = Mesh::default();
    for ([n, a, b], colour) in FACES.iter().zip(colours) {
        let base = m.positions.len() as u32 / 3;
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            m.positions.extend((at + scale * 0.5 * (*n + s * *a + t * *b)).to_array());
            m.uv.extend([(s + 1.0) / 2.0, (1.0 - t) / 2.0]);
            m.colours.extend(colour);
            m.colours.push(1.0);
        }
        m.indices.extend([0, 1, 2, 0, 2, 3].map(|k| base + k));
    }
    m
}

/// A UV sphere of radius `r` about `centre`, `n` segments around and `n / 2` from pole to pole.
fn sphere(centre: Vec3, r: f32, n: u32) -> Mesh {
    let mut m = Mesh::default();
    let rows = n / 2;
    for i in 0..=rows {
        for j in 0..=n {
            let (theta, phi) =
                (std::f32::consts::PI * i as f32 / rows as f32, std::f32::consts::TAU * j as f32 / n as f32);
            let d = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
            m.positions.extend((centre + r * d).to_array());
        }
    }
    for i in 0..rows {
        for j in 0..n {
            let (a, b) = (i * (n + 1) + j, (i + 1) * (n + 1) + j);
            m.indices.extend([a, b, b + 1, a, b + 1, a + 1]);
        }
    }
    m
}

/// A horizontal square of half-width `half` at height `y`, facing up.
fn ground(y: f32, half: f32) -> Mesh {
    let positions = [[-half, y, -half], [-half, y, half], [half, y, half], [half, y, -half]].concat();
    Mesh { positions, indices: vec![0, 1, 2, 0, 2, 3], ..Mesh::default() }
}

/// The four textures (checker, label, lattice, cobbles' normals) and two samplers (nearest, linear), as top-level members.
const TEXTURES: &str = r#", "images": [{"uri": "checker.png"}, {"uri": "label.png"}, {"uri": "lattice.png"},
   {"uri": "cobbles.png"}],
 "samplers": [{"magFilter": 9728, "minFilter": 9728}, {}],
 "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}, {"source": 2, "sampler": 0},
   {"source": 3, "sampler": 1}]"#;

/// A diffuse material of base colour `rgb`.
fn diffuse(rgb: [f32; 3]) -> String {
    format!(
        r#"{{"pbrMetallicRoughness": {{"baseColorFactor": [{}, {}, {}, 1], "metallicFactor": 0}}}}"#,
        rgb[0], rgb[1], rgb[2]
    )
}

/// A diffuse material reading the checker texture.
const CHECKERED: &str = r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}"#;

fn box_model(dir: &Path, name: &str, look: Look) -> std::io::Result<PathBuf> {
    let mut m = Model::default();
    let mut mesh = cube(Vec3::ZERO, 1.0);
    let material = if look == Look::Textured {
        mesh.colours.clear();
        CHECKERED.to_string()
    } else {
        mesh.uv.clear();
        diffuse([1.0; 3])
    };
    let p = m.primitive(&mesh, 0);
    m.write(dir, name, [&format!(r#"{{"primitives": [{p}]}}"#), r#"{"mesh": 0}"#, &material, TEXTURES])
}

fn instanced_spheres(dir: &Path) -> std::io::Result<PathBuf> {
    let mut m = Model::default();
    let s = m.primitive(&sphere(Vec3::new(0.0, 0.5, 0.0), 0.5, 24), 0);
    let g = m.primitive(&ground(0.0, 90.0), 1);
    let offsets: Vec<f32> =
        (0..9).flat_map(|i| [1.3 * (i % 3) as f32 - 1.3, 0.0, 1.3 * (i / 3) as f32 - 1.3]).collect();
    let t = m.floats(&offsets, "VEC3", false);
    let nodes = format!(
        r#"{{"mesh": 0, "extensions": {{"EXT_mesh_gpu_instancing": {{"attributes": {{"TRANSLATION": {t}}}}}}}}}, {{"mesh": 1}}"#
    );
    let meshes = format!(r#"{{"primitives": [{s}]}}, {{"primitives": [{g}]}}"#);
    let materials = format!("{}, {}", diffuse([0.8, 0.5, 0.2]), diffuse([0.6; 3]));
    let more = r#", "extensionsUsed": ["EXT_mesh_gpu_instancing"], "extensionsRequired": ["EXT_mesh_gpu_instancing"]"#;
    m.write(dir, "instanced-spheres", [&meshes, &nodes, &materials, more])
}

fn mirror_sphere(dir: &Path) -> std::io::Result<PathBuf> {
    let mut m = Model::default();
    let mut checker_box = cube(Vec3::new(1.1, 0.4, 0.0), 0.8);
    checker_box.colours.clear();
    let parts = [
        m.primitive(&sphere(Vec3::new(-0.2, 0.6, 0.0), 0.6, 48), 0),
        m.primitive(&checker_box, 1),
        m.primitive(&ground(0.0, 2.0), 2),
    ];
    let meshes = format!(r#"{{"primitives": [{}]}}"#, parts.join(", "));
    let mirror = r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.95, 0.95, 1], "metallicFactor": 1, "roughnessFactor": 0}}"#;
    let materials = format!("{mirror}, {CHECKERED}, {}", diffuse([0.7; 3]));
    m.write(dir, "mirror-sphere", [&meshes, r#"{"mesh": 0}"#, &materials, TEXTURES])
}

fn label_sheet(dir: &Path) -> std::io::Result<PathBuf> {
    let mut m = Model::default();
    let sheet = Mesh {
        positions: [[-1.2, 0.1, -0.6], [-0.2, 0.1, -0.6], [-0.2, 1.1, -0.6], [-1.2, 1.1, -0.6]].concat(),
        uv: vec![0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Mesh::default()
    };
    let mut white_box = cube(Vec3::new(0.5, 0.35, 0.2), 0.7);
    white_box.uv.clear();
    white_box.colours.clear();
    let parts = [m.primitive(&sheet, 0), m.primitive(&white_box, 1), m.primitive(&ground(0.0, 2.0), 1)];
    let meshes = format!(r#"{{"primitives": [{}]}}"#, parts.join(", "));
    let label = r#"{"emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 1},
      "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12}},
      "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}}"#;
    let materials = format!("{label}, {}", diffuse([0.75; 3]));
    let more = format!(r#"{TEXTURES}, "extensionsUsed": ["KHR_materials_emissive_strength"]"#);
    m.write(dir, "label-sheet", [&meshes, r#"{"mesh": 0}"#, &materials, &more])
}

fn fence(dir: &Path) -> std::io::Result<PathBuf> {
    let mut m = Model::default();
    // Texture coordinates 0 to 2 across: the lattice repeats twice each way.
    let panel = |x: [f32; 2], z: f32, uv: f32| Mesh {
        positions: [[x[0], 0.0, z], [x[1], 0.0, z], [x[1], 1.2, z], [x[0], 1.2, z]].concat(),
        uv: vec![0.0, uv, uv, uv, uv, 0.0, 0.0, 0.0],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Mesh::default()
    };
    let parts = [
        m.primitive(&panel([-1.2, 0.6], 0.0, 2.0), 0),
        m.primitive(&panel([0.2, 1.2], 0.6, 1.0), 1),
        m.primitive(&Mesh { uv: vec![0.0, 0.0, 0.0, 8.0, 8.0, 8.0, 8.0, 0.0], ..ground(0.0, 2.5) }, 2),
    ];
    let meshes = format!(r#"{{"primitives": [{}]}}"#, parts.join(", "));
    let cobbled = r#"{"normalTexture": {"index": 3},
      "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.75, 1], "metallicFactor": 0}}"#;
    let lattice = r#"{"alphaMode": "MASK", "doubleSided": true,
      "pbrMetallicRoughness": {"baseColorTexture": {"index": 2}, "metallicFactor": 0}}"#;
    let pane = r#"{"alphaMode": "BLEND", "doubleSided": true,
      "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.5, 0.9, 0.5], "metallicFactor": 0}}"#;
    let materials = format!("{lattice}, {pane}, {cobbled}");
    m.write(dir, "fence", [&meshes, r#"{"mesh": 0}"#, &materials, TEXTURES])
}
