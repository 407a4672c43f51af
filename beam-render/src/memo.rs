//! What one frame made, kept for the next: values that are functions of the bits of their key (a
//! beam of the nonlinear tree is one of its face and its boundary directions), found again by the
//! next frame where it asks with the same bits, so that a camera that stands still or turns about
//! its position rebuilds nothing of its beams, and one that moves pays only the hashing.

use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::hash::Hash;
use std::sync::atomic::{AtomicU64, Ordering};

/// The values made or found during this frame and the last one, by key (`FxHasher`: keys are bits
/// of the scene's own floats, not an adversary's), each with the last frame that asked for it. A
/// frame's values stay for one more frame; older ones go, so it holds two frames' values at most.
/// One map, so that a value found again costs one probe and no insertion; the keys are looked up
/// in parallel (each value's last frame an atomic).
#[derive(Debug)]
pub struct FrameMemo<K, V> {
    values: FxHashMap<K, (V, AtomicU64)>,
    frame: u64,
    found: u64,
}

impl<K, V> Default for FrameMemo<K, V> {
    fn default() -> Self {
        Self { values: FxHashMap::default(), frame: 0, found: 0 }
    }
}

impl<K: Hash + Eq + Send + Sync, V: Clone + Send + Sync> FrameMemo<K, V> {
    /// A new frame begins: values the last frame did not ask for go.
    pub fn next_frame(&mut self) {
        self.frame += 1;
        let last = self.frame - 1;
        self.values.retain(|_, (_, asked)| *asked.get_mut() >= last);
    }

    /// The value of each key of `keys`: found among this frame's and the last one's, else made by
    /// `make(i)` for the `i`-th key (in parallel), and kept for the next frame.
    pub fn values(&mut self, keys: Vec<K>, make: impl Fn(usize) -> V + Sync) -> Vec<V> {
        let frame = self.frame;
        let values = &self.values;
        let found: Vec<Option<V>> = keys
            .par_iter()
            .map(|k| {
                values.get(k).map(|(v, asked)| {
                    asked.store(frame, Ordering::Relaxed);
                    v.clone()
                })
            })
            .collect();
        let missing = found.iter().filter(|f| f.is_none()).count();
        self.found += (found.len() - missing) as u64;
        if missing == 0 {
            return found.into_iter().flatten().collect();
        }
        let values: Vec<V> =
            found.par_iter().enumerate().map(|(i, found)| found.clone().unwrap_or_else(|| make(i))).collect();
        self.values.reserve(missing);
        for ((k, v), was) in keys.into_iter().zip(&values).zip(&found) {
            if was.is_none() {
                self.values.entry(k).or_insert_with(|| (v.clone(), AtomicU64::new(frame)));
            }
        }
        values
    }

    /// How many values it has found so far rather than made.
    #[must_use]
    pub fn found(&self) -> u64 {
        self.found
    }

    /// How many values it holds (this frame's and the last one's).
    #[must_use]
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether it holds none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// A value is made once while its key is asked for every frame; a key not asked for during a
    /// frame stays one more frame, then is made again.
    #[test]
    fn values_last_one_frame_past_their_last_use() {
        let made = AtomicUsize::new(0);
        let make = |k: u32| {
            made.fetch_add(1, Ordering::Relaxed);
            k * 10
        };
        let mut memo = FrameMemo::default();
        let frame = |memo: &mut FrameMemo<u32, u32>, keys: Vec<u32>| {
            memo.next_frame();
            let want: Vec<u32> = keys.iter().map(|k| k * 10).collect();
            let ks = keys.clone();
            assert_eq!(memo.values(keys, |i| make(ks[i])), want);
        };
        frame(&mut memo, vec![1, 2, 3, 2]);
        assert_eq!(made.load(Ordering::Relaxed), 4, "each key is made where a frame first asks");
        frame(&mut memo, vec![1, 2]);
        assert_eq!(made.load(Ordering::Relaxed), 4, "the last frame's values are found");
        frame(&mut memo, vec![1, 3]);
        assert_eq!(made.load(Ordering::Relaxed), 5, "3, unasked for a frame, is made again");
        assert_eq!((memo.len(), memo.found()), (3, 3), "1, 2 and 3 held once each");
    }
}
