//! Our default tree and each peer measured in alternation. The table's figures are each taken at
//! one moment of the run, and on a shared machine whose speed drifts by 15% within minutes (and
//! by more within seconds on a busy host) a ratio of two of them moves with it. Timing the two in
//! turn, back to back, exposes both to the same drift; the ratios printed for our default come
//! from these rounds. Back to back, as the table's: a pause before each build (to let the other
//! library's idle threads sleep) made both slower, Sponza's by 50–100% after 100 ms, ours less
//! than Embree's.

use super::timing::{Clock, KINDS, Rays, throughput};
use crate::bench::peer_set::peer_build_ms;
use crate::bench::stats::median;
use crate::bench::tracer::Tracer;
use beam_bvh::{BuildOptions, Bvh8};
use beam_math::Triangle;
use std::time::Instant;

/// Rounds of each alternation.
pub(super) const PAIRED_ROUNDS: usize = 11;

/// Our tree and a peer timed in alternation.
pub(super) struct Paired {
    pub ours: String,
    pub peer: String,
    /// Median build times (ms) of [`PAIRED_ROUNDS`] builds each, when the peer can rebuild.
    pub build_ms: Option<(f64, f64)>,
    /// `[threaded][kind]`: the median over the rounds of our Mrays/s over the peer's, each
    /// round's two figures taken one after the other.
    pub ratios: [[f64; 3]; 2],
}

/// Our tree `ours` (built with `options`) against every peer, in alternation: builds (median
/// times) and each ray kind on one thread and on all (median of the per-round ratios).
pub(super) fn alternate(
    tris: &[Triangle],
    options: &BuildOptions,
    ours: &dyn Tracer,
    peers: &[&dyn Tracer],
    rays: &Rays,
    clock: Clock,
) -> Vec<Paired> {
    let mut out = Vec::new();
    for peer in peers {
        let name = peer.name();
        let (mut our_ms, mut peer_ms) = (Vec::new(), Vec::new());
        for _ in 0..PAIRED_ROUNDS {
            let Some(ms) = peer_build_ms(&name, tris) else { break };
            peer_ms.push(ms);
            let s = Instant::now();
            std::hint::black_box(Bvh8::build(tris, options));
            our_ms.push(s.elapsed().as_secs_f64() * 1e3);
        }
        let build_ms = (!our_ms.is_empty()).then(|| (median(our_ms), median(peer_ms)));
        let mut ratios = [[0.0; 3]; 2];
        for (parallel, row) in [false, true].into_iter().zip(&mut ratios) {
            for (kind, r) in KINDS.iter().zip(row) {
                let each: Vec<f64> = (0..PAIRED_ROUNDS)
                    .map(|_| {
                        let a = throughput(ours, rays, kind, parallel, clock);
                        a / throughput(*peer, rays, kind, parallel, clock)
                    })
                    .collect();
                *r = median(each);
            }
        }
        out.push(Paired { ours: ours.name(), peer: name, build_ms, ratios });
    }
    if !out.is_empty() {
        println!("\nin alternation ({PAIRED_ROUNDS} rounds; the ratios below use these)");
        for p in &out {
            if let Some((a, b)) = p.build_ms {
                println!("  build: {} {a:.1} ms, {} {b:.1} ms (medians): {:.2}×", p.ours, p.peer, a / b);
            }
        }
    }
    out
}
