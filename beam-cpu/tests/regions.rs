//! Render-farm tiles: every renderer, asked for a rectangle of the frame, gives each of its pixels
//! exactly (bit for bit) the value it has in the whole frame's render. The rectangles are chosen
//! off the renderers' internal grids (shading tiles of 16 pixels, eye-beam regions of 256).

use beam_cpu::glossy::{render_glossy, render_glossy_reference, render_glossy_reference_in};
use beam_cpu::nonlinear::{render_nonlinear, render_smooth_reference};
use beam_cpu::render::render;
use beam_render::glossy::GlossyOptions;
use beam_render::image::Image;
use beam_render::nonlinear::Degree;
use beam_render::nonlinear::NonlinearOptions;
use beam_render::options::{Method, RenderOptions};
use beam_scene::region::PixelRect;
use beam_scene::scene;

/// Rectangles of a `w × h` frame: the middle of three bands, a crop across grid lines, a single
/// pixel, the last corner.
fn rects(w: u32, h: u32) -> Vec<PixelRect> {
    let mut out: Vec<PixelRect> = PixelRect::band(1, 3, w, h).into_iter().collect();
    out.push(PixelRect { x0: 5, y0: 7, x1: w - 3, y1: h / 2 + 1 });
    out.push(PixelRect { x0: w / 2, y0: h / 3, x1: w / 2 + 1, y1: h / 3 + 1 });
    out.push(PixelRect { x0: w - 1, y0: h - 1, x1: w, y1: h });
    out
}

/// `part` equals the pixels of `rect` in `full`, bit for bit.
#[track_caller]
fn same(what: &str, full: &Image, rect: PixelRect, part: &Image) {
    assert_eq!((part.width, part.height), (rect.width(), rect.height()), "{what} {rect:?}");
    let want = rect.cut(full.pixels.clone(), full.width);
    for (i, (a, b)) in want.iter().zip(&part.pixels).enumerate() {
        assert!(
            a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits),
            "{what} {rect:?}: pixel {i} is {b} in the tile, {a} in the frame"
        );
    }
}

#[test]
fn beam_and_ray_tiles_equal_the_frame() {
    let (w, h) = (300, 40);
    for (name, method, primary_beams) in [
        ("cornell", Method::Beam, true),
        ("cornell-point", Method::Beam, true),
        ("cornell", Method::Beam, false),
        ("cornell", Method::Ray, false),
    ] {
        let scene = scene::builtin(name).unwrap();
        let options = RenderOptions { method, primary_beams, spp: 4, primary_spp: 4, ..RenderOptions::exact(w, h) };
        let (full, _) = render(&scene, &options, || {});
        for rect in rects(w, h) {
            let (part, _) = render(&scene, &RenderOptions { region: Some(rect), ..options }, || {});
            same(&format!("{name} {method:?} eye beams {primary_beams}"), &full, rect, &part);
        }
    }
}

/// A render whose shadow beams run past their budget, and whose tiles start from how the tile to
/// their left ended, is the same image bit for bit on one, two or three threads (each row of tiles
/// is shaded in order, its state handed from thread to thread), and its rectangles are the frame's (a rectangle's rows are
/// shaded across the frame), by eye beams and by primary rays.
#[test]
fn a_budgeted_render_does_not_depend_on_the_threads_or_the_rectangle() {
    let scene = scene::builtin("plant").unwrap();
    let (w, h) = (160, 96);
    for primary_beams in [true, false] {
        let options = RenderOptions { spp: 64, primary_beams, exact: false, ..RenderOptions::exact(w, h) };
        let on = |threads: usize, region| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| render(&scene, &RenderOptions { region, ..options }, || {}))
        };
        let (one, stats) = on(1, None);
        assert!(stats.sampled_beams > 0 && stats.exact_pixel_share < 1.0, "no beam ran past its budget");
        // Regions left to rays sample a pixel by its neighbours' centres too.
        assert_eq!(stats.ray_pixels > 0, primary_beams, "{} pixels by rays", stats.ray_pixels);
        let what = format!("eye beams {primary_beams}");
        for threads in [2, 3] {
            same(&format!("{what}, {threads} threads"), &one, PixelRect::full(w, h), &on(threads, None).0);
        }
        for rect in rects(w, h) {
            let (image, stats) = on(2, Some(rect));
            same(&what, &one, rect, &image);
            // A share of the rectangle's pixels, though whole rows of tiles around it are shaded.
            let share = stats.exact_pixel_share;
            assert!((0.0..=1.0).contains(&share), "{what}, {rect:?}: exact pixel share {share}");
        }
    }
}

#[test]
fn a_region_outside_the_frame_renders_nothing() {
    let scene = scene::builtin("cornell").unwrap();
    let outside = PixelRect { x0: 40, y0: 2, x1: 50, y1: 9 };
    for primary_beams in [true, false] {
        let options = RenderOptions { primary_beams, region: Some(outside), ..RenderOptions::exact(32, 24) };
        let (image, _) = render(&scene, &options, || {});
        assert!(image.pixels.is_empty() && image.width * image.height == 0);
    }
    let glossy = GlossyOptions { region: Some(outside), subdivide: 1, ..GlossyOptions::new(32, 24) };
    assert!(render_glossy(&scene::builtin("cardioid-ring").unwrap(), &glossy).unwrap().0.pixels.is_empty());
    let shading = RenderOptions { region: Some(outside), ..RenderOptions::exact(32, 24) };
    assert!(render_smooth_reference(&scene::builtin("mirror-glass").unwrap(), &shading, 10).pixels.is_empty());
}

#[test]
fn nonlinear_tiles_equal_the_frame() {
    let scene = scene::builtin("mirror-glass").unwrap();
    let (w, h) = (40, 30);
    let options = NonlinearOptions {
        degree: Degree::S3,
        texels: 16,
        bounces: 2,
        caustic_strata: 1,
        shading: RenderOptions::exact(w, h),
    };
    let (full, _) = render_nonlinear(&scene, &options).unwrap();
    let reference = render_smooth_reference(&scene, &options.shading, 2000);
    for rect in rects(w, h) {
        let shading = RenderOptions { region: Some(rect), ..options.shading };
        let (part, _) = render_nonlinear(&scene, &NonlinearOptions { shading, ..options }).unwrap();
        same("nonlinear", &full, rect, &part);
        same("nonlinear-reference", &reference, rect, &render_smooth_reference(&scene, &shading, 2000));
    }
}

#[test]
fn glossy_tiles_equal_the_frame() {
    // Glass and mirrors (eye paths through them) and a glossy ring.
    for name in ["cardioid-ring", "mirror-glass"] {
        let scene = scene::builtin(name).unwrap();
        let (w, h) = (40, 30);
        let options = GlossyOptions { subdivide: 1, ..GlossyOptions::new(w, h) };
        let (full, _) = render_glossy(&scene, &options).unwrap();
        let reference = render_glossy_reference(&scene, w, h, 2000, 1).unwrap();
        for rect in rects(w, h) {
            let (part, _) = render_glossy(&scene, &GlossyOptions { region: Some(rect), ..options }).unwrap();
            same(&format!("{name} glossy"), &full, rect, &part);
            let part = render_glossy_reference_in(&scene, (w, h), rect, 2000, 1).unwrap();
            same(&format!("{name} glossy-reference"), &reference, rect, &part);
        }
    }
}
