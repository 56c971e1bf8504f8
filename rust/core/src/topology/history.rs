//! Scores averaged over a sliding window of scans (METHODS §4 "Over time": the project's
//! reading of the paper's "association quality").
//!
//! A pair's averaged score is the mean of its scores over the last `window` scans in which
//! both of its tracks were present, the current one included; a pair unseen for `window`
//! scans is forgotten.
//!
//! Memory is the last `window − 1` scans as they were scored: their track ids, their
//! candidate pairs and their raw scores, in flat arrays (no per-pair allocation, no hashing
//! of pairs). Recording a scan is a copy, so a scan with no earlier scan in the window — the
//! first one — costs the same whatever the window; a later scan looks each of its pairs up in
//! each remembered scan (an index computation without a gate, a binary search with one). A
//! window of 1 keeps nothing.

use std::collections::VecDeque;

use rustc_hash::FxHashMap;

use super::candidates::Candidates;

/// One remembered scan: its ids, its pairs and their raw (not averaged) scores.
#[derive(Debug, Clone)]
struct PastScan {
    local_rows: FxHashMap<i64, u32>,
    system_rows: FxHashMap<i64, u32>,
    pairs: Candidates,
    scores: Vec<f64>,
}

impl PastScan {
    /// The raw score this scan gave the pair of rows `(i, j)`, if it scored it.
    fn score(&self, i: u32, j: u32) -> Option<f64> {
        let k = match &self.pairs {
            Candidates::All { n_system, .. } => i as usize * n_system + j as usize,
            Candidates::Listed(pairs) => {
                let k = pairs.partition_point(|&p| p < (i, j));
                if pairs.get(k) != Some(&(i, j)) {
                    return None;
                }
                k
            }
        };
        self.scores.get(k).copied()
    }
}

fn rows(ids: &[i64]) -> FxHashMap<i64, u32> {
    ids.iter()
        .enumerate()
        .map(|(r, &id)| (id, r as u32))
        .collect()
}

/// The recent scores of every (local id, system id) pair.
#[derive(Debug, Clone, Default)]
pub struct ScoreHistory {
    window: usize,
    /// The last `window − 1` scans, oldest first.
    past: VecDeque<PastScan>,
}

impl ScoreHistory {
    pub fn new(window: usize) -> Self {
        Self {
            window: window.max(1),
            past: VecDeque::new(),
        }
    }

    /// Records this scan's `scores` of the candidate `pairs` (rows into `local_ids` and
    /// `system_ids`) and replaces each score by its window average. On a stop request
    /// (`parallel::interrupted`, polled every 4 096 pairs) it ends early, returns `false`, and
    /// the scores are then part averaged: the caller forgets the history ([`Self::new`]).
    pub fn average_in_place(
        &mut self,
        local_ids: &[i64],
        system_ids: &[i64],
        pairs: &Candidates,
        scores: &mut [f64],
    ) -> bool {
        if self.window == 1 {
            return true;
        }
        let raw = scores.to_vec();
        if !self.past.is_empty() && !self.average(local_ids, system_ids, pairs, scores) {
            return false;
        }
        if self.past.len() == self.window - 1 {
            self.past.pop_front();
        }
        self.past.push_back(PastScan {
            local_rows: rows(local_ids),
            system_rows: rows(system_ids),
            pairs: pairs.clone(),
            scores: raw,
        });
        true
    }

    /// Each score replaced by the mean of the remembered scans' scores of its pair (oldest
    /// first) and its own, summed in that order.
    fn average(
        &self,
        local_ids: &[i64],
        system_ids: &[i64],
        pairs: &Candidates,
        scores: &mut [f64],
    ) -> bool {
        // Row of each current track in each remembered scan (u32::MAX: absent there).
        let map = |ids: &[i64], of: fn(&PastScan) -> &FxHashMap<i64, u32>| -> Vec<Vec<u32>> {
            let rows = |p: &PastScan| -> Vec<u32> {
                let rows = of(p);
                ids.iter()
                    .map(|id| *rows.get(id).unwrap_or(&u32::MAX))
                    .collect()
            };
            self.past.iter().map(rows).collect()
        };
        let local_rows = map(local_ids, |p| &p.local_rows);
        let system_rows = map(system_ids, |p| &p.system_rows);
        let mut seen = Vec::with_capacity(self.past.len() + 1);
        for (k, score) in scores.iter_mut().enumerate() {
            if k % 4096 == 0 && crate::parallel::interrupted() {
                return false;
            }
            let (i, j) = pairs.pair(k);
            seen.clear();
            for (p, past) in self.past.iter().enumerate() {
                let (pi, pj) = (local_rows[p][i], system_rows[p][j]);
                if pi != u32::MAX && pj != u32::MAX {
                    seen.extend(past.score(pi, pj));
                }
            }
            seen.push(*score);
            *score = seen.iter().sum::<f64>() / seen.len() as f64;
        }
        true
    }

    /// Scans currently remembered (at most `window − 1`).
    pub fn len(&self) -> usize {
        self.past.len()
    }

    pub fn is_empty(&self) -> bool {
        self.past.is_empty()
    }
}
