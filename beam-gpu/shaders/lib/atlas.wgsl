// What the atlas's two ways of finding a texel's nearest hit share (`beam_atlas.wgsl` by
// rasterization, `beam_texels.wgsl` by compute): the page's uniforms and its (beam, triangle)
// pairs, and one texel's test against one triangle. CPU twin: beam_cpu::nonlinear::render_beam.

// Twin of beam_gpu::nonlinear::AtlasParams (16 bytes).
struct AtlasParams {
    size: vec2<f32>,  // atlas width and height in texels
    extent: f32,      // the scene's diagonal
    pairs: u32,       // (beam, triangle) pairs on the page
}

@group(0) @binding(0) var<uniform> params: AtlasParams;
@group(0) @binding(1) var<storage, read> beams: array<Beam>;
@group(0) @binding(2) var<storage, read> triangles: array<BvhTriangle>;
@group(0) @binding(3) var<storage, read> pairs: array<vec2<u32>>;   // (beam on the page, scene triangle | PAIR_NEAR)

fn scene_tri(prim: u32) -> Tri {
    let t = triangles[prim];
    return Tri(array<vec3<f32>, 3>(t.v0, t.v1, t.v2));
}

// Whether pair `pair`'s triangle is the surface meeting the beam's base: a triangle of a coarse
// face's ring (PAIR_NEAR), or one sharing a vertex with the base. 3 × 3 iterations (20 counted as
// llvmpipe counts).
fn pair_neighbour(b: Beam, pair: vec2<u32>) -> bool {
    let tri = scene_tri(pair.y & ~PAIR_NEAR);
    var neighbour = (pair.y & PAIR_NEAR) != 0u;
    for (var i = 0u; i < 3u; i++) {
        for (var j = 0u; j < 3u; j++) {
            if all(tri.v[i] == bv(b, j)) { neighbour = true; }
        }
    }
    return neighbour;
}

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

// Whether the texel at base point `w` of a region of side `size` is tested against a triangle
// whose bounding triangle has lower barycentric bounds `lower` (half a texel of slack).
fn texel_tested(w: vec3<f32>, lower: vec3<f32>, size: u32) -> bool {
    return !any(w < lower - vec3<f32>(0.5 / f32(size)));
}

// The texel ray at base point `w` against scene triangle `prim`: (t, the ray direction's length),
// t negative for a miss. A neighbour's hits nearer than the self-hit distance are the surface
// meeting itself. Loops: texel_ray's sum over the S^3 coefficients, 10 iterations.
fn texel_hit(b: Beam, w: vec3<f32>, prim: u32, neighbour: bool) -> vec2<f32> {
    let ray = texel_ray(b, w);
    let len = max(length(ray.direction), 1.17549435e-38);
    var t_min = TEXEL_EPS * params.extent / len;
    if neighbour { t_min = self_hit_distance(b, ray, params.extent) / len; }
    let t = intersect_triangle(shear_ray(ray.origin, ray.direction), triangles[prim], t_min, 3.0e38);
    return vec2<f32>(t, len);
}
