// A lookup's projection (000 §5) in f32: the base point whose S^n ray passes through q, by damped
// Newton's method from a guess, as far as beam_scene::nonlinear::LOOKUP says (LOOKUP_STEPS steps,
// residual LOOKUP_TOLERANCE of the base's size), else the S1 solution of the corner rays nearest
// the base. CPU twin: beam_math's NonlinearBeam::project_nearest_from (in f64), the step that a
// coarse S mesh's composite takes per point and child beam (lookups.wgsl's `reproject`);
// nonlinear_check's `check_lookups` runs it for the conformance suite.

// #import shared/nonlinear.wgsl

// Relative rounding of an f32 residual |O + t·d − q| (a few ulps of its terms): where it exceeds
// LOOKUP_TOLERANCE of the base's size, Newton's method stops at it instead (GPU only).
const LOOKUP_ROUNDING: f32 = 8.0 * 1.1920929e-7;

// ∂O/∂ω1, ∂d/∂ω1, ∂O/∂ω2, ∂d/∂ω2 at w, with ω3 = 1 − ω1 − ω2 (beam_math's Patch::derivatives):
// the Bernstein weights' derivatives, in the order of beam_ray_at.
fn beam_derivatives(b: Beam, w: vec3<f32>) -> array<vec3<f32>, 4> {
    if b.kind.x == 1u {
        let o0 = b.origin[0].xyz;
        let o1 = b.origin[1].xyz;
        let o2 = b.origin[2].xyz;
        let d0 = b.direction[0].xyz;
        let d1 = b.direction[1].xyz;
        let d2 = b.direction[2].xyz;
        return array<vec3<f32>, 4>(o0 - o2, d0 - d2, o1 - o2, d1 - d2);
    }
    let x = w.x;
    let y = w.y;
    let z = w.z;
    // 300, 210, 201, 120, 111, 102, 030, 021, 012, 003
    var kx = array<f32, 10>(
        3.0 * x * x, 6.0 * x * y, 6.0 * x * z - 3.0 * x * x, 3.0 * y * y, 6.0 * (y * z - x * y),
        3.0 * z * z - 6.0 * x * z, 0.0, -3.0 * y * y, -6.0 * y * z, -3.0 * z * z,
    );
    var ky = array<f32, 10>(
        0.0, 3.0 * x * x, -3.0 * x * x, 6.0 * x * y, 6.0 * (x * z - x * y),
        -6.0 * x * z, 3.0 * y * y, 6.0 * y * z - 3.0 * y * y, 3.0 * z * z - 6.0 * y * z, -3.0 * z * z,
    );
    var out = array<vec3<f32>, 4>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    // 10 iterations.
    for (var c = 0u; c < 10u; c++) {
        out[0] += kx[c] * b.origin[c].xyz;
        out[1] += kx[c] * b.direction[c].xyz;
        out[2] += ky[c] * b.origin[c].xyz;
        out[3] += ky[c] * b.direction[c].xyz;
    }
    return out;
}

// O(w) + t·d(w) − q (xyz) and d(w).
struct Residual {
    f: vec3<f32>,
    d: vec3<f32>,
}

fn lookup_residual(b: Beam, q: vec3<f32>, w: vec3<f32>, t: f32) -> Residual {
    let r = beam_ray_at(b, w);
    return Residual(r.origin + t * r.direction - q, r.direction);
}

// The residual at which a lookup's Newton step ends: LOOKUP_TOLERANCE of the base's size (times
// 1 + |t|, as beam-math's), or f32's rounding of the residual's terms where that is larger.
fn lookup_tolerance(scale: f32, q: vec3<f32>, t: f32, d: vec3<f32>) -> f32 {
    return max(LOOKUP_TOLERANCE * scale * (1.0 + abs(t)), LOOKUP_ROUNDING * (length(q) + abs(t) * length(d)));
}

// A lookup's projection: barycentric coordinates (xyz) and t (w), and how it was found.
struct Lookup {
    p: vec4<f32>,
    // LOOKUP_NONE, LOOKUP_POLISHED or LOOKUP_CORNERS.
    found: u32,
}

// Damped Newton's method on F(ω1, ω2, t) = O(ω) + t·d(ω) − q from (w, t) (beam-math's `newton`
// with LOOKUP): a step is halved until the residual decreases (at most 11 tries, the last taken
// whatever it gives). Returns (ω, t) in p and whether it converged (w of the result: 1 or 0).
// Loops: LOOKUP_STEPS × 11 iterations.
fn lookup_newton(b: Beam, q: vec3<f32>, w_in: vec3<f32>, t_in: f32) -> Lookup {
    let scale = max(base_size(b), 1e-30);
    var w = w_in;
    var t = t_in;
    var r = lookup_residual(b, q, w, t);
    for (var step = 0u; step < LOOKUP_STEPS; step++) {
        if length(r.f) <= lookup_tolerance(scale, q, t, r.d) {
            return Lookup(vec4<f32>(w, t), LOOKUP_POLISHED);
        }
        let g = beam_derivatives(b, w);
        let c0 = g[0] + t * g[1];
        let c1 = g[2] + t * g[3];
        let c2 = r.d;
        // J⁻¹ f for J = [c0 c1 c2], by its adjugate's rows.
        let det = dot(c0, cross(c1, c2));
        if !(abs(det) > 0.0) {
            return Lookup(vec4<f32>(0.0), LOOKUP_NONE);
        }
        let s = vec3<f32>(dot(cross(c1, c2), r.f), dot(cross(c2, c0), r.f), dot(cross(c0, c1), r.f)) / det;
        var lambda = 1.0;
        for (var k = 0u; k < 11u; k++) {
            let w1 = w.x - lambda * s.x;
            let w2 = w.y - lambda * s.y;
            let wn = vec3<f32>(w1, w2, 1.0 - w1 - w2);
            let tn = t - lambda * s.z;
            let rn = lookup_residual(b, q, wn, tn);
            if length(rn.f) < length(r.f) || lambda < 1e-3 {
                w = wn;
                t = tn;
                r = rn;
                break;
            }
            lambda *= 0.5;
        }
        let big = max(max(abs(w.x), abs(w.y)), abs(w.z));
        // NaN fails every comparison: `!(… <= …)` is true for it.
        if !(big <= 10.0) || !(abs(t) < 3.0e38) {
            return Lookup(vec4<f32>(0.0), LOOKUP_NONE);
        }
    }
    let accept = lookup_tolerance(scale, q, t, r.d);
    return Lookup(vec4<f32>(w, t), select(LOOKUP_NONE, LOOKUP_POLISHED, length(r.f) <= accept));
}

// An S1 solution s (ω in xyz, t in w) of the corner rays polished by up to 8 Newton steps on their
// S1 beam (O = Σ ωᵢPᵢ, d = Σ ωᵢdᵢ): f32's cubic places a root only roughly near a double root (q
// near the S1 beam's caustic, where Newton's method converges linearly), and beam-math's f64 cubic
// is exact. Loops: 8 iterations.
fn corner_polish(b: Beam, q: vec3<f32>, s: vec4<f32>) -> vec4<f32> {
    var w = s.xyz;
    var t = s.w;
    let scale = max(base_size(b), 1e-30);
    for (var k = 0u; k < 8u; k++) {
        let d = w.x * bd(b, 0u) + w.y * bd(b, 1u) + w.z * bd(b, 2u);
        let f = w.x * bv(b, 0u) + w.y * bv(b, 1u) + w.z * bv(b, 2u) + t * d - q;
        if length(f) <= lookup_tolerance(scale, q, t, d) { break; }
        let c0 = bv(b, 0u) - bv(b, 2u) + t * (bd(b, 0u) - bd(b, 2u));
        let c1 = bv(b, 1u) - bv(b, 2u) + t * (bd(b, 1u) - bd(b, 2u));
        let det = dot(c0, cross(c1, d));
        if !(abs(det) > 0.0) { break; }
        let st = vec3<f32>(dot(cross(c1, d), f), dot(cross(d, c0), f), dot(cross(c0, c1), f)) / det;
        let w1 = w.x - st.x;
        let w2 = w.y - st.y;
        let wn = vec3<f32>(w1, w2, 1.0 - w1 - w2);
        if !(max(max(abs(wn.x), abs(wn.y)), abs(wn.z)) <= 10.0) { break; }
        w = wn;
        t -= st.z;
    }
    return vec4<f32>(w, t);
}

// The projection of q nearest the base with t > 0, polished from the guess (w, t) (beam-math's
// project_nearest_from with LOOKUP): where Newton's method does not converge or ends at t ≤ 0, the
// corner rays' S1 solution with t > 0 least outside the base, unpolished (LOOKUP_CORNERS); none
// where there is none. S1 beams take the S1 solution (their projection is the cubic's).
fn lookup_project(b: Beam, q: vec3<f32>, w: vec3<f32>, t: f32) -> Lookup {
    if b.kind.x != 1u {
        let polished = lookup_newton(b, q, w, t);
        if polished.found == LOOKUP_POLISHED && polished.p.w > 0.0 {
            return polished;
        }
    }
    let sol = s1_solutions(b, q);
    var best = Lookup(vec4<f32>(0.0), LOOKUP_NONE);
    var least = 3.0e38;
    // At most 3 iterations (of 8).
    for (var i = 0u; i < sol.n; i++) {
        let s = corner_polish(b, q, sol.s[i]);
        let outside = max(-min3(s.xyz), 0.0);
        // Ties to the nearer root, as beam-math's roots come in ascending order.
        if s.w > 0.0 && (outside < least || (outside == least && s.w < best.p.w)) {
            least = outside;
            best = Lookup(s, select(LOOKUP_CORNERS, LOOKUP_POLISHED, b.kind.x == 1u));
        }
    }
    return best;
}

