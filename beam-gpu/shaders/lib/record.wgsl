// A composite record: one texel on a specular S-mesh face with child beams, as the composite
// (composite.wgsl) reads it and the eye's records (eye.wgsl, `eye_records`) and a tree level's
// (level_points.wgsl) make it, and the counts of those that make them.

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

// Twin of beam_gpu::nonlinear::RecordCounts (32 bytes): what eye.wgsl and level_points.wgsl append.
struct RecordCounts {
    // Composite records appended.
    records: atomic<u32>,
    // Points appended for the Whitted rays (no child beam).
    rest: atomic<u32>,
    // Of those, points under a coarse face whose child beams do not hold their scattered rays.
    uncovered: atomic<u32>,
    // Of those, the ones on triangles with interpolated normals; in level_points.wgsl where
    // `params.fits`, the texels on such triangles without child beams at their face (elsewhere the
    // host counts those).
    curved: atomic<u32>,
    // Records made under coarse faces.
    coarse: atomic<u32>,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}
