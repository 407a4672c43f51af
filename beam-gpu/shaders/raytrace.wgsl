// Closest-hit and any-hit ray tracing over beam-bvh's GPU layout: one invocation per ray. The CPU
// twin is beam_bvh::FlatBvh::closest_hit / any_hit (front-to-back stack traversal, watertight test).
// shared/bvh.wgsl is prepended by the host.

// Keep in sync with beam_gpu::raytrace::GpuRay (32 bytes).
struct GpuRay {
    origin: vec3<f32>,
    t_max: f32,
    direction: vec3<f32>,
    // 0: closest hit; 1: any hit.
    kind: u32,
}

// Keep in sync with beam_gpu::raytrace::GpuHit (8 bytes): prim is 0xffffffff on a miss; for an
// any-hit ray t is 1 when occluded and 0 otherwise.
struct GpuHit {
    prim: u32,
    t: f32,
}

@group(0) @binding(0) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> triangles: array<BvhTriangle>;
@group(0) @binding(2) var<storage, read> rays: array<GpuRay>;
@group(0) @binding(3) var<storage, read_write> hits: array<GpuHit>;

const STACK: u32 = 64u;

@compute @workgroup_size(64)
fn trace(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&rays) {
        return;
    }
    let ray = rays[i];
    let sheared = shear_ray(ray.origin, ray.direction);
    let inv = 1.0 / ray.direction;
    var best = ray.t_max;
    var prim = 0xffffffffu;
    var stack: array<u32, 64>;
    var sp = 0u;
    if slab(nodes[0], ray.origin, inv, best) < 3.0e38 {
        stack[0] = 0u;
        sp = 1u;
    }
    loop {
        if sp == 0u {
            break;
        }
        sp -= 1u;
        let node = nodes[stack[sp]];
        let index = stack[sp];
        if slab(node, ray.origin, inv, best) >= 3.0e38 {
            continue;
        }
        if node.count > 0u {
            for (var k = 0u; k < node.count; k += 1u) {
                let tri = triangles[node.right_or_first + k];
                let t = intersect_triangle(sheared, tri, 0.0, best);
                if t >= 0.0 && (t < best || (t == best && tri.prim < prim)) {
                    best = t;
                    prim = tri.prim;
                    if ray.kind == 1u {
                        hits[i] = GpuHit(prim, 1.0);
                        return;
                    }
                }
            }
            continue;
        }
        // Inner node: push the farther child first so the nearer is visited first.
        let left = index + 1u;
        let right = node.right_or_first;
        let dl = slab(nodes[left], ray.origin, inv, best);
        let dr = slab(nodes[right], ray.origin, inv, best);
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
    if ray.kind == 1u {
        hits[i] = GpuHit(0xffffffffu, 0.0);
    } else {
        hits[i] = GpuHit(prim, best);
    }
}
