//! The environment in the CPU renderer: eye rays that miss see it, mirrors reflect it, and it
//! lights diffuse surfaces (a constant sky exactly by the beam method, as area lights; a map by
//! sampled rays), under both methods.

use beam_render::image::Image;

use beam_cpu::render::{RenderStats, render};
use beam_math::Triangle;
use beam_math::glam::Vec3;
use beam_render::options::{Method, RenderOptions, Shading};
use beam_scene::mesh;
use beam_scene::scene::{Bump, Camera, Environment, EnvironmentMap, Material, Scene};
use std::sync::Arc;

/// A render of `scene` at `size²` by `method` (eye beams or primary rays for `beam`), exact
/// shading, `spp` shadow rays.
fn draw(scene: &Scene, method: Method, primary_beams: bool, spp: u32, size: u32) -> (Image, RenderStats) {
    let options =
        RenderOptions { method, shading: Shading::Exact, spp, primary_beams, ..RenderOptions::exact(size, size) };
    render(scene, &options, || {})
}

fn camera(position: Vec3, target: Vec3, size: u32) -> Camera {
    Camera { position, target, up: Vec3::Y, fov_y: 40.0, width: size, height: size }
}

/// A map whose colour varies smoothly with direction: `0.5 + 0.5·d` per channel.
fn direction_map() -> EnvironmentMap {
    let (w, h) = (128, 64);
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let d = EnvironmentMap::direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            Vec3::splat(0.5) + 0.5 * d
        })
        .collect();
    EnvironmentMap::new(w, h, texels).unwrap()
}

/// A scene of one mirror sphere (radius 1 at the origin) seen from +z, nothing else, no lights.
fn mirror_sphere(tint: Vec3, environment: Environment) -> Scene {
    let sphere = mesh::sphere(Vec3::ZERO, 1.0, 48, 96);
    let triangles: Vec<(Triangle, u32)> = sphere.triangles().into_iter().map(|t| (t, 0)).collect();
    let materials = vec![Material::Mirror { tint, bump: Bump::NONE }];
    let cam = camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 48);
    let mut scene = Scene::new("mirror sphere".into(), triangles, materials, Vec::new(), cam);
    scene.environment = environment;
    scene
}

/// The ideal sphere's reflection of the camera ray through pixel `i`, or `None` where the ray
/// misses it (or grazes it: within a tenth of the radius of its outline, where the tessellation
/// differs most).
fn reflected(scene: &Scene, i: usize) -> Option<Vec3> {
    let frame = scene.camera.frame();
    let ray = scene.camera.pixel_ray(&frame, i);
    let (o, d) = (ray.origin, ray.direction.normalize());
    let b = o.dot(d);
    let disc = b * b - (o.length_squared() - 1.0);
    if disc < 0.19 {
        return None;
    }
    let n = (o + (-b - disc.sqrt()) * d).normalize();
    Some(d - 2.0 * d.dot(n) * n)
}

/// A mirror sphere under a constant sky shows the sky times its tint, with both methods and both
/// kinds of primary visibility; where the eye misses it, the sky itself.
#[test]
fn mirror_sphere_reflects_a_constant_sky() {
    let (sky, tint) = (Vec3::new(0.3, 0.5, 0.9), Vec3::new(0.9, 0.8, 0.6));
    let scene = mirror_sphere(tint, Environment::Constant(sky));
    for (method, beams) in [(Method::Beam, true), (Method::Beam, false), (Method::Ray, false)] {
        let (image, _) = draw(&scene, method, beams, 4, 48);
        let mut on = 0;
        for (i, p) in image.pixels.iter().enumerate() {
            let want = if reflected(&scene, i).is_some() { tint * sky } else { continue };
            on += 1;
            assert!(p.abs_diff_eq(want, 1e-3), "{method:?} {beams}: pixel {i} is {p}, the mirror shows {want}");
        }
        assert!(on > 300, "{on} pixels on the sphere");
        // The corners see past the sphere: the sky itself.
        assert!(image.pixels[0].abs_diff_eq(sky, 1e-5), "{method:?}: corner {}", image.pixels[0]);
    }
}

/// Under a map whose colour follows the direction, each pixel of the mirror shows the map's
/// colour in its reflected direction, so that its upper half is greener than its lower and its
/// right half redder than its left.
#[test]
fn mirror_sphere_reflects_each_direction_of_a_map() {
    let map = Arc::new(direction_map());
    let tint = Vec3::splat(0.9);
    let scene = mirror_sphere(tint, Environment::Map(map.clone()));
    let (image, _) = draw(&scene, Method::Beam, false, 4, 48);
    let (mut worst, mut on) = (0.0f32, 0);
    for (i, p) in image.pixels.iter().enumerate() {
        let Some(r) = reflected(&scene, i) else { continue };
        on += 1;
        worst = worst.max((*p - tint * map.radiance(r)).abs().max_element());
    }
    assert!(on > 300 && worst < 0.05, "{on} pixels, largest difference from the map's {worst}");
    let (w, c) = (image.width as usize, image.width as usize / 2);
    let at = |x: usize, y: usize| image.pixels[y * w + x];
    let (top, bottom, left, right) = (at(c, c - 12), at(c, c + 12), at(c - 12, c), at(c + 12, c));
    assert!(top.y > bottom.y + 0.3, "top {top}, bottom {bottom}");
    assert!(right.x > left.x + 0.3, "right {right}, left {left}");
}

/// Eye rays that leave the scene see the environment: a constant one exactly, a map in the
/// direction of the pixel, by eye beams and by primary rays alike.
#[test]
fn eye_rays_that_miss_see_the_environment() {
    // One small triangle off to the side, so that the scene is not empty.
    let tri = Triangle::new(Vec3::new(50.0, 0.0, 0.0), Vec3::new(51.0, 0.0, 0.0), Vec3::new(50.0, 1.0, 0.0));
    let cam = camera(Vec3::ZERO, Vec3::new(0.3, 0.2, -1.0), 32);
    let materials = vec![Material::Diffuse { albedo: Vec3::splat(0.5) }];
    let mut scene = Scene::new("void".into(), vec![(tri, 0)], materials, Vec::new(), cam);
    let black = draw(&scene, Method::Beam, true, 4, 32).0;
    assert!(black.pixels.iter().all(|p| *p == Vec3::ZERO), "black by default");
    let sky = Vec3::new(0.25, 0.3, 0.4);
    scene.environment = Environment::Constant(sky);
    for (method, beams) in [(Method::Beam, true), (Method::Beam, false), (Method::Ray, false)] {
        let image = draw(&scene, method, beams, 4, 32).0;
        assert!(image.pixels.iter().all(|p| p.abs_diff_eq(sky, 1e-5)), "{method:?} {beams}");
    }
    let map = Arc::new(direction_map());
    scene.environment = Environment::Map(map.clone());
    let frame = scene.camera.frame();
    for (method, beams) in [(Method::Beam, true), (Method::Ray, false)] {
        let image = draw(&scene, method, beams, 4, 32).0;
        for (i, p) in image.pixels.iter().enumerate() {
            let want = map.radiance(scene.camera.pixel_ray(&frame, i).direction);
            assert!(p.abs_diff_eq(want, 0.01), "{method:?}: pixel {i} is {p}, the map {want}");
        }
    }
}

/// An unoccluded diffuse plane under a constant sky `L`, with no light of its own, receives the
/// irradiance `πL` and so shows `albedo·L`: exactly by shadow beams to the sky's faces, and by
/// cosine-weighted rays; and as much under a constant map, sampled by environment rays.
#[test]
fn open_plane_under_a_sky_shows_albedo_times_sky() {
    let s = 10.0;
    let (a, b, c, d) = (Vec3::new(-s, 0.0, -s), Vec3::new(s, 0.0, -s), Vec3::new(s, 0.0, s), Vec3::new(-s, 0.0, s));
    let triangles = vec![(Triangle::new(a, c, b), 0), (Triangle::new(a, d, c), 0)];
    let albedo = Vec3::new(0.8, 0.6, 0.4);
    let cam = Camera { up: Vec3::Z, ..camera(Vec3::new(0.0, 6.0, 0.0), Vec3::ZERO, 32) };
    let mut scene = Scene::new("plane".into(), triangles, vec![Material::Diffuse { albedo }], Vec::new(), cam);
    let sky = Vec3::new(0.3, 0.35, 0.4);
    let want = albedo * sky;
    scene.environment = Environment::Constant(sky);
    let (beam, stats) = draw(&scene, Method::Beam, true, 64, 32);
    assert_eq!(stats.environment_lights, 6);
    assert!(stats.shadow_beams > 0 && stats.exact_pixel_share == 1.0, "{stats:?}");
    for (i, p) in beam.pixels.iter().enumerate() {
        assert!(p.abs_diff_eq(want, 1e-4 * want.max_element()), "beam: pixel {i} is {p}, want {want}");
    }
    // Rays sample a constant sky over the hemisphere (cosine-weighted): every ray that leaves an
    // open plane brings `L`, so the estimate is exact there too.
    let (ray, stats) = draw(&scene, Method::Ray, false, 64, 32);
    assert_eq!((stats.environment_lights, stats.environment_rays), (0, 64 * 32 * 32));
    for (i, p) in ray.pixels.iter().enumerate() {
        assert!(p.abs_diff_eq(want, 1e-4), "ray: pixel {i} is {p}, want {want}");
    }
    // A map of the same constant radiance: every cosine-weighted ray brings `L`, so the estimate
    // `π/N Σ L` is `πL` exactly; counted as environment rays, and not exact pixels.
    scene.environment = Environment::Map(Arc::new(EnvironmentMap::new(4, 2, vec![sky; 8]).unwrap()));
    for method in [Method::Beam, Method::Ray] {
        let (image, stats) = draw(&scene, method, false, 16, 32);
        assert_eq!(stats.environment_lights, 0);
        assert_eq!(stats.environment_rays, 16 * 32 * 32, "{method:?}");
        for (i, p) in image.pixels.iter().enumerate() {
            assert!(p.abs_diff_eq(want, 1e-4), "{method:?} map: pixel {i} is {p}, want {want}");
        }
        if method == Method::Beam {
            assert_eq!(stats.exact_pixel_share, 0.0);
            assert!(stats.max_error_bound > 0.0);
        }
    }
}

/// A 2 × 2 × 2 box standing on a 24 × 24 plane, both diffuse of `albedo`, lit by `lights`, seen
/// at 32² from above and in front.
fn box_on_plane(albedo: Vec3, lights: Vec<beam_scene::scene::Light>) -> Scene {
    let s = 12.0;
    let (a, b, c, d) = (Vec3::new(-s, 0.0, -s), Vec3::new(s, 0.0, -s), Vec3::new(s, 0.0, s), Vec3::new(-s, 0.0, s));
    let mut triangles = vec![(Triangle::new(a, c, b), 0), (Triangle::new(a, d, c), 0)];
    let cube = mesh::cuboid(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
    triangles.extend(cube.triangles().into_iter().map(|t| (t, 0)));
    let cam = camera(Vec3::new(0.0, 7.0, 7.0), Vec3::ZERO, 32);
    Scene::new("box".into(), triangles, vec![Material::Diffuse { albedo }], lights, cam)
}

/// A box standing on the plane shadows the sky: points beside it receive less than `πL`, and the
/// beam and ray methods agree there within the rays' noise.
#[test]
fn sky_shadows_agree_between_beams_and_rays() {
    let albedo = Vec3::splat(0.7);
    let mut scene = box_on_plane(albedo, Vec::new());
    let sky = Vec3::splat(0.5);
    scene.environment = Environment::Constant(sky);
    let (beam, _) = draw(&scene, Method::Beam, false, 64, 32);
    let (ray, _) = draw(&scene, Method::Ray, false, 256, 32);
    let mean = |im: &Image| im.pixels.iter().map(|p| p.x).sum::<f32>() / im.pixels.len() as f32;
    let (mb, mr) = (mean(&beam), mean(&ray));
    assert!((mb - mr).abs() < 0.01 * mb, "beam {mb}, ray {mr}");
    let shadowed = beam.pixels.iter().filter(|p| p.x < 0.97 * albedo.x * sky.x).count();
    assert!(shadowed > 50, "{shadowed} pixels see less than the open sky");
    let most = beam.pixels.iter().map(|p| p.x).fold(0.0, f32::max);
    assert!(most <= albedo.x * sky.x * 1.0001, "no point gets more than πL: {most}");
}

/// The nonlinear beams (000) show the environment as rays do: each texel of a reflection beam that
/// leaves the scene carries the radiance along its own ray, so a mirror sphere under a constant sky
/// shows the sky times its tint and, under a map, the map's colour in each pixel's reflected
/// direction; the background is the sky. So does the Whitted reference.
#[test]
fn nonlinear_beams_show_the_environment() {
    use beam_cpu::nonlinear::{CpuBeams, render_smooth_reference_with};
    use beam_render::nonlinear::{CAUSTIC_STRATA, Degree, NonlinearOptions, render_nonlinear_with};
    let (sky, tint) = (Vec3::new(0.3, 0.5, 0.9), Vec3::new(0.9, 0.8, 0.6));
    let map = Arc::new(direction_map());
    for environment in [Environment::Constant(sky), Environment::Map(map.clone())] {
        let scene = mirror_sphere(tint, environment.clone());
        let options = NonlinearOptions {
            degree: Degree::S3,
            texels: 32,
            bounces: 2,
            caustic_strata: CAUSTIC_STRATA,
            shading: RenderOptions::exact(48, 48),
        };
        let beams = render_nonlinear_with(&scene, &options, &mut CpuBeams, &CpuBeams).expect("a frame").0;
        let reference = render_smooth_reference_with(&scene, &options.shading, 0, &CpuBeams).expect("a reference");
        let frame = scene.camera.frame();
        for (name, image) in [("beams", &beams), ("reference", &reference)] {
            let (mut worst, mut on) = (0.0f32, 0);
            for (i, p) in image.pixels.iter().enumerate() {
                let want = match reflected(&scene, i) {
                    Some(r) => {
                        on += 1;
                        tint * environment.radiance(r)
                    }
                    None if i == 0 => environment.radiance(scene.camera.pixel_ray(&frame, i).direction),
                    None => continue,
                };
                worst = worst.max((*p - want).abs().max_element());
            }
            let bound = if matches!(environment, Environment::Constant(_)) { 1e-4 } else { 0.05 };
            assert!(on > 300 && worst < bound, "{name}: {on} pixels, largest difference {worst} (bound {bound})");
        }
    }
}

/// The glossy light volumes (002) show the environment where their eye rays and Whitted rays leave
/// the scene: a mirror sphere under a constant sky (and a point light, which a mirror does not
/// show) shows the sky times its tint, and the background the sky.
#[test]
fn glossy_eye_rays_show_the_environment() {
    use beam_cpu::glossy::render_glossy;
    use beam_render::glossy::GlossyOptions;
    let (sky, tint) = (Vec3::new(0.3, 0.5, 0.9), Vec3::new(0.9, 0.8, 0.6));
    let mut scene = mirror_sphere(tint, Environment::Constant(sky));
    scene.lights = vec![beam_scene::scene::Light::Point { position: Vec3::new(0.0, 5.0, 5.0), intensity: Vec3::ONE }];
    let image = render_glossy(&scene, &GlossyOptions::new(48, 48)).expect("a render").0;
    let mut on = 0;
    for (i, p) in image.pixels.iter().enumerate() {
        let want = match reflected(&scene, i) {
            Some(_) => tint * sky,
            None if i == 0 => sky,
            None => continue,
        };
        on += u32::from(i != 0);
        assert!(p.abs_diff_eq(want, 1e-4), "pixel {i} is {p}, want {want}");
    }
    assert!(on > 300, "{on} pixels on the sphere");
}

/// The glossy light volumes (002) are lit by the environment as the other methods are (by
/// cosine-weighted rays, `SKY_RAYS` a point): the box on the plane under a constant sky and a
/// point light, by `--method glossy` and by the beam method (its sky exact), agree on average
/// within 1%, and the sky adds to the glossy image what it adds to the beam method's.
#[test]
fn glossy_volumes_are_lit_by_the_sky() {
    use beam_cpu::glossy::render_glossy;
    use beam_render::glossy::GlossyOptions;
    use beam_scene::scene::Light;
    let light = Light::Point { position: Vec3::new(3.0, 6.0, 2.0), intensity: Vec3::splat(20.0) };
    let mut scene = box_on_plane(Vec3::splat(0.7), vec![light]);
    let mean = |im: &Image| im.pixels.iter().map(|p| p.x).sum::<f32>() / im.pixels.len() as f32;
    let glossy = |scene: &Scene| mean(&render_glossy(scene, &GlossyOptions::new(32, 32)).expect("a render").0);
    let beam = |scene: &Scene| mean(&draw(scene, Method::Beam, false, 64, 32).0);
    let (dark_glossy, dark_beam) = (glossy(&scene), beam(&scene));
    scene.environment = Environment::Constant(Vec3::splat(0.5));
    let (lit_glossy, lit_beam) = (glossy(&scene), beam(&scene));
    eprintln!("glossy {dark_glossy} → {lit_glossy}, beam {dark_beam} → {lit_beam}");
    assert!((lit_glossy - lit_beam).abs() < 0.01 * lit_beam, "glossy {lit_glossy}, beam {lit_beam}");
    let (added_glossy, added_beam) = (lit_glossy - dark_glossy, lit_beam - dark_beam);
    assert!(added_beam > 0.1, "the sky adds {added_beam}");
    assert!((added_glossy - added_beam).abs() < 0.02 * added_beam, "the sky adds {added_glossy}, beams {added_beam}");
}
