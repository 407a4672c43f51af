// A shading input: a point the shading pass (raytrace.wgsl's `shade`) shades, as the passes that
// find such points append it (eye.wgsl, level_points.wgsl, whitted.wgsl).

// Twin of beam_gpu::shade::ShadeInput (32 bytes).
struct ShadeInput {
    p: vec3<f32>,
    prim: u32,
    d: vec3<f32>,   // unit direction of the arriving ray
    seed: u32,
}
