// Closest-hit and any-hit ray tracing over beam-bvh's GPU layout: one invocation per ray. The CPU
// twin is beam_bvh::FlatBvh::closest_hit / any_hit (front-to-back stack traversal, watertight test).
// shared/bvh.wgsl and lib/trace.wgsl (nodes, triangles, trace_ray) are prepended by the host.

// Keep in sync with beam_gpu::raytrace::GpuRay (32 bytes).
struct GpuRay {
    origin: vec3<f32>,
    t_max: f32,
    direction: vec3<f32>,
    // 0: closest hit; 1: any hit.
    kind: u32,
}

@group(0) @binding(2) var<storage, read> rays: array<GpuRay>;
@group(0) @binding(3) var<storage, read_write> hits: array<GpuHit>;

@compute @workgroup_size(64)
fn trace(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&rays) {
        return;
    }
    let ray = rays[i];
    hits[i] = trace_ray(ray.origin, ray.direction, ray.t_max, ray.kind == 1u);
}

// ---- Shading of diffuse, glossy and emissive points (CPU twin: beam_gpu::shade::shade_twin;
// beam_cpu::render::shade_point with point lights exactly, area lights by stratified shadow rays
// with the `Shading::Exact` estimator, seeded by a hash instead of PCG32) ----

// Keep in sync with beam_gpu::shade::ShadeInput (32 bytes).
struct ShadeInput {
    p: vec3<f32>,
    prim: u32,
    d: vec3<f32>,   // unit direction of the arriving ray
    seed: u32,
}

// Keep in sync with beam_gpu::shade::PrimShading (32 bytes).
struct PrimShading {
    normal: vec3<f32>,  // unit geometric normal
    kind: u32,          // 0: diffuse or glossy (color = albedo); 1: emissive (color = radiance)
    color: vec3<f32>,
    plane: i32,         // caustic irradiance plane, −1 for none
}

// Keep in sync with beam_gpu::shade::GpuLight (64 bytes).
struct Light {
    a: vec3<f32>,      // point: position; quad: corner; triangle: v0
    kind: u32,         // 0: point, 1: quad, 2: triangle
    b: vec3<f32>,      // quad: edge_u; triangle: v1 − v0
    area: f32,
    c: vec3<f32>,      // quad: edge_v; triangle: v2 − v0
    pad: u32,
    power: vec3<f32>,  // point: intensity; area lights: radiance
    pad2: u32,
}

// Keep in sync with beam_gpu::shade::CausticPlane (48 bytes).
struct CausticPlane {
    origin: vec3<f32>,
    offset: u32,       // first texel in `flux`
    axis_u: vec3<f32>, // scaled to texels
    width: u32,
    axis_v: vec3<f32>,
    height: u32,
}

// Keep in sync with beam_gpu::shade::ShadeParams (32 bytes).
struct ShadeParams {
    eps: f32,             // offset of shadow-ray origins off the surface
    inv_texel_area: f32,  // 1 / (irradiance-map texel side)²
    lights: u32,
    points: u32,
    spp: u32,             // shadow rays per area light
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(4) var<uniform> shade_params: ShadeParams;
@group(0) @binding(5) var<storage, read> shade_in: array<ShadeInput>;
@group(0) @binding(6) var<storage, read> prim_shading: array<PrimShading>;
@group(0) @binding(7) var<storage, read> lights: array<Light>;
@group(0) @binding(8) var<storage, read> planes: array<CausticPlane>;
@group(0) @binding(9) var<storage, read> flux: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read_write> shade_out: array<vec4<f32>>;

// Caustic irradiance at p on plane `k`: the flux of the four nearest texels, bilinearly weighted,
// over the texel area (beam_cpu::render::IrradianceMap::irradiance).
fn caustic_irradiance(k: u32, p: vec3<f32>) -> vec3<f32> {
    let plane = planes[k];
    let q = p - plane.origin;
    let c = vec2<f32>(dot(q, plane.axis_u), dot(q, plane.axis_v));
    let c0 = floor(c);
    let a = c - c0;
    var sum = vec3<f32>(0.0);
    for (var j = 0; j < 4; j++) {
        let dx = j % 2;
        let dy = j / 2;
        let w = select(1.0 - a.x, a.x, dx == 1) * select(1.0 - a.y, a.y, dy == 1);
        let x = i32(c0.x) + dx;
        let y = i32(c0.y) + dy;
        if w > 0.0 && x >= 0 && y >= 0 && x < i32(plane.width) && y < i32(plane.height) {
            sum += w * flux[plane.offset + u32(y) * plane.width + u32(x)].xyz;
        }
    }
    return sum * shade_params.inv_texel_area;
}

// PCG hash (Jarzynski and Olano 2020).
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A uniform number in [0, 1) from the point's seed and a sample index.
fn uniform01(seed: u32, i: u32) -> f32 {
    return f32(pcg_hash(seed ^ pcg_hash(i)) >> 8u) / 16777216.0;
}

// Irradiance per unit radiance at q (normal n) from area light `l`: `spp` stratified shadow rays,
// area · mean of cos·cos'/r² over the unoccluded ones (Shading::Exact's estimator).
fn area_light(l: Light, q: vec3<f32>, n: vec3<f32>, seed: u32) -> f32 {
    var ln = normalize(cross(l.b, l.c));
    var center = l.a + 0.5 * (l.b + l.c);
    if l.kind == 2u { center = l.a + (l.b + l.c) / 3.0; }
    if dot(ln, q - center) <= 0.0 { return 0.0; }
    let spp = max(shade_params.spp, 1u);
    let k = u32(sqrt(f32(spp)));
    var integral = 0.0;
    for (var i = 0u; i < spp; i++) {
        var s = uniform01(seed, 2u * i);
        var t = uniform01(seed, 2u * i + 1u);
        if i < k * k {
            s = (f32(i % k) + s) / f32(k);
            t = (f32(i / k) + t) / f32(k);
        }
        if l.kind == 2u && s + t > 1.0 {
            s = 1.0 - s;
            t = 1.0 - t;
        }
        let to = l.a + s * l.b + t * l.c - q;
        if trace_ray(q, to, 1.0 - 1e-4, true).t > 0.5 { continue; }
        let r2 = dot(to, to);
        let w = to / sqrt(r2);
        integral += max(dot(n, w), 0.0) * max(-dot(ln, w), 0.0) / r2;
    }
    return l.area * integral / f32(spp);
}

@compute @workgroup_size(64)
fn shade(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * 64u + id.x;
    if i >= shade_params.points {
        return;
    }
    let s = shade_in[i];
    let m = prim_shading[s.prim];
    if m.kind == 1u {
        shade_out[i] = vec4<f32>(m.color, 0.0);
        return;
    }
    var n = m.normal;
    if dot(n, s.d) >= 0.0 {
        n = -n;
    }
    let q = s.p + n * shade_params.eps;
    var e = vec3<f32>(0.0);
    for (var j = 0u; j < shade_params.lights; j++) {
        let light = lights[j];
        if light.kind != 0u {
            e += light.power * area_light(light, q, n, pcg_hash(s.seed ^ pcg_hash(0x9e3779b9u + j)));
            continue;
        }
        let to = light.a - q;
        let r2 = dot(to, to);
        let cosine = dot(n, to) / sqrt(r2);
        if cosine > 0.0 && trace_ray(q, to, 1.0 - 1e-4, true).t < 0.5 {
            e += light.power * cosine / r2;
        }
    }
    if m.plane >= 0 {
        e += caustic_irradiance(u32(m.plane), s.p);
    }
    shade_out[i] = vec4<f32>(m.color / 3.1415927 * e, 0.0);
}
