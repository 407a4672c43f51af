// A composite record: one texel on a specular S-mesh face with child beams, as the composite
// (composite.wgsl) reads it and the eye's records (eye.wgsl, `eye_records`) make it.

// Twin of beam_gpu::nonlinear::composite::CompositeRecord (64 bytes).
struct Record {
    p: vec3<f32>,
    // Its index in the level's radiance.
    texel: u32,
    d: vec3<f32>,
    // Its S-mesh face and its child beams, as indices into the composite dispatch's `faces` and
    // `regions`.
    face: u32,
    reflected: u32,
    // NONE for none.
    refracted: u32,
    pad0: u32,
    pad1: u32,
    // Where the refraction is looked up (p: the reflection; both the hit point on a fine face).
    refracted_p: vec3<f32>,
    pad2: u32,
}
