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
//!
//! Bands are traced while the pixels of those whose rows are not all shaded stay within
//! [`AHEAD`], and a band's surface fragments go once its rows are; twice as many rows as threads
//! shade at a time, each with its state: a large frame holds the fragments of a few bands and the
//! states of a few rows, not all.

use super::context::{Lights, Surface, Thread};
use super::stats::Counters;
use super::trace::{EyeTraced, Trace, Traced};
use crate::render::eye_regions::{Region, TILE};
use beam_math::glam::Vec3;
use rayon::ScopeFifo;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

/// Pixels of the bands traced whose rows are not all shaded, at most (but for one band): 2 M, a
/// 1,448² frame, whose fragments take about 140 MB (a 56-byte [`Surface`] per pixel and 20% more
/// for the edges). Tracing the next band only once fewer than four rows were left to shade took
/// the conference room at 256² 74.6 ms a render instead of 63.5 (warm, 2 threads, medians of 9):
/// its threads waited for a band's regions between its rows.
const AHEAD: usize = 1 << 21;

/// A region's surface fragments sorted by tile, and the lights they gather.
struct Fragments {
    region: Region,
    surfaces: Vec<Surface>,
    lights: Lights,
}

/// One row of tiles of a band being shaded.
struct Chain {
    band: usize,
    /// The band's fragments, region by region.
    fragments: Arc<[Fragments]>,
    /// Its tiles, left to right: `(region of the band, start, end)` of their surfaces.
    tiles: Vec<(usize, usize, usize)>,
    /// Each tile's radiance as it is shaded: `(region, pixel of the region, radiance)`.
    radiance: Vec<(usize, usize, Vec3)>,
    /// Each tile's counters: `(region, counters)`.
    counters: Vec<(usize, Counters)>,
    /// The row's pixels (for the progress).
    rows: Region,
    /// Its state, from its first tile on.
    t: Option<Box<Thread>>,
}

/// One band of regions.
struct Band {
    /// Its regions as traced, until the last of them is.
    traced: Mutex<Vec<Option<EyeTraced>>>,
    /// Its regions still to trace.
    left: AtomicUsize,
    /// Its regions' pixels and counters, each row's radiance added once it is shaded.
    parts: Mutex<Vec<Traced>>,
}

/// What the jobs share.
struct Frame<'a> {
    trace: &'a Trace<'a>,
    bands: &'a [&'a [Region]],
    work: Region,
    band: Vec<Band>,
    /// The next band to trace, and the rows of tiles of the bands started that are not shaded yet.
    queue: Mutex<(usize, usize)>,
    /// The rows waiting to be shaded, and how many are being shaded.
    rows: Mutex<(VecDeque<Chain>, usize)>,
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
    let band = bands
        .iter()
        .map(|b| Band {
            traced: Mutex::new(b.iter().map(|_| None).collect()),
            left: AtomicUsize::new(b.len()),
            parts: Mutex::new(Vec::new()),
        })
        .collect();
    let rows = Mutex::new((VecDeque::new(), 0));
    let frame = Frame { trace, bands, work, band, queue: Mutex::new((0, 0)), rows, rows_done };
    let jobs = &frame;
    rayon::scope_fifo(|s| jobs.start_bands(s, 0));
    frame.band.into_iter().flat_map(|b| b.parts.into_inner().unwrap_or_else(PoisonError::into_inner)).collect()
}

impl<'a> Frame<'a> {
    /// Start tracing bands while [`AHEAD`] allows (`shaded`: rows just shaded).
    fn start_bands(&'a self, s: &ScopeFifo<'a>, shaded: usize) {
        // Rows of tiles, which span the work's width: AHEAD's pixels in them.
        let ahead = AHEAD / (TILE * self.work.width()).max(1) as usize;
        let mut queue = self.queue.lock().unwrap_or_else(PoisonError::into_inner);
        let (next, unshaded) = &mut *queue;
        *unshaded -= shaded;
        while let Some(regions) = self.bands.get(*next) {
            let rows = regions[0].intersect(self.work).height().div_ceil(TILE) as usize;
            if *unshaded > 0 && *unshaded + rows > ahead {
                break;
            }
            let band = *next;
            for (r, &region) in regions.iter().enumerate() {
                s.spawn_fifo(move |s| self.trace_region(s, (band, r), region));
            }
            (*next, *unshaded) = (band + 1, *unshaded + rows);
        }
    }

    /// Trace `region`, region `r` of band `band`; the last of its band starts the band's rows.
    fn trace_region(&'a self, s: &ScopeFifo<'a>, (band, r): (usize, usize), region: Region) {
        let traced = self.trace.eye_region(region, region.intersect(self.work));
        let b = &self.band[band];
        b.traced.lock().unwrap_or_else(PoisonError::into_inner)[r] = Some(traced);
        if b.left.fetch_sub(1, Ordering::AcqRel) > 1 {
            return;
        }
        let traced: Vec<EyeTraced> =
            b.traced.lock().unwrap_or_else(PoisonError::into_inner).drain(..).map(|e| e.expect("traced")).collect();
        let (chains, empty) = self.chains(band, traced);
        if empty > 0 {
            self.start_bands(s, empty);
        }
        self.rows.lock().unwrap_or_else(PoisonError::into_inner).0.extend(chains);
        self.start_rows(s, false);
    }

    /// Start shading rows while fewer than twice the threads are (`done`: one just finished).
    fn start_rows(&'a self, s: &ScopeFifo<'a>, done: bool) {
        let mut rows = self.rows.lock().unwrap_or_else(PoisonError::into_inner);
        let (waiting, shading) = &mut *rows;
        *shading -= usize::from(done);
        while *shading < 2 * rayon::current_num_threads() {
            let Some(chain) = waiting.pop_front() else { break };
            *shading += 1;
            s.spawn_fifo(move |s| self.shade(s, chain));
        }
    }

    /// The rows of tiles of band `band` (its regions `traced`), each with its tiles left to right,
    /// and how many rows are empty (done at once). The regions' pixels and counters wait for the
    /// rows.
    fn chains(&self, band: usize, traced: Vec<EyeTraced>) -> (Vec<Chain>, usize) {
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
        let (parts, fragments): (Vec<Traced>, Vec<Fragments>) = traced
            .into_iter()
            .map(|e| {
                let fragments = Fragments { region: e.traced.region, surfaces: e.surfaces, lights: e.lights };
                (e.traced, fragments)
            })
            .unzip();
        *self.band[band].parts.lock().unwrap_or_else(PoisonError::into_inner) = parts;
        let fragments: Arc<[Fragments]> = fragments.into();
        let (mut chains, mut empty) = (Vec::new(), 0);
        for (row, tiles) in by_row.into_iter().enumerate() {
            let top = y0 + row as u32 * TILE;
            let rows = Region { y0: top, y1: (top + TILE).min(y1), ..first };
            if tiles.is_empty() {
                (self.rows_done)(rows);
                empty += 1;
            } else {
                let (radiance, counters) = (Vec::new(), Vec::new());
                let fragments = Arc::clone(&fragments);
                chains.push(Chain { band, fragments, tiles, radiance, counters, rows, t: None });
            }
        }
        (chains, empty)
    }

    /// Shade the next tile of `chain`, then queue the rest of it behind the jobs queued so far;
    /// the last adds the row's radiance to its regions' pixels.
    fn shade(&'a self, s: &ScopeFifo<'a>, mut chain: Chain) {
        let (r, start, end) = chain.tiles[chain.counters.len()];
        let e = &chain.fragments[r];
        let t = chain.t.get_or_insert_default();
        let before = t.c;
        let out = self.trace.shade_eye_tile(e.region, &e.surfaces[start..end], e.lights, t);
        chain.counters.push((r, t.c.since(&before)));
        chain.radiance.extend(out.into_iter().map(|(i, l)| (r, i, l)));
        if chain.counters.len() < chain.tiles.len() {
            s.spawn_fifo(move |s| self.shade(s, chain));
            return;
        }
        drop(chain.t.take());
        self.start_rows(s, true);
        (self.rows_done)(chain.rows);
        {
            let mut parts = self.band[chain.band].parts.lock().unwrap_or_else(PoisonError::into_inner);
            for (r, i, l) in chain.radiance {
                parts[r].pixels[i] += l;
            }
            for (r, counters) in chain.counters {
                parts[r].counters += counters;
            }
        }
        self.start_bands(s, 1);
    }
}
