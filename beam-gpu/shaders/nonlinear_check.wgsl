// Compute entry points that run the WGSL nonlinear-beam functions on batches of cases, for the
// conformance suite to compare with beam-math (tests/src/gpu.rs).

// #import shared/nonlinear.wgsl
// #import lib/lookup.wgsl

// Twin of beam_gpu::nonlinear::CheckCase (48 bytes): a scene triangle for
// `check_bounding_triangles`, a base point (a.xyz) for `check_rays`, or a point (a.xyz) and a guess
// (b: ω and t) for `check_lookups`; the beam index in a.w.
struct CheckCase {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> beams: array<Beam>;
@group(0) @binding(1) var<storage, read> cases: array<CheckCase>;
@group(0) @binding(2) var<storage, read_write> results: array<vec4<f32>>;

// Per case: the bounding triangle's lower bounds (xyz) and case (w). Loops: at most 2,807
// iterations an invocation or SIMD group (beam_atlas.wgsl's bound_triangles says how), far under
// llvmpipe's 65,535.
@compute @workgroup_size(WORKGROUP_SIZE)
fn check_bounding_triangles(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&cases) { return; }
    let c = cases[i];
    let tri = Tri(array<vec3<f32>, 3>(c.a.xyz, c.b.xyz, c.c.xyz));
    let bt = bounding_triangle(beams[bitcast<u32>(c.a.w)], tri);
    results[i] = vec4<f32>(bt.lower, f32(bt.case_));
}

// Per case: the texel ray's origin and direction (two results). Loops: 10 iterations (S^3).
@compute @workgroup_size(WORKGROUP_SIZE)
fn check_rays(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&cases) { return; }
    let c = cases[i];
    let r = texel_ray(beams[bitcast<u32>(c.a.w)], c.a.xyz);
    results[2u * i] = vec4<f32>(r.origin, 0.0);
    results[2u * i + 1u] = vec4<f32>(r.direction, 0.0);
}

// Per case: the lookup's projection of a.xyz from the guess b (lib/lookup.wgsl; two results: ω
// and t, then how it was found in x). Loops: LOOKUP_STEPS × (11 + 10) iterations.
@compute @workgroup_size(WORKGROUP_SIZE)
fn check_lookups(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&cases) { return; }
    let c = cases[i];
    let l = lookup_project(beams[bitcast<u32>(c.a.w)], c.a.xyz, c.b.xyz, c.b.w);
    results[2u * i] = l.p;
    results[2u * i + 1u] = vec4<f32>(f32(l.found), 0.0, 0.0, 0.0);
}
