// Exact primary visibility of 001 §3 on the GPU, one eye beam per pixel: the beam through the
// pixel's square traverses the BVH front to back and is split exactly into pieces, each owned by
// the nearest triangle seen through it. A triangle splits a piece at its edges (lib/quad.wgsl, the
// rules of 001 §3.2); where it is nearer than the piece's owner over only part of the piece, only
// its part in front splits it, cut along the straight line where the two inverse depths (affine
// over the image plane) are equal (the pieces and their splits: lib/eye_pieces.wgsl). Here: the
// pixel's frame and frustum, each triangle's projection, the traversal and the sums. The pieces are then summed into the pixel's fragments: per
// visible triangle, the share of the pixel it covers (the box filter) and the centroid of its
// pieces. CPU twin: beam_cpu::render::visible_surface over the pixel's square (same near plane,
// same coplanar rule, the same side tests up to their tolerance). A pixel whose pieces pass
// MAX_EYE_PIECES, whose triangles pass MAX_FRAGMENTS, whose work passes the budget, or whose loops
// llvmpipe's cap cut short answers so (EYE_PIECES, EYE_FRAGMENTS, EYE_BUDGET, EYE_CUT): it is
// never silently wrong.

// #import shared/bvh.wgsl
// #import lib/quad.wgsl
// #import lib/eye_pieces.wgsl

// Twin of beam_gpu::eye_beam::EyeBeamParams (96 bytes): the camera's image plane as a beam frame
// (beam_cpu's image_frame: u right, v down the image) and the pixels of this dispatch.
struct EyeBeamParams {
    apex: vec3<f32>,
    width: u32,
    // The ray from the eye to the image's top-left corner on the image plane.
    corner_ray: vec3<f32>,
    height: u32,
    u: vec3<f32>,
    // First pixel (row-major) of this dispatch.
    first: u32,
    v: vec3<f32>,
    // Pixels of this dispatch.
    count: u32,
    // Unit normal of the image plane, away from the apex.
    normal: vec3<f32>,
    // Loop iterations a pixel may run before it answers EYE_BUDGET.
    budget: u32,
    // A pixel's width and height on the image plane.
    pixel: vec2<f32>,
    // Distance from the apex to the image plane.
    plane_distance: f32,
    pad: u32,
}

// Twin of beam_gpu::eye_beam::GpuFragment (16 bytes): a triangle seen in a pixel.
struct EyeFragment {
    // Input index of the triangle.
    prim: u32,
    // Share of the pixel's square it covers.
    coverage: f32,
    // Centroid of its pieces in pixel-local coordinates ([0, 1]², y down).
    centroid: vec2<f32>,
}

// Twin of beam_gpu::eye_beam::GpuPixel (32 + 16·MAX_FRAGMENTS bytes).
struct EyePixel {
    // EYE_DONE, or why the pixel stopped short (then nothing else counts).
    status: u32,
    // Fragments used.
    count: u32,
    // Loop iterations the pixel took.
    work: u32,
    // Share of the pixel that sees no triangle.
    background: f32,
    // Centroid of that share, pixel-local.
    background_centroid: vec2<f32>,
    pad0: u32,
    pad1: u32,
    fragments: array<EyeFragment, MAX_FRAGMENTS>,
}

@group(0) @binding(0) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> triangles: array<BvhTriangle>;
@group(0) @binding(2) var<uniform> params: EyeBeamParams;
@group(0) @binding(3) var<storage, read_write> pixels: array<EyePixel>;

// The pixel's beam: pixel-local coordinates l name the image-plane point
// apex + corner_ray + l.x·pixel.x·u + l.y·pixel.y·v, so the pixel's square is [0, 1]² and an area
// is a share of the pixel. `corner_uv` is corner_ray's (u, v) coordinates.
var<private> apex: vec3<f32>;
var<private> corner_ray: vec3<f32>;
var<private> corner_uv: vec2<f32>;
// The frustum of the pixel: four side planes through the apex, then the near plane, as (outward
// normal, offset): inside where n·x ≤ offset.
var<private> frustum: array<vec4<f32>, 5>;

// The triangle is clipped to the pixel's window widened by this share of a pixel each way
// (ProjectedTriangle::new_in_window).
const MARGIN: f32 = 0.1;

// Point `p` in homogeneous pixel-local coordinates (X, Y, W): l = (X, Y) / W, W its depth
// along the normal (in scene units).
fn homogeneous(p: vec3<f32>) -> vec3<f32> {
    let w = p - apex;
    let h = dot(w, params.normal);
    let d = params.plane_distance;
    return vec3<f32>(
        (d * dot(w, params.u) - h * corner_uv.x) / params.pixel.x,
        (d * dot(w, params.v) - h * corner_uv.y) / params.pixel.y,
        h,
    );
}

// The ray from the apex to pixel-local point `l` of the image plane.
fn local_ray(l: vec2<f32>) -> vec3<f32> {
    return corner_ray + l.x * params.pixel.x * params.u + l.y * params.pixel.y * params.v;
}

// The frustum's planes (BeamFrame::side_normals and the near plane at EYE_NEAR).
fn set_frustum() {
    let q0 = local_ray(vec2<f32>(0.0, 0.0));
    let q1 = local_ray(vec2<f32>(1.0, 0.0));
    let q2 = local_ray(vec2<f32>(1.0, 1.0));
    let q3 = local_ray(vec2<f32>(0.0, 1.0));
    let mid = local_ray(vec2<f32>(0.5, 0.5));
    let n = array<vec3<f32>, 4>(cross(q0, q1), cross(q1, q2), cross(q2, q3), cross(q3, q0));
    work += 6u;
    for (var i = 0u; i < 4u; i += 1u) {
        let m = select(n[i], -n[i], dot(n[i], mid) > 0.0);
        frustum[i] = vec4<f32>(m, dot(m, apex));
    }
    let d = params.normal / params.plane_distance;
    frustum[4] = vec4<f32>(-d, -dot(d, apex) - EYE_NEAR);
}

fn outside_frustum_plane(node: BvhNode, plane: vec4<f32>) -> bool {
    return dot(plane.xyz, select(node.max, node.min, plane.xyz > vec3<f32>(0.0))) > plane.w;
}

// beam_math::collide::aabb_outside_planes (unrolled).
fn outside(node: BvhNode) -> bool {
    return outside_frustum_plane(node, frustum[0]) || outside_frustum_plane(node, frustum[1])
        || outside_frustum_plane(node, frustum[2]) || outside_frustum_plane(node, frustum[3])
        || outside_frustum_plane(node, frustum[4]);
}

// True when the box lies wholly behind `plane`, seen from the eye (InverseDepth::hides).
fn plane_hides(plane: vec4<f32>, node: BvhNode) -> bool {
    let front = dot(plane.xyz, select(node.min, node.max, plane.xyz > vec3<f32>(0.0)));
    return front - plane.w < -1e-5 * (abs(front) + abs(plane.w));
}

// True when every piece sees a triangle in front of the whole box (001 §3.4: a piece goes on only
// while a node may be nearer than what it sees).
fn hidden(node: BvhNode) -> bool {
    work += 2u;
    for (var i = 0u; i < piece_count; i += 1u) {
        work += 1u;
        if owners[i] == MISS || !plane_hides(owner_planes[i], node) {
            return false;
        }
    }
    return true;
}

// Depth of the box's corner nearest the image plane's side of the apex (for the order of visits).
fn near_depth(node: BvhNode) -> f32 {
    return dot(select(node.max, node.min, params.normal > vec3<f32>(0.0)) - apex, params.normal);
}

// Keep the part of polygon `a` (n corners) where plane·(X, Y, W, 1) ≥ 0 (Sutherland–Hodgman in
// homogeneous coordinates, the same as clipping in 3D by the plane through the apex).
var<private> clip_in: array<vec3<f32>, 8>;
var<private> clip_out: array<vec3<f32>, 8>;

fn clip_homogeneous(n: u32, plane: vec4<f32>) -> u32 {
    var m = 0u;
    work += n + 2u;
    for (var i = 0u; i < n; i += 1u) {
        let a = clip_in[i];
        let b = clip_in[select(i + 1u, 0u, i + 1u == n)];
        let da = dot(plane, vec4<f32>(a, 1.0));
        let db = dot(plane, vec4<f32>(b, 1.0));
        if da >= 0.0 && m < 8u {
            clip_out[m] = a;
            m += 1u;
        }
        if (da < 0.0) != (db < 0.0) && m < 8u {
            clip_out[m] = a + (b - a) * (da / (da - db));
            m += 1u;
        }
    }
    work += m + 2u;
    for (var i = 0u; i < m; i += 1u) {
        clip_in[i] = clip_out[i];
    }
    return m;
}

// Triangle `tri` clipped to the near plane and to the pixel's widened window and projected
// (ProjectedTriangle::new_in_window), into `tri_corners` with corners nearer than rounding to the
// previous one dropped; its bounding rectangle, or an empty one when nothing remains.
fn project_triangle(tri: BvhTriangle) -> vec4<f32> {
    let none = vec4<f32>(1.0, 1.0, -1.0, -1.0);
    let c = array<vec3<f32>, 3>(homogeneous(tri.v0), homogeneous(tri.v1), homogeneous(tri.v2));
    var planes = array<vec4<f32>, 5>(
        vec4<f32>(0.0, 0.0, 1.0, -EYE_NEAR * params.plane_distance),
        vec4<f32>(1.0, 0.0, MARGIN, 0.0),
        vec4<f32>(-1.0, 0.0, 1.0 + MARGIN, 0.0),
        vec4<f32>(0.0, 1.0, MARGIN, 0.0),
        vec4<f32>(0.0, -1.0, 1.0 + MARGIN, 0.0),
    );
    // The planes some corner is outside of (bit k for plane k); none when all are outside one.
    var crossed = 0u;
    work += 7u;
    for (var k = 0u; k < 5u; k += 1u) {
        let p = planes[k];
        let d = vec3<f32>(dot(p, vec4<f32>(c[0], 1.0)), dot(p, vec4<f32>(c[1], 1.0)), dot(p, vec4<f32>(c[2], 1.0)));
        if all(d < vec3<f32>(0.0)) || any(d != d) {
            return none;
        }
        if any(d < vec3<f32>(0.0)) {
            crossed |= 1u << k;
        }
    }
    clip_in[0] = c[0];
    clip_in[1] = c[1];
    clip_in[2] = c[2];
    var n = 3u;
    work += 2u;
    loop {
        if crossed == 0u {
            break;
        }
        work += 1u;
        let k = firstTrailingBit(crossed);
        crossed &= crossed - 1u;
        n = clip_homogeneous(n, planes[k]);
        if n < 3u {
            return none;
        }
    }
    tri_count = 0u;
    work += n + 2u;
    for (var i = 0u; i < n; i += 1u) {
        let l = clip_in[i].xy / clip_in[i].z;
        if tri_count == 0u || length(l - tri_corners[tri_count - 1u]) > 16.0 * SIDE_EPS {
            tri_corners[tri_count] = l;
            tri_count += 1u;
        }
    }
    if tri_count > 1u && length(tri_corners[tri_count - 1u] - tri_corners[0]) <= 16.0 * SIDE_EPS {
        tri_count -= 1u;
    }
    if tri_count < 3u {
        return none;
    }
    var b = vec4<f32>(tri_corners[0], tri_corners[0]);
    work += tri_count + 2u;
    for (var i = 1u; i < tri_count; i += 1u) {
        b = vec4<f32>(min(b.xy, tri_corners[i]), max(b.zw, tri_corners[i]));
    }
    // A polygon within a few tolerances of a point hides nothing (split_section).
    if max(b.z - b.x, b.w - b.y) <= 32.0 * SIDE_EPS || b.z < 0.0 || b.w < 0.0 || b.x > 1.0 || b.y > 1.0 {
        return none;
    }
    return b;
}

// Trace triangle `t` into the pieces (EyeTracer::leaf for one triangle).
fn trace_triangle(t: u32) {
    let tri = triangles[t];
    let tb = project_triangle(tri);
    if tb.x > tb.z {
        return;
    }
    // InverseDepth::of: 1/s = n·ray(l) / n·(v0 − apex); none for a plane through the apex.
    let n = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
    let w0 = tri.v0 - apex;
    let h = dot(n, w0);
    if abs(h) <= 1e-12 * length(n) * length(w0) || !(abs(h) > 0.0) {
        return;
    }
    let k = vec3<f32>(
        dot(n, corner_ray),
        params.pixel.x * dot(n, params.u),
        params.pixel.y * dot(n, params.v),
    ) / h;
    let facing = normalize(-n * sign(h));
    split_by(t, k, vec4<f32>(facing, dot(facing, tri.v0)), tb);
}

// Signed area of `q` times its centroid (a fan of triangles), and its signed area.
fn moment(q: Quad) -> vec3<f32> {
    let c0 = quad_corner(q, 0u);
    let c1 = quad_corner(q, 1u);
    let c2 = quad_corner(q, 2u);
    let a1 = 0.5 * ((c1.x - c0.x) * (c2.y - c0.y) - (c1.y - c0.y) * (c2.x - c0.x));
    var m = a1 * (c0 + c1 + c2) / 3.0;
    var a = a1;
    if q.len == 4u {
        let c3 = quad_corner(q, 3u);
        let a2 = 0.5 * ((c2.x - c0.x) * (c3.y - c0.y) - (c2.y - c0.y) * (c3.x - c0.x));
        m += a2 * (c0 + c2 + c3) / 3.0;
        a += a2;
    }
    return vec3<f32>(m, a);
}

fn stopped(status: u32) -> EyePixel {
    var p: EyePixel;
    p.status = status;
    p.work = work;
    return p;
}

// The eye beam through pixel `pixel` traced to the end, or until `work` passes `budget`.
fn eye_pixel(pixel: vec2<u32>, budget: u32) -> EyePixel {
    apex = params.apex;
    corner_ray = params.corner_ray + f32(pixel.x) * params.pixel.x * params.u
        + f32(pixel.y) * params.pixel.y * params.v;
    corner_uv = vec2<f32>(dot(corner_ray, params.u), dot(corner_ray, params.v));
    set_frustum();
    overflow = false;
    piece_count = 0u;
    emit_owner = MISS;
    emit_depth = vec3<f32>(0.0);
    emit_plane = vec4<f32>(0.0);
    emit_piece(quad_from(vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0), 4u));
    // The traversal: depth first, nearer child first, every node neither outside the frustum nor
    // behind what every piece sees.
    var stack: array<u32, TRAVERSAL_STACK>;
    var sp = 0u;
    if !outside(nodes[0]) {
        stack[0] = 0u;
        sp = 1u;
    }
    // Set only where the loop ends by its own test: llvmpipe ends every loop of a SIMD group for
    // good past its cap, and a traversal it cut answers EYE_CUT instead of the pieces it left.
    var traversed = false;
    work += 2u;
    loop {
        if sp == 0u {
            traversed = true;
            break;
        }
        if overflow {
            return stopped(EYE_PIECES);
        }
        if work > budget {
            return stopped(EYE_BUDGET);
        }
        work += 1u;
        sp -= 1u;
        let at = stack[sp];
        let node = nodes[at];
        if outside(node) || hidden(node) {
            continue;
        }
        if node.count > 0u {
            work += node.count + 2u;
            for (var j = 0u; j < node.count; j += 1u) {
                trace_triangle(node.right_or_first + j);
                if overflow {
                    break;
                }
            }
            continue;
        }
        // Cannot happen for a tree GpuBvh::new accepted.
        if sp + 2u > TRAVERSAL_STACK {
            return stopped(EYE_CUT);
        }
        let left = at + 1u;
        let right = node.right_or_first;
        // The farther child is pushed first, so the nearer one is visited first.
        if near_depth(nodes[left]) <= near_depth(nodes[right]) {
            stack[sp] = right;
            stack[sp + 1u] = left;
        } else {
            stack[sp] = left;
            stack[sp + 1u] = right;
        }
        sp += 2u;
    }
    if overflow {
        return stopped(EYE_PIECES);
    }
    if !traversed {
        return stopped(EYE_CUT);
    }
    // The pieces summed by owner. The sums count what they took: past llvmpipe's cap a loop runs
    // one iteration an entry.
    var out: EyePixel;
    var summed = 0u;
    var background = vec3<f32>(0.0);
    var moments: array<vec3<f32>, MAX_FRAGMENTS>;
    var count = 0u;
    work += piece_count + 2u;
    for (var i = 0u; i < piece_count; i += 1u) {
        summed += 1u;
        let m = moment(pieces[i]);
        let owner = owners[i];
        if owner == MISS {
            background += m;
            continue;
        }
        let prim = triangles[owner].prim;
        var f = 0u;
        var found = false;
        loop {
            if f >= count {
                break;
            }
            if out.fragments[f].prim == prim {
                found = true;
                break;
            }
            f += 1u;
        }
        if !found && f != count {
            return stopped(EYE_CUT);
        }
        if !found {
            if count == MAX_FRAGMENTS {
                return stopped(EYE_FRAGMENTS);
            }
            out.fragments[count].prim = prim;
            moments[count] = vec3<f32>(0.0);
            count += 1u;
        }
        moments[f] += m;
    }
    if summed != piece_count {
        return stopped(EYE_CUT);
    }
    var finished = 0u;
    for (var f = 0u; f < count; f += 1u) {
        finished += 1u;
        let m = moments[f];
        out.fragments[f].coverage = abs(m.z);
        out.fragments[f].centroid = select(vec2<f32>(0.5), m.xy / m.z, m.z != 0.0);
    }
    if finished != count {
        return stopped(EYE_CUT);
    }
    out.status = EYE_DONE;
    out.count = count;
    out.work = work;
    out.background = abs(background.z);
    out.background_centroid = select(vec2<f32>(0.5), background.xy / background.z, background.z != 0.0);
    return out;
}

// The fragments of every pixel of the dispatch (row-major from `params.first`).
@compute @workgroup_size(WORKGROUP_SIZE)
fn eye_fragments(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let local = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if local >= params.count {
        return;
    }
    let index = params.first + local;
    work = 0u;
    pixels[local] = eye_pixel(vec2<u32>(index % params.width, index / params.width), params.budget);
}
