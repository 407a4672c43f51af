// The eye's view of a frame (000 §7.3, the eye level of the beam tree) on the GPU: per pixel centre
// of the camera, its primary ray's nearest hit. Diffuse, glossy and emissive hits inside the crop
// are appended as shading inputs (with their pixels) and stay on the GPU for the composite; mirror
// and glass hits anywhere in the frame are appended for the host, which builds the beam tree from
// them. The host zeroes `counts` before a dispatch. CPU twin: beam_scene::scene::Camera::pixel_ray,
// then the nearest hit (beam_bvh::FlatBvh::closest_hit); lib/trace.wgsl is prepended by the host.

// Twin of beam_gpu::nonlinear::EyeParams (96 bytes): the camera's frame (Camera::frame) and the
// dispatch's pixels.
struct EyeParams {
    position: vec3<f32>,
    width: u32,
    forward: vec3<f32>,
    height: u32,
    right: vec3<f32>,
    // First pixel of the dispatch (row-major in the frame).
    first: u32,
    up: vec3<f32>,
    // Pixels of the dispatch.
    count: u32,
    half_width: f32,
    half_height: f32,
    pad0: u32,
    pad1: u32,
    // The crop: pixels x0..x1 × y0..y1 as (x0, y0, x1, y1).
    crop: vec4<u32>,
}

// Twin of beam_gpu::shade::ShadeInput (32 bytes).
struct ShadeInput {
    p: vec3<f32>,
    prim: u32,
    d: vec3<f32>,
    seed: u32,
}

// Twin of beam_gpu::nonlinear::EyeHit (16 bytes): a mirror or glass hit for the host.
struct EyeHit {
    pixel: u32,
    prim: u32,
    t: f32,
    pad: u32,
}

// Twin of beam_gpu::nonlinear::EyeCounts (16 bytes).
struct EyeCounts {
    // Shading inputs appended.
    kept: atomic<u32>,
    // Hits appended for the host.
    others: atomic<u32>,
    // 1 + the largest pixel whose traversal overflowed its stack, 0 for none.
    overflow: atomic<u32>,
    pad: u32,
}

@group(0) @binding(2) var<uniform> params: EyeParams;
// Per scene triangle: 1 where the shading pass shades it (diffuse, glossy, emissive), else 0.
@group(0) @binding(3) var<storage, read> plain: array<u32>;
@group(0) @binding(4) var<storage, read_write> kept: array<ShadeInput>;
// Per shading input: its pixel.
@group(0) @binding(5) var<storage, read_write> targets: array<u32>;
@group(0) @binding(6) var<storage, read_write> others: array<EyeHit>;
@group(0) @binding(7) var<storage, read_write> counts: EyeCounts;

@compute @workgroup_size(WORKGROUP_SIZE)
fn eye_view(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if k >= params.count {
        return;
    }
    let i = params.first + k;
    let x = i % params.width;
    let y = i / params.width;
    // Camera::image_point at the pixel's centre, in the CPU's order of operations.
    let sx = (2.0 * (f32(x) + 0.5) / f32(params.width) - 1.0) * params.half_width;
    let sy = (1.0 - 2.0 * (f32(y) + 0.5) / f32(params.height)) * params.half_height;
    let on_plane = params.position + params.forward + params.right * sx + params.up * sy;
    let d = on_plane - params.position;
    let hit = trace_ray(params.position, d, 3.0e38, false);
    if hit.prim == MISS {
        // A miss at t = −1: the traversal's stack overflowed (lib/trace.wgsl).
        if hit.t < 0.0 {
            atomicMax(&counts.overflow, i + 1u);
        }
        return;
    }
    if plain[hit.prim] == 0u {
        let j = atomicAdd(&counts.others, 1u);
        others[j] = EyeHit(i, hit.prim, hit.t, 0u);
    } else if x >= params.crop.x && x < params.crop.z && y >= params.crop.y && y < params.crop.w {
        let j = atomicAdd(&counts.kept, 1u);
        kept[j] = ShadeInput(params.position + d * hit.t, hit.prim, normalize(d), i);
        targets[j] = i;
    }
}
