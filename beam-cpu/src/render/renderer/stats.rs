//! What a render did ([`RenderStats`], written as the stats JSON) and the per-thread counters it is
//! summed from.

use crate::render::shadow_beam::BeamStats;
use beam_render::options::{Method, RenderOptions, Shading};
use beam_scene::scene::Scene;

/// What a render did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct RenderStats {
    /// Wall time of the render, seconds.
    pub seconds: f64,
    /// `beam` or `ray`.
    pub method: String,
    /// `fraction` (eq. 2) or `exact` (eq. 1).
    pub shading: String,
    /// Shadow rays per shade point and light (0 for beams).
    pub spp: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Triangles rendered.
    pub triangles: usize,
    /// Degenerate triangles filtered out at load.
    pub degenerate_triangles: usize,
    /// Area lights joined into a neighbour at load (`SceneStats::merged_lights`).
    pub merged_lights: usize,
    /// Content of the scene not used, by kind (`Scene::notices`).
    pub notices: Vec<beam_scene::scene::Notice>,
    /// Primary and secondary (mirror, glass) rays.
    pub camera_rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Shadow beams traced.
    pub shadow_beams: u64,
    /// Shadow beams a backend of [`render_queries`](crate::render::render_queries) gave up on past
    /// its limits (pieces or work past a fixed capacity), traced by the host instead (0 for
    /// [`render`](crate::render::render)).
    pub overflow_beams: u64,
    /// Pixels whose eye beam a backend of [`render_queries`](crate::render::render_queries) gave
    /// up on past its limits, their exact primary visibility computed by the host instead.
    pub overflow_pixels: u64,
    /// BVH nodes tested by shadow beams.
    pub bvh_steps: u64,
    /// Beam–triangle splits.
    pub intersections: u64,
    /// Hit pieces produced by shadow beams.
    pub hit_beams: u64,
    /// `hit_beams / pixels`.
    pub hit_beams_per_pixel: f64,
    /// BVH nodes tested by eye beams.
    pub primary_bvh_steps: u64,
    /// Eye-beam–triangle splits.
    pub primary_intersections: u64,
    /// Hit pieces produced by eye beams.
    pub primary_hit_beams: u64,
    /// Distinct triangles seen by the eye beams.
    pub visible_triangles: u64,
    /// `primary_hit_beams / visible_triangles` (001 Fig. 5).
    pub hit_beams_per_visible_triangle: f64,
    /// Shaded fragments (a visible piece within a pixel) of the eye beams.
    pub fragments: u64,
    /// Points the eye beams' fragments were shaded at: a pixel's fragments that see one smooth
    /// stretch of surface are shaded once.
    pub shade_points: u64,
    /// Slivers of edge pixels (at most a quarter of the pixel) shaded at a neighbouring pixel's
    /// point of their stretch of surface instead of their own; none with `--exact`.
    pub lent_fragments: u64,
    /// Pixels whose primary visibility was sampled by primary rays (one through the centre, one
    /// more in each quarter an edge may cross) because their region's eye beam would have cost more than its
    /// budget (sub-pixel triangles, `render/eye_budget.rs`): predicted from a grid of rays, or
    /// found while tracing it; none with `--exact`.
    pub ray_pixels: u64,
    /// Eye beams stopped while tracing, past that budget (their regions are in `ray_pixels`).
    pub over_budget_regions: u64,
    /// Shadow beams met by a triangle between the shade point and their near plane (geometry in
    /// contact with the point: crossing leaves, an object sunk into the floor), whose light was
    /// sampled instead (also in `sampled_beams`); none with `--exact`.
    pub contact_beams: u64,
    /// Shadow beams whose light a cut-out triangle (`alphaMode` `MASK` or `BLEND`) may hide part
    /// of (a shaft test a cluster of shade points), sampled by shadow rays that see through the
    /// cut-outs instead (in `sampled_beams` too, where the light is above the point's horizon),
    /// with `--exact` too.
    pub cut_out_beams: u64,
    /// Eye-beam regions whose view meets a cut-out triangle, sampled by primary rays instead
    /// (their pixels are in `ray_pixels`), with `--exact` too.
    pub cut_out_regions: u64,
    /// Largest `|1 − Σ coverage|` of a pixel (exact coverage sums to one).
    pub coverage_error: f64,
    /// Triangles set up against shadow beams (projected once each).
    pub triangle_tests: u64,
    /// Miss pieces made by shadow-beam splits.
    pub pieces: u64,
    /// Shafts traced (one per cluster of a tile's shade points and area light), whose candidates
    /// replace the shadow beams' own BVH traversals; where beams do not pay (fewer than 16 rays a
    /// light), shafts tested for whether a block of points sees the whole light.
    pub shafts: u64,
    /// BVH nodes tested by the shafts: 8-wide nodes (eight boxes each) for the candidates, binary
    /// ones where a shaft only asks whether a block sees the whole light.
    pub shaft_bvh_steps: u64,
    /// Shadow beams whose occluders entered by their edges (silhouettes, boundaries and depth
    /// cuts) instead of splitting them one at a time.
    pub silhouette_beams: u64,
    /// Projected edges those beams weighed over their lights.
    pub silhouette_edges: u64,
    /// Edge passes given up on an exact tie or too many edges (those beams were split instead).
    pub silhouette_fallbacks: u64,
    /// Shadow beams that ran past their budget (`--spp` rays' worth of work) and sampled the part
    /// of the light they left unresolved (none with `--exact`).
    pub sampled_beams: u64,
    /// Area lights left out of a tile's shading because they face away from the box of its shade
    /// points, summed over tiles.
    pub culled_lights: u64,
    /// The scene's environment: `black`, `constant` (a uniform sky) or `map W×H`.
    pub environment: String,
    /// Area lights a constant environment is shaded as with `beam`: the six faces of a cube about
    /// the scene, of the sky's radiance (its light exactly, with exact shadow beams), added to the
    /// scene's lights; 0 otherwise.
    pub environment_lights: usize,
    /// Rays that sampled the environment's light at diffuse points, `--spp` cosine-weighted
    /// directions a point: a map's with either method, a constant sky's with `ray` (a pixel shaded
    /// with them is not exact).
    pub environment_rays: u64,
    /// Share of the pixels whose every shadow beam was exact.
    pub exact_pixel_share: f64,
    /// Largest bound on a shade point's radiance error from the sampled parts: the sampled part's
    /// unoccluded radiance (the exact value lies between 0 and it, and the estimate too).
    pub max_error_bound: f32,
    /// Thread-seconds spent on primary visibility (rays or eye beams), summed over threads.
    pub primary_seconds: f64,
    /// Thread-seconds spent on shadow beams and shafts (or shadow rays' shading), summed over threads.
    pub shadow_seconds: f64,
    /// Thread-seconds spent on the rest of the shading, summed over threads.
    pub shading_seconds: f64,
}

impl RenderStats {
    /// The stats of a render of `scene` with `options` that took `seconds`: an image of
    /// `width × height` pixels, `total` the counters summed over its parts, `visible_triangles` the
    /// distinct triangles its eye beams saw, `environment_lights` the area lights a constant
    /// environment was shaded as.
    pub(super) fn summed(
        scene: &Scene,
        options: &RenderOptions,
        (width, height): (u32, u32),
        total: &Counters,
        visible_triangles: u64,
        environment_lights: usize,
        seconds: f64,
    ) -> Self {
        let pixels = (width as f64 * height as f64).max(1.0);
        Self {
            seconds,
            method: match options.method {
                Method::Beam => "beam",
                Method::Ray => "ray",
            }
            .into(),
            shading: match options.shading {
                Shading::Fraction => "fraction",
                Shading::Exact => "exact",
            }
            .into(),
            spp: if options.method == Method::Ray { options.spp } else { 0 },
            width,
            height,
            triangles: scene.stats.triangles,
            degenerate_triangles: scene.stats.degenerate,
            merged_lights: scene.stats.merged_lights,
            notices: scene.notices.clone(),
            camera_rays: total.camera_rays,
            shadow_rays: total.shadow_rays,
            shadow_beams: total.shadow_beams,
            overflow_beams: total.overflow_beams,
            overflow_pixels: total.overflow_pixels,
            bvh_steps: total.beams.bvh_steps,
            intersections: total.beams.intersections,
            hit_beams: total.beams.hit_beams,
            hit_beams_per_pixel: total.beams.hit_beams as f64 / pixels,
            primary_bvh_steps: total.primary.bvh_steps,
            primary_intersections: total.primary.intersections,
            primary_hit_beams: total.primary.hit_beams,
            visible_triangles,
            hit_beams_per_visible_triangle: total.primary.hit_beams as f64 / visible_triangles.max(1) as f64,
            fragments: total.fragments,
            shade_points: total.shade_points,
            lent_fragments: total.lent_fragments,
            ray_pixels: total.ray_pixels,
            over_budget_regions: total.over_budget,
            contact_beams: total.contact_beams,
            cut_out_beams: total.cut_out_beams,
            cut_out_regions: total.cut_out_regions,
            coverage_error: total.coverage_error,
            triangle_tests: total.beams.triangle_tests,
            pieces: total.beams.pieces,
            silhouette_beams: total.beams.silhouette_beams,
            silhouette_edges: total.beams.silhouette_edges,
            silhouette_fallbacks: total.beams.silhouette_fallbacks,
            sampled_beams: total.sampled_beams,
            culled_lights: total.culled_lights,
            environment: scene.environment.describe(),
            environment_lights,
            environment_rays: total.environment_rays,
            exact_pixel_share: 1.0 - total.inexact_pixels as f64 / pixels,
            max_error_bound: total.max_error_bound,
            shafts: total.shafts,
            shaft_bvh_steps: total.shaft_bvh_steps,
            primary_seconds: total.primary_seconds,
            shadow_seconds: total.shadow_seconds,
            shading_seconds: total.shading_seconds,
        }
    }
}

/// Per-thread accumulators.
#[derive(Default, Clone, Copy)]
pub(super) struct Counters {
    pub(super) camera_rays: u64,
    pub(super) shadow_rays: u64,
    pub(super) shadow_beams: u64,
    pub(super) overflow_beams: u64,
    pub(super) overflow_pixels: u64,
    pub(super) beams: BeamStats,
    pub(super) primary: BeamStats,
    pub(super) fragments: u64,
    pub(super) shade_points: u64,
    pub(super) lent_fragments: u64,
    pub(super) ray_pixels: u64,
    pub(super) over_budget: u64,
    pub(super) contact_beams: u64,
    pub(super) cut_out_beams: u64,
    pub(super) cut_out_regions: u64,
    pub(super) sampled_beams: u64,
    pub(super) inexact_pixels: u64,
    pub(super) culled_lights: u64,
    pub(super) environment_rays: u64,
    /// Unoccluded irradiance (times radiance) sampled for the shade point being shaded.
    pub(super) pending_bound: f32,
    pub(super) max_error_bound: f32,
    pub(super) coverage_error: f64,
    pub(super) shafts: u64,
    pub(super) shaft_bvh_steps: u64,
    pub(super) primary_seconds: f64,
    pub(super) shadow_seconds: f64,
    pub(super) shading_seconds: f64,
}

impl Counters {
    /// What was counted since `before` (a copy of these counters taken earlier); the largest
    /// coverage error is kept as it is.
    pub(super) fn since(&self, before: &Self) -> Self {
        let d = |a: u64, b: u64| a - b;
        Self {
            camera_rays: d(self.camera_rays, before.camera_rays),
            shadow_rays: d(self.shadow_rays, before.shadow_rays),
            shadow_beams: d(self.shadow_beams, before.shadow_beams),
            overflow_beams: d(self.overflow_beams, before.overflow_beams),
            overflow_pixels: d(self.overflow_pixels, before.overflow_pixels),
            beams: self.beams.since(&before.beams),
            primary: self.primary.since(&before.primary),
            fragments: d(self.fragments, before.fragments),
            shade_points: d(self.shade_points, before.shade_points),
            lent_fragments: d(self.lent_fragments, before.lent_fragments),
            ray_pixels: d(self.ray_pixels, before.ray_pixels),
            over_budget: d(self.over_budget, before.over_budget),
            contact_beams: d(self.contact_beams, before.contact_beams),
            cut_out_beams: d(self.cut_out_beams, before.cut_out_beams),
            cut_out_regions: d(self.cut_out_regions, before.cut_out_regions),
            sampled_beams: d(self.sampled_beams, before.sampled_beams),
            inexact_pixels: d(self.inexact_pixels, before.inexact_pixels),
            culled_lights: d(self.culled_lights, before.culled_lights),
            environment_rays: d(self.environment_rays, before.environment_rays),
            pending_bound: 0.0,
            max_error_bound: self.max_error_bound,
            coverage_error: self.coverage_error,
            shafts: d(self.shafts, before.shafts),
            shaft_bvh_steps: d(self.shaft_bvh_steps, before.shaft_bvh_steps),
            primary_seconds: self.primary_seconds - before.primary_seconds,
            shadow_seconds: self.shadow_seconds - before.shadow_seconds,
            shading_seconds: self.shading_seconds - before.shading_seconds,
        }
    }
}

impl core::ops::AddAssign for Counters {
    fn add_assign(&mut self, o: Self) {
        self.camera_rays += o.camera_rays;
        self.shadow_rays += o.shadow_rays;
        self.shadow_beams += o.shadow_beams;
        self.overflow_beams += o.overflow_beams;
        self.overflow_pixels += o.overflow_pixels;
        self.beams += o.beams;
        self.primary += o.primary;
        self.fragments += o.fragments;
        self.shade_points += o.shade_points;
        self.lent_fragments += o.lent_fragments;
        self.ray_pixels += o.ray_pixels;
        self.over_budget += o.over_budget;
        self.contact_beams += o.contact_beams;
        self.cut_out_beams += o.cut_out_beams;
        self.cut_out_regions += o.cut_out_regions;
        self.sampled_beams += o.sampled_beams;
        self.inexact_pixels += o.inexact_pixels;
        self.culled_lights += o.culled_lights;
        self.environment_rays += o.environment_rays;
        self.max_error_bound = self.max_error_bound.max(o.max_error_bound);
        self.coverage_error = self.coverage_error.max(o.coverage_error);
        self.shafts += o.shafts;
        self.shaft_bvh_steps += o.shaft_bvh_steps;
        self.primary_seconds += o.primary_seconds;
        self.shadow_seconds += o.shadow_seconds;
        self.shading_seconds += o.shading_seconds;
    }
}
