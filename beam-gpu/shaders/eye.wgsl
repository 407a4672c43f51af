// The eye's view of a frame (000 §7.3, the eye level of the beam tree) on the GPU: per pixel centre
// of the camera, its primary ray's nearest hit. Diffuse, glossy and emissive hits inside the crop
// are appended as shading inputs (with their pixels) and stay on the GPU for the composite. Mirror
// and glass hits anywhere in the frame on a triangle that is its own S-mesh face stay too (counted
// per face: the host builds the beam tree's roots from the counts), and so do those under a coarse
// S-mesh face, at the candidate face their point lies nearest (`nearest_face`). After the tree's
// first level is built, `eye_records` makes the composite records of those inside the crop (under
// a coarse face from the point's own scattered rays, lib/coarse.wgsl). The other mirror and glass
// hits (on triangles without an S-mesh face) are appended for the host. The host zeroes `counts`
// before a dispatch. CPU twin: beam_scene::scene::Camera::pixel_ray, then the nearest hit
// (beam_bvh::FlatBvh::closest_hit); beam_cpu::nonlinear's eye view and composites (`SMesh::locate`,
// `Tree::composite`).

// #import shared/nonlinear.wgsl
// #import lib/trace.wgsl
// #import lib/shade_input.wgsl
// #import lib/record.wgsl
// #import lib/coarse.wgsl

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
    // `eye_records`: the scene's diagonal, where a texel's ray leaves the scene (lib/reproject.wgsl).
    far: f32,
    pad: u32,
    // The crop: pixels x0..x1 × y0..y1 as (x0, y0, x1, y1).
    crop: vec4<u32>,
}

// Twin of beam_gpu::nonlinear::EyeHit (16 bytes): a mirror or glass hit for the host.
struct EyeHit {
    pixel: u32,
    prim: u32,
    t: f32,
    // Its S-mesh face: its triangle's own, or the candidate its point lies nearest
    // (`nearest_face`); NONE for none (a hit for the host).
    face: u32,
}

// Twin of beam_gpu::nonlinear::EyeCounts (16 bytes).
struct EyeCounts {
    // Shading inputs appended.
    kept: atomic<u32>,
    // Hits appended for the host.
    others: atomic<u32>,
    // 1 + the largest pixel whose traversal overflowed its stack, 0 for none.
    overflow: atomic<u32>,
    // Mirror and glass hits kept.
    specular: atomic<u32>,
}

@group(0) @binding(2) var<uniform> params: EyeParams;
// Per scene triangle: LEVEL_PLAIN where the shading pass shades it (diffuse, glossy, emissive), |
// LEVEL_CURVED where its normals are interpolated (unread by `eye_view`).
@group(0) @binding(3) var<storage, read> kinds: array<u32>;
@group(0) @binding(4) var<storage, read_write> kept: array<ShadeInput>;
// Per shading input: its pixel.
@group(0) @binding(5) var<storage, read_write> targets: array<u32>;
@group(0) @binding(6) var<storage, read_write> others: array<EyeHit>;
@group(0) @binding(7) var<storage, read_write> counts: EyeCounts;
// Per scene triangle: its S-mesh face where it is the face itself, else NONE (hits for the host).
@group(0) @binding(8) var<storage, read> face_of: array<u32>;
// Per S-mesh face: the kept pixels that see it, of the frame and of the crop.
@group(0) @binding(9) var<storage, read_write> seen: array<atomic<u32>>;
// The mirror and glass hits kept on the GPU.
@group(0) @binding(10) var<storage, read_write> specular: array<EyeHit>;
// Per S-mesh face: its reflection beam and refraction beam in the tree's first level, NONE for none.
@group(0) @binding(11) var<storage, read> children: array<vec2<u32>>;
@group(0) @binding(12) var<storage, read_write> records: array<Record>;
@group(0) @binding(13) var<storage, read_write> rest: array<ShadeInput>;
@group(0) @binding(14) var<storage, read_write> rest_targets: array<u32>;
@group(0) @binding(15) var<storage, read_write> record_counts: RecordCounts;
// Per scene triangle p: at 2p and 2p + 1, the start and end in this array of its candidate S-mesh
// faces (beam_scene::nonlinear::SMesh::candidates).
@group(0) @binding(16) var<storage, read> candidates: array<u32>;
// Per S-mesh face: its three vertices (w unused).
@group(0) @binding(17) var<storage, read> corners: array<vec4<f32>>;
// `eye_records` under coarse faces: the tree's first level of beams (their rays and regions in
// `texel_t`, lib/reproject.wgsl), and the mirror and glass triangles (lib/specular.wgsl).
@group(0) @binding(18) var<storage, read> child_beams: array<Beam>;
@group(0) @binding(19) var<storage, read> texel_t: array<f32>;
// Per scene triangle: its index in `specular_prims`, NONE for a triangle that is not a mirror or glass.
@group(0) @binding(20) var<storage, read> slots: array<u32>;
@group(0) @binding(21) var specular_prims: texture_2d<u32>;

// The unnormalized direction of pixel i's primary ray: Camera::image_point at the pixel's centre,
// in the CPU's order of operations, less the eye.
fn pixel_direction(i: u32) -> vec3<f32> {
    let x = i % params.width;
    let y = i / params.width;
    let sx = (2.0 * (f32(x) + 0.5) / f32(params.width) - 1.0) * params.half_width;
    let sy = (1.0 - 2.0 * (f32(y) + 0.5) / f32(params.height)) * params.half_height;
    let on_plane = params.position + params.forward + params.right * sx + params.up * sy;
    return on_plane - params.position;
}

// Whether pixel i lies in the crop.
fn in_crop(i: u32) -> bool {
    let x = i % params.width;
    let y = i / params.width;
    return x >= params.crop.x && x < params.crop.z && y >= params.crop.y && y < params.crop.w;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn eye_view(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if k >= params.count {
        return;
    }
    let i = params.first + k;
    let d = pixel_direction(i);
    let hit = trace_ray(params.position, d, 3.0e38, false);
    if hit.prim == MISS {
        // A miss at t = −1: the traversal's stack overflowed (lib/trace.wgsl).
        if hit.t < 0.0 {
            atomicMax(&counts.overflow, i + 1u);
        }
        return;
    }
    if (kinds[hit.prim] & LEVEL_PLAIN) == 0u {
        var face = face_of[hit.prim];
        if face == NONE {
            face = nearest_face(hit.prim, params.position + d * hit.t);
        }
        if face == NONE {
            let j = atomicAdd(&counts.others, 1u);
            others[j] = EyeHit(i, hit.prim, hit.t, NONE);
            return;
        }
        atomicAdd(&seen[2u * face], 1u);
        if in_crop(i) { atomicAdd(&seen[2u * face + 1u], 1u); }
        let j = atomicAdd(&counts.specular, 1u);
        specular[j] = EyeHit(i, hit.prim, hit.t, face);
    } else if in_crop(i) {
        let j = atomicAdd(&counts.kept, 1u);
        kept[j] = ShadeInput(params.position + d * hit.t, hit.prim, normalize(d), i);
        targets[j] = i;
    }
}

// The child beams of S-mesh face `face` in the tree's first level (lib/coarse.wgsl).
fn children_of(context: u32, face: u32) -> vec2<u32> {
    return children[face];
}

// The composite of every kept mirror and glass hit inside the crop (`params.count` of them), once
// the tree's first level is built: on a face with child beams, a record looking them up at the hit
// point (a fine face: beam_cpu::nonlinear's `Tree::composite`) or where its own scattered rays
// reach (a coarse face, lib/coarse.wgsl); else a point for the Whitted rays. The host zeroes
// `record_counts` before a dispatch. Loops: `coarse_composite`'s.
@compute @workgroup_size(WORKGROUP_SIZE)
fn eye_records(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if k >= params.count {
        return;
    }
    let h = specular[k];
    if !in_crop(h.pixel) {
        return;
    }
    let d = pixel_direction(h.pixel);
    let p = params.position + d * h.t;
    let c = children[h.face];
    let coarse = face_of[h.prim] == NONE;
    if c.x != NONE {
        if !coarse {
            let j = atomicAdd(&record_counts.records, 1u);
            records[j] = Record(p, h.pixel, normalize(d), h.face, c.x, c.y, 0u, 0u, p, 0u);
            return;
        }
        let r = coarse_composite(0u, h.prim, h.face, p, normalize(d), params.far);
        if r.found {
            atomicAdd(&record_counts.coarse, 1u);
            let j = atomicAdd(&record_counts.records, 1u);
            records[j] = Record(r.reflected_p, h.pixel, normalize(d), r.face, r.children.x, r.children.y, 0u, 0u, r.refracted_p, 0u);
            return;
        }
        atomicAdd(&record_counts.uncovered, 1u);
    }
    if coarse && (kinds[h.prim] & LEVEL_CURVED) != 0u {
        atomicAdd(&record_counts.curved, 1u);
    }
    let j = atomicAdd(&record_counts.rest, 1u);
    rest[j] = ShadeInput(p, h.prim, normalize(d), h.pixel);
    rest_targets[j] = h.pixel;
}
