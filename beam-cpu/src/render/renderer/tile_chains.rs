//! The eye-beam frame as jobs on rayon's pool: each region of the frame's grid traced, and, once
//! every region of a band (a row of the grid) is, each row of tiles across the band shaded as a
//! chain of jobs, one a tile, left to right.
//!
//! A tile starts from how the one before it in its row ended (`TileShadows`), so a row is shaded
//! in order, by one [`Thread`] state that travels with it: the image does not depend on which
//! thread shaded which tile. The chain yields its thread after each tile (FIFO jobs): the rows
//! queued on a thread shade in turn, and a thread out of work takes over a chain another one
//! started. With a row a job instead, the thread that shaded one heavy row went on to the next
//! one it had queued while the other idled: `foliage` at 128², whose two rows under the leaves
//! take 16 and 21 ms, rendered in 40 ms what was 62 thread-ms of work.

use super::context::Thread;
use super::stats::Counters;
use super::trace::{EyeTraced, TileRadiance, Trace, Traced};
use crate::render::eye_regions::{Region, TILE};
use rayon::ScopeFifo;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

/// A tile's radiance and counters: `(region of its band, pixels, counters)`.
type Shaded = (usize, TileRadiance, Counters);

/// One row of tiles of a band being shaded.
struct Chain {
    band: usize,
    /// Its tiles, left to right: `(region of the band, start, end)` of their surfaces.
    tiles: Vec<(usize, usize, usize)>,
    /// The tiles shaded so far.
    shaded: Vec<Shaded>,
    /// The row's pixels (for the progress).
    rows: Region,
    t: Thread,
}

/// What the jobs share.
struct Frame<'a> {
    trace: &'a Trace<'a>,
    /// Per band, its regions once traced.
    traced: Vec<Vec<OnceLock<EyeTraced>>>,
    /// Per band, its regions still to trace.
    left: Vec<AtomicUsize>,
    /// Per band, its tiles once shaded.
    shaded: Vec<Mutex<Vec<Shaded>>>,
    rows_done: &'a (dyn Fn(Region) + Sync),
}

/// Trace the regions of `bands` (the pixels of `work` in each) and shade them, calling
/// `rows_done` with each row of tiles once shaded; the regions in order, band by band.
pub(super) fn trace_and_shade(
    trace: &Trace<'_>,
    bands: &[&[Region]],
    work: Region,
    rows_done: &(dyn Fn(Region) + Sync),
) -> Vec<Traced> {
    let frame = Frame {
        trace,
        traced: bands.iter().map(|b| b.iter().map(|_| OnceLock::new()).collect()).collect(),
        left: bands.iter().map(|b| AtomicUsize::new(b.len())).collect(),
        shaded: bands.iter().map(|_| Mutex::new(Vec::new())).collect(),
        rows_done,
    };
    let jobs = &frame;
    rayon::scope_fifo(|s| {
        for (band, regions) in bands.iter().enumerate() {
            for (r, &region) in regions.iter().enumerate() {
                s.spawn_fifo(move |s| jobs.trace_region(s, (band, r), region, region.intersect(work)));
            }
        }
    });
    let mut parts = Vec::new();
    for (band, shaded) in frame.traced.into_iter().zip(frame.shaded) {
        let mut band: Vec<Traced> =
            band.into_iter().map(|e| e.into_inner().expect("every region traced").traced).collect();
        for (r, out, counters) in shaded.into_inner().expect("no job panicked") {
            let part = &mut band[r];
            for (i, l) in out {
                part.pixels[i] += l;
            }
            part.counters += counters;
        }
        parts.extend(band);
    }
    parts
}

impl<'a> Frame<'a> {
    /// Trace `region`, region `r` of band `band` (the pixels of `window` in it); the last of its
    /// band starts the band's rows of tiles.
    fn trace_region(&'a self, s: &ScopeFifo<'a>, (band, r): (usize, usize), region: Region, window: Region) {
        self.traced[band][r].get_or_init(|| self.trace.eye_region(region, window));
        if self.left[band].fetch_sub(1, Ordering::AcqRel) == 1 {
            for chain in self.chains(band) {
                s.spawn_fifo(move |s| self.shade(s, chain));
            }
        }
    }

    /// The rows of tiles of band `band`, each with its tiles left to right; the empty rows are
    /// done at once.
    fn chains(&self, band: usize) -> Vec<Chain> {
        let traced: Vec<&EyeTraced> = self.traced[band].iter().map(|e| e.get().expect("the band is traced")).collect();
        let first = traced[0].traced.region;
        let (y0, y1) = (first.y0, first.y1);
        let mut by_row: Vec<Vec<(usize, usize, usize)>> = vec![Vec::new(); (y1 - y0).div_ceil(TILE) as usize];
        for (r, e) in traced.iter().enumerate() {
            let mut start = 0;
            for &len in &e.tiles {
                by_row[((e.surfaces[start].y - y0) / TILE) as usize].push((r, start, start + len));
                start += len;
            }
        }
        debug_assert!(by_row.iter().all(|row| row.is_sorted_by_key(|&(r, start, _)| traced[r].surfaces[start].x)));
        let mut chains = Vec::new();
        for (row, tiles) in by_row.into_iter().enumerate() {
            let top = y0 + row as u32 * TILE;
            let rows = Region { y0: top, y1: (top + TILE).min(y1), ..first };
            if tiles.is_empty() {
                (self.rows_done)(rows);
            } else {
                chains.push(Chain { band, tiles, shaded: Vec::new(), rows, t: Thread::default() });
            }
        }
        chains
    }

    /// Shade the next tile of `chain`, then queue the rest of it behind the jobs queued so far.
    fn shade(&'a self, s: &ScopeFifo<'a>, mut chain: Chain) {
        let (r, start, end) = chain.tiles[chain.shaded.len()];
        let e = self.traced[chain.band][r].get().expect("the band is traced");
        let before = chain.t.c;
        let out = self.trace.shade_eye_tile(e.traced.region, &e.surfaces[start..end], e.lights, &mut chain.t);
        chain.shaded.push((r, out, chain.t.c.since(&before)));
        if chain.shaded.len() < chain.tiles.len() {
            s.spawn_fifo(move |s| self.shade(s, chain));
        } else {
            (self.rows_done)(chain.rows);
            self.shaded[chain.band].lock().expect("no job panicked").append(&mut chain.shaded);
        }
    }
}
