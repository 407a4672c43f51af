// Exact soft shadows of 001 §5 on the GPU, one shadow beam per invocation: the beam from a shade
// point to a light polygon is traversed through the BVH by its frustum, each triangle strictly
// between the point and the light splits the remaining (lit) pieces exactly at its edges
// (lib/quad.wgsl), and the pieces left are integrated by Lambert's formula. CPU twin:
// beam_cpu::render::light_seen (same depth range, same projection, same split
// rules and tolerances). A beam whose pieces pass MAX_PIECES, whose work passes the budget, or
// whose loops llvmpipe's cap cut short answers so (SHADOW_PIECES, SHADOW_BUDGET, SHADOW_CUT) and
// is traced again by the host: never dropped.

// #import shared/bvh.wgsl
// #import lib/quad.wgsl

// Twin of beam_gpu::shadow_beam::GpuLightQuery (32 bytes).
struct LightQuery {
    p: vec3<f32>,
    light: u32,
    n: vec3<f32>,
    // QUERY_CLIP_ABOVE: the light is clipped to the half-space above the tangent plane first.
    flags: u32,
}

// Twin of beam_gpu::shadow_beam::GpuLightPolygon (144 bytes): up to MAX_LIGHT_CORNERS corners
// (xyz; w unused), the unit normal of the lit side, the number of corners.
struct LightPolygon {
    corners: array<vec4<f32>, MAX_LIGHT_CORNERS>,
    normal: vec3<f32>,
    count: u32,
}

// Twin of beam_gpu::shadow_beam::GpuLightSeen (16 bytes).
struct LightSeen {
    irradiance: f32,
    fraction: f32,
    // SHADOW_DONE, or why the beam stopped short (SHADOW_PIECES, SHADOW_BUDGET, SHADOW_CUT): the
    // host traces it again.
    status: u32,
    // Loop iterations the beam took.
    work: u32,
}

// Twin of beam_gpu::shadow_beam::ShadowParams (16 bytes).
struct ShadowParams {
    queries: u32,
    // Loop iterations a beam may run before it answers SHADOW_BUDGET.
    budget: u32,
    // First query of this dispatch.
    first: u32,
    pad: u32,
}

@group(0) @binding(0) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> triangles: array<BvhTriangle>;
@group(0) @binding(2) var<uniform> params: ShadowParams;
@group(0) @binding(3) var<storage, read> lights: array<LightPolygon>;
@group(0) @binding(4) var<storage, read> queries: array<LightQuery>;
@group(0) @binding(5) var<storage, read_write> seen: array<LightSeen>;

// The beam's frame (beam_math::polybeam::BeamFrame): apex, reference plane (the light's) through
// `frame_origin` with axes u, v and unit normal away from the apex at `frame_distance`.
var<private> frame_apex: vec3<f32>;
var<private> frame_origin: vec3<f32>;
var<private> frame_u: vec3<f32>;
var<private> frame_v: vec3<f32>;
var<private> frame_normal: vec3<f32>;
var<private> frame_distance: f32;
var<private> frame_apex_uv: vec2<f32>;
var<private> side_eps: f32;

// The remaining (lit) pieces and their bounding rectangles (lo.x, lo.y, hi.x, hi.y).
var<private> pieces: array<Quad, MAX_PIECES>;
var<private> boxes: array<vec4<f32>, MAX_PIECES>;
var<private> piece_count: u32;
var<private> overflow: bool;
// The union of the boxes.
var<private> lo: vec2<f32>;
var<private> hi: vec2<f32>;
// The frustum: four side planes through the apex and the union box, then near and far, as
// (outward normal, offset): inside where n·x ≤ offset.
var<private> planes: array<vec4<f32>, 6>;

fn emit_piece(q: Quad) {
    if piece_count == MAX_PIECES {
        overflow = true;
        return;
    }
    pieces[piece_count] = q;
    boxes[piece_count] = quad_box(q);
    piece_count += 1u;
}

fn union_boxes() {
    var u = vec4<f32>(3.0e38, 3.0e38, -3.0e38, -3.0e38);
    work += piece_count + 2u;
    for (var i = 0u; i < piece_count; i += 1u) {
        u = vec4<f32>(min(u.xy, boxes[i].xy), max(u.zw, boxes[i].zw));
    }
    lo = u.xy;
    hi = u.zw;
}

fn plane_point(c: vec2<f32>) -> vec3<f32> {
    return frame_origin + c.x * frame_u + c.y * frame_v;
}

// BeamFrame::side_normals and ShadowVisitor::update_planes.
fn update_planes() {
    let q = array<vec3<f32>, 4>(
        plane_point(vec2<f32>(lo.x, lo.y)) - frame_apex,
        plane_point(vec2<f32>(hi.x, lo.y)) - frame_apex,
        plane_point(vec2<f32>(hi.x, hi.y)) - frame_apex,
        plane_point(vec2<f32>(lo.x, hi.y)) - frame_apex,
    );
    let mid = plane_point(0.5 * (lo + hi)) - frame_apex;
    work += 6u;
    for (var i = 0u; i < 4u; i += 1u) {
        var n = cross(q[i], q[(i + 1u) % 4u]);
        if dot(n, mid) > 0.0 {
            n = -n;
        }
        planes[i] = vec4<f32>(n, dot(n, frame_apex));
    }
    let d = frame_normal / frame_distance;
    planes[4] = vec4<f32>(-d, -dot(d, frame_apex) - DEPTH_EPS);
    planes[5] = vec4<f32>(d, dot(d, frame_apex) + 1.0 - DEPTH_EPS);
}

fn outside_plane(node: BvhNode, plane: vec4<f32>) -> bool {
    return dot(plane.xyz, select(node.max, node.min, plane.xyz > vec3<f32>(0.0))) > plane.w;
}

// beam_math::collide::aabb_outside_planes (unrolled: no loop for llvmpipe's cap to count).
fn outside(node: BvhNode) -> bool {
    return outside_plane(node, planes[0]) || outside_plane(node, planes[1]) || outside_plane(node, planes[2])
        || outside_plane(node, planes[3]) || outside_plane(node, planes[4]) || outside_plane(node, planes[5]);
}

// Remove from the pieces what the polygon in `poly_corners` (box [plo, phi]) hides; true when a
// piece was hit. Twin of ShadowBeam::split_pieces.
fn split_pieces(plo: vec2<f32>, phi: vec2<f32>) -> bool {
    var hit = false;
    var dropped = false;
    var lines_made = false;
    var end = piece_count;
    var i = 0u;
    work += 2u;
    loop {
        if i >= end || overflow {
            break;
        }
        work += 1u;
        let b = boxes[i];
        if b.z < plo.x || b.w < plo.y || b.x > phi.x || b.y > phi.y {
            i += 1u;
            continue;
        }
        if !lines_made {
            if !set_polygon(side_eps * side_eps) {
                return false;
            }
            lines_made = true;
        }
        let len = piece_count;
        let cover = split_quad(pieces[i], side_eps);
        if cover == COVER_OUTSIDE {
            piece_count = len;
            i += 1u;
        } else if cover == COVER_CROSSED && piece_count > len {
            // The last missed part takes this piece's place.
            hit = true;
            piece_count -= 1u;
            pieces[i] = pieces[piece_count];
            boxes[i] = boxes[piece_count];
            i += 1u;
        } else {
            // Wholly hidden: the last unvisited piece moves here, the last piece to its place.
            hit = true;
            dropped = true;
            end -= 1u;
            pieces[i] = pieces[end];
            boxes[i] = boxes[end];
            piece_count -= 1u;
            pieces[end] = pieces[piece_count];
            boxes[end] = boxes[piece_count];
        }
    }
    if dropped {
        union_boxes();
    }
    return hit;
}

// Remove from the pieces what `tri` hides: only its part strictly between the apex and the light
// counts. Twin of ShadowBeam::occlude.
fn occlude(tri: BvhTriangle) -> bool {
    let near = DEPTH_EPS * frame_distance;
    let far = (1.0 - DEPTH_EPS) * frame_distance;
    let w = array<vec3<f32>, 3>(tri.v0 - frame_apex, tri.v1 - frame_apex, tri.v2 - frame_apex);
    let h = vec3<f32>(dot(w[0], frame_normal), dot(w[1], frame_normal), dot(w[2], frame_normal));
    if all(h < vec3<f32>(near)) || all(h > vec3<f32>(far)) || any(h != h) {
        return false;
    }
    var n = 0u;
    if all(h >= vec3<f32>(near)) && all(h <= vec3<f32>(far)) {
        work += 5u;
        for (var i = 0u; i < 3u; i += 1u) {
            poly_corners[i] = frame_apex_uv + vec2<f32>(dot(w[i], frame_u), dot(w[i], frame_v)) * (frame_distance / h[i]);
        }
        n = 3u;
    } else {
        // Clip to the depth range (the two parallel planes), each edge's crossings in order.
        var clipped: array<vec4<f32>, POLY_EDGES>;
        work += 2u * POLY_EDGES + 9u;
        for (var i = 0u; i < 3u; i += 1u) {
            let a = w[i];
            let b = w[(i + 1u) % 3u];
            let ha = h[i];
            let hb = h[(i + 1u) % 3u];
            if ha >= near && ha <= far && n < POLY_EDGES {
                clipped[n] = vec4<f32>(a, ha);
                n += 1u;
            }
            var t0 = 3.0e38;
            var t1 = 3.0e38;
            if (ha < near) != (hb < near) {
                t0 = (near - ha) / (hb - ha);
            }
            if (ha < far) != (hb < far) {
                t1 = (far - ha) / (hb - ha);
            }
            let c0 = vec4<f32>(a + (b - a) * t0, near);
            let c1 = vec4<f32>(a + (b - a) * t1, far);
            let first = select(c0, c1, t1 < t0);
            let second = select(c1, c0, t1 < t0);
            if min(t0, t1) < 3.0e38 && n < POLY_EDGES {
                clipped[n] = first;
                n += 1u;
            }
            if max(t0, t1) < 3.0e38 && n < POLY_EDGES {
                clipped[n] = second;
                n += 1u;
            }
        }
        if n < 3u {
            return false;
        }
        for (var i = 0u; i < n; i += 1u) {
            let c = clipped[i];
            poly_corners[i] = frame_apex_uv + vec2<f32>(dot(c.xyz, frame_u), dot(c.xyz, frame_v)) * (frame_distance / c.w);
        }
    }
    var plo = poly_corners[0];
    var phi = poly_corners[0];
    work += n + 2u;
    for (var i = 1u; i < n; i += 1u) {
        plo = min(plo, poly_corners[i]);
        phi = max(phi, poly_corners[i]);
    }
    if phi.x < lo.x || phi.y < lo.y || plo.x > hi.x || plo.y > hi.y {
        return false;
    }
    poly_corner_count = n;
    return split_pieces(plo, phi);
}

// atan(x) for x ≥ 0 to about 1 ulp (Cephes' atanf: two range reductions and a minimax polynomial):
// WGSL allows its own atan2 an error of 4,096 ulp, which left Lambert's sum 2·10⁻⁴ off on lavapipe.
fn precise_atan(x: f32) -> f32 {
    var y = 0.0;
    var t = x;
    if x > 2.414213562373095 {
        y = 1.5707963267948966;
        t = -1.0 / x;
    } else if x > 0.4142135623730950 {
        y = 0.7853981633974483;
        t = (x - 1.0) / (x + 1.0);
    }
    let z = t * t;
    return y + (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1) * z * t + t;
}

// atan2(y, x) for y ≥ 0, in [0, π].
fn precise_angle(y: f32, x: f32) -> f32 {
    if x > 0.0 {
        return precise_atan(y / x);
    }
    if x < 0.0 {
        return 3.141592653589793 - precise_atan(y / -x);
    }
    return 1.5707963267948966;
}

// One edge's term ½ Θ (n · γ̂) of Lambert's formula from corner `a` to `b` of the reference plane
// (beam_cpu::render::lambert::edge_irradiance_f64): with `ra` = a − apex and the edge vector taken
// on the plane, ra × rb = ra × (b − a) keeps its relative precision however far the light is.
fn edge_term(n: vec3<f32>, a: vec2<f32>, b: vec2<f32>) -> f32 {
    let ra = plane_point(a) - frame_apex;
    let e = (b.x - a.x) * frame_u + (b.y - a.y) * frame_v;
    let c = cross(ra, e);
    let len = length(c);
    if !(len > 0.0) {
        return 0.0;
    }
    return 0.5 * precise_angle(len, dot(ra, ra + e)) * dot(n, c / len);
}

// Lambert's irradiance of piece `q` at the apex (normal n), per unit radiance; `edges_summed`
// counts the edges it took.
var<private> edges_summed: u32;

fn piece_irradiance(n: vec3<f32>, q: Quad) -> f32 {
    var sum = 0.0;
    for (var i = 0u; i < q.len; i += 1u) {
        sum += edge_term(n, quad_corner(q, i), quad_corner(q, (i + 1u) % q.len));
        edges_summed += 1u;
    }
    return abs(sum);
}

fn answer(status: u32, irradiance: f32, fraction: f32) -> LightSeen {
    return LightSeen(irradiance, fraction, status, work);
}

// Cross-section area of the beam on the light's plane (before any occluder).
var<private> beam_area: f32;

// Set up the beam of `query`: its frame, its pieces (the light polygon as quads) and its frustum.
// False where there is no beam (the light is behind the point or seen edge-on): its answer is
// SHADOW_DONE with nothing seen.
fn begin_beam(query: LightQuery) -> bool {
    let light = lights[query.light];
    overflow = false;
    piece_count = 0u;
    // The light, clipped above the tangent plane for exact shading (lambert::clip_above).
    var corners: array<vec3<f32>, 9>;
    var count = 0u;
    let clip = (query.flags & QUERY_CLIP_ABOVE) != 0u;
    for (var i = 0u; i < light.count; i += 1u) {
        let a = light.corners[i].xyz;
        let b = light.corners[(i + 1u) % light.count].xyz;
        let da = dot(query.n, a - query.p);
        let db = dot(query.n, b - query.p);
        if !clip || da >= 0.0 {
            corners[count] = a;
            count += 1u;
        }
        if clip && (da < 0.0) != (db < 0.0) {
            corners[count] = a + (b - a) * (da / (da - db));
            count += 1u;
        }
    }
    // light_beam: none from the light's plane or behind it.
    if count < 3u || dot(light.normal, query.p - corners[0]) <= 0.0 {
        return false;
    }
    // BeamFrame::new(p, corners[0], light normal, corners[1] − corners[0]).
    frame_apex = query.p;
    frame_origin = corners[0];
    frame_normal = normalize(light.normal);
    frame_distance = dot(frame_origin - frame_apex, frame_normal);
    if frame_distance < 0.0 {
        frame_normal = -frame_normal;
        frame_distance = -frame_distance;
    }
    if !(frame_distance > 0.0) {
        return false;
    }
    let hint = corners[1] - corners[0];
    let along = hint - dot(hint, frame_normal) * frame_normal;
    if length(along) > 0.0 {
        frame_u = normalize(along);
    } else {
        // glam's any_orthonormal_vector.
        let s = select(-1.0, 1.0, frame_normal.z >= 0.0);
        let a = -1.0 / (s + frame_normal.z);
        let b = frame_normal.x * frame_normal.y * a;
        frame_u = vec3<f32>(b, s + frame_normal.y * frame_normal.y * a, -frame_normal.y);
    }
    frame_v = cross(frame_normal, frame_u);
    let r = frame_apex - frame_origin;
    frame_apex_uv = vec2<f32>(dot(r, frame_u), dot(r, frame_v));
    // PolyBeam::new: the corners projected onto the plane, counter-clockwise.
    var section: array<vec2<f32>, 9>;
    var twice_area = 0.0;
    var centroid = vec2<f32>(0.0);
    for (var i = 0u; i < count; i += 1u) {
        let w = corners[i] - frame_apex;
        let depth = dot(w, frame_normal) / frame_distance;
        if !(depth > 0.0) {
            return false;
        }
        let q = frame_apex + w / depth - frame_origin;
        section[i] = vec2<f32>(dot(q, frame_u), dot(q, frame_v));
        centroid += section[i];
    }
    for (var i = 0u; i < count; i += 1u) {
        let a = section[i];
        let b = section[(i + 1u) % count];
        twice_area += a.x * b.y - a.y * b.x;
    }
    if twice_area < 0.0 {
        for (var i = 0u; i < count / 2u; i += 1u) {
            let t = section[i];
            section[i] = section[count - 1u - i];
            section[count - 1u - i] = t;
        }
    }
    beam_area = 0.5 * abs(twice_area);
    centroid /= f32(count);
    var scale = 0.0;
    for (var i = 0u; i < count; i += 1u) {
        scale = max(scale, length(section[i] - centroid));
    }
    side_eps = SHADOW_SIDE_EPS * max(scale, 1.17549435e-38);
    // ShadowBeam::new: a fan of quads around corner 0 (those of negative area dropped).
    var first = 1u;
    loop {
        if first + 1u >= count {
            break;
        }
        let last = min(first + 2u, count - 1u);
        var q: Quad;
        if last == first + 2u {
            q = quad_from(section[0], section[first], section[first + 1u], section[last], 4u);
        } else {
            q = quad_from(section[0], section[first], section[last], section[0], 3u);
        }
        if quad_signed_area(q) >= 0.0 {
            emit_piece(q);
        }
        first = last;
    }
    union_boxes();
    update_planes();
    return true;
}

// Remove from the pieces what the triangles of leaf `node` hide, the frustum narrowed after each
// that hid some; stops once nothing is left or the pieces overflowed.
fn occlude_leaf(node: BvhNode) {
    work += node.count + 2u;
    for (var k = 0u; k < node.count; k += 1u) {
        if occlude(triangles[node.right_or_first + k]) {
            if piece_count == 0u || overflow {
                break;
            }
            update_planes();
        }
    }
}

// The shadow beam of `query` traced to the end, or until `work` (the invocation's loop iterations
// so far) passes `budget`.
fn shadow_beam(query: LightQuery, budget: u32) -> LightSeen {
    if !begin_beam(query) {
        return answer(SHADOW_DONE, 0.0, 0.0);
    }
    // The traversal (beam_bvh's `traverse` with ShadowVisitor): depth first, every node whose box
    // is not wholly outside one of the frustum's planes.
    var stack: array<u32, TRAVERSAL_STACK>;
    var sp = 0u;
    if !outside(nodes[0]) {
        stack[0] = 0u;
        sp = 1u;
    }
    // Set only where the loop ends by its own test: llvmpipe ends every loop of a SIMD group for
    // good past its cap (LP_MAX_TGSI_LOOP_ITERATIONS), and a traversal it cut answers
    // SHADOW_CUT instead of the pieces it left.
    var traversed = false;
    work += 2u;
    loop {
        if sp == 0u || piece_count == 0u {
            traversed = true;
            break;
        }
        if overflow {
            return answer(SHADOW_PIECES, 0.0, 0.0);
        }
        if work > budget {
            return answer(SHADOW_BUDGET, 0.0, 0.0);
        }
        work += 1u;
        sp -= 1u;
        let node = nodes[stack[sp]];
        let at = stack[sp];
        if outside(node) {
            continue;
        }
        if node.count > 0u {
            occlude_leaf(node);
            continue;
        }
        // Cannot happen for a tree GpuBvh::new accepted (lib/trace.wgsl's `stack`).
        if sp + 2u > TRAVERSAL_STACK {
            return answer(SHADOW_CUT, 0.0, 0.0);
        }
        stack[sp] = node.right_or_first;
        stack[sp + 1u] = at + 1u;
        sp += 2u;
    }
    return finish_beam(query.n, traversed);
}

// The answer of a beam whose traversal ended (`traversed`: by its own test, not llvmpipe's cap):
// its pieces integrated by Lambert's formula at the apex (normal n).
fn finish_beam(n: vec3<f32>, traversed: bool) -> LightSeen {
    if overflow {
        return answer(SHADOW_PIECES, 0.0, 0.0);
    }
    if !traversed {
        return answer(SHADOW_CUT, 0.0, 0.0);
    }
    // The sums count what they took: past llvmpipe's cap (reached by the other lanes of the group
    // after this one's traversal ended) a loop runs one iteration an entry.
    var irradiance = 0.0;
    var area = 0.0;
    var summed = 0u;
    var corners_in = 0u;
    edges_summed = 0u;
    for (var i = 0u; i < piece_count; i += 1u) {
        irradiance += piece_irradiance(n, pieces[i]);
        area += abs(quad_signed_area(pieces[i]));
        summed += 1u;
        corners_in += pieces[i].len;
    }
    if summed != piece_count || edges_summed != corners_in {
        return answer(SHADOW_CUT, 0.0, 0.0);
    }
    var fraction = 0.0;
    if beam_area > 0.0 {
        fraction = min(area / beam_area, 1.0);
    }
    return answer(SHADOW_DONE, irradiance, fraction);
}

// One shadow beam per invocation, each walking the BVH alone.
@compute @workgroup_size(WORKGROUP_SIZE)
fn visible_light(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.queries {
        return;
    }
    let index = params.first + id.x;
    work = 0u;
    seen[index] = shadow_beam(queries[index], params.budget);
}

// The workgroup's traversal, shared by its WORKGROUP_SIZE beams (visible_light_together): the pending
// nodes, the stack's height, the beams that took the node on top, the beams still traversing, and
// the loop iterations its lanes have run, and whether the walk ended early (GROUP_CUT: the stack
// would have overflowed; GROUP_SPENT: the iterations passed the group's budget).
const GROUP_CUT: u32 = 1u;
const GROUP_SPENT: u32 = 2u;
var<workgroup> group_stack: array<u32, TRAVERSAL_STACK>;
var<workgroup> group_sp: u32;
var<workgroup> group_wanted: atomic<u32>;
var<workgroup> group_live: atomic<u32>;
var<workgroup> group_work: atomic<u32>;
var<workgroup> group_ended: u32;

// One shadow beam per invocation, the workgroup's beams (neighbouring shade points, mostly) walking
// the BVH together: one node at a time from a shared stack, tested by every beam that would pop it
// alone, its children pushed when any beam took it. A beam that finds a node outside its frustum
// skips the node's descendants (the slots above it on the stack), so each beam tests the nodes and
// meets the triangles it would alone, in the same order, and answers what shadow_beam answers
// wherever both finish, while the nodes and triangles are read once for the group and its lanes
// step together instead of each down its own path. `work` counts the group's steps (a beam's
// budget ends it sooner than alone). The loop holds barriers, so every lane must leave it at the
// same step: llvmpipe's cap (65,535 iterations of a SIMD group's loops, all counted together) must
// not cut it. The group's iterations, summed over its lanes (at least any SIMD group's count), end
// the walk past 5 beams' budgets (40,960 on software devices, leaving one step's worth and the
// set-up and sums below the cap; 5·2²⁰ on hardware); the beams still walking then answer
// SHADOW_BUDGET. The host picks the walk (beam_gpu::shadow_beam::Walk).
@compute @workgroup_size(WORKGROUP_SIZE)
fn visible_light_together(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let valid = id.x < params.queries;
    let index = params.first + id.x;
    work = 0u;
    var query: LightQuery;
    var begun = false;
    if valid {
        query = queries[index];
        begun = begin_beam(query);
    }
    if lane == 0u {
        group_stack[0] = 0u;
        group_sp = 1u;
        group_ended = 0u;
        atomicStore(&group_work, 0u);
        atomicStore(&group_wanted, 0u);
        atomicStore(&group_live, 0u);
    }
    workgroupBarrier();
    var live = begun;
    if live {
        atomicAdd(&group_live, 1u);
    }
    // Why a beam stopped before the walk ended (SHADOW_PIECES, SHADOW_BUDGET), else SHADOW_DONE.
    var stopped = SHADOW_DONE;
    // Set only where the loop ends by its own test (shadow_beam's `traversed`).
    var traversed = false;
    // The stack slot of the last node this beam found outside (NONE: none).
    var skip_from = NONE;
    work += 2u;
    loop {
        let sp = workgroupUniformLoad(&group_sp);
        if sp == 0u {
            traversed = true;
            break;
        }
        let before = work;
        let slot = sp - 1u;
        let at = group_stack[slot];
        let node = nodes[at];
        // Above the slot of a node this beam found outside lie only that node's descendants, which
        // the beam alone would never pop; the first pop below it ends the skip.
        let mine = slot < skip_from;
        if mine {
            skip_from = NONE;
        }
        // shadow_beam's loop head, for this beam.
        if live && mine && (piece_count == 0u || overflow || work > params.budget) {
            if piece_count != 0u {
                stopped = select(SHADOW_BUDGET, SHADOW_PIECES, overflow);
            }
            live = false;
            atomicSub(&group_live, 1u);
        }
        work += 1u;
        if live && mine {
            if outside(node) {
                skip_from = slot;
            } else {
                atomicAdd(&group_wanted, 1u);
                if node.count > 0u {
                    occlude_leaf(node);
                }
            }
        }
        atomicAdd(&group_work, work - before);
        workgroupBarrier();
        if lane == 0u {
            var next = sp - 1u;
            let wanted = atomicExchange(&group_wanted, 0u) > 0u;
            if atomicLoad(&group_live) == 0u {
                next = 0u;
            } else if atomicLoad(&group_work) > 5u * min(params.budget, 0x20000000u) {
                group_ended = GROUP_SPENT;
                next = 0u;
            } else if wanted && node.count == 0u {
                // Cannot happen for a tree GpuBvh::new accepted (lib/trace.wgsl's `stack`).
                if next + 2u > TRAVERSAL_STACK {
                    group_ended = GROUP_CUT;
                    next = 0u;
                } else {
                    group_stack[next] = node.right_or_first;
                    group_stack[next + 1u] = at + 1u;
                    next += 2u;
                }
            }
            group_sp = next;
        }
    }
    let ended = workgroupUniformLoad(&group_ended);
    if !valid {
        return;
    }
    if !begun {
        seen[index] = answer(SHADOW_DONE, 0.0, 0.0);
    } else if stopped != SHADOW_DONE {
        seen[index] = answer(stopped, 0.0, 0.0);
    } else if ended != 0u && piece_count != 0u {
        seen[index] = answer(select(SHADOW_BUDGET, SHADOW_CUT, ended == GROUP_CUT), 0.0, 0.0);
    } else {
        seen[index] = finish_beam(query.n, traversed);
    }
}

// Twin of beam_gpu::gbuffer::GBufferParams (32 bytes).
struct GBufferParams {
    width: u32,
    height: u32,
    lights: u32,
    // Loop iterations all of a pixel's beams together may run.
    budget: u32,
    // How far a shade point is lifted off its surface along its normal.
    offset: f32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(6) var<uniform> gbuffer: GBufferParams;
// A G-buffer: a world-space position per pixel (w = 1 where a surface is, 0 elsewhere) and the
// unit normal facing the viewer.
@group(0) @binding(7) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read> normals: array<vec4<f32>>;
// Each light's emitted radiance (rgb).
@group(0) @binding(9) var<storage, read> radiance: array<vec4<f32>>;
// Irradiance per pixel (rgb; a = the lights whose beams stopped short there, 0 where exact).
@group(0) @binding(10) var irradiance_out: texture_storage_2d<rgba32float, write>;
// Beams that stopped short, over the whole dispatch.
@group(0) @binding(11) var<storage, read_write> stopped_short: atomic<u32>;

// The irradiance of every pixel of a G-buffer from every light, by exact shadow beams (001 eq. 1
// with Lambert's formula), written to a texture on the device. The lights are clipped above each
// pixel's tangent plane. A beam that stops short adds nothing, counts in the pixel's alpha and in
// `stopped_short`: the engine sees where and how many, and can trace those again.
@compute @workgroup_size(WORKGROUP_SIZE)
fn gbuffer_irradiance(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if index >= gbuffer.width * gbuffer.height {
        return;
    }
    let pixel = vec2<u32>(index % gbuffer.width, index / gbuffer.width);
    let position = positions[index];
    if position.w == 0.0 {
        textureStore(irradiance_out, pixel, vec4<f32>(0.0));
        return;
    }
    let n = normals[index].xyz;
    let p = position.xyz + gbuffer.offset * n;
    work = 0u;
    var e = vec3<f32>(0.0);
    var short = 0u;
    // Lights taken: fewer than all where llvmpipe's cap cut the loop (those count as stopped short).
    var taken = 0u;
    work += 2u;
    for (var l = 0u; l < gbuffer.lights; l += 1u) {
        // No beam begins past the pixel's budget: the rest count as stopped short (a beam's set-up
        // loops are not guarded the way its traversal is).
        if work > gbuffer.budget {
            break;
        }
        work += 1u;
        taken += 1u;
        let answer = shadow_beam(LightQuery(p, l, n, QUERY_CLIP_ABOVE), gbuffer.budget);
        if answer.status == SHADOW_DONE {
            e += radiance[l].rgb * answer.irradiance;
        } else {
            short += 1u;
        }
    }
    short += gbuffer.lights - taken;
    if short > 0u {
        atomicAdd(&stopped_short, short);
    }
    textureStore(irradiance_out, pixel, vec4<f32>(e, f32(short)));
}
