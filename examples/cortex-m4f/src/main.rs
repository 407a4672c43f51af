//! beam-math on a Cortex-M4F, without an allocator or the standard library.
//!
//! A point on a floor sees a square area light past two occluding triangles. The light's visible
//! fraction — the exact soft-shadow term of 001 — is the area of the shadow beam's cross-section
//! left after splitting it by each triangle (001 §3.2), over the area it started with. Here the
//! triangles hide exactly a half and a quarter of the light, so the answer is exactly 1/4. The
//! collision routines (004 App. A) check it from two more sides: a watertight ray–triangle hit and
//! the separating-axis frustum–box test that culls a BVH node against the beam.
//!
//! Build: `cargo build --release` in this folder (the target is set in `.cargo/config.toml`).
//! Run under QEMU's STM32F405 board (`qemu-system-arm`): `cargo run --release`. It prints the
//! results by semihosting and exits with status 0 when every check holds.

#![no_std]
#![no_main]

use beam_math::collide::{Frustum, frustum_aabb, ray_triangle};
use beam_math::glam::Vec3;
use beam_math::polybeam::{BeamFrame, PolyBeam, Section};
use beam_math::{Aabb, Ray, Triangle};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_halt as _;

/// The shaded point, apex of the shadow beam.
const POINT: Vec3 = Vec3::ZERO;
/// Half the side of the square light, at height [`LIGHT_Y`], centred above the point.
const LIGHT_HALF: f32 = 0.5;
const LIGHT_Y: f32 = 2.0;

/// Seen from the point, this triangle (at height 1, half way) covers the light's half `x < 0`.
const HALF: Triangle = Triangle::new(Vec3::new(0.0, 1.0, -1.0), Vec3::new(0.0, 1.0, 1.0), Vec3::new(-1.0, 1.0, 0.0));
/// And this one its quarter `x ≥ 0, z ≥ 0`.
const QUARTER: Triangle = Triangle::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.5));

/// Fuzzy side-test tolerance, a fraction of a section's size (001 App. A).
const EPS: f32 = 1e-5;

#[entry]
fn main() -> ! {
    let ok = soft_shadow() & ray_hit() & culling();
    hprintln!("{}", if ok { "all checks hold" } else { "a check FAILED" });
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    loop {
        core::hint::spin_loop();
    }
}

/// The light's corners, counter-clockwise seen from below.
fn light_corners() -> [Vec3; 4] {
    let (h, y) = (LIGHT_HALF, LIGHT_Y);
    [Vec3::new(-h, y, -h), Vec3::new(h, y, -h), Vec3::new(h, y, h), Vec3::new(-h, y, h)]
}

/// The visible fraction of the light by exact beam splitting: the beam's miss pieces after the
/// first triangle are split by the second, and what misses both is what the point sees.
fn soft_shadow() -> bool {
    let Some(frame) = BeamFrame::new(POINT, Vec3::new(0.0, LIGHT_Y, 0.0), Vec3::Y, Vec3::X) else {
        return false;
    };
    let Some(beam) = PolyBeam::new(frame, &light_corners()) else {
        return false;
    };
    // Depths in units of the reference-plane distance: the occluders count between the point (0)
    // and the light (1).
    let (near, far) = (0.0, 1.0);
    let mut visible = 0.0;
    let mut pieces = 0;
    let Ok(first) = beam.split(&HALF, near, far, EPS) else {
        return false;
    };
    for section in first.miss.iter() {
        let piece = PolyBeam { frame, section: *section };
        let Ok(second) = piece.split(&QUARTER, near, far, EPS) else {
            return false;
        };
        visible += second.miss.iter().map(Section::area).sum::<f32>();
        pieces += second.miss.len();
    }
    let fraction = visible / beam.area();
    hprintln!("soft shadow: light visible {} (exact 0.25) in {} pieces", fraction, pieces);
    (fraction - 0.25).abs() < 1e-5
}

/// A ray from the point to a spot of the light behind the first triangle hits it half way.
fn ray_hit() -> bool {
    let ray = Ray::new(POINT, Vec3::new(-0.25, LIGHT_Y, 0.1));
    let hit = ray_triangle(ray, &HALF);
    hprintln!("ray-triangle: t = {:?} (exact 0.5)", hit.map(|h| h.t));
    hit.is_some_and(|h| (h.t - 0.5).abs() < 1e-6)
}

/// The shadow beam's frustum meets a box around the second triangle and misses one off to the side.
fn culling() -> bool {
    let dirs = light_corners().map(|c| c - POINT);
    let frustum = Frustum::from_apex(POINT, dirs, Vec3::Y, 0.1, LIGHT_Y);
    let near_box = Aabb::from_points(&QUARTER.v);
    let far_box = Aabb::from_points(&[Vec3::new(3.0, 0.5, 3.0), Vec3::new(4.0, 1.5, 4.0)]);
    let (meets, misses) = (frustum_aabb(&frustum, near_box), !frustum_aabb(&frustum, far_box));
    hprintln!("frustum-box: occluder's box met {}, box beside the beam culled {}", meets, misses);
    meets && misses
}
