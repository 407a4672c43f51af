// The gather of the glossy light volumes (002 §3.1, §4.2–4.3), one invocation per receiver point:
// through the cone hierarchy, every beam whose cones hold the point adds its irradiance — specular
// by eq. 1, glossy by eq. 3 with the exact Gaussian volume over the scatter-angle domain (Owen's T)
// — unless a shadow ray from the point to the beam's source point is blocked (second-order shadows);
// shadow beams mark the lights whose direct light they remove. CPU twin:
// beam_scene::glossy::LightVolumes::gather.

// #import lib/trace.wgsl

// Twin of beam_gpu::glossy::GpuLightBeam (112 bytes).
struct LightBeam {
    o0: vec3<f32>,
    // Φs / I = Ω, the light's solid angle through the scatterer.
    flux: f32,
    o1: vec3<f32>,
    // Micro-facet standard deviation (radians); 0: specular.
    sigma: f32,
    o2: vec3<f32>,
    light: u32,
    d0: vec3<f32>,
    // 1: a negative shadow beam.
    shadow: u32,
    d1: vec3<f32>,
    pad0: u32,
    d2: vec3<f32>,
    pad1: u32,
    power: vec3<f32>,
    pad2: u32,
}

// Twin of beam_gpu::glossy::GpuCone (32 bytes): cos = −1 holds every point.
struct Cone {
    apex: vec3<f32>,
    cos: f32,
    axis: vec3<f32>,
    pad: u32,
}

// Twin of beam_gpu::glossy::GpuConeNode (48 bytes).
struct ConeNode {
    apex: vec3<f32>,
    cos: f32,
    axis: vec3<f32>,
    // Inner node: its second child (the first follows it); leaf: its first beam.
    right_or_first: u32,
    // Beams of a leaf; 0 for an inner node.
    count: u32,
    // The node after its subtree in depth-first order (the node count after the last).
    skip: u32,
    pad1: u32,
    pad2: u32,
}

// Twin of beam_gpu::glossy::GatherPoint (32 bytes).
struct GatherPoint {
    p: vec3<f32>,
    pad0: u32,
    n: vec3<f32>,
    pad1: u32,
}

// Twin of beam_gpu::glossy::GpuGathered (32 bytes). Also the walk's state between
// passes: zero before the first.
struct Gathered {
    irradiance: vec3<f32>,
    shadowed: u32,
    tested: u32,
    // The node the walk goes on at (done from the node count on).
    next: u32,
    // Beams of leaf `next` already added.
    in_leaf: u32,
    pad: u32,
}

// Twin of beam_gpu::glossy::GatherParams (32 bytes).
struct GatherParams {
    points: u32,
    nodes: u32,
    // SECOND_ORDER_SHADOWS.
    flags: u32,
    // Offset of shadow-ray ends off the scatterer.
    eps: f32,
    // Loop iterations an invocation may run in one pass before it stops and leaves its walk's
    // state for the next pass.
    budget: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(2) var<uniform> params: GatherParams;
@group(0) @binding(3) var<storage, read> beams: array<LightBeam>;
@group(0) @binding(4) var<storage, read> cones: array<Cone>;
@group(0) @binding(5) var<storage, read> tree: array<ConeNode>;
@group(0) @binding(6) var<storage, read> points: array<GatherPoint>;
@group(0) @binding(7) var<storage, read_write> gathered: array<Gathered>;
// Points whose walk a pass left unfinished (the host zeroes it before each pass).
@group(0) @binding(8) var<storage, read_write> unfinished: atomic<u32>;

// Loop iterations of this invocation in this pass, besides trace_ray's (trace_work).
var<private> work: u32;

const PI: f32 = 3.14159265;

fn in_cone(apex: vec3<f32>, axis: vec3<f32>, cos_angle: f32, p: vec3<f32>) -> bool {
    let q = p - apex;
    return dot(q, axis) >= length(q) * cos_angle;
}

// Barycentric coordinates of p in the plane of triangle abc (beam_math::Triangle::barycentric);
// (−1, −1, −1) when degenerate.
fn barycentric(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let n = cross(b - a, c - a);
    let nn = dot(n, n);
    if !(nn > 0.0) {
        return vec3<f32>(-1.0);
    }
    let w0 = dot(cross(b - p, c - p), n) / nn;
    let w1 = dot(cross(c - p, a - p), n) / nn;
    return vec3<f32>(w0, w1, 1.0 - w0 - w1);
}

// A beam's flux triangle at f (002 §3.1): its rays meet the plane through f perpendicular to their
// mean direction. `ok` is false when the mean vanishes or a ray is parallel to the plane.
struct Flux {
    a: vec3<f32>,
    b: vec3<f32>,
    c: vec3<f32>,
    normal: vec3<f32>,
    ok: bool,
}

fn line_plane(o: vec3<f32>, d: vec3<f32>, n: vec3<f32>, f: vec3<f32>) -> vec4<f32> {
    let nd = dot(n, d);
    if nd == 0.0 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(o + d * (dot(n, f - o) / nd), 1.0);
}

fn flux_triangle(b: LightBeam, f: vec3<f32>) -> Flux {
    var out: Flux;
    let mean = b.d0 + b.d1 + b.d2;
    if dot(mean, mean) == 0.0 {
        out.ok = false;
        return out;
    }
    let n = normalize(mean);
    let a = line_plane(b.o0, b.d0, n, f);
    let bb = line_plane(b.o1, b.d1, n, f);
    let c = line_plane(b.o2, b.d2, n, f);
    out.a = a.xyz;
    out.b = bb.xyz;
    out.c = c.xyz;
    out.normal = n;
    out.ok = a.w > 0.0 && bb.w > 0.0 && c.w > 0.0;
    return out;
}

// f lies downstream of the scatterer (beam_math::glossy::LightBeam::in_front).
fn in_front(b: LightBeam, f: vec3<f32>) -> bool {
    let n = cross(b.o1 - b.o0, b.o2 - b.o0);
    let side = dot(b.d0 + b.d1 + b.d2, n);
    return side != 0.0 && dot(f - b.o0, n) * side > 0.0;
}

fn in_beam(t: Flux, f: vec3<f32>) -> bool {
    let w = barycentric(t.a, t.b, t.c, f);
    return min(w.x, min(w.y, w.z)) >= 0.0;
}

fn area(t: Flux) -> f32 {
    return 0.5 * length(cross(t.b - t.a, t.c - t.a));
}

// ---- The Gaussian volume over a triangle of the scatter-angle plane (beam_math::glossy::gaussian) ----

// Standard normal distribution function, by erfc (Abramowitz and Stegun 7.1.26, error < 1.5e-7).
fn normal_cdf(x: f32) -> f32 {
    let z = abs(x) / sqrt(2.0);
    let t = 1.0 / (1.0 + 0.3275911 * z);
    let poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    let erfc = poly * exp(-z * z);
    return select(1.0 - 0.5 * erfc, 0.5 * erfc, x < 0.0);
}

// Owen's T(h, a) for h ≥ 0 and 0 ≤ a ≤ 1: composite five-point Gauss–Legendre on up to 3 panels
// over the part of [0, a] where the integrand is not negligible (as beam_math::glossy::owens_t).
fn owens_t_small(h: f32, a: f32) -> f32 {
    if a == 0.0 || h > 40.0 {
        return 0.0;
    }
    let nodes = array<f32, 5>(0.0, -0.5384693, 0.5384693, -0.9061798, 0.9061798);
    let weights = array<f32, 5>(0.5688889, 0.4786287, 0.4786287, 0.2369269, 0.2369269);
    let upper = select(a, 8.95 / h, h * a > 8.95);
    let panels = max(i32(ceil(max(h * upper / 3.0, 3.0 * upper))), 1);
    work += 6u * u32(panels) + 1u;
    let width = upper / f32(panels);
    var sum = 0.0;
    for (var p = 0; p < panels; p++) {
        let mid = (f32(p) + 0.5) * width;
        for (var k = 0; k < 5; k++) {
            let t = mid + 0.5 * width * nodes[k];
            let q = 1.0 + t * t;
            sum += weights[k] * exp(-0.5 * h * h * q) / q;
        }
    }
    return sum * 0.5 * width / (2.0 * PI);
}

// Owen's T(h, a) for any a (odd in a), h ≥ 0 (beam_math::glossy::owens_t).
fn owens_t(h_in: f32, a_in: f32) -> f32 {
    let h = abs(h_in);
    let a = abs(a_in);
    var t: f32;
    if a <= 1.0 {
        t = owens_t_small(h, a);
    } else if a > 3.0e38 {
        t = 0.5 * (1.0 - normal_cdf(h));
    } else {
        let ah = a * h;
        t = 0.5 * normal_cdf(h) + 0.5 * normal_cdf(ah) - normal_cdf(h) * normal_cdf(ah) - owens_t_small(ah, 1.0 / a);
    }
    return select(t, -t, a_in < 0.0);
}

fn perp_dot(a: vec2<f32>, b: vec2<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// Signed Gaussian volume over the triangle (0, a, b) (beam_math::glossy::sector_volume).
fn sector_volume(a: vec2<f32>, b: vec2<f32>, sigma: f32) -> f32 {
    let e = b - a;
    let len = length(e);
    let cr = perp_dot(a, b);
    if len == 0.0 || cr == 0.0 {
        return 0.0;
    }
    let t = e / len;
    let h = abs(cr) / len;
    let foot = a - dot(a, t) * t;
    let sa = dot(a - foot, t);
    let sb = dot(b - foot, t);
    let ga = atan2(sa, h) / (2.0 * PI) - owens_t(h / sigma, sa / h);
    let gb = atan2(sb, h) / (2.0 * PI) - owens_t(h / sigma, sb / h);
    return sign(cr) * (gb - ga);
}

fn gaussian_volume(a: vec2<f32>, b: vec2<f32>, c: vec2<f32>, sigma: f32) -> f32 {
    return abs(sector_volume(a, b, sigma) + sector_volume(b, c, sigma) + sector_volume(c, a, sigma));
}

// The angle between f − o and d (002 §4.2.1's φ).
fn scatter_angle(o: vec3<f32>, d: vec3<f32>, f: vec3<f32>) -> f32 {
    let to_f = f - o;
    if dot(to_f, to_f) == 0.0 {
        return 0.0;
    }
    return acos(clamp(dot(normalize(to_f), normalize(d)), -1.0, 1.0));
}

// A vertex of the angular domain: φ times the unit direction from f to the flux vertex, in the
// frame (u, v) of the flux plane.
fn domain_vertex(phi: f32, vertex: vec3<f32>, f: vec3<f32>, u: vec3<f32>, v: vec3<f32>) -> vec2<f32> {
    let l = vertex - f;
    if dot(l, l) == 0.0 {
        return vec2<f32>(0.0);
    }
    let lu = normalize(l);
    return phi * vec2<f32>(dot(lu, u), dot(lu, v));
}

// Irradiance per unit of `power` at f (unit normal n): eq. 1 for a specular beam, eq. 3 with the
// exact Gaussian volume for a glossy one.
fn beam_irradiance(b: LightBeam, f: vec3<f32>, n: vec3<f32>) -> f32 {
    let t = flux_triangle(b, f);
    if !t.ok || !in_front(b, f) {
        return 0.0;
    }
    let a = area(t);
    if !(a > 0.0) {
        return 0.0;
    }
    if b.sigma <= 0.0 {
        return select(0.0, b.flux / a * max(dot(-t.normal, n), 0.0), in_beam(t, f));
    }
    // The cosine along the light's arrival from its source point (beam_math's glossy_irradiance).
    let w = source_weights(b, f);
    var arrival = t.normal;
    var to_f = vec3<f32>(0.0);
    if w.w > 0.0 {
        to_f = f - (b.o0 * w.x + b.o1 * w.y + b.o2 * w.z);
        arrival = select(vec3<f32>(0.0), normalize(to_f), dot(to_f, to_f) > 0.0);
    }
    let e = b.flux / a * max(dot(-arrival, n), 0.0);
    // Any orthonormal frame of the flux plane: the volume does not depend on it.
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(t.normal.x) > 0.9);
    let u = normalize(cross(t.normal, helper));
    let v = cross(t.normal, u);
    let da = domain_vertex(scatter_angle(b.o0, b.d0, f), t.a, f, u, v);
    let db = domain_vertex(scatter_angle(b.o1, b.d1, f), t.b, f, u, v);
    let dc = domain_vertex(scatter_angle(b.o2, b.d2, f), t.c, f, u, v);
    let p_e = min(gaussian_volume(da, db, dc, b.sigma), 1.0);
    var tail = 1.0;
    if w.w > 0.0 {
        let dir = normalize(b.d0 * w.x + b.d1 * w.y + b.d2 * w.z);
        tail = tail_factor(to_f, dir, a, 0.5 * abs(perp_dot(db - da, dc - da)));
    }
    return e * p_e * (p_e + (1.0 - p_e) * clamp(tail, 0.5, 2.0));
}

// Eq. 3's tail correction (beam_math's tail_factor): (φ/sin φ)·A⊥/(r²·|ABC|), 1 where undefined.
fn tail_factor(to: vec3<f32>, dir: vec3<f32>, area: f32, domain: f32) -> f32 {
    let r2 = dot(to, to);
    if !(r2 > 0.0 && domain > 0.0) {
        return 1.0;
    }
    let phi = acos(clamp(dot(to / sqrt(r2), dir), -1.0, 1.0));
    let stretch = select(1.0, phi / sin(phi), phi > 1e-4);
    return stretch * area / (r2 * domain);
}

// The barycentric weights of f's source point on the scatterer (w = 1), or w = 0 where there is none
// (beam_math's LightBeam::source_point).
fn source_weights(b: LightBeam, f: vec3<f32>) -> vec4<f32> {
    let t = flux_triangle(b, f);
    if !t.ok {
        return vec4<f32>(0.0);
    }
    var w = barycentric(t.a, t.b, t.c, f);
    if w.x == -1.0 && w.y == -1.0 {
        return vec4<f32>(0.0);
    }
    w = max(w, vec3<f32>(0.0));
    w = w / max(w.x + w.y + w.z, 1e-30);
    return vec4<f32>(w, 1.0);
}

// The scatterer point whose light reaches f (beam_math's LightBeam::source_point).
fn source_point(b: LightBeam, f: vec3<f32>) -> vec4<f32> {
    let w = source_weights(b, f);
    return vec4<f32>(b.o0 * w.x + b.o1 * w.y + b.o2 * w.z, w.w);
}

fn add_beam(j: u32, f: vec3<f32>, n: vec3<f32>, g: ptr<function, Gathered>) {
    (*g).tested += 1u;
    let cone = cones[j];
    if !in_cone(cone.apex, cone.axis, cone.cos, f) {
        return;
    }
    let b = beams[j];
    if b.shadow == 1u {
        let bit = 1u << min(b.light, MAX_LIGHTS - 1u);
        if ((*g).shadowed & bit) == 0u {
            let t = flux_triangle(b, f);
            if t.ok && in_front(b, f) && in_beam(t, f) {
                (*g).shadowed |= bit;
            }
        }
        return;
    }
    let e = beam_irradiance(b, f, n);
    if e == 0.0 {
        return;
    }
    if (params.flags & SECOND_ORDER_SHADOWS) != 0u {
        let s = source_point(b, f);
        if s.w > 0.0 {
            let to = s.xyz - f;
            let len = length(to);
            if len > params.eps && trace_ray(f, to, 1.0 - max(2.0 * params.eps / len, DEPTH_EPS), true).t > 0.5 {
                return;
            }
        }
    }
    (*g).irradiance += b.power * e;
}

// One pass of the walk of point i's hierarchy, in depth-first order (the CPU's stack order) by the
// nodes' skip indices, so that its whole state is the node it goes on at and the beams of that
// leaf already added: it stops after `params.budget` loop iterations (counting trace_ray's and
// Owen's T's) and the host runs passes until every walk is done. Software Vulkan (Mesa llvmpipe /
// lavapipe) ends every loop of an invocation group for good once all its loops together have run
// 65,535 iterations, which a walk over many beams passes (the walks of a whole SIMD group cut
// short, at the same iteration): hence the passes.
@compute @workgroup_size(WORKGROUP_SIZE)
fn gather(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= params.points {
        return;
    }
    var g = gathered[i];
    if g.next >= params.nodes {
        return;
    }
    let f = points[i].p;
    let n = points[i].n;
    work = 0u;
    trace_work = 0u;
    loop {
        if g.next >= params.nodes {
            break;
        }
        if work + trace_work >= params.budget {
            atomicAdd(&unfinished, 1u);
            break;
        }
        work += 1u;
        let k = g.next;
        let node = tree[k];
        if !in_cone(node.apex, node.axis, node.cos, f) {
            g.next = node.skip;
            continue;
        }
        if node.count == 0u {
            // Its first child follows it.
            g.next = k + 1u;
            continue;
        }
        loop {
            if g.in_leaf >= node.count || work + trace_work >= params.budget {
                break;
            }
            work += 1u;
            add_beam(node.right_or_first + g.in_leaf, f, n, &g);
            g.in_leaf += 1u;
        }
        if g.in_leaf >= node.count {
            g.next = node.skip;
            g.in_leaf = 0u;
        }
    }
    gathered[i] = g;
}
