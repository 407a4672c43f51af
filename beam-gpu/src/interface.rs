//! The numbers the WGSL shaders share with Rust, in one table ([`CONSTANTS`]): the traversal stack
//! and workgroup sizes, sentinels, the codes of kinds and flags, limits, and the tolerances of the
//! CPU twins. [`crate::shaders::source`] writes them into every shader as WGSL `const`
//! declarations ([`wgsl`]); the shaders declare none of them themselves, and the pipelines use the
//! Rust constants below. The tests of this module check that (`constants_match`), every
//! `#[repr(C)]` struct against naga's layout of its WGSL twin (`twins`), and every binding index
//! and element size against the order the pipelines bind their buffers in (`bindings`).

use beam_bvh::gpu::GPU_STACK_SIZE;
use std::fmt::Write;

#[cfg(test)]
mod bindings;
#[cfg(test)]
mod constants_match;
#[cfg(test)]
mod parsed;
#[cfg(test)]
mod twins;

/// Invocations per workgroup of every compute entry point (`@workgroup_size(WORKGROUP_SIZE)`): the
/// pipelines dispatch `⌈items / WORKGROUP_SIZE⌉` groups, and the shaders that take more than 65,535
/// of them fold `y` into their index (`id.y * groups.x * WORKGROUP_SIZE + id.x`).
pub const WORKGROUP_SIZE: u32 = 64;

/// Entries of `trace_ray`'s traversal stack ([`beam_bvh::gpu::GPU_STACK_SIZE`], which
/// [`beam_bvh::gpu::GpuBvh::new`] checks every tree against).
pub const TRAVERSAL_STACK: u32 = GPU_STACK_SIZE as u32;

/// `prim` of a ray that hit nothing ([`crate::raytrace::GpuHit`]).
pub const MISS: u32 = u32::MAX;

/// `light` of a point whose shading is done ([`crate::shade::ShadeState`]).
pub const SHADED: u32 = u32::MAX;

/// "None" in a `u32`: in [`crate::nonlinear::CompositeRecord`], a face without a refraction beam;
/// in `shadow_beam.wgsl`'s walk together, no stack slot to skip from.
pub const NONE: u32 = u32::MAX;

/// `kind` of a closest-hit ray ([`crate::raytrace::GpuRay`]).
pub const RAY_CLOSEST: u32 = 0;

/// `kind` of an any-hit (shadow) ray.
pub const RAY_ANY: u32 = 1;

/// `kind` of a point light ([`crate::shade::GpuLight`]).
pub const LIGHT_POINT: u32 = 0;

/// `kind` of a quad light.
pub const LIGHT_QUAD: u32 = 1;

/// `kind` of a triangle light.
pub const LIGHT_TRIANGLE: u32 = 2;

/// `kind` of a diffuse or glossy triangle ([`crate::shade::PrimShading`]; `color` the albedo).
pub const SURFACE_REFLECTING: u32 = 0;

/// `kind` of an emissive triangle (`color` the radiance).
pub const SURFACE_EMISSIVE: u32 = 1;

/// `kind` of a triangle the shading pass does not shade (mirror, glass).
pub const SURFACE_UNSHADED: u32 = 2;

/// [`crate::nonlinear::SpecularPrim`]'s `kind`: a mirror (tinted, maybe bump-mapped).
pub const SPECULAR_MIRROR: u32 = 0;
/// [`crate::nonlinear::SpecularPrim`]'s `kind`: glass (Fresnel split of reflection and refraction).
pub const SPECULAR_GLASS: u32 = 1;
/// [`crate::nonlinear::SpecularPrim`]'s `kind`: a thin pane (the ray passes straight, tinted).
pub const SPECULAR_THIN: u32 = 2;

/// Bit of [`crate::glossy::GatherParams`]'s `flags`: second-order shadows.
pub const SECOND_ORDER_SHADOWS: u32 = 1;

/// Point emitters the glossy gather's shadow mask holds (one bit each of a `u32`):
/// [`beam_render::glossy::MAX_EMITTERS`].
pub const MAX_LIGHTS: u32 = beam_render::glossy::MAX_EMITTERS as u32;

/// Bernstein control points a GPU beam holds (S3: 10; [`crate::nonlinear::GpuBeam`]).
pub const MAX_CONTROL_POINTS: u32 = 10;

/// Bounding-triangle case: the whole base (brute force).
pub const BOUNDING_BRUTE_FORCE: u32 = 0;

/// Bounding-triangle case: 000 Alg. 3's general case.
pub const BOUNDING_GENERAL: u32 = 1;

/// Bounding-triangle case: the unique-projection case.
pub const BOUNDING_UNIQUE_PROJECTION: u32 = 2;

/// Bounding-triangle case: none, the triangle lies behind the base.
pub const BOUNDING_BEHIND: u32 = 3;

/// Shadow rays stop this fraction short of their end ([`beam_render::tolerance::DEPTH_EPS`]).
pub const DEPTH_EPS: f32 = beam_render::tolerance::DEPTH_EPS;

/// Barycentric tolerance of a projection inside the base
/// ([`beam_math::nonlinear::BARY_TOLERANCE`]).
pub const BARY_TOLERANCE: f32 = beam_math::nonlinear::BARY_TOLERANCE;

/// Least elevation of a beam's rays above its base ([`beam_math::nonlinear::MIN_ELEVATION`]).
pub const MIN_ELEVATION: f32 = beam_math::nonlinear::MIN_ELEVATION;

/// Least rise of a texel ray in its self-hit distance ([`beam_render::nonlinear::MIN_RISE`]).
pub const MIN_RISE: f32 = beam_render::nonlinear::MIN_RISE;

/// Nearest texel-ray hit, in scene diagonals ([`beam_render::nonlinear::TEXEL_EPS`]).
pub const TEXEL_EPS: f32 = beam_render::nonlinear::TEXEL_EPS;

/// Bit of a (beam, triangle) pair's triangle index in `beam_atlas.wgsl` that marks the triangle as
/// in the beam's ring ([`beam_render::nonlinear::Exclude::near`]): its hits nearer than the self-hit
/// distance are the surface meeting itself, as for a triangle sharing a vertex with the base.
pub const PAIR_NEAR: u32 = 1 << 31;

/// Most (beam, triangle) pairs one workgroup of `beam_texels.wgsl` tests its texels against: its
/// loop over them stays within what llvmpipe runs in one loop (65,535 iterations); a beam with more
/// pairs spreads them over several workgroups.
pub const TEXEL_JOB_PAIRS: u32 = 16_384;

/// Most bounces of a Whitted path past the beam tree ([`beam_render::specular::MAX_DEPTH`]).
pub const MAX_DEPTH: u32 = beam_render::specular::MAX_DEPTH;

/// Paths `whitted.wgsl`'s `paths` keeps on its private stack: depth first, each of at most
/// [`MAX_DEPTH`] bounces replaces the path it traces by at most two, so the stack never holds more
/// than `MAX_DEPTH + 1`.
pub const PATH_STACK: u32 = MAX_DEPTH + 1;

/// Bit of a scene triangle's kind in `level_points.wgsl`: the shading pass shades it (diffuse,
/// glossy, emissive; [`crate::shade::PointShader::shades`]).
pub const LEVEL_PLAIN: u32 = 1;

/// Bit of a scene triangle's kind in `level_points.wgsl`: its normals are interpolated (a curved
/// mirror or glass, counted as the host counts its points traced by rays).
pub const LEVEL_CURVED: u32 = 2;

/// Bit of a scene triangle's kind in `level_points.wgsl`: the tree goes on from it (its texels
/// go to the host, which builds the next level's beams from them).
pub const LEVEL_CONTINUES: u32 = 4;

/// Most Newton steps of a lookup's projection (`lib/lookup.wgsl`; [`beam_render::nonlinear::LOOKUP`]).
pub const LOOKUP_STEPS: u32 = beam_render::nonlinear::LOOKUP.steps;

/// Residual, relative to the base's size, below which a lookup's Newton step ends
/// ([`beam_render::nonlinear::LOOKUP`]; the shader adds a floor for f32's rounding).
#[allow(clippy::cast_possible_truncation, reason = "the f64 tolerance rounded to the f32 the shader compares with")]
pub const LOOKUP_TOLERANCE: f32 = beam_render::nonlinear::LOOKUP.tolerance as f32;

/// A lookup's projection (`lib/lookup.wgsl`): none (no corner-ray solution in front of the base).
pub const LOOKUP_NONE: u32 = 0;

/// A lookup's projection polished by Newton's method (or an S1 beam's, which needs none).
pub const LOOKUP_POLISHED: u32 = 1;

/// A lookup's projection where Newton's method did not converge: the corner rays' S1 solution.
pub const LOOKUP_CORNERS: u32 = 2;

/// How many texels outside a child beam's base a coarse face's lookup may fall before its point is
/// traced by rays (`eye.wgsl`; [`beam_render::nonlinear::OUTSIDE_TEXELS`]).
pub const OUTSIDE_TEXELS: f32 = beam_render::nonlinear::OUTSIDE_TEXELS;

/// How much less outside its beam's base another candidate face's lookup must lie to be taken
/// (`eye.wgsl`; [`beam_render::nonlinear::LOOKUP_PREFERENCE`]).
pub const LOOKUP_PREFERENCE: f32 = beam_render::nonlinear::LOOKUP_PREFERENCE;

/// Words of a slot of a level's fit table (`lib/fit.wgsl`, [`crate::nonlinear::FitTable`]): its
/// key, its number of samples, and the fit's 15 sums as (low, high) word pairs.
pub const FIT_WORDS: u32 = 32;

/// Most slots a sample of a level's fit table probes for its key's (`lib/fit.wgsl`).
pub const FIT_PROBES: u32 = 128;

/// A fit term's fixed-point scale (`lib/fit.wgsl`): 2²², so that f32's 24-bit significand of a
/// term below 1 keeps its bits down to about 2⁻²².
pub const FIT_SCALE: f32 = 4_194_304.0;

/// Largest magnitude of a fit term (`lib/fit.wgsl`): products of barycentric coordinates and unit
/// directions, which stay below 2 but for points far outside their face, clamped there.
pub const FIT_LIMIT: f32 = 3.99;

/// Added to each fixed-point fit term (`lib/fit.wgsl`), so that it is never negative:
/// `FIT_LIMIT · FIT_SCALE` < `FIT_BIAS`, and a sum's low word only carries upwards.
pub const FIT_BIAS: u32 = 1 << 24;

/// Pieces a GPU shadow beam holds (`shaders/shadow_beam.wgsl`); a beam that needs more answers
/// [`SHADOW_PIECES`] and is traced again by the host.
pub const MAX_PIECES: u32 = 64;

/// Corners a light polygon of a shadow beam has at most ([`beam_render::queries::MAX_LIGHT_CORNERS`]).
pub const MAX_LIGHT_CORNERS: u32 = beam_render::queries::MAX_LIGHT_CORNERS as u32;

/// Bit of a shadow-beam query's `flags`: clip the light above the point's tangent plane first.
pub const QUERY_CLIP_ABOVE: u32 = 1;

/// A shadow beam's status: traced to the end.
pub const SHADOW_DONE: u32 = 0;

/// A shadow beam's status: it needed more than [`MAX_PIECES`] pieces (its values mean nothing).
pub const SHADOW_PIECES: u32 = 1;

/// A shadow beam's status: its work passed its budget.
pub const SHADOW_BUDGET: u32 = 2;

/// A shadow beam's status: a loop was cut short (llvmpipe's cap on a SIMD group's iterations, or
/// a traversal stack a tree accepted by `GpuBvh::new` cannot need).
pub const SHADOW_CUT: u32 = 3;

/// Fuzzy tolerance of a shadow beam's side tests, as a fraction of the light's size (001 App. A;
/// beam-cpu's `SIDE_EPS`).
pub const SHADOW_SIDE_EPS: f32 = 1e-6;

/// Triangles a pixel's eye beam reports at most (`shaders/eye_beam.wgsl`); a pixel that sees more
/// answers [`EYE_FRAGMENTS`].
pub const MAX_FRAGMENTS: u32 = 8;

/// Pieces a pixel's eye beam holds (`shaders/eye_beam.wgsl`); a pixel that needs more answers
/// [`EYE_PIECES`].
pub const MAX_EYE_PIECES: u32 = 64;

/// Near clipping depth of the eye beams, in units of the image-plane distance (beam-cpu's
/// `render::NEAR`, which the conformance suite checks it against).
pub const EYE_NEAR: f32 = 1e-4;

/// Fuzzy tolerance of an eye beam's side tests, as a fraction of the piece's size (001 App. A;
/// beam-cpu's `primary_beam::SPLIT_EPS`).
pub const EYE_SPLIT_EPS: f32 = 1e-5;

/// Planes whose inverse depths differ by at most this fraction over a piece count as the same
/// plane there, and the piece's owner keeps it (beam-cpu's `primary_beam::COPLANAR`).
pub const EYE_COPLANAR: f32 = 1e-5;

/// A pixel's eye-beam status: traced to the end.
pub const EYE_DONE: u32 = 0;

/// A pixel's eye-beam status: it needed more than [`MAX_EYE_PIECES`] pieces (its values mean
/// nothing).
pub const EYE_PIECES: u32 = 1;

/// A pixel's eye-beam status: its work passed its budget.
pub const EYE_BUDGET: u32 = 2;

/// A pixel's eye-beam status: a loop was cut short (llvmpipe's cap on a SIMD group's iterations).
pub const EYE_CUT: u32 = 3;

/// A pixel's eye-beam status: it sees more than [`MAX_FRAGMENTS`] triangles.
pub const EYE_FRAGMENTS: u32 = 4;

/// A constant's value, typed as in WGSL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// `u32`.
    U32(u32),
    /// `f32`.
    F32(f32),
}

/// Every constant the shaders share with Rust: its WGSL name (the Rust constant's) and value.
pub const CONSTANTS: &[(&str, Value)] = {
    use Value::{F32, U32};
    &[
        ("WORKGROUP_SIZE", U32(WORKGROUP_SIZE)),
        ("TRAVERSAL_STACK", U32(TRAVERSAL_STACK)),
        ("MISS", U32(MISS)),
        ("SHADED", U32(SHADED)),
        ("NONE", U32(NONE)),
        ("RAY_CLOSEST", U32(RAY_CLOSEST)),
        ("RAY_ANY", U32(RAY_ANY)),
        ("LIGHT_POINT", U32(LIGHT_POINT)),
        ("LIGHT_QUAD", U32(LIGHT_QUAD)),
        ("LIGHT_TRIANGLE", U32(LIGHT_TRIANGLE)),
        ("SURFACE_REFLECTING", U32(SURFACE_REFLECTING)),
        ("SURFACE_EMISSIVE", U32(SURFACE_EMISSIVE)),
        ("SURFACE_UNSHADED", U32(SURFACE_UNSHADED)),
        ("SPECULAR_MIRROR", U32(SPECULAR_MIRROR)),
        ("SPECULAR_GLASS", U32(SPECULAR_GLASS)),
        ("SPECULAR_THIN", U32(SPECULAR_THIN)),
        ("SECOND_ORDER_SHADOWS", U32(SECOND_ORDER_SHADOWS)),
        ("MAX_LIGHTS", U32(MAX_LIGHTS)),
        ("MAX_CONTROL_POINTS", U32(MAX_CONTROL_POINTS)),
        ("BOUNDING_BRUTE_FORCE", U32(BOUNDING_BRUTE_FORCE)),
        ("BOUNDING_GENERAL", U32(BOUNDING_GENERAL)),
        ("BOUNDING_UNIQUE_PROJECTION", U32(BOUNDING_UNIQUE_PROJECTION)),
        ("BOUNDING_BEHIND", U32(BOUNDING_BEHIND)),
        ("PAIR_NEAR", U32(PAIR_NEAR)),
        ("TEXEL_JOB_PAIRS", U32(TEXEL_JOB_PAIRS)),
        ("MAX_DEPTH", U32(MAX_DEPTH)),
        ("PATH_STACK", U32(PATH_STACK)),
        ("LEVEL_PLAIN", U32(LEVEL_PLAIN)),
        ("LEVEL_CURVED", U32(LEVEL_CURVED)),
        ("LEVEL_CONTINUES", U32(LEVEL_CONTINUES)),
        ("LOOKUP_STEPS", U32(LOOKUP_STEPS)),
        ("LOOKUP_NONE", U32(LOOKUP_NONE)),
        ("LOOKUP_POLISHED", U32(LOOKUP_POLISHED)),
        ("LOOKUP_CORNERS", U32(LOOKUP_CORNERS)),
        ("DEPTH_EPS", F32(DEPTH_EPS)),
        ("BARY_TOLERANCE", F32(BARY_TOLERANCE)),
        ("MIN_ELEVATION", F32(MIN_ELEVATION)),
        ("MIN_RISE", F32(MIN_RISE)),
        ("TEXEL_EPS", F32(TEXEL_EPS)),
        ("LOOKUP_TOLERANCE", F32(LOOKUP_TOLERANCE)),
        ("OUTSIDE_TEXELS", F32(OUTSIDE_TEXELS)),
        ("LOOKUP_PREFERENCE", F32(LOOKUP_PREFERENCE)),
        ("FIT_WORDS", U32(FIT_WORDS)),
        ("FIT_PROBES", U32(FIT_PROBES)),
        ("FIT_SCALE", F32(FIT_SCALE)),
        ("FIT_LIMIT", F32(FIT_LIMIT)),
        ("FIT_BIAS", U32(FIT_BIAS)),
        ("MAX_PIECES", U32(MAX_PIECES)),
        ("MAX_LIGHT_CORNERS", U32(MAX_LIGHT_CORNERS)),
        ("QUERY_CLIP_ABOVE", U32(QUERY_CLIP_ABOVE)),
        ("SHADOW_DONE", U32(SHADOW_DONE)),
        ("SHADOW_PIECES", U32(SHADOW_PIECES)),
        ("SHADOW_BUDGET", U32(SHADOW_BUDGET)),
        ("SHADOW_CUT", U32(SHADOW_CUT)),
        ("SHADOW_SIDE_EPS", F32(SHADOW_SIDE_EPS)),
        ("MAX_FRAGMENTS", U32(MAX_FRAGMENTS)),
        ("MAX_EYE_PIECES", U32(MAX_EYE_PIECES)),
        ("EYE_NEAR", F32(EYE_NEAR)),
        ("EYE_SPLIT_EPS", F32(EYE_SPLIT_EPS)),
        ("EYE_COPLANAR", F32(EYE_COPLANAR)),
        ("EYE_DONE", U32(EYE_DONE)),
        ("EYE_PIECES", U32(EYE_PIECES)),
        ("EYE_BUDGET", U32(EYE_BUDGET)),
        ("EYE_CUT", U32(EYE_CUT)),
        ("EYE_FRAGMENTS", U32(EYE_FRAGMENTS)),
    ]
};

/// The WGSL declarations of [`CONSTANTS`], one `const NAME: type = value;` a line (floats in
/// Rust's shortest round-trip form, which the tests check naga reads back bit for bit).
#[must_use]
pub fn wgsl() -> String {
    let mut out = String::from("// Generated from beam_gpu::interface::CONSTANTS.\n");
    for (name, value) in CONSTANTS {
        let _ = match value {
            Value::U32(v) => writeln!(out, "const {name}: u32 = {v}u;"),
            Value::F32(v) => writeln!(out, "const {name}: f32 = {v:?};"),
        };
    }
    out
}
