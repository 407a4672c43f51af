//! Every `#[repr(C)]` struct the pipelines upload or read back, against naga's layout of its WGSL
//! twin: the same members in the same order, each at Rust's `offset_of!` with Rust's size, the
//! listed Rust fields covering the whole struct, and the WGSL struct's size (`span`) equal to
//! `size_of`. Adding a struct is one line of [`twins`].

use super::parsed::{Modules, member_size};
use crate::eye_beam::{EyeBeamParams, GpuFragment, GpuPixel};
use crate::gbuffer::GBufferParams;
use crate::glossy::{GatherParams, GatherPoint, GpuCone, GpuConeNode, GpuGathered, GpuLightBeam};
use crate::nonlinear::{
    AtlasParams, BeamCull, CheckCase, CompositeParams, CompositeRecord, EndWeight, EyeCounts, EyeHit, EyeParams,
    GpuBeam, GpuFace, GpuLookupJob, HostTexel, LevelCounts, LevelParams, RecordCounts, SpecularPrim, WhittedCounts,
    WhittedParams, WhittedPath,
};
use crate::raytrace::{GpuHit, GpuRay};
use crate::shade::{CausticPlane, GpuLight, PrimShading, STATE_HEADER, ShadeInput, ShadeParams, ShadeState};
use crate::shadow_beam::{GpuLightPolygon, GpuLightQuery, GpuLightSeen, ShadowParams};
use beam_bvh::FlatNode;
use beam_bvh::gpu::GpuTriangle;
use core::mem::offset_of;

/// A Rust struct as its WGSL twin's members list it.
struct Twin {
    rust: &'static str,
    /// A shader whose source declares the twin.
    shader: &'static str,
    wgsl: &'static str,
    size: usize,
    /// WGSL member name, Rust offset and size.
    members: Vec<(&'static str, usize, usize)>,
}

/// One member: `field` (same name in WGSL), `field => member`, or `field[i] => member` (element `i`
/// of a Rust array that WGSL spells as separate members).
macro_rules! member {
    ($zero:ident, $t:ty, $field:ident) => {
        (stringify!($field), offset_of!($t, $field), size_of_val(&$zero.$field))
    };
    ($zero:ident, $t:ty, $field:ident => $member:ident) => {
        (stringify!($member), offset_of!($t, $field), size_of_val(&$zero.$field))
    };
    ($zero:ident, $t:ty, $field:ident [$i:literal] => $member:ident) => {
        (
            stringify!($member),
            offset_of!($t, $field) + $i * size_of_val(&$zero.$field[0]),
            size_of_val(&$zero.$field[$i]),
        )
    };
}

/// `twin!("shader", RustType => WgslType { members… })`.
macro_rules! twin {
    ($shader:literal, $rust:ty => $wgsl:ident { $($field:ident $([$i:literal])? $(=> $member:ident)?),* $(,)? }) => {{
        let zero = <$rust as bytemuck::Zeroable>::zeroed();
        Twin {
            rust: stringify!($rust),
            shader: $shader,
            wgsl: stringify!($wgsl),
            size: size_of::<$rust>(),
            members: vec![$(member!(zero, $rust, $field $([$i])? $(=> $member)?)),*],
        }
    }};
}

fn twins() -> Vec<Twin> {
    vec![
        twin!("raytrace", FlatNode => BvhNode { min, right_or_first, max, count }),
        twin!("raytrace", GpuTriangle => BvhTriangle { v0, prim, v1, pad1, v2, pad2 }),
        twin!("raytrace", GpuRay => GpuRay { origin, t_max, direction, kind }),
        twin!("raytrace", GpuHit => GpuHit { prim, t }),
        twin!("raytrace", ShadeInput => ShadeInput { p, prim, d, seed }),
        twin!("raytrace", PrimShading => PrimShading { normal, kind, color, plane }),
        twin!("raytrace", GpuLight => Light { a, kind, b, area, c, pad, power, pad2 }),
        twin!("raytrace", CausticPlane => CausticPlane { origin, offset, axis_u, width, axis_v, height }),
        twin!("raytrace", ShadeParams => ShadeParams {
            eps, inv_texel_area, lights, points, spp, budget, pad[0] => pad1, pad[1] => pad2
        }),
        twin!("raytrace", ShadeState => ShadeState { e, integral, light, sample, pad[0] => pad0, pad[1] => pad1 }),
        twin!("glossy_gather", GpuLightBeam => LightBeam {
            o0, flux, o1, sigma, o2, light, d0, shadow, d1, pad0, d2, pad1, power, pad2
        }),
        twin!("glossy_gather", GpuCone => Cone { apex, cos, axis, pad }),
        twin!("glossy_gather", GpuConeNode => ConeNode {
            apex, cos, axis, right_or_first, count, skip, pad[0] => pad1, pad[1] => pad2
        }),
        twin!("glossy_gather", GatherPoint => GatherPoint { p, pad0, n, pad1 }),
        twin!("glossy_gather", GpuGathered => Gathered { irradiance, shadowed, tested, next, in_leaf, pad }),
        twin!("glossy_gather", GatherParams => GatherParams {
            points, nodes, flags, eps, budget, pad[0] => pad0, pad[1] => pad1, pad[2] => pad2
        }),
        twin!("beam_atlas", AtlasParams => AtlasParams { size, extent, pairs }),
        twin!("beam_atlas", GpuBeam => Beam {
            base, dirs, extremal, normal, threshold, heights, offsets, bump, region, kind, origin, direction
        }),
        twin!("beam_cull", BeamCull => BeamCull {
            apex, cos_angle, axis, sin_angle, floor_normal, floor, base0, has_floor, base1, prim, base2, pad,
            patch_list, ring_list
        }),
        twin!("nonlinear_check", CheckCase => CheckCase { a, b, c }),
        twin!("lookups", GpuLookupJob => LookupJob { p, beam, truth, far, w, pad }),
        twin!("composite", GpuFace => Face {
            v[0] => v0, v[1] => v1, v[2] => v2, n[0] => n0, n[1] => n1, n[2] => n2, normal, material
        }),
        twin!("composite", CompositeRecord => Record {
            p, texel, d, face, reflected, refracted, pad[0] => pad0, pad[1] => pad1, refracted_p, pad2
        }),
        twin!("level_points", LevelParams => LevelParams {
            first, count, inverted, beams, far, depths, fits, faces
        }),
        twin!("level_points", LevelCounts => LevelCounts { direct, other, curved, host }),
        twin!("level_points", ShadeInput => ShadeInput { p, prim, d, seed }),
        twin!("level_points", HostTexel => HostTexel { p, prim, d, t, beam, texel, node, face }),
        twin!("level_points", CompositeRecord => Record {
            p, texel, d, face, reflected, refracted, pad[0] => pad0, pad[1] => pad1, refracted_p, pad2
        }),
        twin!("level_points", RecordCounts => RecordCounts {
            records, rest, uncovered, curved, coarse, pad[0] => pad0, pad[1] => pad1, pad[2] => pad2
        }),
        twin!("level_points", GpuBeam => Beam {
            base, dirs, extremal, normal, threshold, heights, offsets, bump, region, kind, origin, direction
        }),
        twin!("composite", CompositeParams => CompositeParams {
            records, points, first, pad
        }),
        twin!("eye", EyeParams => EyeParams {
            position, width, forward, height, right, first, up, count, half_width, half_height, far, pad, crop
        }),
        twin!("eye", ShadeInput => ShadeInput { p, prim, d, seed }),
        twin!("eye", EyeHit => EyeHit { pixel, prim, t, face }),
        twin!("eye", EyeCounts => EyeCounts { kept, others, overflow, specular }),
        twin!("eye", RecordCounts => RecordCounts {
            records, rest, uncovered, curved, coarse, pad[0] => pad0, pad[1] => pad1, pad[2] => pad2
        }),
        twin!("whitted", WhittedParams => WhittedParams { count, first, last, eps }),
        twin!("whitted", ShadeInput => ShadeInput { p, prim, d, seed }),
        twin!("whitted", SpecularPrim => SpecularPrim {
            v0, kind, v1, ior, v2, has_normals, n0, delta, n1, wavelength, n2, pad0, normal, pad1, tint, pad2
        }),
        twin!("whitted", WhittedPath => Path { origin, dest, direction, seed, weight, pad }),
        twin!("whitted", EndWeight => EndWeight { weight, dest }),
        twin!("whitted", WhittedCounts => WhittedCounts { paths, ends, overflow, pad }),
        twin!("shadow_beam", GpuLightQuery => LightQuery { p, light, n, flags }),
        twin!("shadow_beam", GpuLightPolygon => LightPolygon { corners, normal, count }),
        twin!("shadow_beam", GpuLightSeen => LightSeen { irradiance, fraction, status, work }),
        twin!("shadow_beam", ShadowParams => ShadowParams { queries, budget, first, pad }),
        twin!("eye_beam", EyeBeamParams => EyeBeamParams {
            apex, width, corner_ray, height, u, first, v, count, normal, budget, pixel, plane_distance, pad
        }),
        twin!("eye_beam", GpuFragment => EyeFragment { prim, coverage, centroid }),
        twin!("eye_beam", GpuPixel => EyePixel {
            status, count, work, background, background_centroid, pad[0] => pad0, pad[1] => pad1, fragments
        }),
        twin!("shadow_beam", GBufferParams => GBufferParams {
            width, height, lights, budget, offset, pad[0] => pad0, pad[1] => pad1, pad[2] => pad2
        }),
    ]
}

/// What differs between `twin` and its WGSL struct.
fn differences(modules: &mut Modules, twin: &Twin) -> Vec<String> {
    let module = modules.get(twin.shader);
    let Some(naga::TypeInner::Struct { members, span }) =
        module.types.iter().find(|(_, t)| t.name.as_deref() == Some(twin.wgsl)).map(|(_, t)| &t.inner)
    else {
        return vec![format!("{}: no struct {} in {}.wgsl", twin.rust, twin.wgsl, twin.shader)];
    };
    let head = format!("{} vs {} ({}.wgsl)", twin.rust, twin.wgsl, twin.shader);
    let mut out = Vec::new();
    if *span as usize != twin.size {
        out.push(format!("{head}: size_of {} but WGSL size {span}", twin.size));
    }
    let listed: usize = twin.members.iter().map(|m| m.2).sum();
    if listed != twin.size {
        out.push(format!("{head}: the listed Rust fields cover {listed} of {} bytes", twin.size));
    }
    let names: Vec<&str> = members.iter().map(|m| m.name.as_deref().unwrap_or("?")).collect();
    if members.len() != twin.members.len() {
        let rust: Vec<&str> = twin.members.iter().map(|m| m.0).collect();
        out.push(format!("{head}: {} Rust members {rust:?}, {} WGSL members {names:?}", rust.len(), names.len()));
    }
    for ((name, offset, size), (m, wgsl_name)) in twin.members.iter().zip(members.iter().zip(&names)) {
        let wgsl_size = member_size(module, m.ty);
        if name != wgsl_name || *offset != m.offset as usize || *size != wgsl_size {
            out.push(format!(
                "{head}: Rust {name} at {offset} ({size} bytes), WGSL {wgsl_name} at {} ({wgsl_size} bytes)",
                m.offset
            ));
        }
    }
    out
}

#[test]
fn every_gpu_struct_matches_its_wgsl_twin() {
    let mut modules = Modules::default();
    let twins = twins();
    let errors: Vec<String> = twins.iter().flat_map(|t| differences(&mut modules, t)).collect();
    assert!(
        errors.is_empty(),
        "{} of {} structs differ from their WGSL twins:\n{}",
        errors.len(),
        twins.len(),
        errors.join("\n")
    );
}

#[test]
fn shade_states_follow_their_header() {
    let mut modules = Modules::default();
    let module = modules.get("raytrace");
    let points = module.types.iter().find_map(|(_, t)| match &t.inner {
        naga::TypeInner::Struct { members, .. } if t.name.as_deref() == Some("ShadeStates") => {
            members.iter().find(|m| m.name.as_deref() == Some("points")).map(|m| m.offset)
        }
        _ => None,
    });
    assert_eq!(points.map(u64::from), Some(STATE_HEADER), "ShadeStates.points must start at STATE_HEADER");
}
