// Small polygon beams of 001 §3.2 (Fig. 2h) in WGSL: cross-sections of at most four corners in
// 4-lane vectors, and their exact split by a convex polygon (a projected triangle) into the missed
// parts. CPU twin: beam_math::polybeam::Quad::split (same fuzzy rules of 001 App. A, same order of
// cuts, same re-cut into pieces of at most four corners). Imported by shadow_beam.wgsl and
// lib/eye_pieces.wgsl, each of which owns the piece list the missed parts go to (`emit_piece`).

// A convex cross-section of 3 or 4 corners, counter-clockwise; unused lanes repeat corner 0.
struct Quad {
    x: vec4<f32>,
    y: vec4<f32>,
    len: u32,
}

// Most edge lines of a polygon a split takes: a triangle clipped by the near and far planes keeps
// at most 5 corners, 9 with repeats (beam_math::polybeam::MAX_EDGES bounds the CPU's).
const POLY_EDGES: u32 = 9u;
// Corners of the working polygon of a cut: a quad cut by POLY_EDGES lines gains one a line.
const CUT_CORNERS: u32 = 13u;

// The occluding polygon: outward edge lines (n.x, n.y, d), inside where n·c − d ≤ 0, and corners.
var<private> poly_lines: array<vec3<f32>, POLY_EDGES>;
var<private> poly_line_count: u32;
var<private> poly_corners: array<vec2<f32>, POLY_EDGES>;
var<private> poly_corner_count: u32;

// The working polygon of a cut and its two halves.
var<private> rest: array<vec2<f32>, CUT_CORNERS>;
var<private> rest_len: u32;
var<private> inner: array<vec2<f32>, CUT_CORNERS>;
var<private> inner_len: u32;
var<private> outer: array<vec2<f32>, CUT_CORNERS>;
var<private> outer_len: u32;
var<private> dist: array<f32, CUT_CORNERS>;

// Loop iterations this invocation has run (Mesa's software Vulkan stops a SIMD group's loops for
// good past 65,535 together): every loop adds its iterations and 2 per entry.
var<private> work: u32;

fn quad_corner(q: Quad, i: u32) -> vec2<f32> {
    return vec2<f32>(q.x[i], q.y[i]);
}

fn quad_from(c0: vec2<f32>, c1: vec2<f32>, c2: vec2<f32>, c3: vec2<f32>, len: u32) -> Quad {
    return Quad(vec4<f32>(c0.x, c1.x, c2.x, c3.x), vec4<f32>(c0.y, c1.y, c2.y, c3.y), len);
}

// Shoelace area (004 App. A.10), positive counter-clockwise.
fn quad_signed_area(q: Quad) -> f32 {
    let a = q.x * q.y.yzwx - q.x.yzwx * q.y;
    if q.len == 3u {
        return 0.5 * (a.x + a.y + (q.x[2] * q.y[0] - q.x[0] * q.y[2]));
    }
    return 0.5 * (a.x + a.y + a.z + a.w);
}

// Bounding rectangle (lo.x, lo.y, hi.x, hi.y).
fn quad_box(q: Quad) -> vec4<f32> {
    return vec4<f32>(
        min(min(q.x.x, q.x.y), min(q.x.z, q.x.w)),
        min(min(q.y.x, q.y.y), min(q.y.z, q.y.w)),
        max(max(q.x.x, q.x.y), max(q.x.z, q.x.w)),
        max(max(q.y.x, q.y.y), max(q.y.z, q.y.w)),
    );
}

// The occluding polygon's edge lines from its corners (either winding); false when its area is at
// most `min_area` (a sliver or an edge-on triangle hides nothing). Twin of EdgeLines::new.
fn set_polygon(min_area: f32) -> bool {
    let k = poly_corner_count;
    var twice_area = 0.0;
    work += k + 2u;
    for (var i = 0u; i < k; i += 1u) {
        let a = poly_corners[i];
        let b = poly_corners[select(i + 1u, 0u, i + 1u == k)];
        twice_area += a.x * b.y - a.y * b.x;
    }
    if !(0.5 * abs(twice_area) > min_area) {
        return false;
    }
    let s = sign(twice_area);
    poly_line_count = 0u;
    work += k + 2u;
    for (var i = 0u; i < k; i += 1u) {
        let a = poly_corners[i];
        let e = poly_corners[select(i + 1u, 0u, i + 1u == k)] - a;
        let m = s * vec2<f32>(e.y, -e.x);
        let len = length(m);
        // A repeated corner bounds nothing.
        if len > 0.0 {
            let n = m / len;
            poly_lines[poly_line_count] = vec3<f32>(n, dot(n, a));
            poly_line_count += 1u;
        }
    }
    return true;
}

// Split `rest` by a line, given its corners' signed distances `dist` (positive outside), into
// `inner` and `outer`; corners within eps count on both sides, halves of < 3 corners are empty.
// Twin of Poly::split.
fn split_rest(eps: f32) {
    inner_len = 0u;
    outer_len = 0u;
    work += rest_len + 2u;
    for (var i = 0u; i < rest_len; i += 1u) {
        let j = select(i + 1u, 0u, i + 1u == rest_len);
        let p = rest[i];
        let q = rest[j];
        let dp = dist[i];
        let dq = dist[j];
        if dp <= eps && inner_len < CUT_CORNERS {
            inner[inner_len] = p;
            inner_len += 1u;
        }
        if dp >= -eps && outer_len < CUT_CORNERS {
            outer[outer_len] = p;
            outer_len += 1u;
        }
        if (dp < -eps && dq > eps) || (dp > eps && dq < -eps) {
            let x = p + (q - p) * (dp / (dp - dq));
            if inner_len < CUT_CORNERS {
                inner[inner_len] = x;
                inner_len += 1u;
            }
            if outer_len < CUT_CORNERS {
                outer[outer_len] = x;
                outer_len += 1u;
            }
        }
    }
    if inner_len < 3u {
        inner_len = 0u;
    }
    if outer_len < 3u {
        outer_len = 0u;
    }
}

// Hand `outer` out as pieces of at most four corners (a fan around corner 0). Twin of Poly::recut.
fn recut_outer() {
    var first = 1u;
    work += 2u;
    loop {
        if first + 1u >= outer_len {
            break;
        }
        work += 1u;
        let last = min(first + 2u, outer_len - 1u);
        if last == first + 2u {
            emit_piece(quad_from(outer[0], outer[first], outer[first + 1u], outer[last], 4u));
        } else {
            emit_piece(quad_from(outer[0], outer[first], outer[last], outer[0], 3u));
        }
        first = last;
    }
}

const COVER_OUTSIDE: u32 = 0u;
const COVER_INSIDE: u32 = 1u;
const COVER_CROSSED: u32 = 2u;

// Split `q` by the occluding polygon (001 §3.2): COVER_OUTSIDE when no part of it meets the
// polygon (Fig. 2a, 2b, or an empty intersection), COVER_INSIDE when all of it does (Fig. 2c),
// else COVER_CROSSED after handing the missed parts to `emit_piece` (Fig. 2d–g); what was emitted
// counts only for COVER_CROSSED. Twin of Quad::split and Quad::cut.
fn split_quad(q: Quad, eps: f32) -> u32 {
    // Fig. 2a and 2c, one multiply-add a line; the lines that cross the section are kept.
    var crossing = 0u;
    var dists: array<vec4<f32>, POLY_EDGES>;
    work += poly_line_count + 2u;
    for (var k = 0u; k < poly_line_count; k += 1u) {
        let l = poly_lines[k];
        let d = q.x * l.x + q.y * l.y - vec4<f32>(l.z);
        if all(d >= vec4<f32>(-eps)) {
            return COVER_OUTSIDE;
        }
        if !all(d <= vec4<f32>(eps)) {
            crossing |= 1u << k;
            dists[k] = d;
        }
    }
    if crossing == 0u {
        return COVER_INSIDE;
    }
    // Fig. 2b: a section edge with every corner of the polygon outside.
    let ex = q.x.yzwx - q.x;
    let ey = q.y.yzwx - q.y;
    let length2 = ex * ex + ey * ey;
    let tol2 = vec4<f32>(eps * eps) * length2;
    var separates = length2 > vec4<f32>(0.0);
    work += poly_corner_count + 2u;
    for (var i = 0u; i < poly_corner_count; i += 1u) {
        let c = poly_corners[i];
        let d = ey * (vec4<f32>(c.x) - q.x) - ex * (vec4<f32>(c.y) - q.y);
        separates = separates & ((d >= vec4<f32>(0.0)) | (d * d <= tol2));
    }
    let lanes = select(vec4<bool>(true, true, true, true), vec4<bool>(true, true, true, false), q.len == 3u);
    if any(separates & lanes) {
        return COVER_OUTSIDE;
    }
    // Fig. 2d–g: cut line by line, the one that cuts off the most first.
    let valid = select(vec4<f32>(1.0), vec4<f32>(1.0, 1.0, 1.0, 0.0), q.len == 3u);
    var first = firstTrailingBit(crossing);
    if (crossing & (crossing - 1u)) != 0u {
        var most = -1.0;
        var m = crossing;
        work += 2u;
        loop {
            if m == 0u {
                break;
            }
            work += 1u;
            let k = firstTrailingBit(m);
            m &= m - 1u;
            let off = dot(max(dists[k], vec4<f32>(0.0)), valid);
            if off > most {
                most = off;
                first = k;
            }
        }
    }
    rest_len = q.len;
    work += 6u;
    for (var i = 0u; i < 4u; i += 1u) {
        rest[i] = quad_corner(q, i);
        dist[i] = dists[first][i];
    }
    crossing &= ~(1u << first);
    var cut = false;
    work += 2u;
    loop {
        work += 1u;
        split_rest(eps);
        if inner_len == 0u {
            return COVER_OUTSIDE;
        }
        if outer_len > 0u {
            recut_outer();
            cut = true;
        }
        rest_len = inner_len;
        work += inner_len + 2u;
        for (var i = 0u; i < inner_len; i += 1u) {
            rest[i] = inner[i];
        }
        // The next line that crosses what is left.
        var next = false;
        loop {
            if crossing == 0u || next {
                break;
            }
            work += 1u;
            let l = poly_lines[firstTrailingBit(crossing)];
            crossing &= crossing - 1u;
            work += rest_len + 2u;
            for (var i = 0u; i < rest_len; i += 1u) {
                dist[i] = dot(l.xy, rest[i]) - l.z;
                next = next || dist[i] > eps;
            }
        }
        if !next {
            break;
        }
    }
    return select(COVER_INSIDE, COVER_CROSSED, cut);
}
