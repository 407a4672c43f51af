// What the atlas's two ways of finding a texel's nearest hit share (`beam_atlas.wgsl` by
// rasterization, `beam_texels.wgsl` by compute): the page's uniforms and its (beam, triangle)
// pairs, and one texel's test against one triangle. CPU twin: beam_cpu::nonlinear::render_beam.

// #import shared/bvh.wgsl
// #import shared/nonlinear.wgsl

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

// Whether `p` is a corner of beam `b`'s base.
fn base_corner(b: Beam, p: vec3<f32>) -> bool {
    return all(p == bv(b, 0u)) || all(p == bv(b, 1u)) || all(p == bv(b, 2u));
}

// Whether pair `pair`'s triangle is the surface meeting the beam's base: a triangle of a coarse
// face's ring (PAIR_NEAR), or one sharing a vertex with the base. No loops.
fn pair_neighbour(b: Beam, pair: vec2<u32>) -> bool {
    let t = triangles[pair.y & ~PAIR_NEAR];
    return (pair.y & PAIR_NEAR) != 0u || base_corner(b, t.v0) || base_corner(b, t.v1) || base_corner(b, t.v2);
}

// Whether the texel at base point `w` of a region of side `size` is tested against a triangle
// whose bounding triangle has lower barycentric bounds `lower` (half a texel of slack).
fn texel_tested(w: vec3<f32>, lower: vec3<f32>, size: u32) -> bool {
    return !any(w < lower - vec3<f32>(0.5 / f32(size)));
}

// A texel's ray at base point `w`, ready for triangle tests: sheared, the length of its
// direction (t is in those units), and the nearest t of a hit on any triangle and on a neighbour
// (nearer, a neighbour's hit is the surface meeting itself). Loops: texel_ray's sum over the S^3
// coefficients, 10 iterations.
struct TexelQuery {
    ray: ShearedRay,
    len: f32,
    t_min: f32,
    t_near: f32,
}

fn texel_query(b: Beam, w: vec3<f32>) -> TexelQuery {
    let ray = texel_ray(b, w);
    let len = max(length(ray.direction), 1.17549435e-38);
    let t_near = self_hit_distance(b, ray, params.extent) / len;
    return TexelQuery(shear_ray(ray.origin, ray.direction), len, TEXEL_EPS * params.extent / len, t_near);
}

// t of query `q`'s hit on scene triangle `prim` (negative for a miss).
fn texel_hit(q: TexelQuery, prim: u32, neighbour: bool) -> f32 {
    return intersect_triangle(q.ray, triangles[prim], select(q.t_min, q.t_near, neighbour), 3.0e38);
}
