// The texels of a beam's region (beam_scene::nonlinear::BeamTexture): a texel's point on the base,
// and the row-by-row order in which a page lists its regions' texels (beam_gpu::nonlinear::page).
// Shared by the atlas's passes, the level's points (level_points.wgsl) and the lookups
// (lib/reproject.wgsl).

// beam_scene::nonlinear::BeamTexture::barycentric: texel (x, y) of a size × size region; margin
// texels (u + v > 1) take the nearest point of the base's edge.
fn texel_barycentric(x: u32, y: u32, size: u32) -> vec3<f32> {
    let u = (f32(x) + 0.5) / f32(size);
    let v = (f32(y) + 0.5) / f32(size);
    if u + v <= 1.0 { return vec3<f32>(1.0 - u - v, u, v); }
    let excess = 0.5 * (u + v - 1.0);
    let uc = clamp(u - excess, 0.0, 1.0);
    let vc = clamp(v - excess, 0.0, 1.0);
    return max(vec3<f32>(1.0 - uc - vc, uc, vc), vec3<f32>(0.0));
}

// Triangular numbers: texels of the rows from the last one up to, not including, row `s − n` of a
// region of side `s` (those rows hold 1, 2, …, n texels).
fn triangular(n: u32) -> u32 {
    return n * (n + 1u) / 2u;
}

// (x, y) of the j-th texel of a region of side s, its texels counted row by row as
// beam_gpu::nonlinear::page unpacks them: row 0 holds s texels, row y ≥ 1 holds s + 1 − y (the
// texels with x + y ≤ s). Rows 1..s, counted from the last, hold 1, 2, …, s texels, so the row of
// the r-th texel from the end is the inverse of the triangular numbers; the float root is at most
// one row off, and one integer step each way puts it right.
fn region_texel(j: u32, s: u32) -> vec2<u32> {
    if j < s { return vec2<u32>(j, 0u); }
    let r = triangular(s) - 1u - (j - s);
    var n = u32(max(floor((sqrt(8.0 * f32(r) + 1.0) - 1.0) * 0.5), 0.0));
    if triangular(n + 1u) <= r { n += 1u; }
    if n > 0u && triangular(n) > r { n -= 1u; }
    // Row s − n holds n + 1 texels; the r-th from the end is the (r − n(n+1)/2)-th of it from the right.
    return vec2<u32>(n - (r - triangular(n)), s - n);
}
