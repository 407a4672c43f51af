// The final composite of 000 §7.3, one tree level per dispatch: `scatter` copies every shaded
// texel's radiance into the level (records are needed only where there is something to composite),
// and `composite` takes each texel on a specular S-mesh face with child beams and samples the
// children's radiance (the level below, still on the GPU) at the face's barycentric point, tinted
// for a mirror and Fresnel-weighted for glass. A level's radiance is an RGBA16F texture (rgb as half floats, 8
// bytes a texel), texel i at (i mod width, i / width): no storage binding bounds its size. Each
// dispatch binds only the faces and child regions its records reference (compacted by the host;
// the eye's records made on the GPU index the whole S mesh and level).
// CPU twin: beam_cpu::nonlinear::composite_levels.

// #import lib/record.wgsl

// Twin of beam_gpu::nonlinear::composite::GpuFace (128 bytes): an S-mesh face.
struct Face {
    v0: vec4<f32>,
    v1: vec4<f32>,
    v2: vec4<f32>,
    // Unit vertex normals, on the side of the geometric normal.
    n0: vec4<f32>,
    n1: vec4<f32>,
    n2: vec4<f32>,
    // The scene triangle's unit geometric normal.
    normal: vec4<f32>,
    // rgb: a mirror's tint; w: a glass's index of refraction, 0 for a mirror.
    material: vec4<f32>,
}

// Twin of beam_gpu::nonlinear::composite::CompositeParams (16 bytes).
struct CompositeParams {
    // Records of `composite`.
    records: u32,
    // Shaded texels of `scatter`, from its element `first` of `shaded` on.
    points: u32,
    first: u32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> params: CompositeParams;
@group(0) @binding(1) var<storage, read> records: array<Record>;
@group(0) @binding(2) var<storage, read> faces: array<Face>;
@group(0) @binding(3) var<storage, read> shaded: array<vec4<f32>>;
@group(0) @binding(4) var below: texture_2d<f32>;
// Per child beam the dispatch's records reference: its first texel below and its texels per side.
@group(0) @binding(5) var<storage, read> regions: array<vec2<u32>>;
@group(0) @binding(6) var radiance: texture_storage_2d<rgba16float, write>;
// Per shaded radiance (`shaded[i]`): the texel it is written to.
@group(0) @binding(7) var<storage, read> targets: array<u32>;

// Where texel `index` of a level lies in a texture `width` texels wide.
fn texel_coords(index: u32, width: u32) -> vec2<u32> {
    return vec2<u32>(index % width, index / width);
}

// Bilinear lookup at barycentric w of beam `beam`'s region below, over its rendered texels
// (x + y ≤ size): beam_scene::nonlinear::sample_region.
fn sample_region(beam: u32, w: vec3<f32>) -> vec3<f32> {
    let region = regions[beam];
    let size = region.y;
    let n = f32(size);
    let f = vec2<f32>(w.y * n - 0.5, w.z * n - 0.5);
    let f0 = floor(f);
    let a = f - f0;
    let dims = textureDimensions(below);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    // The shader's only loop: 4 iterations, at most twice an invocation (reflected and refracted
    // regions), whatever the scene or the tree: far under llvmpipe's cap of 65,535.
    for (var j = 0; j < 4; j++) {
        let dx = j % 2;
        let dy = j / 2;
        let k = select(1.0 - a.x, a.x, dx == 1) * select(1.0 - a.y, a.y, dy == 1);
        let x = u32(clamp(i32(f0.x) + dx, 0, i32(size) - 1));
        let y = u32(clamp(i32(f0.y) + dy, 0, i32(size) - 1));
        let index = region.x + y * size + x;
        if x + y < size + 1u && k > 0.0 && index < dims.x * dims.y {
            sum += k * textureLoad(below, texel_coords(index, dims.x), 0).rgb;
            weight += k;
        }
    }
    return select(vec3<f32>(0.0), sum / weight, weight > 0.0);
}

// Barycentric coordinates of p in the face's plane (beam_math::Triangle::barycentric; the centre
// for a degenerate face).
fn face_barycentric(f: Face, p: vec3<f32>) -> vec3<f32> {
    let n = cross(f.v1.xyz - f.v0.xyz, f.v2.xyz - f.v0.xyz);
    let nn = dot(n, n);
    if !(nn > 0.0) {
        return vec3<f32>(1.0 / 3.0);
    }
    let w0 = dot(cross(f.v1.xyz - p, f.v2.xyz - p), n) / nn;
    let w1 = dot(cross(f.v2.xyz - p, f.v0.xyz - p), n) / nn;
    return vec3<f32>(w0, w1, 1.0 - w0 - w1);
}

// Radiance leaving a point of a specular face towards the arriving ray (beam_scene::nonlinear::composite).
fn composite_texel(r: Record) -> vec3<f32> {
    let f = faces[r.face];
    let w = face_barycentric(f, r.p);
    let reflected = sample_region(r.reflected, w);
    let ior = f.material.w;
    if ior == 0.0 {
        return f.material.xyz * reflected;
    }
    if r.refracted == NONE {
        return reflected;
    }
    // Snell's law and Schlick's Fresnel about the interpolated normal (beam_scene::specular::dielectric).
    let entering = dot(r.d, f.normal.xyz) < 0.0;
    let interpolated = w.x * f.n0.xyz + w.y * f.n1.xyz + w.z * f.n2.xyz;
    var n = select(vec3<f32>(0.0), normalize(interpolated), dot(interpolated, interpolated) > 0.0);
    if !entering {
        n = -n;
    }
    let eta = select(ior, 1.0 / ior, entering);
    let cos_i = -dot(n, r.d);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        return reflected;
    }
    let t = eta * r.d + (eta * cos_i - sqrt(k)) * n;
    let q = (1.0 - ior) / (1.0 + ior);
    let r0 = q * q;
    let m = 1.0 - select(-dot(t, n), cos_i, entering);
    let fresnel = r0 + (1.0 - r0) * m * m * m * m * m;
    return fresnel * reflected + (1.0 - fresnel) * sample_region(r.refracted, face_barycentric(f, r.refracted_p));
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn composite(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= params.records {
        return;
    }
    let r = records[i];
    textureStore(radiance, texel_coords(r.texel, textureDimensions(radiance).x), vec4<f32>(composite_texel(r), 0.0));
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn scatter(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= params.points {
        return;
    }
    let c = shaded[params.first + i].xyz;
    textureStore(radiance, texel_coords(targets[i], textureDimensions(radiance).x), vec4<f32>(c, 0.0));
}
