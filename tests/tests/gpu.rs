//! Thin `#[test]` wrappers: one per property of beam-gpu (skipped, saying why, without an adapter).

beam_conformance::conformance_tests!(
    beam_conformance::Backend::Gpu,
    gpu_bounding_triangles_match_math,
    gpu_texel_rays_match_math,
    gpu_ray_hits_equal_cpu_hits,
    gpu_beam_texels_equal_cpu,
    gpu_images_equal_cpu,
    gpu_shading_equals_cpu,
    gpu_composite_equals_cpu,
    gpu_glossy_gather_equals_cpu,
    gpu_glossy_gather_area_lights_equal_cpu,
);
