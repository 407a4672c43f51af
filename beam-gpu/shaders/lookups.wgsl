// The coarse S mesh's lookups (000 §7.1, §7.3) on the GPU: per point of a fine surface under a
// coarse face, where it reads the face's child beam for its own scattered ray (lib/reproject.wgsl's
// `reproject`). The host gathers the points and finishes each composite with the answers. CPU
// twin: beam_cpu::nonlinear::lookup::reproject.

// #import shared/nonlinear.wgsl
// #import lib/reproject.wgsl

// Twin of beam_gpu::nonlinear::GpuLookupJob (48 bytes).
struct LookupJob {
    p: vec3<f32>,
    // The child beam, an index into `beams`.
    beam: u32,
    // The point's scattered unit direction.
    truth: vec3<f32>,
    // Where its ray leaves the scene.
    far: f32,
    // Its barycentric coordinates on the face.
    w: vec3<f32>,
    pad: u32,
}

@group(0) @binding(0) var<storage, read> beams: array<Beam>;
// Per texel of the beams' regions (a beam's region.x: its first of size² texels, row-major as
// beam_scene's BeamTexture): the ray parameter of its nearest hit, negative where it hits nothing.
@group(0) @binding(1) var<storage, read> texel_t: array<f32>;
@group(0) @binding(2) var<storage, read> jobs: array<LookupJob>;
@group(0) @binding(3) var<storage, read_write> answers: array<vec4<f32>>;

// Per job: the coordinates (xyz) and how far outside the base (w). Loops: reproject's.
@compute @workgroup_size(WORKGROUP_SIZE)
fn lookups(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if k >= arrayLength(&jobs) { return; }
    let j = jobs[k];
    answers[k] = reproject(beams[j.beam], j.p, j.truth, j.w, j.far);
}
