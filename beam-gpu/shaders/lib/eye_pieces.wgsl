// The pieces of a pixel's eye beam (001 §3) and their exact split by one triangle, in WGSL: the
// piece list (each piece a quad of lib/quad.wgsl with the triangle it sees and that triangle's
// inverse depth and plane), the split of every piece by a projected triangle where the triangle is
// nearer than what the piece sees, and the join of the parts that see the same triangle again.
// CPU twin: beam_cpu::render::primary_beam's EyeTracer (split_piece, resolve, join). Imported by
// eye_beam.wgsl, which projects the triangles into `tri_corners` and reads the pieces.

// #import lib/quad.wgsl

// The pieces: cross-section, bounding rectangle (lo.x, lo.y, hi.x, hi.y), owner (index into
// `triangles`, MISS for the background), the owner's inverse depth (k0, kx, ky: 1/s = k0 + k·l,
// larger = nearer) and its plane (unit normal towards the eye, offset).
var<private> pieces: array<Quad, MAX_EYE_PIECES>;
var<private> boxes: array<vec4<f32>, MAX_EYE_PIECES>;
var<private> owners: array<u32, MAX_EYE_PIECES>;
var<private> depths: array<vec3<f32>, MAX_EYE_PIECES>;
var<private> owner_planes: array<vec4<f32>, MAX_EYE_PIECES>;
var<private> piece_count: u32;
var<private> overflow: bool;
// The owner that `emit_piece` gives the pieces lib/quad.wgsl hands it.
var<private> emit_owner: u32;
var<private> emit_depth: vec3<f32>;
var<private> emit_plane: vec4<f32>;

// The triangle being traced, clipped and projected (pixel-local), before any clip by depth.
var<private> tri_corners: array<vec2<f32>, POLY_EDGES>;
var<private> tri_count: u32;

// Side tolerance of the splits, in pixel widths (beam_cpu's SPLIT_EPS times the square's size).
const SIDE_EPS: f32 = EYE_SPLIT_EPS * 0.70710678;

fn emit_piece(q: Quad) {
    if piece_count == MAX_EYE_PIECES {
        overflow = true;
        return;
    }
    pieces[piece_count] = q;
    boxes[piece_count] = quad_box(q);
    owners[piece_count] = emit_owner;
    depths[piece_count] = emit_depth;
    owner_planes[piece_count] = emit_plane;
    piece_count += 1u;
}

fn move_piece(src: u32, dst: u32) {
    pieces[dst] = pieces[src];
    boxes[dst] = boxes[src];
    owners[dst] = owners[src];
    depths[dst] = depths[src];
    owner_planes[dst] = owner_planes[src];
}
// The part of the projected triangle where g = g.x + g.y·l.x + g.z·l.y ≥ 0 (ProjectedTriangle::clip)
// into `poly_corners`; its bounding rectangle, or an empty one when fewer than 3 corners remain.
fn clip_front(g: vec3<f32>) -> vec4<f32> {
    var n = 0u;
    var b = vec4<f32>(3.0e38, 3.0e38, -3.0e38, -3.0e38);
    work += tri_count + 2u;
    for (var i = 0u; i < tri_count; i += 1u) {
        let a = tri_corners[i];
        let c = tri_corners[select(i + 1u, 0u, i + 1u == tri_count)];
        let da = g.x + dot(g.yz, a);
        let dc = g.x + dot(g.yz, c);
        if da >= 0.0 && n < POLY_EDGES {
            poly_corners[n] = a;
            b = vec4<f32>(min(b.xy, a), max(b.zw, a));
            n += 1u;
        }
        if (da < 0.0) != (dc < 0.0) && n < POLY_EDGES {
            let x = a + (c - a) * (da / (da - dc));
            poly_corners[n] = x;
            b = vec4<f32>(min(b.xy, x), max(b.zw, x));
            n += 1u;
        }
    }
    poly_corner_count = n;
    if n < 3u {
        return vec4<f32>(1.0, 1.0, -1.0, -1.0);
    }
    return b;
}

// Split the pieces by the projected triangle `t` (index into `triangles`; corners in
// `tri_corners`, bounding rectangle `tb`) of inverse depth `k` and plane `plane`, where it is
// nearer than what they see. Twin of EyeTracer::split_piece and resolve for each piece; parts made
// by this triangle are not split by it again.
fn split_by(t: u32, k: vec3<f32>, plane: vec4<f32>, tb: vec4<f32>) {
    let end = piece_count;
    var i = 0u;
    touched_count = 0u;
    // Whether poly_lines hold the whole projected triangle's lines.
    var whole = false;
    work += 2u;
    loop {
        if i >= end || overflow {
            break;
        }
        work += 1u;
        let b = boxes[i];
        if b.z < tb.x || b.w < tb.y || b.x > tb.z || b.y > tb.w {
            i += 1u;
            continue;
        }
        let q = pieces[i];
        var clipped = false;
        if owners[i] != MISS {
            // How much nearer the triangle's plane is than the owner's, at the piece's corners
            // (affine, so its extremes are there), snapped to 0 within COPLANAR (Piece::nearer).
            let o = depths[i];
            let g = k - o;
            let gv = vec4<f32>(g.x) + g.y * q.x + g.z * q.y;
            let ov = abs(vec4<f32>(o.x) + o.y * q.x + o.z * q.y);
            let tol = EYE_COPLANAR * max(max(ov.x, ov.y), max(ov.z, ov.w));
            let s = select(gv, vec4<f32>(0.0), abs(gv) <= vec4<f32>(tol));
            let most = max(max(s.x, s.y), max(s.z, s.w));
            let least = min(min(s.x, s.y), min(s.z, s.w));
            if most <= 0.0 {
                i += 1u;
                continue;
            }
            if least < 0.0 {
                // Only the triangle's part in front splits the piece.
                let fb = clip_front(g);
                whole = false;
                if fb.z < b.x || fb.w < b.y || fb.x > b.z || fb.y > b.w
                    || max(fb.z - fb.x, fb.w - fb.y) <= 32.0 * SIDE_EPS || !set_polygon(SIDE_EPS * SIDE_EPS) {
                    i += 1u;
                    continue;
                }
                clipped = true;
            }
        }
        if !clipped && !whole {
            work += tri_count + 2u;
            for (var j = 0u; j < tri_count; j += 1u) {
                poly_corners[j] = tri_corners[j];
            }
            poly_corner_count = tri_count;
            if !set_polygon(SIDE_EPS * SIDE_EPS) {
                // A sliver or an edge-on triangle hides nothing.
                return;
            }
            whole = true;
        }
        // Missed parts keep the piece's owner.
        emit_owner = owners[i];
        emit_depth = depths[i];
        emit_plane = owner_planes[i];
        let len = piece_count;
        let cover = split_quad(q, SIDE_EPS);
        if cover == COVER_OUTSIDE {
            piece_count = len;
        } else if cover == COVER_INSIDE {
            piece_count = len;
            touched[touched_count] = i;
            touched_count += 1u;
            owners[i] = t;
            depths[i] = k;
            owner_planes[i] = plane;
        } else {
            // The hit part (`rest`) to the triangle, as pieces of at most four corners; the last
            // part made takes this piece's place.
            emit_owner = t;
            emit_depth = k;
            emit_plane = plane;
            outer_len = rest_len;
            work += rest_len + 2u;
            for (var j = 0u; j < rest_len; j += 1u) {
                outer[j] = rest[j];
            }
            recut_outer();
            if overflow {
                break;
            }
            piece_count -= 1u;
            move_piece(piece_count, i);
            touched[touched_count] = i;
            touched_count += 1u;
        }
        i += 1u;
    }
    if overflow {
        return;
    }
    work += piece_count - end + 2u;
    for (var j = end; j < piece_count; j += 1u) {
        touched[touched_count] = j;
        touched_count += 1u;
    }
    join_touched();
}

// The pieces a triangle split or took whole, and the parts it made (each once).
var<private> touched: array<u32, MAX_EYE_PIECES>;
var<private> touched_count: u32;

// Corners of two pieces nearer than this (pixel widths) are the same corner when they are joined.
const JOIN_EPS: f32 = 1e-6;

// Pieces `a` and `b` as one piece of at most four corners, when they share a whole edge and their
// union is convex (collinear corners dropped) with the same area: the union's corners, or
// len 0. Twin of beam_math::polybeam::merge (for quads).
fn joined(a: Quad, b: Quad) -> Quad {
    var none: Quad;
    none.len = 0u;
    // The edge a_i → a_(i+1) that b runs the other way, b_(j+1) → b_j.
    var ia = 4u;
    var jb = 0u;
    work += 2u * a.len + 2u;
    for (var i = 0u; i < a.len; i += 1u) {
        let p = quad_corner(a, i);
        let q = quad_corner(a, select(i + 1u, 0u, i + 1u == a.len));
        for (var j = 0u; j < b.len; j += 1u) {
            let r = quad_corner(b, j);
            let t = quad_corner(b, select(j + 1u, 0u, j + 1u == b.len));
            if ia == 4u && length(p - t) <= JOIN_EPS && length(q - r) <= JOIN_EPS {
                ia = i;
                jb = j;
            }
        }
    }
    if ia == 4u {
        return none;
    }
    // The union: a from a_(i+1) round to a_i, then b past the shared edge.
    var u: array<vec2<f32>, 8>;
    var n = 0u;
    work += a.len + b.len + 4u;
    for (var k = 1u; k <= a.len; k += 1u) {
        u[n] = quad_corner(a, (ia + k) % a.len);
        n += 1u;
    }
    for (var k = 2u; k < b.len; k += 1u) {
        u[n] = quad_corner(b, (jb + k) % b.len);
        n += 1u;
    }
    // Corners on the line through their neighbours go; the rest must turn left.
    var kept: array<vec2<f32>, 8>;
    var m = 0u;
    work += n + 2u;
    for (var k = 0u; k < n; k += 1u) {
        let p = u[(k + n - 1u) % n];
        let c = u[k];
        let q = u[(k + 1u) % n];
        let e = q - p;
        let len = length(e);
        let side = (e.x * (c.y - p.y) - e.y * (c.x - p.x));
        if abs(side) <= SIDE_EPS * len {
            continue;
        }
        if side > 0.0 || m >= 4u {
            return none;
        }
        kept[m] = c;
        m += 1u;
    }
    if m < 3u {
        return none;
    }
    var j: Quad;
    if m == 4u {
        j = quad_from(kept[0], kept[1], kept[2], kept[3], 4u);
    } else {
        j = quad_from(kept[0], kept[1], kept[2], kept[0], 3u);
    }
    let area = quad_signed_area(j);
    if !(area > 0.0) || abs(area - quad_signed_area(a) - quad_signed_area(b)) > 1e-6 {
        return none;
    }
    return j;
}

// Join the touched pieces that see the same triangle (or both the background) and share a whole
// edge, while their union stays a convex quad (EyeTracer::join): the first keeps the union, the
// other goes; then the pieces gone are dropped.
fn join_touched() {
    var joins = 0u;
    work += touched_count + 2u;
    for (var x = 0u; x < touched_count; x += 1u) {
        let ia = touched[x];
        var y = x + 1u;
        loop {
            if y >= touched_count || pieces[ia].len == 0u {
                break;
            }
            work += 1u;
            let ib = touched[y];
            y += 1u;
            let ba = boxes[ia];
            let bb = boxes[ib];
            if pieces[ib].len == 0u || owners[ia] != owners[ib] || ba.z < bb.x - JOIN_EPS || bb.z < ba.x - JOIN_EPS
                || ba.w < bb.y - JOIN_EPS || bb.w < ba.y - JOIN_EPS {
                continue;
            }
            let j = joined(pieces[ia], pieces[ib]);
            if j.len == 0u {
                continue;
            }
            pieces[ia] = j;
            boxes[ia] = quad_box(j);
            pieces[ib].len = 0u;
            joins += 1u;
            y = x + 1u;
        }
    }
    if joins == 0u {
        return;
    }
    var i = 0u;
    work += 2u;
    loop {
        if i >= piece_count {
            break;
        }
        work += 1u;
        if pieces[i].len == 0u {
            piece_count -= 1u;
            move_piece(piece_count, i);
        } else {
            i += 1u;
        }
    }
}
