//! Thin `#[test]` wrappers: one per (property, backend) of the CPU renderers.

use beam_conformance::{Backend, check};

#[test]
fn soft_shadow_closed_form() {
    check("soft_shadow_closed_form", Backend::Cpu);
}

#[test]
fn soft_shadow_vs_monte_carlo() {
    check("soft_shadow_vs_monte_carlo", Backend::Cpu);
}

#[test]
fn beam_and_ray_images_agree() {
    check("beam_and_ray_images_agree", Backend::Cpu);
}

#[test]
fn primary_coverage_sums_to_one() {
    check("primary_coverage_sums_to_one", Backend::Cpu);
}
