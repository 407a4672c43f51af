// The GPU layout of beam-bvh (beam-bvh/src/gpu.rs) and the watertight ray–triangle test of
// beam-math (collide/ray_triangle.rs, Woop, Benthin, Wald 2013) in WGSL.

// Twin of beam_bvh::FlatNode (32 bytes).
struct BvhNode {
    min: vec3<f32>,
    right_or_first: u32,
    max: vec3<f32>,
    count: u32,
}

// Twin of beam_bvh::gpu::GpuTriangle (48 bytes).
struct BvhTriangle {
    v0: vec3<f32>,
    prim: u32,
    v1: vec3<f32>,
    pad1: u32,
    v2: vec3<f32>,
    pad2: u32,
}

// A ray sheared so that its direction is +z (the watertight test's set-up).
struct ShearedRay {
    origin: vec3<f32>,
    kx: u32,
    ky: u32,
    kz: u32,
    s: vec3<f32>,
}

fn component(v: vec3<f32>, k: u32) -> f32 {
    if k == 0u { return v.x; }
    if k == 1u { return v.y; }
    return v.z;
}

fn shear_ray(origin: vec3<f32>, d: vec3<f32>) -> ShearedRay {
    let a = abs(d);
    var kz = 2u;
    if a.x > a.y {
        if a.x > a.z { kz = 0u; }
    } else if a.y > a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if component(d, kz) < 0.0 {
        let t = kx;
        kx = ky;
        ky = t;
    }
    let dz = component(d, kz);
    return ShearedRay(origin, kx, ky, kz, vec3<f32>(component(d, kx) / dz, component(d, ky) / dz, 1.0 / dz));
}

fn shear_point(r: ShearedRay, p: vec3<f32>) -> vec3<f32> {
    let q = p - r.origin;
    let z = component(q, r.kz);
    return vec3<f32>(component(q, r.kx) - r.s.x * z, component(q, r.ky) - r.s.y * z, r.s.z * z);
}

// Distance along the ray to the triangle in [t_min, t_max], or -1 for a miss.
fn intersect_triangle(r: ShearedRay, tri: BvhTriangle, t_min: f32, t_max: f32) -> f32 {
    let a = shear_point(r, tri.v0);
    let b = shear_point(r, tri.v1);
    let c = shear_point(r, tri.v2);
    let u = c.x * b.y - c.y * b.x;
    let v = a.x * c.y - a.y * c.x;
    let w = b.x * a.y - b.y * a.x;
    // (The CPU falls back to f64 when an edge function is exactly 0; WGSL has no portable f64, so a
    // ray exactly on an edge may be decided differently here: the conformance test states it.)
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return -1.0;
    }
    let det = u + v + w;
    if det == 0.0 {
        return -1.0;
    }
    let t = (u * a.z + v * b.z + w * c.z) / det;
    if !(t >= t_min && t <= t_max) {
        return -1.0;
    }
    return t;
}

// Slab entry distance into a node, or a huge value when the ray misses it before t_max.
fn slab(node: BvhNode, origin: vec3<f32>, inv: vec3<f32>, t_max: f32) -> f32 {
    let t1 = (node.min - origin) * inv;
    let t2 = (node.max - origin) * inv;
    let near = max(max(max(min(t1.x, t2.x), min(t1.y, t2.y)), min(t1.z, t2.z)), 0.0);
    let far = min(min(min(max(t1.x, t2.x), max(t1.y, t2.y)), max(t1.z, t2.z)), t_max);
    if near <= far {
        return near;
    }
    return 3.0e38;
}
