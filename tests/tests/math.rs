//! Thin `#[test]` wrappers: one per property of the math core.

beam_conformance::conformance_tests!(
    beam_conformance::Backend::Math,
    slab_vs_brute_force,
    watertight_ray_triangle,
    sat_vs_sampling,
    clipping_area_vs_monte_carlo,
    cone_sphere_vs_sampling,
    roots_vs_polynomial,
    projection_inverts_intersection,
    threshold_plane_unique_projection,
    bounding_triangle_s1,
    bounding_triangle_s3,
    bounding_triangle_bump,
    bounding_cone_contains_beam,
    polybeam_split_is_exact,
    gaussian_volume_vs_integration,
    gaussian_volume_continuous,
    glossy_irradiance_vs_integration,
    flux_triangle_vs_rays,
    projected_area_vs_sampling,
);
