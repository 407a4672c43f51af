// The closest-hit and any-hit traversal over beam-bvh's GPU layout, bound at group 0 bindings 0
// (nodes) and 1 (triangles); imported by the shaders that trace rays (raytrace, glossy_gather, eye,
// whitted).
// CPU twin: beam_bvh::FlatBvh::closest_hit / any_hit (front-to-back stack traversal, watertight).

// #import shared/bvh.wgsl

// Twin of beam_gpu::raytrace::GpuHit (8 bytes): prim is MISS on a miss; for an any-hit ray t is 1
// when occluded and 0 otherwise. (The shared constants, TRAVERSAL_STACK, MISS, …, are generated
// from beam_gpu::interface and prepended by the host.)
struct GpuHit {
    prim: u32,
    t: f32,
}

@group(0) @binding(0) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> triangles: array<BvhTriangle>;

// Loop iterations trace_ray has run in this invocation, as software Vulkan (Mesa llvmpipe /
// lavapipe) counts them towards its cap of 65,535 per SIMD group: a traversal step each, and per
// leaf its triangles + 2 (the leaf's loop, entered). Shaders that bound their work per dispatch
// (glossy_gather, raytrace's shade) read it.
var<private> trace_work: u32;

// The nearest hit before t_max (any hit when `any`) of the ray (origin, direction): GpuHit with
// prim MISS on a miss; for `any`, t is 1 when occluded and 0 otherwise.
fn trace_ray(origin: vec3<f32>, direction: vec3<f32>, t_max: f32, any: bool) -> GpuHit {
    let sheared = shear_ray(origin, direction);
    let inv = 1.0 / direction;
    var best = t_max;
    var prim = MISS;
    // Pending nodes. After popping a node at depth d at most d are pending (one sibling per
    // ancestor: those pushed after it were popped first, with their subtrees), so pushing the
    // children of an inner node needs at most the tree's depth + 1 entries, which
    // beam_bvh::gpu::GpuBvh::new checks against TRAVERSAL_STACK (beam_bvh::gpu::stack_entries).
    var stack: array<u32, TRAVERSAL_STACK>;
    var sp = 0u;
    if slab(nodes[0], origin, inv, best) < 3.0e38 {
        stack[0] = 0u;
        sp = 1u;
    }
    // Loop bound: every node is pushed at most once (children of a node popped once), so at most
    // 2·leaves − 1 steps plus, per leaf reached, its triangles + 2: at worst every node and every
    // triangle, past 65,535 for a mesh of 66K triangles (Sponza: 59,115 nodes; conference: 249,805).
    // Real rays stop far sooner. Counted as llvmpipe counts (per SIMD group of 8 rays in lockstep)
    // over 65,536 primary rays, 40,000 random segments, 8,000 grazing rays and 64 shadow rays per
    // point towards a quad light on Cornell, Sponza (66K), Šibenik (75K), the bunny (69K) and the
    // conference room (278K): at most 518 for one ray and 569 for a group, 1/115 of the cap. A
    // caller that traces many rays per invocation must bound them (raytrace's shade, glossy_gather).
    loop {
        if sp == 0u {
            break;
        }
        sp -= 1u;
        trace_work += 1u;
        let node = nodes[stack[sp]];
        let index = stack[sp];
        if slab(node, origin, inv, best) >= 3.0e38 {
            continue;
        }
        if node.count > 0u {
            trace_work += node.count + 2u;
            for (var k = 0u; k < node.count; k += 1u) {
                let tri = triangles[node.right_or_first + k];
                let t = intersect_triangle(sheared, tri, 0.0, best);
                if t >= 0.0 && (t < best || (t == best && tri.prim < prim)) {
                    best = t;
                    prim = tri.prim;
                    if any {
                        return GpuHit(prim, 1.0);
                    }
                }
            }
            continue;
        }
        // Inner node: push the farther child first so the nearer is visited first.
        let left = index + 1u;
        let right = node.right_or_first;
        let dl = slab(nodes[left], origin, inv, best);
        let dr = slab(nodes[right], origin, inv, best);
        // Cannot happen for a tree GpuBvh::new accepted (see `stack`); were it to, the traversal
        // ends with t = −1, which no hit or miss has (RayTracer::trace reports it), rather than
        // drop a subtree and answer as if it had been searched.
        if sp + 2u > TRAVERSAL_STACK {
            return GpuHit(MISS, -1.0);
        }
        if dl <= dr {
            if dr < 3.0e38 { stack[sp] = right; sp += 1u; }
            if dl < 3.0e38 { stack[sp] = left; sp += 1u; }
        } else {
            if dl < 3.0e38 { stack[sp] = left; sp += 1u; }
            if dr < 3.0e38 { stack[sp] = right; sp += 1u; }
        }
    }
    if any {
        return GpuHit(MISS, 0.0);
    }
    return GpuHit(prim, best);
}
