//! The next tree level's fits summed on the GPU (`shaders/lib/fit.wgsl`): where the composite
//! shades a kept level's texels itself, the host needs of the texels from which the tree goes on
//! only the sums of each beam's fits per S-mesh face (beam-render's [`Fit`], 000 §7.2), not the
//! texels (270 K a frame on the glass lens, 13 MB). `level_points` adds every such texel to its
//! (beam, face) slot of a table in 64-bit fixed point, whose sums do not depend on the order of
//! the texels: the same texels give the same bits, and the host's memos of the next level's beams
//! find them frame after frame. Host twin: beam-render's `Tree::requests`, summing in f32.

use crate::buffers::{output, read_all};
use crate::interface::{FIT_BIAS, FIT_SCALE, FIT_WORDS};
use crate::{Gpu, GpuError};
use beam_math::glam::Mat3;
use beam_render::nonlinear::Fit;

/// Fewest slots of a table (a power of two; `lib/fit.wgsl` hashes into at least 2¹⁰).
pub const MIN_FIT_SLOTS: u32 = 1 << 10;

/// A level's fit table on the GPU: per (beam of the level, S-mesh face) that its texels hit, the
/// sums of their fit (`lib/fit.wgsl` lays it out).
pub struct FitTable {
    buffer: wgpu::Buffer,
    slots: u32,
    faces: u32,
    beams: usize,
}

/// The fits a table held, read back.
pub struct ReadFits {
    /// Per beam of the level, its fits per face, ascending by face.
    pub fits: Vec<Vec<(u32, Fit)>>,
    /// Slots used.
    pub used: usize,
}

impl FitTable {
    /// A zeroed table of `slots` slots (a power of two, at least [`MIN_FIT_SLOTS`]) for the fits
    /// of `beams` beams over `faces` faces; `None` where there is no face, or its keys
    /// (`beam · faces + face + 1`) do not fit 32 bits, or its words one binding of `max_binding`
    /// bytes.
    pub fn new(gpu: &Gpu, slots: u32, beams: usize, faces: usize, max_binding: u64) -> Option<Self> {
        debug_assert!(slots.is_power_of_two() && slots >= MIN_FIT_SLOTS);
        let keys = (beams as u64).checked_mul(faces as u64)?;
        let bytes = (u64::from(slots) + 1) * u64::from(FIT_WORDS) * 4;
        if faces == 0 || keys >= u64::from(u32::MAX) || bytes > max_binding {
            return None;
        }
        let buffer = output(gpu, "fit table", bytes);
        Some(Self { buffer, slots, faces: faces as u32, beams })
    }

    /// Its slots and the S mesh's faces, as `LevelParams` gives them to `level_points`.
    #[must_use]
    pub fn params(&self) -> (u32, u32) {
        (self.slots, self.faces)
    }

    /// The buffer `level_points` binds.
    #[must_use]
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// The fits, read back after the level's dispatches; `None` where a sample found no slot
    /// (the table was too full: the host sums the fits itself).
    pub fn read(&self, gpu: &Gpu) -> Result<Option<ReadFits>, GpuError> {
        let words: Vec<u32> = read_all(gpu, Vec::new(), [(&self.buffer, self.buffer.size())].into_iter())?;
        decode(&words, self.beams, self.faces)
    }
}

/// [`FitTable::read`] of a table's words, for `beams` beams over `faces` faces.
fn decode(words: &[u32], beams: usize, faces: u32) -> Result<Option<ReadFits>, GpuError> {
    let (header, slots) = words.split_at(FIT_WORDS as usize);
    if header[0] != 0 {
        return Ok(None);
    }
    let mut fits: Vec<Vec<(u32, Fit)>> = vec![Vec::new(); beams];
    let mut used = 0;
    for slot in slots.chunks_exact(FIT_WORDS as usize).filter(|s| s[0] != 0) {
        let key = slot[0] - 1;
        let (beam, face) = ((key / faces) as usize, key % faces);
        let beam = fits.get_mut(beam).ok_or(GpuError::Internal("a fit past the level's beams"))?;
        beam.push((face, fit_of(slot)));
        used += 1;
    }
    for beam in &mut fits {
        beam.sort_unstable_by_key(|&(face, _)| face);
    }
    Ok(Some(ReadFits { fits, used }))
}

/// Slots for a level's table: twice those the same level used last frame, four times where it
/// overflowed (`None`: the first frame, eight a beam), a power of two of at least
/// [`MIN_FIT_SLOTS`].
#[must_use]
pub fn fit_slots(last: Option<(usize, bool)>, beams: usize) -> u32 {
    let wanted = match last {
        Some((used, false)) => 2 * used,
        Some((used, true)) => 4 * used,
        None => 8 * beams,
    };
    u32::try_from(wanted.next_power_of_two()).unwrap_or(1 << 31).max(MIN_FIT_SLOTS)
}

/// The fit a slot's words hold: its samples, and each sum less the bias its samples added.
fn fit_of(slot: &[u32]) -> Fit {
    let samples = slot[1];
    let sum = |i: usize| {
        let total = u64::from(slot[3 + 2 * i]) << 32 | u64::from(slot[2 + 2 * i]);
        let biased = i128::from(total) - i128::from(samples) * i128::from(FIT_BIAS);
        (biased as f64 / f64::from(FIT_SCALE)) as f32
    };
    let [g00, g01, g02, g11, g12, g22] = [0, 1, 2, 3, 4, 5].map(sum);
    let gram = Mat3::from_cols_array(&[g00, g01, g02, g01, g11, g12, g02, g12, g22]);
    let moment = Mat3::from_cols_array(&std::array::from_fn(|k| sum(6 + k)));
    Fit::from_sums(gram, moment, samples as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interface::FIT_LIMIT;
    use beam_math::glam::Vec3;

    /// A slot's words as `lib/fit.wgsl` adds `samples` to them (its fixed point, in Rust).
    fn slot_of(key: u32, samples: &[(Vec3, Vec3)]) -> Vec<u32> {
        let mut slot = vec![0u32; FIT_WORDS as usize];
        slot[0] = key;
        slot[1] = samples.len() as u32;
        let mut add = |i: usize, x: f32| {
            let q = ((x.clamp(-FIT_LIMIT, FIT_LIMIT) * FIT_SCALE).round() as i32 + FIT_BIAS as i32) as u32;
            let (low, carry) = slot[2 + 2 * i].overflowing_add(q);
            slot[2 + 2 * i] = low;
            slot[3 + 2 * i] += u32::from(carry);
        };
        for &(w, d) in samples {
            let g = [w.x * w.x, w.x * w.y, w.x * w.z, w.y * w.y, w.y * w.z, w.z * w.z];
            for (i, x) in g.into_iter().enumerate() {
                add(i, x);
            }
            for j in 0..3 {
                for i in 0..3 {
                    add(6 + 3 * j + i, d[i] * w[j]);
                }
            }
        }
        slot
    }

    /// Samples of a field of directions over a face, some of their terms negative.
    fn samples(n: usize) -> Vec<(Vec3, Vec3)> {
        (0..n)
            .map(|i| {
                let (u, v) = ((i % 13) as f32 / 13.0, (i / 13 % 11) as f32 / 11.0 * (1.0 - (i % 13) as f32 / 13.0));
                let w = Vec3::new(1.0 - u - v, u, v);
                (w, Vec3::new(u - 0.5, -v, -1.0).normalize())
            })
            .collect()
    }

    /// A slot's fixed-point sums decode to the f32 sums of its samples within f32's rounding,
    /// carries into the high words and negative sums included.
    #[test]
    fn decodes_the_sums_of_its_samples() {
        for n in [40, 1000, 70_000] {
            let samples = samples(n);
            let got = fit_of(&slot_of(1, &samples));
            let mut want = Fit::default();
            for &(w, d) in &samples {
                want.add(w, d);
            }
            assert_eq!(got.samples(), n);
            let (g, w) = (got.directions().expect("spans"), want.directions().expect("spans"));
            for (g, w) in g.iter().zip(w) {
                assert!(g.angle_between(w) < 1e-4, "{n} samples: {g} vs {w}");
            }
        }
    }

    /// A table's slots decode to their beams and faces, each beam's ascending by face; a table
    /// where a sample found no slot reads as none.
    #[test]
    fn decodes_keys_to_beams_and_faces() {
        let one = samples(5);
        let keyed = [(2 * 10 + 7 + 1, &one[..]), (2 * 10 + 3 + 1, &one[..4]), (9 + 1, &one[..3])];
        let mut words = vec![0u32; FIT_WORDS as usize];
        for (key, samples) in keyed {
            words.extend(slot_of(key, samples));
        }
        words.extend(vec![0u32; FIT_WORDS as usize]);
        let read = decode(&words, 3, 10).expect("in range").expect("no overflow");
        let faces = |b: usize| read.fits[b].iter().map(|(f, fit)| (*f, fit.samples())).collect::<Vec<_>>();
        assert_eq!((read.used, faces(0), faces(1), faces(2)), (3, vec![(9, 3)], vec![], vec![(3, 4), (7, 5)]));
        words[0] = 1;
        assert!(decode(&words, 3, 10).expect("in range").is_none());
        words[0] = 0;
        words[FIT_WORDS as usize] = 3 * 10 + 1;
        assert!(decode(&words, 3, 10).is_err(), "a beam past the level");
    }
}
