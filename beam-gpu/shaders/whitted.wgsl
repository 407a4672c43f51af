// Whitted rays past the beam tree on the GPU: mirror and glass points send on their specular rays
// (at most MAX_DEPTH bounces), the points the paths end on are appended as shading inputs (shaded
// by raytrace.wgsl's `shade`), and `gather` adds each end's radiance, times its path's weight, to
// its destination. `paths` follows each point's paths to their ends in one dispatch, depth first
// (the siblings still to trace on a private stack), appending only ends, as many as `ends` holds
// (the count goes on past it: the host sizes the outputs again and dispatches again). The waves
// do the same in a dispatch per bounce: `start` takes the points to shade, `wave` one wave of
// paths; both append up to two paths per item (the host sizes the outputs) and zero ends or one.
// Each dispatch gets new, zeroed `counts`. CPU twin: beam_scene::nonlinear::shade_by_waves with
// beam_scene::specular::specular_rays.

// #import shared/nonlinear.wgsl
// #import lib/trace.wgsl
// #import lib/shade_input.wgsl
// #import lib/specular.wgsl

// Twin of beam_gpu::nonlinear::WhittedParams (16 bytes).
struct WhittedParams {
    // Items of the dispatch. `wave`: its first path in `paths_in`; `start`, `paths`: the
    // destination of its first point (point k's is first + k).
    count: u32,
    first: u32,
    // `wave`: 1 on the last wave (specular hits end there, unshaded).
    last: u32,
    // Offset of the specular rays' origins off the surface (beam_scene::tolerance::shading_eps).
    eps: f32,
}

// Twin of beam_gpu::nonlinear::WhittedPath (48 bytes): a path's next ray, where its radiance goes
// and with what weight.
struct Path {
    origin: vec3<f32>,
    dest: u32,
    direction: vec3<f32>,
    // The shading seed of its ends (seed32 of the point it started from).
    seed: u32,
    weight: vec3<f32>,
    pad: u32,
}

// Twin of beam_gpu::nonlinear::EndWeight (16 bytes): of an appended end, its path's weight and
// destination.
struct EndWeight {
    weight: vec3<f32>,
    dest: u32,
}

// Twin of beam_gpu::nonlinear::WhittedCounts (16 bytes).
struct WhittedCounts {
    paths: atomic<u32>,
    ends: atomic<u32>,
    // 1 + the largest item whose traversal overflowed its stack, 0 for none.
    overflow: atomic<u32>,
    pad: u32,
}

@group(0) @binding(2) var<uniform> params: WhittedParams;
// Per scene triangle: its index in `specular_prims`, NONE for a triangle that is not a mirror or glass.
@group(0) @binding(3) var<storage, read> slots: array<u32>;
// The SpecularPrims, eight texels each (texel i at (i mod width, i / width)): a texture, so that no
// storage binding bounds their number.
@group(0) @binding(4) var specular_prims: texture_2d<u32>;
// `start`: the points to shade.
@group(0) @binding(5) var<storage, read> points: array<ShadeInput>;
// `wave`: the paths to trace.
@group(0) @binding(6) var<storage, read> paths_in: array<Path>;
@group(0) @binding(7) var<storage, read_write> paths_out: array<Path>;
@group(0) @binding(8) var<storage, read_write> ends: array<ShadeInput>;
@group(0) @binding(9) var<storage, read_write> end_weights: array<EndWeight>;
@group(0) @binding(10) var<storage, read_write> counts: WhittedCounts;
// `gather`: the ends' shaded radiance, and the radiance (vec4 per destination, f32 bits) it adds to.
@group(0) @binding(11) var<storage, read> shaded: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read_write> radiance: array<atomic<u32>>;

// `paths`: the paths still to trace of the item's point, each with its bounce (as the waves
// number them), and how many; the bounce of the paths `bounce` pushes. Depth first, a path is
// replaced by at most two: the stack never holds more than MAX_DEPTH + 1.
var<private> depth_first: bool;
var<private> stack: array<Path, PATH_STACK>;
var<private> stack_bounce: array<u32, PATH_STACK>;
var<private> stack_top: u32;
var<private> next_bounce: u32;

fn push_path(origin: vec3<f32>, direction: vec3<f32>, weight: vec3<f32>, dest: u32, seed: u32) {
    let path = Path(origin, dest, direction, seed, weight, 0u);
    if depth_first {
        stack[stack_top] = path;
        stack_bounce[stack_top] = next_bounce;
        stack_top += 1u;
        return;
    }
    let j = atomicAdd(&counts.paths, 1u);
    paths_out[j] = path;
}

// The point p of triangle `prim`, reached along unit d by a path of weight `weight`: a mirror or
// glass point sends on its specular rays (specular_rays; none on the last wave), any other is
// appended as an end.
fn bounce(prim: u32, p: vec3<f32>, d: vec3<f32>, weight: vec3<f32>, dest: u32, seed: u32, last: bool) {
    let slot = slots[prim];
    if slot == NONE {
        // Counted past the room there is (`paths`: the host dispatches again with more).
        let j = atomicAdd(&counts.ends, 1u);
        if j < min(arrayLength(&ends), arrayLength(&end_weights)) {
            ends[j] = ShadeInput(p, prim, d, seed);
            end_weights[j] = EndWeight(weight, dest);
        }
        return;
    }
    if last {
        return;
    }
    let s = specular_prim(slot);
    let side = facing(s, p, d);
    let n = side.n;
    let sn = side.sn;
    let eps = params.eps;
    if s.kind == SPECULAR_MIRROR {
        var r = mirrored(d, sn);
        if s.delta > 0.0 {
            let e = s.v1 - s.v0;
            let le = length(e);
            var u = vec3<f32>(0.0);
            if le > 0.0 && le < 3.0e38 {
                u = e / le;
            }
            r = perturb(normalize(r), n, u, tilt_at(s.wavelength, u, n, p), s.delta);
        }
        push_path(p + n * eps, r, weight * s.tint, dest, seed);
    } else if s.kind == SPECULAR_GLASS {
        let reflected = mirrored(d, sn);
        // Snell's law and Schlick's Fresnel split (beam_scene::specular::dielectric).
        let t4 = refracted(d, sn, select(s.ior, 1.0 / s.ior, side.entering));
        if t4.w > 0.0 {
            let t = t4.xyz;
            let r0 = ((1.0 - s.ior) / (1.0 + s.ior)) * ((1.0 - s.ior) / (1.0 + s.ior));
            let cos_t = select(-dot(t, sn), -dot(sn, d), side.entering);
            let m = 1.0 - cos_t;
            let fresnel = r0 + (1.0 - r0) * (m * m * m * m * m);
            push_path(p + n * eps, reflected, weight * fresnel, dest, seed);
            push_path(p - n * eps, t, weight * (1.0 - fresnel), dest, seed);
        } else {
            push_path(p + n * eps, reflected, weight, dest, seed);
        }
    } else {
        push_path(p - n * eps, d, weight * s.tint, dest, seed);
    }
}

fn item(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.y * groups.x * WORKGROUP_SIZE + id.x;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn start(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = item(id, groups);
    if k >= params.count {
        return;
    }
    let s = points[k];
    bounce(s.prim, s.p, s.d, vec3<f32>(1.0), params.first + k, s.seed, false);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn wave(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = item(id, groups);
    if k >= params.count {
        return;
    }
    follow(paths_in[params.first + k], k, params.last != 0u);
}

// Trace `path` (of item k) and bounce it where it hits (`last`: its last bounce); a miss ends it.
fn follow(path: Path, k: u32, last: bool) {
    let hit = trace_ray(path.origin, path.direction, 3.0e38, false);
    if hit.prim == MISS {
        // A miss at t = −1: the traversal's stack overflowed (lib/trace.wgsl).
        if hit.t < 0.0 {
            atomicMax(&counts.overflow, k + 1u);
        }
        return;
    }
    let p = path.origin + hit.t * path.direction;
    bounce(hit.prim, p, normalize(path.direction), path.weight, path.dest, path.seed, last);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn paths(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = item(id, groups);
    if k >= params.count {
        return;
    }
    let s = points[k];
    depth_first = true;
    stack_top = 0u;
    next_bounce = 1u;
    bounce(s.prim, s.p, s.d, vec3<f32>(1.0), params.first + k, s.seed, false);
    while stack_top > 0u {
        stack_top -= 1u;
        let depth = stack_bounce[stack_top];
        next_bounce = depth + 1u;
        follow(stack[stack_top], k, depth == MAX_DEPTH);
    }
}

// Adds f to the f32 whose bits are radiance[i].
fn add_to(i: u32, f: f32) {
    var old = atomicLoad(&radiance[i]);
    loop {
        let r = atomicCompareExchangeWeak(&radiance[i], old, bitcast<u32>(bitcast<f32>(old) + f));
        if r.exchanged {
            break;
        }
        old = r.old_value;
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn gather(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = item(id, groups);
    if i >= params.count {
        return;
    }
    let k = params.first + i;
    let e = end_weights[k];
    let c = e.weight * shaded[k].xyz;
    add_to(4u * e.dest, c.x);
    add_to(4u * e.dest + 1u, c.y);
    add_to(4u * e.dest + 2u, c.z);
}
