// A mirror or glass triangle as the GPU reads it (`specular_prims`, a texture of eight texels a
// triangle that the including shader binds) and the geometry of its specular rays: what
// beam_scene::specular::specular_rays reads. Imported by whitted.wgsl (the Whitted rays) and
// lib/coarse.wgsl (a point's own scattered rays under a coarse S-mesh face).

// Twin of beam_gpu::nonlinear::SpecularPrim (128 bytes): a mirror or glass triangle.
struct SpecularPrim {
    v0: vec3<f32>,
    // SPECULAR_MIRROR, SPECULAR_GLASS or SPECULAR_THIN.
    kind: u32,
    v1: vec3<f32>,
    // A glass's index of refraction.
    ior: f32,
    v2: vec3<f32>,
    // 1 where n0..n2 are smooth vertex normals, 0 for none.
    has_normals: u32,
    n0: vec3<f32>,
    // A mirror's bump map: largest tilt δ (0 for none) and wavelength.
    delta: f32,
    n1: vec3<f32>,
    wavelength: f32,
    n2: vec3<f32>,
    pad0: u32,
    // Unit geometric normal (Scene::normal).
    normal: vec3<f32>,
    pad1: u32,
    // A mirror's or thin pane's tint.
    tint: vec3<f32>,
    pad2: u32,
}

// Texel i of `specular_prims`.
fn specular_texel(i: u32) -> vec4<u32> {
    let w = textureDimensions(specular_prims).x;
    return textureLoad(specular_prims, vec2<u32>(i % w, i / w), 0);
}

// The SpecularPrim in `slot`.
fn specular_prim(slot: u32) -> SpecularPrim {
    var t: array<vec4<u32>, 8>;
    for (var k = 0u; k < 8u; k++) {
        t[k] = specular_texel(8u * slot + k);
    }
    let f = array<vec3<f32>, 8>(
        bitcast<vec3<f32>>(t[0].xyz), bitcast<vec3<f32>>(t[1].xyz), bitcast<vec3<f32>>(t[2].xyz),
        bitcast<vec3<f32>>(t[3].xyz), bitcast<vec3<f32>>(t[4].xyz), bitcast<vec3<f32>>(t[5].xyz),
        bitcast<vec3<f32>>(t[6].xyz), bitcast<vec3<f32>>(t[7].xyz),
    );
    return SpecularPrim(
        f[0], t[0].w, f[1], bitcast<f32>(t[1].w), f[2], t[2].w, f[3], bitcast<f32>(t[3].w),
        f[4], bitcast<f32>(t[4].w), f[5], t[5].w, f[6], t[6].w, f[7], t[7].w,
    );
}

// Triangle::barycentric of p, or none (x = −3e38) for a degenerate triangle.
fn barycentric(s: SpecularPrim, p: vec3<f32>) -> vec3<f32> {
    let n = cross(s.v1 - s.v0, s.v2 - s.v0);
    let nn = dot(n, n);
    if !(nn > 0.0) || nn > 3.0e38 {
        return vec3<f32>(-3.0e38, 0.0, 0.0);
    }
    let w0 = dot(cross(s.v1 - p, s.v2 - p), n) / nn;
    let w1 = dot(cross(s.v2 - p, s.v0 - p), n) / nn;
    return vec3<f32>(w0, w1, 1.0 - w0 - w1);
}

// Scene::shading_normal: the Phong interpolation of the smooth vertex normals, else the geometric
// normal.
fn shading_normal(s: SpecularPrim, p: vec3<f32>) -> vec3<f32> {
    if s.has_normals == 0u {
        return s.normal;
    }
    let w = barycentric(s, p);
    let m = w.x * s.n0 + w.y * s.n1 + w.z * s.n2;
    let l = length(m);
    if w.x == -3.0e38 || !(l > 0.0) || l > 3.0e38 {
        return s.normal;
    }
    return m / l;
}

// reflect: d mirrored about unit n.
fn mirrored(d: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return d - 2.0 * dot(d, n) * n;
}

// Where unit d meets s at p (specular_rays' n, entering and s): the geometric normal on the side
// d comes from, whether d enters the front, and the shading normal on that side.
struct Facing {
    n: vec3<f32>,
    entering: bool,
    sn: vec3<f32>,
}

fn facing(s: SpecularPrim, p: vec3<f32>, d: vec3<f32>) -> Facing {
    let entering = dot(s.normal, d) < 0.0;
    let n = select(-s.normal, s.normal, entering);
    let sn = shading_normal(s, p) * select(-1.0, 1.0, dot(n, s.normal) >= 0.0);
    return Facing(n, entering, sn);
}

// Snell's law (beam_scene::specular::refract): d refracted through unit n (facing against d)
// with relative index eta in xyz, w 1; w 0 under total internal reflection.
fn refracted(d: vec3<f32>, n: vec3<f32>, eta: f32) -> vec4<f32> {
    let cos_i = -dot(n, d);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if !(k >= 0.0) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(eta * d + (eta * cos_i - sqrt(k)) * n, 1.0);
}
