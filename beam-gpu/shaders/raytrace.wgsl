// Closest-hit and any-hit ray tracing over beam-bvh's GPU layout: one invocation per ray. The CPU
// twin is beam_bvh::FlatBvh::closest_hit / any_hit (front-to-back stack traversal, watertight test).
// The traversal (nodes, triangles, trace_ray) is lib/trace.wgsl's.

// #import lib/trace.wgsl
// #import lib/shade_input.wgsl

// Twin of beam_gpu::raytrace::GpuRay (32 bytes).
struct GpuRay {
    origin: vec3<f32>,
    t_max: f32,
    direction: vec3<f32>,
    // RAY_CLOSEST or RAY_ANY.
    kind: u32,
}

@group(0) @binding(2) var<storage, read> rays: array<GpuRay>;
@group(0) @binding(3) var<storage, read_write> hits: array<GpuHit>;

// One trace_ray per invocation. Its loops (lib/trace.wgsl) are bounded by the BVH: at most every
// node once and every triangle once, far past llvmpipe's 65,535 for a mesh of 66K triangles or
// more, but measured on real scenes at no more than 569 iterations for a SIMD group of 8 rays (see
// trace_ray): no pass splitting here.
@compute @workgroup_size(WORKGROUP_SIZE)
fn trace(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&rays) {
        return;
    }
    let ray = rays[i];
    hits[i] = trace_ray(ray.origin, ray.direction, ray.t_max, ray.kind == RAY_ANY);
}

// ---- Shading of diffuse, glossy and emissive points (CPU twin: beam_gpu::shade::shade_twin;
// beam_cpu::render::shade_point with point lights exactly, area lights by stratified shadow rays
// with the `Shading::Exact` estimator, seeded by a hash instead of PCG32) ----

// Twin of beam_gpu::shade::PrimShading (32 bytes).
struct PrimShading {
    normal: vec3<f32>,  // unit geometric normal
    kind: u32,          // SURFACE_REFLECTING (color = albedo), SURFACE_EMISSIVE (color = radiance)
    color: vec3<f32>,
    plane: i32,         // front grid of its caustic irradiance plane (the back one next), −1 for none
}

// Twin of beam_gpu::shade::GpuLight (64 bytes).
struct Light {
    a: vec3<f32>,      // point: position; quad: corner; triangle: v0
    kind: u32,         // LIGHT_POINT, LIGHT_QUAD or LIGHT_TRIANGLE
    b: vec3<f32>,      // quad: edge_u; triangle: v1 − v0
    area: f32,
    c: vec3<f32>,      // quad: edge_v; triangle: v2 − v0
    pad: u32,
    power: vec3<f32>,  // point: intensity; area lights: radiance
    pad2: u32,
}

// Twin of beam_gpu::shade::CausticPlane (48 bytes).
struct CausticPlane {
    origin: vec3<f32>,
    offset: u32,       // first texel in `flux` (texel i at (i mod width, i / width))
    axis_u: vec3<f32>, // scaled to texels
    width: u32,
    axis_v: vec3<f32>,
    height: u32,
}

// Twin of beam_gpu::shade::ShadeParams (32 bytes).
struct ShadeParams {
    eps: f32,             // offset of shadow-ray origins off the surface
    inv_texel_area: f32,  // 1 / (irradiance-map texel side)²
    lights: u32,
    points: u32,
    spp: u32,             // shadow rays per area light
    // Loop iterations (shadow rays, and their BVH steps and triangle tests) an invocation may run
    // in one pass before it leaves its state for the next (beam_gpu::shade::PASS_BUDGET).
    budget: u32,
    pad1: u32,
    pad2: u32,
}

// Twin of beam_gpu::shade::ShadeState (32 bytes): a point's shading between passes,
// zero before the first.
struct ShadeState {
    // Irradiance of the lights before `light`.
    e: vec3<f32>,
    // Area light `light`'s sum over its samples before `sample`.
    integral: f32,
    // The light the point goes on at; SHADED once its radiance is written.
    light: u32,
    // The next sample of area light `light`.
    sample: u32,
    pad0: u32,
    pad1: u32,
}

// Twin of beam_gpu::shade (a 16-byte header, then one ShadeState per point).
struct ShadeStates {
    // Points a pass left unfinished (the host zeroes it before each pass).
    unfinished: atomic<u32>,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    points: array<ShadeState>,
}

@group(0) @binding(4) var<uniform> shade_params: ShadeParams;
@group(0) @binding(5) var<storage, read> shade_in: array<ShadeInput>;
@group(0) @binding(6) var<storage, read> prim_shading: array<PrimShading>;
@group(0) @binding(7) var<storage, read> lights: array<Light>;
@group(0) @binding(8) var<storage, read> planes: array<CausticPlane>;
// The caustic maps' flux (rgb as f32 bits): a texture, so that no storage binding bounds it.
@group(0) @binding(9) var flux: texture_2d<u32>;
@group(0) @binding(10) var<storage, read_write> shade_out: array<vec4<f32>>;
@group(0) @binding(11) var<storage, read_write> shade_state: ShadeStates;

// Caustic irradiance at p on plane `k`: the flux of the four nearest texels, bilinearly weighted,
// over the texel area (beam_scene::irradiance_map::IrradianceMap::irradiance). Its loop: 4 iterations.
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
            let index = plane.offset + u32(y) * plane.width + u32(x);
            let row = textureDimensions(flux).x;
            sum += w * bitcast<vec3<f32>>(textureLoad(flux, vec2<u32>(index % row, index / row), 0).xyz);
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

// Sample i of the `spp` stratified shadow rays from q (normal n) to area light `l` (unit normal
// ln): cos·cos'/r² when the ray reaches the light, else 0 (Shading::Exact's estimator: the light's
// irradiance per unit radiance is its area times the mean of these).
fn area_sample(l: Light, ln: vec3<f32>, q: vec3<f32>, n: vec3<f32>, seed: u32, i: u32, spp: u32) -> f32 {
    let k = u32(sqrt(f32(spp)));
    var s = uniform01(seed, 2u * i);
    var t = uniform01(seed, 2u * i + 1u);
    if i < k * k {
        s = (f32(i % k) + s) / f32(k);
        t = (f32(i / k) + t) / f32(k);
    }
    if l.kind == LIGHT_TRIANGLE && s + t > 1.0 {
        s = 1.0 - s;
        t = 1.0 - t;
    }
    let to = l.a + s * l.b + t * l.c - q;
    if trace_ray(q, to, 1.0 - DEPTH_EPS, true).t > 0.5 { return 0.0; }
    let r2 = dot(to, to);
    let w = to / sqrt(r2);
    return max(dot(n, w), 0.0) * max(-dot(ln, w), 0.0) / r2;
}

// One pass of the shading of point i. A point takes one shadow ray per point light and `spp` per
// area light: lights × spp rays, each of up to a few hundred loop iterations on a real scene (see
// trace_ray), well past the 65,535 iterations after which software Vulkan (Mesa llvmpipe /
// lavapipe) ends every loop of a SIMD group of 8 invocations for good (4,096 rays on the Cornell box
// are about 150,000). So the loop over lights and samples keeps its whole state in shade_state (the
// light, the sample, the sums), stops once it has run `budget` iterations (trace_ray's included) and
// the host runs passes until no point is left unfinished. A pass runs at most budget + 1 shadow
// rays' worth of iterations per invocation.
@compute @workgroup_size(WORKGROUP_SIZE)
fn shade(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= shade_params.points {
        return;
    }
    var st = shade_state.points[i];
    if st.light == SHADED {
        return;
    }
    let s = shade_in[i];
    let m = prim_shading[s.prim];
    if m.kind == SURFACE_EMISSIVE {
        shade_out[i] = vec4<f32>(m.color, 0.0);
        shade_state.points[i].light = SHADED;
        return;
    }
    var n = m.normal;
    if dot(n, s.d) >= 0.0 {
        n = -n;
    }
    let q = s.p + n * shade_params.eps;
    let spp = max(shade_params.spp, 1u);
    var work = 0u;
    trace_work = 0u;
    loop {
        if st.light >= shade_params.lights {
            break;
        }
        if work + trace_work >= shade_params.budget {
            atomicAdd(&shade_state.unfinished, 1u);
            shade_state.points[i] = st;
            return;
        }
        work += 1u;
        let light = lights[st.light];
        if light.kind == LIGHT_POINT {
            let to = light.a - q;
            let r2 = dot(to, to);
            let cosine = dot(n, to) / sqrt(r2);
            if cosine > 0.0 && trace_ray(q, to, 1.0 - DEPTH_EPS, true).t < 0.5 {
                st.e += light.power * cosine / r2;
            }
            st.light += 1u;
            continue;
        }
        let ln = normalize(cross(light.b, light.c));
        var center = light.a + 0.5 * (light.b + light.c);
        if light.kind == LIGHT_TRIANGLE { center = light.a + (light.b + light.c) / 3.0; }
        // Only a light facing the point is sampled.
        let facing = dot(ln, q - center) > 0.0;
        if facing && st.sample < spp {
            let seed = pcg_hash(s.seed ^ pcg_hash(0x9e3779b9u + st.light));
            st.integral += area_sample(light, ln, q, n, seed, st.sample, spp);
            st.sample += 1u;
            continue;
        }
        if facing {
            st.e += light.power * (light.area * st.integral / f32(spp));
        }
        st.light += 1u;
        st.sample = 0u;
        st.integral = 0.0;
    }
    if m.plane >= 0 {
        // The plane's front grid, or its back one where the eye's ray travels along its normal.
        let front = planes[m.plane];
        let back = dot(cross(front.axis_u, front.axis_v), s.d) > 0.0;
        st.e += caustic_irradiance(u32(m.plane) + select(0u, 1u, back), s.p);
    }
    shade_out[i] = vec4<f32>(m.color / 3.1415927 * st.e, 0.0);
    shade_state.points[i].light = SHADED;
}
