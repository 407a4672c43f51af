//! Thin `#[test]` wrappers: one per property that runs on beam-gpu, the GPU-only ones and those whose
//! body runs on the CPU and the GPU alike (SKIPPED without an adapter, a failure under
//! `BEAM_REQUIRE_GPU=1`).

beam_conformance::conformance_tests!(
    beam_conformance::Backend::Gpu,
    gpu_bounding_triangles_match_math,
    gpu_texel_rays_match_math,
    gpu_lookup_projections_equal_cpu,
    gpu_ray_hits_equal_cpu_hits,
    gpu_eye_view_equals_cpu,
    gpu_beam_texels_equal_cpu,
    gpu_cone_culling_equals_host,
    gpu_images_equal_cpu,
    gpu_coarse_smesh_equals_cpu,
    gpu_eye_locates_as_cpu,
    gpu_shading_equals_cpu,
    gpu_composite_equals_cpu,
    gpu_whitted_equals_cpu,
    gpu_images_fit_narrow_bindings,
    gpu_kept_level_equals_host_texels,
    gpu_kept_level_images_equal_read_back,
    gpu_summed_fits_equal_host_fits,
    gpu_glossy_gather_equals_cpu,
    gpu_glossy_gather_area_lights_equal_cpu,
    gpu_readbacks_reuse_buffers,
    nonlinear_texels_equal_ray_hits,
    nonlinear_images_vs_reference,
    bvh_hits_equal_brute_force,
    soft_shadow_closed_form,
    soft_shadow_vs_monte_carlo,
    gpu_shadow_beams_equal_cpu,
    gpu_images_of_beam_and_ray_equal_cpu,
);
