//! Thin `#[test]` wrappers: one per property of the CPU renderers (001 beams and 000 nonlinear beams).

beam_conformance::conformance_tests!(
    beam_conformance::Backend::Cpu,
    soft_shadow_closed_form,
    soft_shadow_vs_monte_carlo,
    beam_and_ray_images_agree,
    hard_shadow_images_agree,
    silhouettes_equal_splitting,
    sampled_beams_stay_in_their_bound,
    primary_coverage_sums_to_one,
    nonlinear_texels_equal_ray_hits,
    nonlinear_images_vs_reference,
    caustics_match_photon_tracing,
    area_light_caustics_converge,
    s3_removes_s1_kinks,
    glossy_shadow_beams_equal_shadow_rays,
    glossy_cone_hierarchy_is_conservative,
    glossy_beams_match_photon_tracing,
    glossy_splat_equals_integrated_gather,
);
