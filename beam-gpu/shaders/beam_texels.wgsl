// The atlas's nearest hits by compute instead of rasterization (beam_gpu::nonlinear::atlas), for
// devices with 64-bit atomics: after `bound_triangles` (beam_atlas.wgsl), one invocation per
// (beam, triangle) pair walks the texels of the beam's region that the pair's bounding triangle
// keeps (the fragments `intersect_texel` would test), intersects each texel's ray with the
// triangle and keeps the nearest hit with one 64-bit atomic max: (t, triangle) packed and inverted,
// so that a larger key is a nearer hit (t ≥ 0 orders as its bits do; ties go to the lower
// triangle) and the buffer's zeroes are misses. The texels are written straight into the dense
// per-beam lists that `gather_regions` makes from a page, so that pass and the page are not needed.
// A software rasterizer shades vertices on one thread and a compute GPU rasterizes on few of its
// cores; here every core works. CPU twin: beam_cpu::nonlinear::render_beam.

@group(0) @binding(4) var<storage, read> bounds_in: array<vec4<f32>>; // lower bounds (xyz), case (w)
// Per beam on the page: scene triangles not culled as behind its base, texels tested (overdraw).
@group(0) @binding(5) var<storage, read_write> counters: array<atomic<u32>>;
// Per beam on the page, its first texel in `texel_hits`; then the number of texels of them all.
@group(0) @binding(6) var<storage, read> firsts: array<u32>;
// Per texel of every region, row by row: !((bits of t) << 32 | triangle + 1), 0 for a miss.
@group(0) @binding(7) var<storage, read_write> texel_hits: array<atomic<u64>>;

// Index of texel (x, y) in a region's list of side s: row 0 holds s texels, row y ≥ 1 holds
// s + 1 − y (beam_gpu::nonlinear::atlas unpacks them so).
fn region_index(x: u32, y: u32, s: u32) -> u32 {
    if y == 0u { return x; }
    return s + (y - 1u) * (s + 1u) - (y - 1u) * y / 2u + x;
}

// Loops: rows and texels of one region, at most s × (s + 2) iterations with s ≤ MAX_TEXEL_REGION
// (16,640 for 128, within llvmpipe's 65,535 per loop of a SIMD group), each texel_hit's 10.
@compute @workgroup_size(WORKGROUP_SIZE)
fn nearest_hits(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= params.pairs { return; }
    let bt = bounds_in[i];
    if bt.w == f32(BOUNDING_BEHIND) { return; }
    let pair = pairs[i];
    let b = beams[pair.x];
    let prim = pair.y & ~PAIR_NEAR;
    let neighbour = pair_neighbour(b, pair);
    let s = min(b.region.z, MAX_TEXEL_REGION);
    let fs = f32(s);
    // The texels texel_tested keeps, with a texel of margin: u ≥ lower.y and v ≥ lower.z bound x
    // and y from below; u + v ≤ 1 − lower.x bounds x + y + 1 by `reach` (a margin texel, x + y = s,
    // passes only where reach ≥ s).
    let low = bt.xyz - vec3<f32>(0.5 / fs);
    let x0 = u32(clamp(floor(low.y * fs - 0.5) - 1.0, 0.0, fs));
    let y0 = u32(clamp(floor(low.z * fs - 0.5) - 1.0, 0.0, fs));
    let reach = (1.0 - low.x) * fs;
    let first = firsts[pair.x];
    var tested = 0u;
    for (var y = y0; y < s; y++) {
        let end = reach - f32(y) + 1.0;
        if !(end >= f32(x0)) { break; }
        let x1 = min(min(s - 1u, s - y), u32(min(end, fs)));
        for (var x = x0; x <= x1; x++) {
            let w = texel_barycentric(x, y, s);
            if !texel_tested(w, bt.xyz, s) { continue; }
            tested += 1u;
            let hit = texel_hit(b, w, prim, neighbour);
            if hit.x < 0.0 { continue; }
            let key = (u64(bitcast<u32>(hit.x)) << 32u) | u64(prim + 1u);
            atomicMax(&texel_hits[first + region_index(x, y, s)], ~key);
        }
    }
    if tested > 0u { atomicAdd(&counters[2u * pair.x + 1u], tested); }
}
