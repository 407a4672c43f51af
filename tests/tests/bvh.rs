//! Thin `#[test]` wrappers: one per (property, backend) of the BVH.

use beam_conformance::{Backend, check};

#[test]
fn bvh_hits_equal_brute_force() {
    check("bvh_hits_equal_brute_force", Backend::Bvh);
}

#[test]
fn bvh_refit_hits_equal_brute_force() {
    check("bvh_refit_hits_equal_brute_force", Backend::Bvh);
}
