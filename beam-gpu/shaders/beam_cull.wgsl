// Bounding-cone culling split as 000 splits it (App. A; §7: objects on the CPU, triangles on the
// GPU): the host keeps the 8-wide BVH's leaf blocks whose boxes meet a beam's bounding cone, and
// here each lane of a kept (beam, block) becomes the page's (beam, triangle) pair, or (beam, NONE)
// where its triangle is culled: by its bounding sphere against the cone, as one the beam skips
// (its base's triangle, a coarse face's patch), or as a neighbour of the base wholly below the
// self-hit floor. A triangle of a coarse face's ring is marked PAIR_NEAR. `bound_triangles`
// (beam_atlas.wgsl) follows. CPU twin: beam_scene::nonlinear::ConeCull::keeps.

// #import lib/atlas.wgsl

// Twin of beam_gpu::nonlinear::BeamCull (112 bytes).
struct BeamCull {
    apex: vec3<f32>,
    cos_angle: f32,
    axis: vec3<f32>,
    sin_angle: f32,
    floor_normal: vec3<f32>,
    floor: f32,
    base0: vec3<f32>,
    has_floor: u32,
    base1: vec3<f32>,
    prim: u32,
    base2: vec3<f32>,
    pad: u32,
    patch_list: vec2<u32>,  // first in `lists`, count
    ring_list: vec2<u32>,
}

// The page's (beam on the page, block) kept by their boxes; params.pairs is four times their count.
@group(0) @binding(4) var<storage, read> blocks: array<vec2<u32>>;
// The scene triangle in each lane of each block (NONE in an unused lane).
@group(0) @binding(5) var<storage, read> block_prims: array<u32>;
// Per beam on the page.
@group(0) @binding(6) var<storage, read> culls: array<BeamCull>;
// The beams' patches and rings, each ascending.
@group(0) @binding(7) var<storage, read> lists: array<u32>;
// Per scene triangle: its bounding sphere's centre (xyz) and radius (w).
@group(0) @binding(8) var<storage, read> spheres: array<vec4<f32>>;
// Per lane: (beam on the page, scene triangle | PAIR_NEAR), or (beam, NONE).
@group(0) @binding(9) var<storage, read_write> pairs_out: array<vec2<u32>>;

// Whether `prim` is in `lists[range.x .. range.x + range.y]`. Loops: a binary search, at most 32
// halvings (constant bound).
fn in_list(range: vec2<u32>, prim: u32) -> bool {
    var lo = range.x;
    var hi = range.x + range.y;
    for (var i = 0u; i < 32u && lo < hi; i++) {
        let mid = (lo + hi) / 2u;
        let v = lists[mid];
        if v == prim { return true; }
        if v < prim { lo = mid + 1u; } else { hi = mid; }
    }
    return false;
}

// Whether the sphere `s` meets the cone: beam_math::collide::ConeSpheres::meets, which says why.
fn cone_meets(c: BeamCull, s: vec4<f32>) -> bool {
    let v = s.xyz - c.apex;
    let d2 = dot(v, v);
    let dist = sqrt(d2);
    let inside = d2 <= s.w * s.w;
    let wide = c.cos_angle <= 0.0 && s.w >= dist * c.sin_angle;
    // Clamped where the apex is inside the sphere, which passes anyway (no NaN on the GPU).
    let bound = c.cos_angle * sqrt(max(d2 - s.w * s.w, 0.0)) - c.sin_angle * s.w;
    return inside || wide || dot(v, c.axis) + 1e-5 * dist > bound;
}

fn on_base(c: BeamCull, p: vec3<f32>) -> bool {
    return all(p == c.base0) || all(p == c.base1) || all(p == c.base2);
}

// `prim | PAIR_NEAR` where it is in the ring, `prim` where it is kept, NONE where it is culled.
fn kept(c: BeamCull, prim: u32) -> u32 {
    if prim == NONE || prim == c.prim || !cone_meets(c, spheres[prim]) || in_list(c.patch_list, prim) {
        return NONE;
    }
    let near = in_list(c.ring_list, prim);
    if c.has_floor != 0u {
        let t = triangles[prim];
        let n = c.floor_normal;
        let h = vec3<f32>(dot(n, t.v0 - c.base0), dot(n, t.v1 - c.base0), dot(n, t.v2 - c.base0));
        let neighbour = near || on_base(c, t.v0) || on_base(c, t.v1) || on_base(c, t.v2);
        if neighbour && all(h < vec3<f32>(c.floor)) { return NONE; }
    }
    return prim | select(0u, PAIR_NEAR, near);
}

// Loops: kept's two binary searches (constant bounds).
@compute @workgroup_size(WORKGROUP_SIZE)
fn cull_triangles(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= params.pairs { return; }
    let block = blocks[i / 4u];
    pairs_out[i] = vec2<u32>(block.x, kept(culls[block.x], block_prims[4u * block.y + i % 4u]));
}
