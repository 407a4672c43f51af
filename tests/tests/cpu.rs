//! Thin `#[test]` wrappers: one per property of the CPU renderers.

beam_conformance::conformance_tests!(
    beam_conformance::Backend::Cpu,
    soft_shadow_closed_form,
    soft_shadow_vs_monte_carlo,
    beam_and_ray_images_agree,
    hard_shadow_images_agree,
    primary_coverage_sums_to_one,
);
