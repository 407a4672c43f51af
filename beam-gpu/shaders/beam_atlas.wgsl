// The nonlinear pipeline of 000 §3 (Alg. 1) in two GPU passes per atlas page:
// 1. `bound_triangles` (compute): per (beam, scene triangle) pair that survives the beam's
//    bounding-cone culling (`beam_cull.wgsl`; NONE for a culled one), the bounding triangle on
//    the beam base (Algs. 3–4, eq. 5), once;
// 2. one draw per beam (the instance) over its pairs: the vertex stage pulls the pair and its
//    bounding triangle from storage buffers (vertex index / 3) and emits the triangle on the beam's
//    atlas region; the fragment stage rebuilds the texel's ray, intersects the scene triangle,
//    discards misses and writes the hit with its distance as depth, so the depth test keeps each
//    texel's nearest hit;
// 3. `gather_regions` (compute): every beam's texels copied out of the page into one dense list,
//    region after region, so that only they are read back (a region fills less than half of the
//    power-of-two square it is packed in).
// (000 computes the bounding triangle in the vertex stage itself; a compute pass computes it once
// per pair instead of once per corner, and runs on every core of a software rasterizer, which
// shades vertices on one thread.) Where the device has 64-bit atomics, `beam_texels.wgsl` takes
// the place of passes 2 and 3. CPU twin: beam_cpu::nonlinear::render_beam.

// #import shared/nonlinear.wgsl
// #import lib/atlas.wgsl
// #import lib/region.wgsl

@group(0) @binding(4) var<storage, read_write> bounds_out: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> bounds_in: array<vec4<f32>>; // lower bounds (xyz), case (w)
// Per beam on the page: scene triangles not culled as behind its base, texels tested (overdraw).
@group(0) @binding(6) var<storage, read_write> counters: array<atomic<u32>>;

// Loop bound (software Vulkan, Mesa llvmpipe / lavapipe, ends every loop of a SIMD group of 8
// invocations once they have run 65,535 iterations together; a nested loop costs its iterations + 2
// each time it is entered): bounding_triangle (shared/nonlinear.wgsl) has only loops of constant
// bounds, whatever the scene. Per cubic_roots at most 293 (3 brackets × 80 Newton steps of
// `refine`, the rest over at most 4 points and 3 roots); per s1_solutions 298; Alg. 3/4's three
// classify_s1, the unique-projection case's three s1_solutions and two enclose_transfers (25 each)
// 1,873; θ1 of eq. 5 914; the bump expansion 20: at most 2,807 for an invocation, and for a SIMD
// group (divergent branches both run, each loop as long as its longest lane: the sum above already
// counts every loop at its longest), 1/23 of the cap. No passes needed.
@compute @workgroup_size(WORKGROUP_SIZE)
fn bound_triangles(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= params.pairs { return; }
    let pair = pairs[i];
    // A triangle `cull_triangles` (beam_cull.wgsl) culled.
    if pair.y == NONE {
        bounds_out[i] = vec4<f32>(0.0, 0.0, 0.0, f32(BOUNDING_BEHIND));
        return;
    }
    let bt = bounding_triangle(beams[pair.x], scene_tri(pair.y & ~PAIR_NEAR));
    bounds_out[i] = vec4<f32>(bt.lower, f32(bt.case_));
    if bt.case_ != BOUNDING_BEHIND { atomicAdd(&counters[2u * pair.x], 1u); }
}

struct Fragment {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) beam: u32,
    @location(1) @interpolate(flat) prim: u32,
    @location(2) @interpolate(flat) lower: vec3<f32>,
    @location(3) @interpolate(flat) neighbour: u32,
}

@vertex
fn emit_bounding_triangle(@builtin(vertex_index) vertex: u32, @builtin(instance_index) beam: u32) -> Fragment {
    let b = beams[beam];
    let pair = vertex / 3u;
    let prim = pairs[pair].y & ~PAIR_NEAR;
    let bt = bounds_in[pair];
    var out: Fragment;
    out.beam = beam;
    out.prim = prim;
    out.lower = bt.xyz;
    out.position = vec4<f32>(-2.0, -2.0, 0.0, 1.0);
    if bt.w == f32(BOUNDING_BEHIND) { return out; }
    out.neighbour = select(0u, 1u, pair_neighbour(b, pairs[pair]));
    let size = f32(b.region.z);
    // The texels tested are those with ω ≥ lower − ½ texel (slack); the rasterized triangle is
    // 1.5 texels larger still, clamped to the beam's region (edges parallel, so clamping is a max).
    let r = max(bt.xyz - vec3<f32>(2.0 / size), vec3<f32>(-2.0 / size, -1.0 / size, -1.0 / size));
    if r.x + r.y + r.z >= 1.0 { return out; }
    let k = vertex % 3u;
    var w = vec3<f32>(1.0 - r.y - r.z, r.y, r.z);
    if k == 1u { w = vec3<f32>(r.x, 1.0 - r.x - r.z, r.z); }
    if k == 2u { w = vec3<f32>(r.x, r.y, 1.0 - r.x - r.y); }
    let p = vec2<f32>(f32(b.region.x), f32(b.region.y)) + w.yz * size;
    out.position = vec4<f32>(p.x / params.size.x * 2.0 - 1.0, 1.0 - p.y / params.size.y * 2.0, 0.5, 1.0);
    return out;
}

struct Hit {
    @location(0) hit: vec2<u32>,  // scene triangle + 1, bits of t
    @builtin(frag_depth) depth: f32,
}

// Loops: texel_query's (lib/atlas.wgsl); nothing scales with the scene.
@fragment
fn intersect_texel(f: Fragment) -> Hit {
    let b = beams[f.beam];
    let size = b.region.z;
    let xi = i32(floor(f.position.x)) - i32(b.region.x);
    let yi = i32(floor(f.position.y)) - i32(b.region.y);
    if xi < 0 || yi < 0 || xi >= i32(size) || yi >= i32(size) || xi + yi >= i32(size) + 1 { discard; }
    let w = texel_barycentric(u32(xi), u32(yi), size);
    if !texel_tested(w, f.lower, size) { discard; }
    atomicAdd(&counters[2u * f.beam + 1u], 1u);
    let q = texel_query(b, w);
    let t = texel_hit(q, f.prim, f.neighbour == 1u);
    if t < 0.0 { discard; }
    var out: Hit;
    out.hit = vec2<u32>(f.prim + 1u, bitcast<u32>(t));
    let dist = t * q.len;
    out.depth = dist / (dist + params.extent);
    return out;
}

// The page's hits (scene triangle + 1, bits of t) for `gather_regions`.
@group(0) @binding(7) var page_hits: texture_2d<u32>;
// Per beam on the page, its first texel in `dense`; then the number of texels of them all.
@group(0) @binding(8) var<storage, read> firsts: array<u32>;
@group(0) @binding(9) var<storage, read_write> dense: array<vec2<u32>>;

// Loops: a binary search over the page's beams, at most 32 halvings (constant bound).
@compute @workgroup_size(WORKGROUP_SIZE)
fn gather_regions(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = id.y * groups.x * WORKGROUP_SIZE + id.x;
    let beams_here = arrayLength(&firsts) - 1u;
    if k >= firsts[beams_here] { return; }
    // The last beam whose first texel is at most k.
    var lo = 0u;
    var hi = beams_here;
    for (var i = 0u; i < 32u && hi - lo > 1u; i++) {
        let mid = (lo + hi) / 2u;
        if firsts[mid] <= k { lo = mid; } else { hi = mid; }
    }
    let r = beams[lo].region;
    let at = region_texel(k - firsts[lo], r.z);
    dense[k] = textureLoad(page_hits, vec2<u32>(r.x + at.x, r.y + at.y), 0).xy;
}
