//! Scores averaged over a sliding window of scans (METHODS §4 "Over time": the project's
//! reading of the paper's "association quality").
//!
//! A pair's averaged score is the mean of its scores over the last `window` scans in which
//! both of its tracks were present, the current one included; a pair unseen for `window`
//! scans is forgotten. Memory is one small ring per pair seen within the window, so a
//! window of 1 keeps nothing.

use std::collections::VecDeque;

use rustc_hash::FxHashMap;

use super::candidates::Candidates;

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

    /// Records this scan's `scores` of the candidate `pairs` (rows into `local_ids` and
    /// `system_ids`) and replaces each score by its window average. On a stop request
    /// (`parallel::interrupted`, polled every 4 096 pairs) it ends early, returns `false`, and
    /// the history is then part this scan's: the caller forgets it ([`Self::new`]).
    pub fn average_in_place(
        &mut self,
        local_ids: &[i64],
        system_ids: &[i64],
        pairs: &Candidates,
        scores: &mut [f64],
    ) -> bool {
        self.scan += 1;
        if self.window == 1 {
            return true;
        }
        let oldest = self.scan.saturating_sub(self.window as u64 - 1);
        for (k, score) in scores.iter_mut().enumerate() {
            if k % 4096 == 0 && crate::parallel::interrupted() {
                return false;
            }
            let (i, j) = pairs.pair(k);
            let key = (local_ids[i], system_ids[j]);
            let ring = self.pairs.entry(key).or_default();
            while ring.front().is_some_and(|&(scan, _)| scan < oldest) {
                ring.pop_front();
            }
            ring.push_back((self.scan, *score));
            *score = ring.iter().map(|&(_, s)| s).sum::<f64>() / ring.len() as f64;
        }
        self.pairs
            .retain(|_, ring| ring.back().is_some_and(|&(last, _)| last >= oldest));
        true
    }

    /// Pairs currently remembered (for tests and memory accounting).
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }
}
