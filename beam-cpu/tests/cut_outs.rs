//! Cut-out occluders cast the right shadows and are seen through: a leaf whose texture's alpha cuts
//! away its right half, between a floor and a small area light, renders as the opaque left half
//! alone does (rendered exactly by beams), within the noise of the shadow rays that sample the
//! lights the cut-out may hide; eye beams leave the regions that see it to primary rays. Seen in a
//! mirror floor, the nonlinear beams' texels see through it as rays do. Rendered through a backend
//! blind to alpha (as a GPU's ray tracer is), the host-driven frame sees through it too.

use beam_bvh::Hit;
use beam_cpu::nonlinear::render_nonlinear;
use beam_cpu::render::{light_seen, render, render_queries};
use beam_math::Ray;
use beam_math::Triangle;
use beam_math::glam::{Affine2, Vec2, Vec3};
use beam_render::BackendError;
use beam_render::image::Image;
use beam_render::nonlinear::Degree;
use beam_render::nonlinear::NonlinearOptions;
use beam_render::options::RenderOptions;
use beam_render::queries::{BeamQueries, LightPolygon, LightQuery, LightSeen, RayQueries};
use beam_scene::scene::surface::{AlphaCut, MaterialMaps, Surfaces, TextureRef};
use beam_scene::scene::texture::{Filter, Texture, Wrap};
use beam_scene::scene::{Bump, Camera, Light, Material, Scene};
use std::sync::Arc;

/// The two triangles of the rectangle `x ∈ [x0, x1], z ∈ [z0, z1]` at height `y`, facing up.
fn rectangle(x: [f32; 2], z: [f32; 2], y: f32) -> [Triangle; 2] {
    let p = |x: f32, z: f32| Vec3::new(x, y, z);
    let (a, b, c, d) = (p(x[0], z[0]), p(x[0], z[1]), p(x[1], z[1]), p(x[1], z[0]));
    [Triangle::new(a, b, c), Triangle::new(a, c, d)]
}

/// A floor (material 0) and, above it, a leaf (material 1) over `x ∈ [−1, leaf_end]`, under a
/// small area light; with `cut`, the leaf spans `x ∈ [−1, 1]` and a 2 × 1 texture's alpha cuts its
/// right half away.
fn scene(leaf_end: f32, cut: bool) -> Scene {
    let light = Light::Quad {
        corner: Vec3::new(-0.3, 2.0, -0.3),
        edge_u: Vec3::new(0.6, 0.0, 0.0),
        edge_v: Vec3::new(0.0, 0.0, 0.6),
        radiance: Vec3::splat(20.0),
    };
    leaf_over(Material::Diffuse { albedo: Vec3::splat(0.8) }, vec![light], leaf_end, cut)
}

/// [`scene`]'s leaf over a floor of `floor`, lit by `lights`; a mirror floor gets an emissive
/// ceiling (material 2) to reflect.
fn leaf_over(floor: Material, lights: Vec<Light>, leaf_end: f32, cut: bool) -> Scene {
    let mut triangles: Vec<(Triangle, u32)> = rectangle([-3.0, 3.0], [-3.0, 3.0], 0.0).map(|t| (t, 0)).to_vec();
    triangles.extend(rectangle([-1.0, leaf_end], [-0.6, 0.6], 1.0).map(|t| (t, 1)));
    let mut materials = vec![floor, Material::Diffuse { albedo: Vec3::new(0.3, 0.6, 0.2) }];
    if matches!(floor, Material::Mirror { .. }) {
        triangles.extend(rectangle([-8.0, 8.0], [-8.0, 8.0], 4.0).map(|t| (t, 2)));
        materials.push(Material::Emissive { radiance: Vec3::new(1.0, 0.8, 0.6) });
    }
    let camera = Camera {
        position: Vec3::new(0.0, 3.2, 2.6),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 50.0,
        width: 48,
        height: 48,
    };
    let mut surfaces = Surfaces::default();
    if cut {
        // u = (x + 1) / 2 on the leaf; the floor's coordinates are zeros (unused).
        let u = |t: &Triangle| t.v.map(|v| Vec2::new((v.x + 1.0) / 2.0, 0.5));
        surfaces.uv[0] = triangles.iter().map(|(t, m)| if *m == 1 { u(t) } else { [Vec2::ZERO; 3] }).collect();
        surfaces.textures.push(Texture {
            width: 2,
            height: 1,
            texels: Arc::new([[255, 255, 255, 255], [255, 255, 255, 0]]),
            wrap: [Wrap::ClampToEdge; 2],
            filter: Filter::Nearest,
        });
        let texture = TextureRef { texture: 0, tex_coord: 0, transform: Affine2::IDENTITY };
        let alpha = AlphaCut { factor: 1.0, texture: Some(texture), cutoff: Some(0.5) };
        surfaces.maps = vec![MaterialMaps::default(), MaterialMaps { alpha: Some(alpha), ..MaterialMaps::default() }];
    }
    Scene::with_surfaces("leaf".into(), triangles, materials, lights, camera, surfaces)
}

/// Root-mean-square difference of two images, over the mean of the second.
fn relative_rmse(a: &Image, b: &Image) -> f32 {
    let n = a.pixels.len() as f32;
    let mse = a.pixels.iter().zip(&b.pixels).map(|(p, q)| (*p - *q).length_squared()).sum::<f32>() / n;
    let mean = b.pixels.iter().map(|p| p.length()).sum::<f32>() / n;
    mse.sqrt() / mean
}

/// The default beam render's options at 48² with `spp` shadow rays where it samples.
fn options(primary_beams: bool) -> RenderOptions {
    RenderOptions { spp: 256, primary_spp: 16, primary_beams, exact: false, ..RenderOptions::exact(48, 48) }
}

#[test]
fn a_cut_out_leaf_shadows_and_shows_like_its_opaque_part() {
    let (cut, half, whole) = (scene(1.0, true), scene(0.0, false), scene(1.0, false));
    assert!(cut.has_cut_outs() && !half.has_cut_outs());
    for primary_beams in [false, true] {
        let o = options(primary_beams);
        let (reference, ref_stats) = render(&half, &o, || {});
        assert_eq!(ref_stats.cut_out_beams, 0);
        let (image, stats) = render(&cut, &o, || {});
        let (opaque, _) = render(&whole, &o, || {});
        let error = relative_rmse(&image, &reference);
        let opaque_error = relative_rmse(&opaque, &reference);
        assert!(stats.cut_out_beams > 0, "the lights the leaf may hide are sampled");
        // Shadow rays' noise alone: 0.002 here. With eye beams, the regions that see the leaf take
        // 2 × 2 primary rays a pixel, whose edges alias against exact coverage: 0.06.
        let bound = if primary_beams { 0.1 } else { 0.01 };
        assert!(error < bound, "eye beams {primary_beams}: relative RMSE {error} against the opaque half");
        assert!(opaque_error > 8.0 * error, "an opaque whole leaf differs: {opaque_error} against {error}");
        if primary_beams {
            assert!(stats.cut_out_regions > 0 && stats.ray_pixels > 0, "regions that see the leaf go to rays");
        }
    }
}

/// Pixels of `a` that differ from `b`'s by more than `tolerance` in some channel.
fn differing(a: &Image, b: &Image, tolerance: f32) -> usize {
    a.pixels.iter().zip(&b.pixels).filter(|(p, q)| (**p - **q).abs().max_element() > tolerance).count()
}

/// The leaf over a mirror floor, under an emissive ceiling and no light: the mirror shows the
/// ceiling where the leaf does not hide it, and the leaf's unlit underside where it does. The
/// nonlinear beams' texels (000 Alg. 1) test the leaf's alpha at their hits and go on to the
/// ceiling where it is cut away, as rays do: the cut leaf renders as its opaque half alone does,
/// but for the pixels on the cut's edge, and not as the whole leaf does.
#[test]
fn nonlinear_beams_see_through_a_cut_out_as_rays_do() {
    let mirror = Material::Mirror { tint: Vec3::ONE, bump: Bump::NONE };
    let scenes = [(1.0, true), (0.0, false), (1.0, false)].map(|(end, cut)| leaf_over(mirror, Vec::new(), end, cut));
    let shading = RenderOptions::exact(48, 48);
    let options = NonlinearOptions { degree: Degree::S3, texels: 16, bounces: 1, caustic_strata: 0, shading };
    let [cut, half, whole] = scenes.map(|s| render_nonlinear(&s, &options).expect("a render").0);
    let n = cut.pixels.len();
    let (apart, from_whole) = (differing(&cut, &half, 1e-3), differing(&cut, &whole, 1e-3));
    assert!(apart * 100 <= n, "{apart} of {n} pixels differ from the opaque half's");
    assert!(from_whole * 10 >= n, "only {from_whole} of {n} pixels differ from the whole leaf's");
}

/// A backend blind to alpha, as a GPU's ray tracer and shadow beams are: every triangle opaque.
struct AlphaBlind;

impl RayQueries for AlphaBlind {
    fn closest_hits(&self, scene: &Scene, rays: &[Ray]) -> Result<Vec<Option<Hit>>, BackendError> {
        Ok(rays.iter().map(|&r| scene.bvh.closest_hit(&scene.triangles, r, f32::INFINITY)).collect())
    }

    fn any_hits(&self, scene: &Scene, segments: &[(Ray, f32)]) -> Result<Vec<bool>, BackendError> {
        Ok(segments.iter().map(|&(r, t_max)| scene.bvh.any_hit(&scene.triangles, r, t_max)).collect())
    }
}

impl BeamQueries for AlphaBlind {
    fn light_visibility(
        &self,
        scene: &Scene,
        lights: &[LightPolygon],
        queries: &[LightQuery],
    ) -> Result<Vec<Option<LightSeen>>, BackendError> {
        Ok(queries
            .iter()
            .map(|q| Some(light_seen(&scene.bvh, &scene.triangles, &lights[q.light as usize], q)))
            .collect())
    }
}

/// The host-driven frame (`render_queries`, the GPU's) sees through cut-outs whatever its backend
/// sees: the leaf's hits are checked against its alpha and the rays sent on, the light it may hide
/// is sampled by shadow rays, and a frame that may see it goes to primary rays. Through a backend
/// blind to alpha, the cut leaf renders as the CPU renders its opaque half, and not as the whole
/// leaf renders.
#[test]
fn a_backend_blind_to_alpha_sees_through_cut_outs() {
    let (cut, half, whole) = (scene(1.0, true), scene(0.0, false), scene(1.0, false));
    for primary_beams in [false, true] {
        let o = RenderOptions { spp: 256, primary_spp: 16, primary_beams, ..RenderOptions::exact(48, 48) };
        let (reference, _) = render(&half, &o, || {});
        let (image, stats) = render_queries(&cut, &o, &AlphaBlind, || {}).expect("a render");
        let (opaque, _) = render_queries(&whole, &o, &AlphaBlind, || {}).expect("a render");
        let (error, opaque_error) = (relative_rmse(&image, &reference), relative_rmse(&opaque, &reference));
        eprintln!("eye beams {primary_beams}: relative RMSE {error}; the whole leaf's {opaque_error}");
        assert!(stats.cut_out_beams > 0, "the lights the leaf may hide are sampled");
        assert_eq!(stats.cut_out_regions, u64::from(primary_beams), "a frame that sees the leaf goes to rays");
        // 16 primary rays a pixel against exact coverage alias at the edges with eye beams.
        let bound = if primary_beams { 0.1 } else { 0.01 };
        assert!(error < bound, "eye beams {primary_beams}: relative RMSE {error} against the opaque half");
        assert!(opaque_error > 8.0 * error, "an opaque whole leaf differs: {opaque_error} against {error}");
    }
}

/// With several bands of rows, only those that may see a cut-out go to primary rays: a 512 × 64
/// frame (two bands of 32 rows) whose lower half alone sees the leaf keeps its eye beams in the
/// upper half, and renders as the CPU renders the opaque half.
#[test]
fn only_the_bands_that_see_a_cut_out_go_to_rays() {
    let framed = |mut s: Scene| {
        s.camera = Camera { target: Vec3::new(0.0, 0.0, -2.5), width: 512, height: 64, ..s.camera };
        s
    };
    let (cut, half) = (framed(scene(1.0, true)), framed(scene(0.0, false)));
    let o = RenderOptions { spp: 64, primary_spp: 16, primary_beams: true, ..RenderOptions::exact(512, 64) };
    let (reference, _) = render(&half, &o, || {});
    let (image, stats) = render_queries(&cut, &o, &AlphaBlind, || {}).expect("a render");
    let error = relative_rmse(&image, &reference);
    eprintln!(
        "{} regions by rays, {} ray pixels, {} fragments; relative RMSE {error}",
        stats.cut_out_regions, stats.ray_pixels, stats.fragments
    );
    assert_eq!((stats.cut_out_regions, stats.ray_pixels), (1, 512 * 32), "the lower band alone sees the leaf");
    // The upper band sees the far floor's edge, the rest sky: its fragments are the eye beams'.
    assert!(stats.fragments > 100, "the upper band keeps its eye beams: {} fragments", stats.fragments);
    assert!(error < 0.1, "relative RMSE {error} against the opaque half");
}

/// The glossy light volumes' eye rays blend a `BLEND` pane as `beam` and `ray` do (front to back,
/// without noise): a pane of alpha ¼ over a sky shows ¼ of the opaque pane's radiance and ¾ of the
/// sky in every pixel, where one stochastic ray a pixel would show one or the other.
#[test]
fn glossy_eye_rays_blend_a_pane() {
    use beam_cpu::glossy::render_glossy;
    use beam_render::glossy::GlossyOptions;
    use beam_scene::scene::Environment;
    let sky = Vec3::new(0.2, 0.3, 0.5);
    let pane = |alpha: Option<f32>| {
        let triangles = rectangle([-1.0, 1.0], [-1.0, 1.0], 0.0).map(|t| (t, 0)).to_vec();
        let materials = vec![Material::Diffuse { albedo: Vec3::splat(0.8) }];
        let lights = vec![Light::Point { position: Vec3::new(0.0, 3.0, 0.0), intensity: Vec3::splat(20.0) }];
        let camera = Camera {
            position: Vec3::new(0.0, 3.0, 1.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y: 60.0,
            width: 32,
            height: 32,
        };
        let mut surfaces = Surfaces::default();
        if let Some(factor) = alpha {
            let alpha = Some(AlphaCut { factor, texture: None, cutoff: None });
            surfaces.maps = vec![MaterialMaps { alpha, ..MaterialMaps::default() }];
        }
        let mut scene = Scene::with_surfaces("pane".into(), triangles, materials, lights, camera, surfaces);
        scene.environment = Environment::Constant(sky);
        render_glossy(&scene, &GlossyOptions::new(32, 32)).expect("a render").0
    };
    let (opaque, blended) = (pane(None), pane(Some(0.25)));
    let mut on = 0;
    for (i, (o, b)) in opaque.pixels.iter().zip(&blended.pixels).enumerate() {
        on += u32::from(*o != sky);
        let want = if *o == sky { sky } else { 0.25 * *o + 0.75 * sky };
        assert!(b.abs_diff_eq(want, 1e-4), "pixel {i}: {b}, want {want}");
    }
    assert!(on > 200, "{on} pixels on the pane");
}
