//! The streaming associator of one local source against the system picture: every scan,
//! score the candidate (local, system) pairs, average the scores over the window, decide the
//! pairs (on the closeness alone, or fused with the registered distance: `fusion.rs`), and
//! refit the bias to the pairs believed so far (`memory.rs`).

use super::bias::BiasEstimate;
use super::candidates::{auto_gated, chi2_gated, gated_pairs, pair_distances, Candidates};
use super::closeness::pair_closeness;
use super::decision::decide;
use super::fusion::{fused_pairs, reliable, Scan};
use super::history::ScoreHistory;
use super::memory::PairMemory;
use super::options::{Decision, DecisionOptions, Gate, Reference, TopologyOptions};
use super::scan::ScanTracks;
use super::vectors::topology_vectors;
use crate::error::{CoreError, CoreResult};

/// What one pair's score is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scoring {
    /// The closeness W of the two tracks' topology vectors (METHODS §4).
    Topology(TopologyOptions),
    /// Minus the distance between the two positions: the nearest-neighbour baseline.
    Distance,
}

/// The pairs one scan decided, as indices into that scan's local and system tracks.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ScanPairs {
    pub pairs: Vec<(usize, usize)>,
    /// The window-averaged score of each pair.
    pub scores: Vec<f64>,
}

/// Candidate pairs scored at most in one scan, with or without a position or χ² gate: a
/// larger picture needs a position gate that keeps fewer pairs. A pair takes 8 bytes of pair
/// and 8 of score, and about 50 more in the decision when every pair may be made (the
/// nearest-neighbour scoring without a gate): at the cap, 4 000 × 4 000 tracks, that peaked
/// at 1.07 GB. It was 64 million, and only without a gate: a wide gate listed every pair
/// (5 000 × 5 000 tracks took 1.8 GB).
pub const MAX_PAIRS: usize = 16_000_000;

/// [`MAX_PAIRS`] with a window longer than one scan, where every scored pair is remembered
/// for the window's average: each of the last `window − 1` scans keeps its raw scores (8
/// bytes a pair) and, with a gate, its pair list (8 more). The cap was set when each pair
/// took a hashed ring of about 250 bytes (2 000 × 2 000 tracks at a window of 6 then peaked
/// at 1.08 GB); it is kept.
pub const MAX_REMEMBERED_PAIRS: usize = 4_000_000;

/// One local source's association with the system picture, scan after scan.
#[derive(Debug, Clone)]
pub struct Associator {
    scoring: Scoring,
    decision: DecisionOptions,
    history: ScoreHistory,
    memory: PairMemory,
    /// The rigid estimate after the latest scan, its `reliable` flag from the bounds.
    estimate: Option<BiasEstimate>,
}

impl Associator {
    pub fn new(scoring: Scoring, decision: DecisionOptions) -> Self {
        Self {
            scoring,
            decision,
            history: ScoreHistory::new(decision.window()),
            memory: PairMemory::default(),
            estimate: None,
        }
    }

    /// Associates one scan. `local` and `system` are the two sources' tracks at the same time.
    pub fn update(
        &mut self,
        local: &ScanTracks<'_>,
        system: &ScanTracks<'_>,
    ) -> CoreResult<ScanPairs> {
        let cap = if self.decision.window() > 1 {
            MAX_REMEMBERED_PAIRS
        } else {
            MAX_PAIRS
        };
        let chi2 = self.decision.chi2_gate();
        let pairs = match self.decision.gate() {
            Gate::Off => gated_pairs(local, system, (None, chi2), cap)?,
            Gate::Distance(g) => gated_pairs(local, system, (Some(g), chi2), cap)?,
            Gate::Auto => {
                let near = auto_gated(local, system, self.decision.max_offset());
                let pairs = match chi2 {
                    Some(threshold) => chi2_gated(local, system, &near, threshold)?,
                    None => near,
                };
                if pairs.len() > cap {
                    return Err(CoreError::CapExceeded {
                        what: "track pairs in one scan",
                        count: pairs.len(),
                        cap,
                        hint: "give a smaller bias bound or range, or a position gate: too many pairs lie within the automatic gate",
                    });
                }
                pairs
            }
        };
        let mut scores = self.scores(local, system, &pairs)?;
        if crate::parallel::interrupted() {
            return Err(CoreError::Interrupted); // the scores may be partial: decide nothing
        }
        if !(self.history).average_in_place(local.ids(), system.ids(), &pairs, &mut scores) {
            return Err(self.stopped());
        }
        let threshold = match (self.scoring, self.decision.gate()) {
            // Distances without a gate in metres: every allowed pair is worth more than any
            // sum of distances, so the decision makes the most pairs, then the least total
            // distance (the classic gated assignment).
            (Scoring::Distance, Gate::Off | Gate::Auto) => {
                -(1.0 + 2.0 * scores.iter().map(|s| s.abs()).sum::<f64>())
            }
            _ => self.decision.threshold(),
        };
        self.memory.record(local, system);
        let dims = (local.len(), system.len());
        let decided = match (self.scoring, self.decision.decision()) {
            (Scoring::Topology(grid), Decision::Fused) => {
                let topology = match decide(&pairs, &scores, dims, threshold, Decision::Assignment)
                {
                    Err(CoreError::Interrupted) => return Err(self.stopped()),
                    topology => topology?,
                };
                let cells = grid.cells() as f64;
                let closeness: Vec<f64> = scores.iter().map(|s| s / cells).collect();
                let scan = Scan {
                    local,
                    system,
                    pairs: &pairs,
                    closeness: &closeness,
                    topology: &topology,
                    lambda: threshold / cells,
                };
                fused_pairs(&scan, &self.memory, self.estimate.as_ref(), &self.decision)
            }
            (_, decision) => decide(&pairs, &scores, dims, threshold, decision),
        };
        let decided = match decided {
            Err(CoreError::Interrupted) => return Err(self.stopped()),
            decided => decided?,
        };
        self.memory.commit(local, system, &decided);
        self.estimate = self.memory.fit(&self.memory.believed(), None).map(|mut e| {
            e.reliable = reliable(&e, &self.decision);
            e
        });
        let kept = decided
            .iter()
            .map(|&(i, j)| scores[pairs.index_of(i, j)])
            .collect();
        Ok(ScanPairs {
            pairs: decided,
            scores: kept,
        })
    }

    /// A scan stopped once its scores entered the window: a history holding (part of) a
    /// scan that decided nothing would bias every later average, so the window starts afresh
    /// (the bias estimate and the believed pairs, which only decided scans feed, are kept).
    fn stopped(&mut self) -> CoreError {
        self.history = ScoreHistory::new(self.decision.window());
        CoreError::Interrupted
    }

    /// The rigid bias estimate, fitted to every scan of the pairs believed after the latest
    /// scan (`memory.rs`); `reliable` says whether it rests on enough track pairs, with a
    /// small honest spread, within the bias bound.
    pub fn bias(&self) -> Option<BiasEstimate> {
        self.estimate
    }

    /// The rotation-only bias estimate about `centre` (the local radar), from the same pairs.
    pub fn bias_about(&self, centre: [f64; 2]) -> Option<BiasEstimate> {
        self.memory
            .fit(&self.memory.believed(), Some(centre))
            .map(|mut e| {
                e.reliable = reliable(&e, &self.decision);
                e
            })
    }

    fn scores(
        &self,
        local: &ScanTracks<'_>,
        system: &ScanTracks<'_>,
        pairs: &Candidates,
    ) -> CoreResult<Vec<f64>> {
        match &self.scoring {
            Scoring::Topology(options) => {
                if options.reference() == Reference::Heading
                    && !(local.has_velocities() && system.has_velocities())
                {
                    return Err(CoreError::ill_posed(
                        "velocities",
                        "the heading-referenced grid needs both sides' velocities",
                    ));
                }
                let a = topology_vectors(local, options);
                let b = topology_vectors(system, options);
                Ok(pair_closeness(&a, &b, options.cells(), pairs))
            }
            Scoring::Distance => Ok(pair_distances(local, system, pairs)
                .into_iter()
                .map(|d| -d)
                .collect()),
        }
    }
}
