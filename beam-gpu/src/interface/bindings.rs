//! Every shader's bindings against the order the pipelines bind their buffers in (the slices they
//! pass to `buffers::dispatch`, binding `i` the `i`-th, and the numbered entries of the shading and
//! atlas passes), with the Rust type of each binding's element: a WGSL binding at another index, one
//! missing from the table, or an element of another size fails.

use super::parsed::{Modules, member_size};
use crate::eye_beam::{EyeBeamParams, GpuPixel};
use crate::gbuffer::GBufferParams;
use crate::glossy::{GatherParams, GatherPoint, GpuCone, GpuConeNode, GpuGathered, GpuLightBeam};
use crate::nonlinear::{
    AtlasParams, BeamCull, CheckCase, CompositeParams, CompositeRecord, EndWeight, EyeCounts, EyeHit, EyeParams,
    GpuBeam, GpuFace, GpuLookupJob, HostTexel, LevelCounts, LevelParams, RecordCounts, WhittedCounts, WhittedParams,
    WhittedPath,
};
use crate::raytrace::{GpuHit, GpuRay};
use crate::shade::{CausticPlane, GpuLight, PrimShading, ShadeInput, ShadeParams};
use crate::shadow_beam::{GpuLightPolygon, GpuLightQuery, GpuLightSeen, ShadowParams};
use beam_bvh::FlatNode;
use beam_bvh::gpu::GpuTriangle;

/// `bindings!("shader" => [global: ElementType, …])`: group 0's globals by binding index, each
/// with the Rust type of its array element (or of the whole buffer); no type for a buffer with a
/// header (`shade_state`).
macro_rules! bindings {
    ($shader:literal => [$($name:ident $(: $t:ty)?),* $(,)?]) => {
        ($shader, vec![$((stringify!($name), None $(.or(Some(size_of::<$t>())))?)),*])
    };
}

type Table = (&'static str, Vec<(&'static str, Option<usize>)>);

fn tables() -> Vec<Table> {
    vec![
        bindings!("raytrace" => [
            nodes: FlatNode, triangles: GpuTriangle, rays: GpuRay, hits: GpuHit, shade_params: ShadeParams,
            shade_in: ShadeInput, prim_shading: PrimShading, lights: GpuLight, planes: CausticPlane, flux,
            shade_out: [f32; 4], shade_state,
        ]),
        bindings!("glossy_gather" => [
            nodes: FlatNode, triangles: GpuTriangle, params: GatherParams, beams: GpuLightBeam, cones: GpuCone,
            tree: GpuConeNode, points: GatherPoint, gathered: GpuGathered, unfinished: u32,
        ]),
        bindings!("beam_atlas" => [
            params: AtlasParams, beams: GpuBeam, triangles: GpuTriangle, pairs: [u32; 2], bounds_out: [f32; 4],
            bounds_in: [f32; 4], counters: u32, page_hits, firsts: u32, dense: [u32; 2],
        ]),
        bindings!("beam_cull" => [
            params: AtlasParams, beams: GpuBeam, triangles: GpuTriangle, pairs: [u32; 2], blocks: [u32; 2],
            block_prims: u32, culls: BeamCull, lists: u32, spheres: [f32; 4], pairs_out: [u32; 2],
        ]),
        bindings!("beam_texels" => [
            params: AtlasParams, beams: GpuBeam, triangles: GpuTriangle, pairs: [u32; 2], bounds_in: [f32; 4],
            counters: u32, firsts: u32, texel_hits: u64, jobs: [u32; 4],
        ]),
        bindings!("shadow_beam" => [
            nodes: FlatNode, triangles: GpuTriangle, params: ShadowParams, lights: GpuLightPolygon,
            queries: GpuLightQuery, seen: GpuLightSeen, gbuffer: GBufferParams, positions: [f32; 4],
            normals: [f32; 4], radiance: [f32; 4], irradiance_out, stopped_short: u32,
        ]),
        bindings!("eye_beam" => [nodes: FlatNode, triangles: GpuTriangle, params: EyeBeamParams, pixels: GpuPixel]),
        bindings!("nonlinear_check" => [beams: GpuBeam, cases: CheckCase, results: [f32; 4]]),
        bindings!("lookups" => [beams: GpuBeam, texel_t: f32, jobs: GpuLookupJob, answers: [f32; 4]]),
        bindings!("composite" => [
            params: CompositeParams, records: CompositeRecord, faces: GpuFace, shaded: [f32; 4], below,
            regions: [u32; 2], radiance, targets: u32,
        ]),
        bindings!("eye" => [
            nodes: FlatNode, triangles: GpuTriangle, params: EyeParams, kinds: u32, kept: ShadeInput, targets: u32,
            others: EyeHit, counts: EyeCounts, face_of: u32, seen: u32, specular: EyeHit, children: [u32; 2],
            records: CompositeRecord, rest: ShadeInput, rest_targets: u32, record_counts: RecordCounts,
            candidates: u32, corners: [f32; 4], child_beams: GpuBeam, texel_t: f32, slots: u32, specular_prims,
        ]),
        bindings!("level_points" => [
            params: LevelParams, beams: GpuBeam, firsts: u32, texels: [u32; 2], placed: [u32; 4], kinds: u32,
            direct: ShadeInput, direct_targets: u32, other: ShadeInput, other_targets: u32, counts: LevelCounts,
            host: HostTexel, face_of: u32, nodes: [u32; 2], child_firsts: u32, child_entries: [u32; 4],
            records: CompositeRecord, record_counts: RecordCounts, candidates: u32, corners: [f32; 4],
            child_beams: GpuBeam, texel_t: f32, slots: u32, specular_prims, depths: f32, fits: u32,
        ]),
        bindings!("whitted" => [
            nodes: FlatNode, triangles: GpuTriangle, params: WhittedParams, slots: u32, specular_prims,
            points: ShadeInput, paths_in: WhittedPath, paths_out: WhittedPath, ends: ShadeInput,
            end_weights: EndWeight, counts: WhittedCounts, shaded: [f32; 4], radiance: u32,
        ]),
    ]
}

/// What differs between a shader's bindings and its table.
fn differences(modules: &mut Modules, (shader, table): &Table) -> Vec<String> {
    let module = modules.get(shader);
    let mut out = Vec::new();
    let mut bound = vec![false; table.len()];
    for (_, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else { continue };
        let name = var.name.as_deref().unwrap_or("?");
        let at = format!("{shader}.wgsl @group({}) @binding({}) {name}", rb.group, rb.binding);
        match table.get(rb.binding as usize) {
            _ if rb.group != 0 => out.push(format!("{at}: the pipelines bind group 0 only")),
            None => out.push(format!("{at}: not in the Rust table")),
            Some((rust, _)) if *rust != name => out.push(format!("{at}: the Rust table binds {rust} there")),
            Some((_, size)) => {
                bound[rb.binding as usize] = true;
                let wgsl = member_size(module, var.ty);
                if size.is_some_and(|s| s != wgsl) {
                    out.push(format!("{at}: elements of {wgsl} bytes in WGSL, {} in Rust", size.unwrap_or(0)));
                }
            }
        }
    }
    for ((rust, _), i) in table.iter().zip(0..).filter(|(_, i)| !bound[*i]) {
        out.push(format!("{shader}.wgsl: the Rust table binds {rust} at {i}, the shader does not"));
    }
    out
}

#[test]
fn every_binding_matches_the_rust_table() {
    let mut modules = Modules::default();
    let errors: Vec<String> = tables().iter().flat_map(|t| differences(&mut modules, t)).collect();
    assert!(errors.is_empty(), "bindings differ:\n{}", errors.join("\n"));
}
