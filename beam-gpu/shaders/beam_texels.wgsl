// The atlas's nearest hits by compute instead of rasterization (beam_gpu::nonlinear::atlas), for
// devices with 64-bit atomics. After `bound_triangles` (beam_atlas.wgsl), a workgroup takes a job:
// WORKGROUP_SIZE consecutive texels of one beam's region (an invocation each) against a run of
// that beam's (beam, triangle) pairs. Each invocation builds its texel's ray once, tests it against
// every pair whose bounding triangle keeps the texel (the fragments `intersect_texel` would shade)
// and keeps the nearest hit; a beam with more pairs than a job takes spreads them over several
// jobs, merged by one 64-bit atomic max per texel and job on the inverted (t, triangle) key, so
// that a larger key is a nearer hit (t ≥ 0 orders as its bits do; ties go to the lower triangle)
// and the buffer's zeroes are misses. The texels are written straight into the per-beam lists that
// `gather_regions` makes from a page. A software rasterizer shades vertices on one thread, and a
// compute GPU rasterizes on few of its cores; here every core works, every invocation of a
// workgroup walks the same pairs, and no invocation waits on another's larger triangle.
// CPU twin: beam_cpu::nonlinear::render_beam.

// #import lib/atlas.wgsl
// #import lib/region.wgsl

@group(0) @binding(4) var<storage, read> bounds_in: array<vec4<f32>>; // lower bounds (xyz), case (w)
// Per beam on the page: scene triangles not culled as behind its base, texels tested (overdraw).
@group(0) @binding(5) var<storage, read_write> counters: array<atomic<u32>>;
// Per beam on the page, its first texel in `texel_hits`; then the number of texels of them all.
@group(0) @binding(6) var<storage, read> firsts: array<u32>;
// Per texel of every region, row by row: !((bits of t) << 32 | triangle + 1), 0 for a miss.
@group(0) @binding(7) var<storage, read_write> texel_hits: array<atomic<u64>>;
// The jobs: beam on the page, its texels from WORKGROUP_SIZE × this on, its pairs [first, end).
@group(0) @binding(8) var<storage, read> jobs: array<vec4<u32>>;

// Loops: texel_query's 10 iterations, then one per pair of the job (at most TEXEL_JOB_PAIRS, within
// llvmpipe's 65,535 per loop of a SIMD group; nothing in it loops).
@compute @workgroup_size(WORKGROUP_SIZE)
fn nearest_hits(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let j = group.y * groups.x + group.x;
    if j >= arrayLength(&jobs) { return; }
    let job = jobs[j];
    let first = firsts[job.x];
    let k = job.y * WORKGROUP_SIZE + lane;
    if k >= firsts[job.x + 1u] - first { return; }
    let b = beams[job.x];
    let s = b.region.z;
    let at = region_texel(k, s);
    let w = texel_barycentric(at.x, at.y, s);
    let q = texel_query(b, w);
    var nearest = 0lu;
    var tested = 0u;
    for (var p = job.z; p < min(job.w, job.z + TEXEL_JOB_PAIRS); p++) {
        let bt = bounds_in[p];
        if bt.w == f32(BOUNDING_BEHIND) || !texel_tested(w, bt.xyz, s) { continue; }
        tested += 1u;
        let pair = pairs[p];
        let prim = pair.y & ~PAIR_NEAR;
        let t = texel_hit(q, prim, pair_neighbour(b, pair));
        if t < 0.0 { continue; }
        nearest = max(nearest, ~((u64(bitcast<u32>(t)) << 32u) | u64(prim + 1u)));
    }
    if nearest != 0lu { atomicMax(&texel_hits[first + k], nearest); }
    if tested > 0u { atomicAdd(&counters[2u * job.x + 1u], tested); }
}
