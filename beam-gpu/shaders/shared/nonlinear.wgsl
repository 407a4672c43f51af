// The nonlinear beam of 000 §4–6 in WGSL: the S^n ray at a base point (eq. 1), S1 projection
// (the cubic of §5), and the bounding triangle of a scene triangle on the beam base (Algs. 3–4,
// eq. 5 for bump-mapped beams). Twin of beam-math's `nonlinear` module; the per-beam quantities
// (extremal directions, threshold plane, μ_b, μ_d, heights, θ2) are computed there, once per beam,
// as 000 does ("pre-computed per B"), and uploaded in `Beam`.
//
// beam-math works in f64 where these functions use f32. Where f32 cannot decide a branch as
// beam-math does (a vertex on the beam's side surface, on the threshold plane, on the base plane)
// these functions take the larger triangle of the two branches, so they stay conservative.

// Twin of beam_gpu::nonlinear::GpuBeam (576 bytes).
struct Beam {
    base: array<vec4<f32>, 3>,      // P_i
    dirs: array<vec4<f32>, 3>,      // unit boundary directions d_i
    extremal: array<vec4<f32>, 3>,  // extremal directions d̂_i (§6.2)
    normal: vec4<f32>,              // inner unit normal n of Π_b; w: winding (±1)
    threshold: vec4<f32>,           // Π_T: normal (xyz) and offset d (w)
    heights: vec4<f32>,             // heights h_k of the base (xyz); w: t_max of Π_T
    offsets: vec4<f32>,             // μ_b, μ_d (eq. 4), bump δ, τ = δ + φ
    bump: vec4<f32>,                // θ2 = asin(min n·d_i), bump wavelength, lift (self-hits), unused
    region: vec4<u32>,              // atlas x, y, texels per side, excluded scene triangle
    kind: vec4<u32>,                // degree n, control points, bumped (0 or 1), unused
    origin: array<vec4<f32>, MAX_CONTROL_POINTS>,   // Bernstein control points of O(ω)
    direction: array<vec4<f32>, MAX_CONTROL_POINTS>, // Bernstein control points of d(ω)
}

// A bounding triangle {ω : ω_k ≥ lower_k}; case BOUNDING_BRUTE_FORCE (the whole base),
// BOUNDING_GENERAL, BOUNDING_UNIQUE_PROJECTION, or BOUNDING_BEHIND (none, behind the base).
// (The shared constants are generated from beam_gpu::interface and prepended by the host.)
struct BoundingTriangle {
    lower: vec3<f32>,
    case_: u32,
}

// Margins (GPU only) within which f32 does not decide a branch (barycentric units, and base sizes for t).
const AMBIGUOUS_BARY: f32 = 1e-4;
const AMBIGUOUS_T: f32 = 1e-4;

fn bv(b: Beam, i: u32) -> vec3<f32> { return b.base[i].xyz; }
fn bd(b: Beam, i: u32) -> vec3<f32> { return b.dirs[i].xyz; }
fn be(b: Beam, i: u32) -> vec3<f32> { return b.extremal[i].xyz; }

fn base_size(b: Beam) -> f32 {
    return max(distance(bv(b, 1u), bv(b, 0u)), distance(bv(b, 2u), bv(b, 0u)));
}

// A ray: origin and (not unit) direction.
struct BeamRay {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

// (O(ω), d(ω)) of eq. 1: Bernstein sums over the control points, in the order of beam-math's
// `indices(n)` (i from n down, then j from n − i down): S1 (3 points) or S3 (10).
fn beam_ray_at(b: Beam, w: vec3<f32>) -> BeamRay {
    if b.kind.x == 1u {
        let o = w.x * b.origin[0].xyz + w.y * b.origin[1].xyz + w.z * b.origin[2].xyz;
        let d = w.x * b.direction[0].xyz + w.y * b.direction[1].xyz + w.z * b.direction[2].xyz;
        return BeamRay(o, d);
    }
    let x = w.x;
    let y = w.y;
    let z = w.z;
    // 300, 210, 201, 120, 111, 102, 030, 021, 012, 003
    var k = array<f32, 10>(
        x * x * x, 3.0 * x * x * y, 3.0 * x * x * z, 3.0 * x * y * y, 6.0 * x * y * z,
        3.0 * x * z * z, y * y * y, 3.0 * y * y * z, 3.0 * y * z * z, z * z * z,
    );
    var o = vec3<f32>(0.0);
    var d = vec3<f32>(0.0);
    for (var c = 0u; c < 10u; c++) {
        o += k[c] * b.origin[c].xyz;
        d += k[c] * b.direction[c].xyz;
    }
    return BeamRay(o, d);
}

// The bump map's tilt at point p of the base (beam_scene::scene::Bump::tilt): the tangential part
// of B(p) = (sin k(y+z), sin k(z+x), sin k(x+y))/√3 in the frame (u, n × u), arguments reduced
// to one period first.
fn bump_tilt(b: Beam, p: vec3<f32>) -> vec2<f32> {
    return tilt_at(b.bump.y, normalize(bv(b, 1u) - bv(b, 0u)), b.normal.xyz, p);
}

// Bump::tilt of a bump map of wavelength `wavelength` at p, in the frame (u, n × u).
fn tilt_at(wavelength: f32, u: vec3<f32>, n: vec3<f32>, p: vec3<f32>) -> vec2<f32> {
    let tau = 6.2831855;
    let l = max(wavelength, 1e-30);
    let s = vec3<f32>(p.y + p.z, p.z + p.x, p.x + p.y) / l;
    let v = sin(tau * (s - floor(s))) / sqrt(3.0);
    return vec2<f32>(dot(v, u), dot(v, cross(n, u)));
}

// beam_math::nonlinear::perturb: unit d rotated by δ·|tilt| towards the tangent direction tilt.
fn perturb(d: vec3<f32>, n: vec3<f32>, u: vec3<f32>, tilt: vec2<f32>, delta: f32) -> vec3<f32> {
    let len = min(length(tilt), 1.0);
    if len == 0.0 { return d; }
    let v = cross(n, u);
    let t = normalize(tilt.x * u + tilt.y * v);
    let c = cross(d, t);
    var axis = vec3<f32>(0.0);
    if dot(c, c) > 0.0 { axis = normalize(c); }
    let a = delta * len;
    let rotated = d * cos(a) + cross(axis, d) * sin(a) + axis * dot(axis, d) * (1.0 - cos(a));
    if dot(rotated, n) >= MIN_ELEVATION { return rotated; }
    return d;
}

// The texel ray at base point w: the S^n ray, tilted by the bump map for a bumped beam (000 §6.3).
fn texel_ray(b: Beam, w: vec3<f32>) -> BeamRay {
    let r = beam_ray_at(b, w);
    if b.kind.z == 0u { return r; }
    let p = w.x * bv(b, 0u) + w.y * bv(b, 1u) + w.z * bv(b, 2u);
    let u = normalize(bv(b, 1u) - bv(b, 0u));
    return BeamRay(r.origin, perturb(normalize(r.direction), b.normal.xyz, u, bump_tilt(b, p), b.offsets.z));
}

// ---- Roots of a cubic (beam_math::roots::cubic in f32) ----

struct Roots3 {
    x: array<f32, 3>,
    n: u32,
    // A critical point where |p| is within 64 ulps of its magnitude: a double root, or a pair of
    // roots f32 may find or lose where f64 does the opposite.
    near_double: bool,
}

fn poly_eval(c: vec4<f32>, x: f32) -> vec2<f32> {
    // p(x) and the bound Σ|c_i||x|^i.
    let p = ((c.w * x + c.z) * x + c.y) * x + c.x;
    let ax = abs(x);
    let b = ((abs(c.w) * ax + abs(c.z)) * ax + abs(c.y)) * ax + abs(c.x);
    return vec2<f32>(p, b);
}

fn roots_push(r: ptr<function, Roots3>, x: f32) {
    if (*r).n < 3u && x == x && abs(x) < 3.0e38 {
        for (var i = 0u; i < (*r).n; i++) {
            if abs((*r).x[i] - x) <= 1e-6 * (1.0 + abs(x)) { return; }
        }
        (*r).x[(*r).n] = x;
        (*r).n++;
    }
}

fn quadratic_roots(a: f32, b: f32, c: f32) -> Roots3 {
    var r: Roots3;
    r.n = 0u;
    r.near_double = false;
    if a == 0.0 {
        if b != 0.0 { roots_push(&r, -c / b); }
        return r;
    }
    let disc = b * b - 4.0 * a * c;
    let err = 8.0 * 1.1920929e-7 * (b * b + abs(4.0 * a * c));
    if abs(disc) <= err {
        roots_push(&r, -b / (2.0 * a));
        return r;
    }
    if disc < 0.0 { return r; }
    let s = sqrt(disc);
    var sb = s;
    if b < 0.0 { sb = -s; }
    let q = -0.5 * (b + sb);
    if q == 0.0 {
        roots_push(&r, 0.0);
        return r;
    }
    let x1 = q / a;
    let x2 = c / q;
    roots_push(&r, min(x1, x2));
    roots_push(&r, max(x1, x2));
    return r;
}

// The root of c in [lo, hi] (p(lo)·p(hi) < 0) by Newton steps kept in a shrinking bracket.
fn refine(c: vec4<f32>, lo_in: f32, hi_in: f32) -> f32 {
    var lo = lo_in;
    var hi = hi_in;
    let rising = poly_eval(c, lo).x < 0.0;
    var x = 0.5 * (lo + hi);
    for (var it = 0; it < 80; it++) {
        let p = poly_eval(c, x).x;
        let d = (3.0 * c.w * x + 2.0 * c.z) * x + c.y;
        if p == 0.0 { return x; }
        if (p < 0.0) == rising { lo = x; } else { hi = x; }
        let newton = x - p / d;
        var next = 0.5 * (lo + hi);
        if d != 0.0 && newton > lo && newton < hi { next = newton; }
        if abs(next - x) <= 4.0 * 1.1920929e-7 * abs(x) || hi - lo <= 2.0 * 1.1920929e-7 * max(abs(lo), abs(hi)) {
            return next;
        }
        x = next;
    }
    return x;
}

// Real roots of c.w x³ + c.z x² + c.y x + c.x in [−limit, limit], by isolation between the
// critical points (beam-math searches all reals in f64; in f32 a nearly vanishing c.w puts the
// Cauchy bound where x³ overflows).
fn cubic_roots(c: vec4<f32>, limit: f32) -> Roots3 {
    if c.w == 0.0 { return quadratic_roots(c.z, c.y, c.x); }
    let crit = quadratic_roots(3.0 * c.w, 2.0 * c.z, c.y);
    let bound = min(1.0 + max(max(abs(c.x / c.w), abs(c.y / c.w)), abs(c.z / c.w)), limit);
    var pts = array<f32, 4>(-bound, 0.0, 0.0, bound);
    var m = 1u;
    for (var i = 0u; i < crit.n; i++) {
        pts[m] = clamp(crit.x[i], -bound, bound);
        m++;
    }
    pts[m] = bound;
    m++;
    var out: Roots3;
    out.n = 0u;
    out.near_double = false;
    var vals: array<vec2<f32>, 4>;
    for (var i = 0u; i < m; i++) { vals[i] = poly_eval(c, pts[i]); }
    // |p| within 8 ulps of its magnitude is a double root; within 64, f32 cannot tell a double
    // root from a close pair or none.
    let tol = 8.0 * 1.1920929e-7;
    for (var i = 1u; i + 1u < m; i++) {
        if abs(vals[i].x) <= tol * vals[i].y { roots_push(&out, pts[i]); }
        if abs(vals[i].x) <= 64.0 * 1.1920929e-7 * vals[i].y { out.near_double = true; }
    }
    for (var i = 0u; i + 1u < m; i++) {
        let za = abs(vals[i].x) <= tol * vals[i].y;
        let zb = abs(vals[i + 1u].x) <= tol * vals[i + 1u].y;
        if !za && !zb && (vals[i].x < 0.0) != (vals[i + 1u].x < 0.0) {
            roots_push(&out, refine(c, pts[i], pts[i + 1u]));
        }
    }
    return out;
}

// ---- Projection (000 §5) ----

// Every S1 projection of q: barycentric coordinates (xyz) and t (w), as beam-math's
// `s1_solutions`.
struct Solutions {
    s: array<vec4<f32>, 3>,
    n: u32,
    near_double: bool,
}

fn s1_solutions(b: Beam, q: vec3<f32>) -> Solutions {
    let p0 = bv(b, 0u);
    let e1 = bv(b, 1u) - p0;
    let e2 = bv(b, 2u) - p0;
    let f1 = bd(b, 1u) - bd(b, 0u);
    let f2 = bd(b, 2u) - bd(b, 0u);
    let r = q - p0;
    let dd = -bd(b, 0u);
    let n0 = cross(e1, e2);
    let n1 = cross(e1, f2) + cross(f1, e2);
    let n2 = cross(f1, f2);
    // Rays rise at least MIN_ELEVATION above the base, so |t| ≤ (|q − P1| + base size)/MIN_ELEVATION:
    // the search stops a factor 4 beyond.
    let limit = 4.0 / MIN_ELEVATION * (length(r) + base_size(b));
    let c = vec4<f32>(dot(n0, r), dot(n1, r) + dot(n0, dd), dot(n2, r) + dot(n1, dd), dot(n2, dd));
    let roots = cubic_roots(c, limit);
    var out: Solutions;
    out.n = 0u;
    for (var i = 0u; i < roots.n; i++) {
        let w = affine_barycentric(b, q, roots.x[i]);
        if w.w == 0.0 { continue; }
        out.s[out.n] = vec4<f32>(w.xyz, roots.x[i]);
        out.n++;
    }
    out.near_double = roots.near_double;
    return out;
}

// Barycentric coordinates (xyz) of q in the affine triangle Δa(t); w = 0 when it is degenerate.
fn affine_barycentric(b: Beam, q: vec3<f32>, t: f32) -> vec4<f32> {
    let h0 = bv(b, 0u) + t * bd(b, 0u);
    let h1 = bv(b, 1u) + t * bd(b, 1u);
    let h2 = bv(b, 2u) + t * bd(b, 2u);
    let n = cross(h1 - h0, h2 - h0);
    let nn = dot(n, n);
    if !(nn > 0.0) { return vec4<f32>(0.0); }
    let w0 = dot(cross(h1 - q, h2 - q), n) / nn;
    let w1 = dot(cross(h2 - q, h0 - q), n) / nn;
    return vec4<f32>(w0, w1, 1.0 - w0 - w1, 1.0);
}

fn min3(v: vec3<f32>) -> f32 { return min(min(v.x, v.y), v.z); }

// Inside the S1 beam through the boundary rays (beam-math's `contains_s1`): 1 inside, 0 outside,
// 2 when f32 cannot tell (a projection within the margins of the side surfaces or the base, or a
// nearly double root: q near the beam's caustic surface).
fn classify_s1(b: Beam, q: vec3<f32>) -> u32 {
    let sol = s1_solutions(b, q);
    if sol.near_double { return 2u; }
    let et = AMBIGUOUS_T * base_size(b);
    var sure_in = false;
    var maybe_in = false;
    for (var i = 0u; i < sol.n; i++) {
        let w = min3(sol.s[i].xyz);
        let t = sol.s[i].w;
        if t >= et && w >= -BARY_TOLERANCE + AMBIGUOUS_BARY { sure_in = true; }
        if t >= -et && w >= -BARY_TOLERANCE - AMBIGUOUS_BARY { maybe_in = true; }
    }
    if sure_in { return 1u; }
    if !maybe_in { return 0u; }
    return 2u;
}

// ---- Bounding triangles (000 §6, Algs. 3 and 4) ----

struct Tri {
    v: array<vec3<f32>, 3>,
}

fn tri_barycentric(t: Tri, p: vec3<f32>) -> vec4<f32> {
    // xyz: coordinates, w: 1 when valid.
    let n = cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
    let nn = dot(n, n);
    if !(nn > 0.0) || nn > 3.0e38 { return vec4<f32>(0.0); }
    let w0 = dot(cross(t.v[1] - p, t.v[2] - p), n) / nn;
    let w1 = dot(cross(t.v[2] - p, t.v[0] - p), n) / nn;
    return vec4<f32>(w0, w1, 1.0 - w0 - w1, 1.0);
}

fn tri_heights(t: Tri) -> vec3<f32> {
    let a = length(cross(t.v[1] - t.v[0], t.v[2] - t.v[0]));
    return vec3<f32>(a / length(t.v[2] - t.v[1]), a / length(t.v[0] - t.v[2]), a / length(t.v[1] - t.v[0]));
}

// Lower bounds of the transfers of `tri`'s vertices along the extremal directions onto the plane
// (normal pn, offset pd) through `reference`, expanded by mu / sin θ_min (beam-math's
// `enclose_transfers`); w = 0 when a direction is parallel or the reference degenerate.
fn enclose_transfers(b: Beam, tri: Tri, pn: vec3<f32>, pd: f32, reference: Tri, mu: f32, h: vec3<f32>) -> vec4<f32> {
    let n = normalize(pn);
    var sin_min = 3.0e38;
    for (var j = 0u; j < 3u; j++) {
        sin_min = min(sin_min, abs(dot(n, be(b, j))) / length(be(b, j)));
    }
    if !(sin_min > 0.0) { return vec4<f32>(0.0); }
    var lower = vec3<f32>(3.0e38);
    for (var i = 0u; i < 3u; i++) {
        for (var j = 0u; j < 3u; j++) {
            let d = be(b, j);
            let nd = dot(pn, d);
            if nd == 0.0 { return vec4<f32>(0.0); }
            let h = tri.v[i] - (dot(pn, tri.v[i]) + pd) / nd * d;
            let w = tri_barycentric(reference, h);
            if w.w == 0.0 { return vec4<f32>(0.0); }
            lower = min(lower, w.xyz);
        }
    }
    let out = lower - vec3<f32>(mu / sin_min) / h;
    if !(abs(out.x) < 3.0e38 && abs(out.y) < 3.0e38 && abs(out.z) < 3.0e38) { return vec4<f32>(0.0); }
    return vec4<f32>(out, 1.0);
}

fn base_tri(b: Beam) -> Tri {
    return Tri(array<vec3<f32>, 3>(bv(b, 0u), bv(b, 1u), bv(b, 2u)));
}

fn general_case(b: Beam, tri: Tri) -> BoundingTriangle {
    let n = b.normal.xyz;
    let e = enclose_transfers(b, tri, n, -dot(n, bv(b, 0u)), base_tri(b), b.offsets.x, b.heights.xyz);
    if e.w == 0.0 { return BoundingTriangle(vec3<f32>(0.0), BOUNDING_BRUTE_FORCE); }
    return BoundingTriangle(e.xyz, BOUNDING_GENERAL);
}

// The unique-projection case (transfers onto Π_a(t_top)); case 0 when it does not apply.
fn unique_projection_case(b: Beam, tri: Tri) -> BoundingTriangle {
    var t_top = -3.0e38;
    for (var i = 0u; i < 3u; i++) {
        let sol = s1_solutions(b, tri.v[i]);
        for (var k = 0u; k < sol.n; k++) { t_top = max(t_top, sol.s[k].w); }
    }
    let none = BoundingTriangle(vec3<f32>(0.0), BOUNDING_BRUTE_FORCE);
    if !(t_top > b.heights.w) || t_top > 3.0e38 { return none; }
    let affine = Tri(array<vec3<f32>, 3>(bv(b, 0u) + t_top * bd(b, 0u), bv(b, 1u) + t_top * bd(b, 1u), bv(b, 2u) + t_top * bd(b, 2u)));
    let pn = b.normal.w * cross(affine.v[1] - affine.v[0], affine.v[2] - affine.v[0]);
    let pd = -dot(pn, affine.v[0]);
    let s = vec3<f32>(dot(pn, be(b, 0u)), dot(pn, be(b, 1u)), dot(pn, be(b, 2u)));
    let same_side = (s.x > 0.0 && s.y > 0.0 && s.z > 0.0) || (s.x < 0.0 && s.y < 0.0 && s.z < 0.0);
    if !same_side { return none; }
    let mu = b.offsets.x + t_top * b.offsets.y;
    let e = enclose_transfers(b, tri, pn, pd, affine, mu, tri_heights(affine));
    if e.w == 0.0 { return none; }
    return BoundingTriangle(e.xyz, BOUNDING_UNIQUE_PROJECTION);
}

// Barycentric margin added to every computed (non-brute-force) bounding triangle: the f32 rounding
// of the transfers, of t_top and of θ1 (beam-math: f64 roots), as measured by the conformance suite.
const F32_MARGIN: f32 = 2e-3;

// 000 Alg. 3 (S1) and Alg. 4 (S^n) for the unperturbed beam.
fn bounding_triangle_sn(b: Beam, tri: Tri) -> BoundingTriangle {
    let base = BoundingTriangle(vec3<f32>(0.0), BOUNDING_BRUTE_FORCE);
    let n = b.normal.xyz;
    let pd = -dot(n, bv(b, 0u));
    let margin = b.offsets.x + AMBIGUOUS_T * base_size(b);
    if dot(n, tri.v[0]) + pd < -margin && dot(n, tri.v[1]) + pd < -margin && dot(n, tri.v[2]) + pd < -margin {
        return BoundingTriangle(vec3<f32>(0.0), BOUNDING_BEHIND);
    }
    let c0 = classify_s1(b, tri.v[0]);
    let c1 = classify_s1(b, tri.v[1]);
    let c2 = classify_s1(b, tri.v[2]);
    if c0 == 2u || c1 == 2u || c2 == 2u || c0 != c1 || c1 != c2 { return base; }
    // Above Π_T: every vertex strictly on its positive side, beyond f32's doubt.
    let tn = b.threshold.xyz;
    let eps = AMBIGUOUS_T * base_size(b) * length(tn);
    let e = vec3<f32>(dot(tn, tri.v[0]), dot(tn, tri.v[1]), dot(tn, tri.v[2])) + b.threshold.w;
    if min3(e) > eps {
        let u = unique_projection_case(b, tri);
        if u.case_ == BOUNDING_UNIQUE_PROJECTION { return u; }
    }
    return general_case(b, tri);
}

// θ1 of eq. 5: asin(min n·d_Q) over the unperturbed projections of the vertices (−π/2 when a
// vertex has none in front of the base).
fn theta1(b: Beam, tri: Tri) -> f32 {
    var s = 1.0;
    let bt = base_tri(b);
    for (var i = 0u; i < 3u; i++) {
        let sol = s1_solutions(b, tri.v[i]);
        var any = false;
        for (var k = 0u; k < sol.n; k++) {
            if sol.s[k].w > 0.0 {
                let w = sol.s[k].xyz;
                let p = w.x * bt.v[0] + w.y * bt.v[1] + w.z * bt.v[2];
                let d = tri.v[i] - p;
                var u = vec3<f32>(0.0);
                if dot(d, d) > 0.0 { u = normalize(d); }
                s = min(s, dot(b.normal.xyz, u));
                any = true;
            }
        }
        if !any { return -1.5707964; }
    }
    return asin(clamp(s, -1.0, 1.0));
}

// The bounding triangle of `tri` on the base (Algs. 3–4; for a bumped beam the S1 triangle
// expanded by D of eq. 5).
fn bounding_triangle(b: Beam, tri: Tri) -> BoundingTriangle {
    var s1 = bounding_triangle_sn(b, tri);
    if s1.case_ == BOUNDING_BRUTE_FORCE || s1.case_ == BOUNDING_BEHIND { return s1; }
    s1.lower -= vec3<f32>(F32_MARGIN);
    if b.kind.z == 0u { return s1; }
    let tau = b.offsets.w;
    let theta2 = b.bump.x;
    var theta3 = theta2;
    if !(theta2 > tau) {
        theta3 = theta1(b, tri);
        if !(theta3 > tau) { return BoundingTriangle(vec3<f32>(0.0), BOUNDING_BRUTE_FORCE); }
    }
    let n = b.normal.xyz;
    let pd = -dot(n, bv(b, 0u));
    var reach = 0.0;
    for (var i = 0u; i < 3u; i++) {
        for (var j = 0u; j < 3u; j++) {
            let d = be(b, j);
            let nd = dot(n, d);
            if nd == 0.0 { return BoundingTriangle(vec3<f32>(0.0), BOUNDING_BRUTE_FORCE); }
            let t = -(dot(n, tri.v[i]) + pd) / nd;
            reach = max(reach, length(t * d));
        }
    }
    let dd = reach * sin(tau) / sin(theta3 - tau);
    return BoundingTriangle(s1.lower - vec3<f32>(dd) / b.heights.xyz, s1.case_);
}

// Distance along `ray` below which a hit on a triangle sharing a vertex with the base is the
// surface meeting itself (beam_scene::nonlinear::self_hit_distance).
fn self_hit_distance(b: Beam, ray: BeamRay, extent: f32) -> f32 {
    let rise = max(dot(normalize(ray.direction), b.normal.xyz), MIN_RISE);
    return max(TEXEL_EPS * extent, 2.0 * b.bump.z / rise);
}
