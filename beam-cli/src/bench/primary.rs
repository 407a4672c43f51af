//! `beam bench primary`: exact primary visibility by eye beams (001 §3, box-filtered coverage)
//! against 1, 4 and 16 stratified jittered primary rays per pixel — ours (4-wide BVH) and, with
//! `--features peers`, Embree's closest hit on the same rays — on an image where only visibility
//! matters: each visible triangle is flat, a fixed colour per triangle times `|cos|` of the view
//! angle, on black. Prints seconds, RMSE against the eye beams' exact image and the ratio of each
//! time to the eye beams'.

use super::primary_shading::flat;
use beam_cpu::render::{Visibility, difference, pixel_samples, primary_image};
use beam_math::Ray;
use beam_math::glam::Vec3;
use beam_render::image::Image;
use beam_render::queries::ClosestHit;
use beam_scene::scene::{self, Camera, Scene};
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

/// The default scenes: the shared Sponza and conference room.
pub(crate) const SCENES: [&str; 2] = ["sponza", "conference"];

/// A scene to benchmark: its name for tables and files, the scene, and whether it is a bare mesh
/// (which gets [`Camera::interior`]).
pub(crate) struct Loaded {
    /// Short name (built-in name or file stem).
    pub name: String,
    /// The scene.
    pub scene: Scene,
    /// A bare `.obj` mesh.
    pub mesh: bool,
}

/// Load `arg`: `sponza` and `conference` name the shared OBJ files (under `$BEAM_SCENES` or
/// `../shared/scenes`), anything else is a built-in, a `.toml` scene or an `.obj` mesh. `Ok(None)`
/// with a printed reason when a shared scene is absent.
pub(crate) fn load(arg: &str) -> Result<Option<Loaded>, String> {
    let shared = match arg {
        "sponza" => Some("sponza_dabrovic/sponza.obj"),
        "conference" => Some("conference/conference.obj"),
        _ => None,
    };
    let path = match shared {
        Some(rel) => match beam_scene::scenes::scenes_dir().map(|d| d.join(rel)) {
            Ok(p) if p.is_file() => p.display().to_string(),
            Ok(p) => return skip(arg, &format!("{} not found", p.display())),
            Err(e) => return skip(arg, &e.to_string()),
        },
        None => arg.to_string(),
    };
    let scene = scene::load(&path).map_err(|e| e.to_string())?;
    let name = Path::new(arg).file_stem().map_or_else(|| arg.to_string(), |s| s.to_string_lossy().into_owned());
    Ok(Some(Loaded { name, scene, mesh: path.ends_with(".obj") }))
}

fn skip(arg: &str, why: &str) -> Result<Option<Loaded>, String> {
    println!("skipping {arg}: {why}");
    Ok(None)
}

/// The benchmark's view of `loaded` at `size × size`: the interior view for a bare mesh, else the
/// scene's camera.
pub(crate) fn camera(loaded: &Loaded, size: u32) -> Camera {
    if loaded.mesh {
        Camera::interior(loaded.scene.bounds(), size, size)
    } else {
        loaded.scene.camera.with_size(size, size)
    }
}

/// The image of `spp` stratified jittered primary rays per pixel (a `k × k` grid, `k = ⌊√spp⌋`;
/// the pixel centre for one), seeded per pixel so that every tracer gets the same rays; rows in
/// parallel. Returns the image and its seconds.
pub(crate) fn ray_image(
    scene: &Scene,
    camera: &Camera,
    spp: u32,
    hit: &ClosestHit<'_>,
    row_done: &(dyn Fn() + Sync),
) -> (Image, f64) {
    let start = Instant::now();
    let shade = flat(scene);
    let frame = camera.frame();
    let k = ((spp.max(1) as f32).sqrt() as u32).max(1);
    let mut image = Image::new(camera.width, camera.height);
    image.pixels.par_chunks_mut(camera.width as usize).enumerate().for_each(|(y, row)| {
        for (x, px) in row.iter_mut().enumerate() {
            let mut sum = Vec3::ZERO;
            for (sx, sy) in pixel_samples(x as u32, y as u32, k) {
                let ray = camera.ray(&frame, sx, sy);
                if let Some((prim, t)) = hit(ray) {
                    sum += shade(prim, ray.origin + t * ray.direction, ray.direction.normalize());
                }
            }
            *px = sum / (k * k) as f32;
        }
        row_done();
    });
    (image, start.elapsed().as_secs_f64())
}

/// Our closest hit: the scene's 4-wide BVH.
pub(crate) fn ours(scene: &Scene) -> impl Fn(Ray) -> Option<(u32, f32)> + Sync + '_ {
    move |ray| scene.closest_hit(ray, f32::INFINITY).map(|h| (h.prim, h.t))
}

/// The table on each of `scenes` at `size × size`; images into `out` when given. With `gpu`, also
/// the GPU's rays on the same rays ([`super::primary_gpu`]), in the table and in a table of their
/// own.
pub(crate) fn run(scenes: &[String], size: u32, out: Option<&Path>, gpu: Option<&beam_gpu::Gpu>) -> Result<(), String> {
    for arg in scenes {
        let Some(loaded) = load(arg)? else { continue };
        let scene = &loaded.scene;
        let camera = camera(&loaded, size);
        let bar = crate::progress::bar(u64::from(size) * u64::from(size), "eye beams");
        let (exact, ps) = primary_image(scene, &camera, Visibility::Exact, flat(scene), |pixels| bar.inc(pixels));
        bar.finish_and_clear();
        println!(
            "\n{}: {} triangles, {size}×{size}; eye beams: {} visible triangles, {} hit beams ({:.2} per visible \
             triangle), {} BVH steps, {} splits, coverage error {:.1e}",
            loaded.name,
            scene.stats.triangles,
            ps.visible_triangles,
            ps.hit_beams,
            ps.hit_beams_per_visible_triangle,
            ps.bvh_steps,
            ps.intersections,
            ps.coverage_error
        );
        let mut rows: Vec<(String, f64, Image)> = vec![("eye beams (exact)".into(), ps.seconds, exact.clone())];
        #[cfg_attr(not(feature = "peers"), expect(unused_mut, reason = "the peers feature pushes Embree's tracer"))]
        let mut tracers: Vec<(&str, Box<ClosestHit<'_>>)> = vec![("rays", Box::new(ours(scene)))];
        #[cfg(feature = "peers")]
        tracers.push(("embree3", super::peers::embree_closest(&scene.triangles)?));
        for (tracer, hit) in &tracers {
            for spp in [1, 4, 16] {
                let bar = crate::progress::bar(u64::from(size), "primary rays");
                let (img, seconds) = ray_image(scene, &camera, spp, &**hit, &|| bar.inc(1));
                bar.finish_and_clear();
                rows.push((format!("{tracer} {spp} spp"), seconds, img));
            }
        }
        let on_gpu = gpu.map(|g| super::primary_gpu::images(g, scene, &camera)).transpose()?.unwrap_or_default();
        let cpu_rows = rows.len();
        rows.extend(on_gpu.iter().map(|r| (format!("gpu rays {} spp", r.spp), r.host_seconds, r.image.clone())));
        println!("{:<18} {:>9} {:>9} {:>8} {:>12}", "method", "seconds", "RMSE", "PSNR dB", "× eye beams");
        for (method, seconds, img) in &rows {
            let d = difference(img, &exact).map_err(|e| e.to_string())?;
            println!("{method:<18} {seconds:>9.3} {:>9.5} {:>8.2} {:>12.3}", d.rmse, d.psnr, seconds / ps.seconds);
        }
        if let Some(g) = gpu {
            // Our CPU rays of each count, in the order they ran.
            let cpu: Vec<(u32, &Image, f64)> =
                [1, 4, 16].into_iter().zip(&rows[1..cpu_rows]).map(|(spp, (_, s, img))| (spp, img, *s)).collect();
            super::primary_gpu::print_table(g, &on_gpu, &cpu)?;
        }
        if let Some(dir) = out {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            for (method, _, img) in &rows {
                let file = method.split_whitespace().take(3).collect::<Vec<_>>().join("-").replace(['(', ')'], "");
                img.save_png(&dir.join(format!("primary-{}-{file}.png", loaded.name))).map_err(|e| e.to_string())?;
            }
            println!("images in {}", dir.display());
        }
    }
    Ok(())
}
