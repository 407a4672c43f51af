// A point of a fine mirror or glass surface under a coarse S-mesh face (000 §7.1) composited on
// the GPU: the face it lies nearest among its triangle's candidates (`nearest_face`,
// beam_scene::nonlinear::SMesh::locate), and where its own scattered rays read that face's child
// beams, or a neighbouring candidate's (`coarse_composite`, beam_cpu::nonlinear's
// `Tree::composite`). Imported by eye.wgsl (the eye's hits) and level_points.wgsl (a tree level's
// texels). The
// including shader binds `candidates` (per scene triangle p, at 2p and 2p + 1, the start and end
// in the same array of its candidate faces), `corners` (per face, its three vertices),
// `child_beams` and `texel_t` (the child level's beams, lib/reproject.wgsl), `slots` and
// `specular_prims` (the mirror and glass triangles, lib/specular.wgsl), and defines
// `children_of(context, face)`: the face's reflection and refraction beams in the child level
// (NONE for none) for the point's `context`.

// #import lib/reproject.wgsl
// #import lib/specular.wgsl

// The point of triangle abc nearest p (beam_math::collide::closest_point_on_triangle, Ericson
// §5.1.5, in its order of operations).
fn closest_point_on_triangle(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// The squared distance from p to S-mesh face f.
fn face_distance_squared(f: u32, p: vec3<f32>) -> f32 {
    let q = closest_point_on_triangle(p, corners[3u * f].xyz, corners[3u * f + 1u].xyz, corners[3u * f + 2u].xyz);
    let e = q - p;
    return dot(e, e);
}

// The candidate face of triangle `prim` nearest p, the first of equally near ones (SMesh::locate's
// choice: a lone candidate without a distance; a NaN distance loses to a number); NONE for a
// triangle without candidates. Loops: once per candidate (a handful: the faces a fine triangle's
// points lie nearest), within the table.
fn nearest_face(prim: u32, p: vec3<f32>) -> u32 {
    if 2u * prim + 1u >= arrayLength(&candidates) {
        return NONE;
    }
    let start = candidates[2u * prim];
    let end = min(candidates[2u * prim + 1u], arrayLength(&candidates));
    if start >= end {
        return NONE;
    }
    var best = candidates[start];
    if end - start == 1u {
        return best;
    }
    var best_squared = face_distance_squared(best, p);
    for (var k = start + 1u; k < end; k++) {
        let f = candidates[k];
        let s = face_distance_squared(f, p);
        let nan = best_squared != best_squared;
        if (s < best_squared && sqrt(s) < sqrt(best_squared)) || (nan && s == s) {
            best = f;
            best_squared = s;
        }
    }
    return best;
}

// Barycentric coordinates of p in S-mesh face f's plane (SFace::barycentric: the centre for a
// degenerate face).
fn face_barycentric(f: u32, p: vec3<f32>) -> vec3<f32> {
    let a = corners[3u * f].xyz;
    let b = corners[3u * f + 1u].xyz;
    let c = corners[3u * f + 2u].xyz;
    let n = cross(b - a, c - a);
    let nn = dot(n, n);
    if !(nn > 0.0) || nn > 3.0e38 {
        return vec3<f32>(1.0 / 3.0);
    }
    let w0 = dot(cross(b - p, c - p), n) / nn;
    let w1 = dot(cross(c - p, a - p), n) / nn;
    return vec3<f32>(w0, w1, 1.0 - w0 - w1);
}

// The point of S-mesh face f at barycentric w.
fn face_point(f: u32, w: vec3<f32>) -> vec3<f32> {
    return w.x * corners[3u * f].xyz + w.y * corners[3u * f + 1u].xyz + w.z * corners[3u * f + 2u].xyz;
}

// The unit directions of a point's own scattered rays (beam_scene::specular::specular_rays about
// its triangle's shading normal): reflected (or passed through a thin pane) in `reflected`,
// refracted in `refracted` (w 1 where there is one). `specular` false for a triangle that is not a
// mirror or glass. A bump-mapped mirror's tilt is left out: its child beams are bumped, and no
// lookup follows the point's ray into them.
struct OwnRays {
    reflected: vec3<f32>,
    refracted: vec4<f32>,
    specular: bool,
}

fn own_rays(prim: u32, p: vec3<f32>, d: vec3<f32>) -> OwnRays {
    let slot = slots[prim];
    if slot == NONE {
        return OwnRays(vec3<f32>(0.0), vec4<f32>(0.0), false);
    }
    let s = specular_prim(slot);
    let side = facing(s, p, d);
    if s.kind == SPECULAR_THIN {
        return OwnRays(normalize(d), vec4<f32>(0.0), true);
    }
    var t = vec4<f32>(0.0);
    if s.kind == SPECULAR_GLASS {
        t = refracted(d, side.sn, select(s.ior, 1.0 / s.ior, side.entering));
        t = vec4<f32>(normalize(t.xyz), t.w);
    }
    return OwnRays(normalize(mirrored(d, side.sn)), t, true);
}

// Where point p, at w on its face, reads child beam `beam` for its own scattered unit direction
// (xyz) and how far outside the beam's base (w), in a scene whose diagonal is `far`:
// lib/reproject.wgsl's `reproject`, or w and 0 for a bumped beam or a direction that is not finite
// (beam_cpu::nonlinear's `reproject`).
fn look_up(beam: u32, p: vec3<f32>, truth: vec3<f32>, w: vec3<f32>, far: f32) -> vec4<f32> {
    let b = child_beams[beam];
    if b.kind.z != 0u || !all(abs(truth) < vec3<f32>(3.0e38)) {
        return vec4<f32>(w, 0.0);
    }
    return reproject(b, p, truth, w, far);
}

// How far outside child beam `beam`'s base a lookup may fall: OUTSIDE_TEXELS of its texels.
fn slack(beam: u32) -> f32 {
    return OUTSIDE_TEXELS / f32(child_beams[beam].region.z);
}

// Where a point's composite reads its child beams (`coarse_composite`): the face, its child beams
// (reflection, refraction or NONE), and the points of the face at the barycentric coordinates where
// each is looked up; `found` false where a lookup lies more than `slack` outside its beam's base
// (the point is for the Whitted rays).
struct CoarseComposite {
    found: bool,
    face: u32,
    children: vec2<u32>,
    reflected_p: vec3<f32>,
    refracted_p: vec3<f32>,
}

// The composite of point p on triangle `prim` (unit direction d), `context` its shader's, under
// coarse face `located`, which has child beams, in a scene whose diagonal is `far`
// (beam_cpu::nonlinear's `Tree::composite`): the located face first, then its triangle's other
// candidates with child beams until a lookup lies inside its reflection beam's base; the face whose
// reflection lookup lies least outside wins (by more than LOOKUP_PREFERENCE), and its refraction is
// looked up from the face's own coordinates. Loops: once per candidate, and reproject's.
fn coarse_composite(context: u32, prim: u32, located: u32, p: vec3<f32>, d: vec3<f32>, far: f32) -> CoarseComposite {
    var face = located;
    var c = children_of(context, located);
    var reflected_at = face_barycentric(located, p);
    var refracted_at = reflected_at;
    let own = own_rays(prim, p, d);
    if own.specular {
        var best = 3.0e38;
        let start = candidates[2u * prim];
        let end = min(candidates[2u * prim + 1u], arrayLength(&candidates));
        // The located face, then the other candidates in order.
        for (var k = start; k <= end; k++) {
            if best <= 0.0 {
                break;
            }
            var g = located;
            if k > start {
                g = candidates[k - 1u];
                if g == located {
                    continue;
                }
            }
            let cg = children_of(context, g);
            if cg.x == NONE {
                continue;
            }
            let wg = face_barycentric(g, p);
            let at = look_up(cg.x, p, own.reflected, wg, far);
            if at.w < best - LOOKUP_PREFERENCE {
                best = at.w;
                face = g;
                c = cg;
                reflected_at = at.xyz;
                refracted_at = wg;
            }
        }
        let missed = CoarseComposite(false, face, c, p, p);
        if best > slack(c.x) {
            return missed;
        }
        if c.y != NONE {
            var at = vec4<f32>(refracted_at, 0.0);
            if own.refracted.w > 0.0 {
                at = look_up(c.y, p, own.refracted.xyz, refracted_at, far);
            }
            if at.w > slack(c.y) {
                return missed;
            }
            refracted_at = at.xyz;
        }
    }
    return CoarseComposite(true, face, c, face_point(face, reflected_at), face_point(face, refracted_at));
}
