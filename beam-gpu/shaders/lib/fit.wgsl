// The next tree level's fits summed on the GPU (beam_scene::nonlinear::Fit; the table is
// beam_gpu::nonlinear::FitTable): per (beam of the level, S-mesh face) a slot of FIT_WORDS words
// in `fits`, found by open addressing on its key (beam · faces + face + 1; 0 is an empty slot).
// A slot holds its key, its number of samples, then the fit's 15 sums, each a 64-bit fixed-point
// number in two words (low, high) to which every sample adds round(x · FIT_SCALE) + FIT_BIAS:
// Σ w wᵀ's six (w₀w₀, w₀w₁, w₀w₂, w₁w₁, w₁w₂, w₂w₂), then Σ d wᵀ's nine column by column (d·w₀,
// d·w₁, d·w₂). Integer sums do not depend on the order the samples come in, so a frame's fits are
// the same bits as the last frame's for the same texels (the host finds its beams by those bits).
// Slot s lies at words (s + 1) · FIT_WORDS; word 0 counts the samples that found no slot within
// FIT_PROBES probes (the host then sums the fits itself). The including shader binds `fits`
// (array<atomic<u32>>).

// Add x, clamped to ±FIT_LIMIT (a NaN as 0), to the 64-bit sum at words `at`, `at + 1`.
fn fit_term(at: u32, x: f32) {
    let q = u32(i32(round(clamp(select(0.0, x, x == x), -FIT_LIMIT, FIT_LIMIT) * FIT_SCALE)) + i32(FIT_BIAS));
    let old = atomicAdd(&fits[at], q);
    // The low word wrapped: carry into the high one.
    if old + q < old {
        atomicAdd(&fits[at + 1u], 1u);
    }
}

// Add the sample at barycentric point w with unit direction d to the slot of `key` in a table of
// `slots` slots (a power of two, at least 2¹⁰), claiming an empty one. Loops: at most FIT_PROBES
// probes (constant bound).
fn fit_sample(key: u32, slots: u32, w: vec3<f32>, d: vec3<f32>) {
    // Fibonacci hashing: the product's top bits.
    var s = (key * 2654435761u) >> (32u - countTrailingZeros(slots));
    for (var n = 0u; n < FIT_PROBES; n++) {
        let at = (s + 1u) * FIT_WORDS;
        let claimed = atomicCompareExchangeWeak(&fits[at], 0u, key);
        if claimed.exchanged || claimed.old_value == key {
            atomicAdd(&fits[at + 1u], 1u);
            var g = array<f32, 6>(w.x * w.x, w.x * w.y, w.x * w.z, w.y * w.y, w.y * w.z, w.z * w.z);
            for (var i = 0u; i < 6u; i++) {
                fit_term(at + 2u + 2u * i, g[i]);
            }
            for (var j = 0u; j < 3u; j++) {
                let m = d * w[j];
                for (var i = 0u; i < 3u; i++) {
                    fit_term(at + 14u + 6u * j + 2u * i, m[i]);
                }
            }
            return;
        }
        // A weak exchange may fail on an empty slot: try it again.
        if claimed.old_value != 0u {
            s = (s + 1u) & (slots - 1u);
        }
    }
    atomicAdd(&fits[0], 1u);
}
