//! The lookup's projection in WGSL (`lib/lookup.wgsl`: damped Newton's method from a guess, in
//! f32) against beam-math's in f64 ([`Beam::project_in`] under [`LOOKUP`]): the step a coarse
//! S mesh's composite takes per point to find the texel of a child beam that its own reflected ray
//! reaches (000 §5, §7.1).

use super::beams::{kind, random_beams};
use super::device::adapter;
use crate::generate::{self, Rng64, uniform};
use crate::property::{Backend, Config, Outcome};
use beam_gpu::nonlinear::{LookupFound, NonlinearCheck};
use beam_math::glam::Vec3;
use beam_math::nonlinear::Projection;
use beam_render::nonlinear::Beam;
use beam_render::nonlinear::LOOKUP;

/// How far apart the GPU's and the CPU's `ω` may lie, and their `t` relative to the base's size
/// plus `t`: a thirtieth of a texel at 32 texels a side, where f32's Newton's method stops at its
/// rounding.
const LOOKUP_AGREE: f32 = 1e-3;

/// On 300 random S1 and S3 beams, 40 points each: 30 that a ray of the beam reaches (from inside
/// the base and up to 0.1 outside it, at 0.3 to 3 base sizes), looked up from a guess 0.05 off in
/// `ω` and 10% off in `t`, as a lookup's first projection is; 10 points anywhere above the base
/// (some no ray reaches), from the base's centre. Both find a projection or neither does. Where
/// beam-math's lies a base or more outside (a lookup sent to rays), the shader's lies at least half
/// a base outside. Otherwise both converge or both fall back on the corner rays' S1 solution, and
/// agree within [`LOOKUP_AGREE`]. At most 1% of the cases part: where the point lies at a fold
/// (convergence decided otherwise, or two roots that both reach it), or where both fell back on
/// corner-ray roots that f32's cubic places otherwise.
pub(super) fn gpu_lookup_projections_equal_cpu(_: Backend, _: &Config) -> Result<Outcome, String> {
    let gpu = match adapter()? {
        Ok(g) => g,
        Err(o) => return Ok(o),
    };
    let check = NonlinearCheck::new(&gpu).map_err(|e| e.to_string())?;
    let beams: Vec<Beam> = random_beams(31, 50).into_iter().filter(|b| !matches!(b, Beam::Bumped(_))).collect();
    let mut rng = generate::rng(32);
    let mut cases = Vec::new();
    for (i, beam) in beams.iter().enumerate() {
        let base = beam.texel_beam().base();
        let size = base[1].distance(base[0]).max(base[2].distance(base[0]));
        for k in 0..40 {
            if k < 30 {
                let w = outside_by(generate::barycentric(&mut rng), &mut rng, 0.1);
                let t = uniform(&mut rng, 0.3, 3.0) * size;
                let q = beam.ray_at(w).at(t);
                let off = Vec3::new(uniform(&mut rng, -0.05, 0.05), uniform(&mut rng, -0.05, 0.05), 0.0);
                let guess =
                    Projection { bary: w + off - Vec3::Z * (off.x + off.y), t: t * uniform(&mut rng, 0.9, 1.1) };
                cases.push((i as u32, q, guess));
            } else {
                let centre = (base[0] + base[1] + base[2]) / 3.0;
                let normal = (base[1] - base[0]).cross(base[2] - base[0]).normalize();
                let side =
                    if beam.ray_at(Vec3::splat(1.0 / 3.0)).direction.dot(normal) < 0.0 { -normal } else { normal };
                let away =
                    Vec3::new(uniform(&mut rng, -1.0, 1.0), uniform(&mut rng, -1.0, 1.0), uniform(&mut rng, -1.0, 1.0));
                let q = centre + (away + side * 1.2).normalize() * uniform(&mut rng, 0.5, 4.0) * size;
                cases.push((i as u32, q, Projection { bary: Vec3::splat(1.0 / 3.0), t: q.distance(centre) }));
            }
        }
    }
    let got = check.lookups(&gpu, &beams, &cases).map_err(|e| e.to_string())?;
    let (mut polished, mut corners, mut none, mut parted, mut far, mut worst) = (0u64, 0u64, 0u64, 0u64, 0u64, 0.0f32);
    for ((i, q, guess), gpu_answer) in cases.iter().zip(&got) {
        let beam = &beams[*i as usize];
        let cpu = beam.project_in(*q, LOOKUP, Some(*guess));
        let base = beam.texel_beam().base();
        let size = base[1].distance(base[0]).max(base[2].distance(base[0]));
        let case = || format!("{} beam {i}, q {q}, guess {guess:?}: GPU {gpu_answer:?}, CPU {cpu:?}", kind(beam));
        let (cpu, gpu_answer) = match (cpu, gpu_answer) {
            (None, None) => {
                none += 1;
                continue;
            }
            (Some(c), Some(g)) => (c, g),
            _ => return Err(format!("one found a projection, the other none: {}", case())),
        };
        // beam-math's answer converged where its ray reaches `q` (within f32's rounding of the ray).
        let reaches = |p: &Projection| beam.ray_at(p.bary).at(p.t).distance(*q) <= 1e-4 * size * (1.0 + p.t / size);
        let cpu_found = if reaches(&cpu) { LookupFound::Polished } else { LookupFound::Corners };
        if cpu_found != gpu_answer.1 {
            parted += 1;
            continue;
        }
        // A projection a base or more outside it sends a lookup to rays (f32 places it only
        // roughly, where the affine triangles flatten): the shader's must lie well outside too.
        let outside = |p: &Projection| -p.bary.min_element();
        if outside(&cpu) > 1.0 {
            if !(outside(&gpu_answer.0) > 0.5) {
                return Err(format!("far outside on the CPU only: {}", case()));
            }
            far += 1;
            continue;
        }
        let error =
            (gpu_answer.0.bary - cpu.bary).abs().max_element().max((gpu_answer.0.t - cpu.t).abs() / (size + cpu.t));
        if !(error <= LOOKUP_AGREE) {
            // Both rays reach `q`: two roots of a fold that f32 does not tell apart; or both fell
            // back on corner-ray roots that f32 places otherwise (a cubic with close roots).
            if cpu_found == LookupFound::Corners || reaches(&gpu_answer.0) {
                parted += 1;
                continue;
            }
            return Err(format!("ω or t differ by {error:.1e}: {}", case()));
        }
        worst = worst.max(error);
        match cpu_found {
            LookupFound::Polished => polished += 1,
            LookupFound::Corners => corners += 1,
        }
    }
    let n = cases.len() as u64;
    if parted * 100 > n {
        return Err(format!("{parted} of {n} lookups converged on one side only (more than 1%)"));
    }
    if polished * 2 < n {
        return Err(format!("only {polished} of {n} lookups converged: the cases do not test Newton's method"));
    }
    Ok(Outcome {
        cases: n,
        note: format!(
            "polished {polished}, corner rays {corners}, none {none}, a base or more outside {far}, parted {parted}; \
             worst |Δω| or |Δt|/(size + t) {worst:.1e}"
        ),
    })
}

/// `w` moved up to `by` outside the base, in a random direction in its plane.
fn outside_by(w: Vec3, rng: &mut Rng64, by: f32) -> Vec3 {
    let (a, b) = (uniform(rng, -by, by), uniform(rng, -by, by));
    w + Vec3::new(a, b, -a - b)
}
