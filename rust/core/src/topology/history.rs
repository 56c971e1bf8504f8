//! Scores averaged over a sliding window of scans (METHODS §4 "Over time": the project's
//! reading of the paper's "association quality").
//!
//! A pair's averaged score is the mean of its scores over the last `window` scans in which
//! both of its tracks were present, the current one included; a pair unseen for `window`
//! scans is forgotten. Memory is one small ring per pair seen within the window, so a
//! window of 1 keeps nothing.

use std::collections::VecDeque;

use rustc_hash::FxHashMap;

/// The recent scores of every (local id, system id) pair.
#[derive(Debug, Clone, Default)]
pub struct ScoreHistory {
    window: usize,
    scan: u64,
    pairs: FxHashMap<(i64, i64), VecDeque<(u64, f64)>>,
}

impl ScoreHistory {
    pub fn new(window: usize) -> Self {
        Self {
            window: window.max(1),
            scan: 0,
            pairs: FxHashMap::default(),
        }
    }

    /// Records this scan's `scores` (`(n_local, n_system)` row-major, NaN = no score) and
    /// replaces each entry by its window average (NaN stays NaN: a forbidden pair is not
    /// made however good its past).
    pub fn average_in_place(&mut self, local_ids: &[i64], system_ids: &[i64], scores: &mut [f64]) {
        self.scan += 1;
        if self.window == 1 {
            return;
        }
        let oldest = self.scan.saturating_sub(self.window as u64 - 1);
        let n_system = system_ids.len();
        for (i, &a) in local_ids.iter().enumerate() {
            for (j, &b) in system_ids.iter().enumerate() {
                let score = &mut scores[i * n_system + j];
                if score.is_nan() {
                    continue;
                }
                let ring = self.pairs.entry((a, b)).or_default();
                while ring.front().is_some_and(|&(scan, _)| scan < oldest) {
                    ring.pop_front();
                }
                ring.push_back((self.scan, *score));
                *score = ring.iter().map(|&(_, s)| s).sum::<f64>() / ring.len() as f64;
            }
        }
        let scan = self.scan;
        self.pairs.retain(|_, ring| {
            ring.back()
                .is_some_and(|&(last, _)| last >= oldest && last <= scan)
        });
    }

    /// Pairs currently remembered (for tests and memory accounting).
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }
}
