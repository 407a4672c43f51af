// Where a point of a fine surface under a coarse S-mesh face reads a child beam for its own
// scattered ray (000 §7.1, §7.3): the depth of the texel at its coordinates, then the projection
// (lib/lookup.wgsl) of the point that far along its ray. CPU twin:
// beam_cpu::nonlinear::lookup::reproject. The including shader binds `texel_t`: per texel of the
// beams' regions (a beam's region.x: its first of size² texels, row-major as beam_scene's
// BeamTexture), the ray parameter of its nearest hit, negative where it hits nothing. Imported by
// lookups.wgsl and lib/coarse.wgsl.

// #import shared/nonlinear.wgsl
// #import lib/lookup.wgsl
// #import lib/region.wgsl

// The hit point of the rendered texel nearest w (beam_cpu's lookup `depth`) in xyz, and
// in w 1 where it hits, else 0. Loops: at most 2·size iterations.
fn lookup_depth(b: Beam, w: vec3<f32>) -> vec4<f32> {
    let n = b.region.z;
    let x0 = min(u32(max(floor(w.y * f32(n)), 0.0)), n - 1u);
    let y0 = min(u32(max(floor(w.z * f32(n)), 0.0)), n - 1u);
    var x = x0;
    var y = y0;
    while !(x + y < n + 1u) && x + y > 0u {
        if x >= y { x -= 1u; } else { y -= 1u; }
    }
    let t = texel_t[b.region.x + y * n + x];
    if !(t >= 0.0) {
        return vec4<f32>(0.0);
    }
    let ray = beam_ray_at(b, texel_barycentric(x, y, n));
    return vec4<f32>(ray.origin + t * ray.direction, 1.0);
}

// w moved onto the base triangle (negative coordinates to 0, then scaled to sum 1).
fn lookup_clamped(w: vec3<f32>) -> vec3<f32> {
    let c = max(w, vec3<f32>(0.0));
    let sum = c.x + c.y + c.z;
    return select(vec3<f32>(1.0 / 3.0), c / sum, sum > 0.0);
}

// Where point p of the fine surface, at w on its face, reads beam b for its own scattered unit
// direction `truth` (beam_cpu::nonlinear::lookup::reproject): twice, the depth s of the texel at
// the current coordinates (`far` where it hits nothing), then the projection of p + s·truth onto
// the beam from the last answer (the first from (w, s)), clamped to the base. Returns the
// coordinates (xyz) and how far outside the base the last projection lay (w); w and 0 where a
// projection fails. Loops: 2 iterations.
fn reproject(b: Beam, p: vec3<f32>, truth: vec3<f32>, w: vec3<f32>, far: f32) -> vec4<f32> {
    var at = w;
    var outside = 0.0;
    var guess = vec4<f32>(0.0);
    var have_guess = false;
    for (var round = 0u; round < 2u; round++) {
        let hit = lookup_depth(b, at);
        let s = select(far, distance(hit.xyz, p), hit.w > 0.0);
        let start = select(vec4<f32>(w, s), guess, have_guess);
        let l = lookup_project(b, p + truth * s, start.xyz, start.w);
        let finite = all(abs(l.p.xyz) < vec3<f32>(3.0e38));
        if l.found == LOOKUP_NONE || !finite {
            break;
        }
        at = lookup_clamped(l.p.xyz);
        outside = max(-min3(l.p.xyz), 0.0);
        guess = l.p;
        have_guess = true;
    }
    return vec4<f32>(at, outside);
}
