//! Thin `#[test]` wrappers: one per property of the nonlinear beam tracer.

beam_conformance::conformance_tests!(
    beam_conformance::Backend::Cpu,
    nonlinear_texels_equal_ray_hits,
    nonlinear_images_vs_reference,
    caustics_match_photon_tracing,
    s3_removes_s1_kinks,
);
