//! Thin `#[test]` wrappers: one per property of the BVH.

beam_conformance::conformance_tests!(
    beam_conformance::Backend::Bvh,
    bvh_hits_equal_brute_force,
    bvh_refit_hits_equal_brute_force,
);
