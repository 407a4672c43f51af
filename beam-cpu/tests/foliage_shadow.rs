//! The built-in foliage scene (`beam_scene::scene::foliage`) casts the shadow it is built for.

use beam_cpu::beam_math::glam::Vec3;
use beam_cpu::render::{BeamStats, visible_light};
use beam_scene::scene::foliage::{LEAVES, foliage};

#[test]
fn the_crown_shadows_the_ground_and_far_corners_see_the_whole_light() {
    let s = foliage(LEAVES, 1);
    let light = &s.lights[0];
    let fraction = |q: Vec3| {
        let vis = visible_light(&s.bvh, &s.triangles, q, &light.polygon(), light.normal(), &mut BeamStats::default());
        vis.expect("ground points see the light's front").fraction()
    };
    let umbra = fraction(Vec3::new(-1.5, 1e-3, 0.0));
    assert!(umbra < 0.5, "under the crown's shadow {umbra} of the light is visible");
    let corner = fraction(Vec3::new(-11.0, 1e-3, 11.0));
    assert!((corner - 1.0).abs() < 1e-4, "from a far corner {corner} of the light is visible");
}
