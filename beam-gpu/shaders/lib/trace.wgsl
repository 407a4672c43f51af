// The closest-hit and any-hit traversal over beam-bvh's GPU layout, bound at group 0 bindings 0
// (nodes) and 1 (triangles); included by the shaders that trace rays (raytrace, glossy_gather).
// CPU twin: beam_bvh::FlatBvh::closest_hit / any_hit (front-to-back stack traversal, watertight).

// Keep in sync with beam_gpu::raytrace::GpuHit (8 bytes): prim is 0xffffffff on a miss; for an
// any-hit ray t is 1 when occluded and 0 otherwise.
struct GpuHit {
    prim: u32,
    t: f32,
}

@group(0) @binding(0) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> triangles: array<BvhTriangle>;

const STACK: u32 = 64u;

// Loop iterations trace_ray has run in this invocation (its traversal steps and triangle tests):
// shaders that must bound their work per dispatch (glossy_gather) read it.
var<private> trace_work: u32;

// The nearest hit before t_max (any hit when `any`) of the ray (origin, direction): GpuHit with
// prim 0xffffffff on a miss; for `any`, t is 1 when occluded and 0 otherwise.
fn trace_ray(origin: vec3<f32>, direction: vec3<f32>, t_max: f32, any: bool) -> GpuHit {
    let sheared = shear_ray(origin, direction);
    let inv = 1.0 / direction;
    var best = t_max;
    var prim = 0xffffffffu;
    var stack: array<u32, 64>;
    var sp = 0u;
    if slab(nodes[0], origin, inv, best) < 3.0e38 {
        stack[0] = 0u;
        sp = 1u;
    }
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
            trace_work += node.count + 1u;
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
        if sp + 2u > STACK {
            continue;
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
        return GpuHit(0xffffffffu, 0.0);
    }
    return GpuHit(prim, best);
}
