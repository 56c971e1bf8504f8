//! The streaming associator of one local source against the system picture: every scan,
//! score the candidate (local, system) pairs, average the scores over the window, decide the
//! pairs (on the closeness alone, or fused with the registered distance: `fusion.rs`), and
//! refit the bias to the pairs believed so far (`memory.rs`).

use super::bias::BiasEstimate;
use super::candidates::{auto_gated, candidate_pairs, chi2_gated, pair_distances, Candidates};
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

/// Candidate pairs scored at most in one scan: 8 bytes of pair and 8 of score each, so this
/// bounds a scan's working memory near 1 GB; beyond it a position gate is needed. With a
/// window longer than one scan the same number bounds the pairs remembered.
pub const MAX_PAIRS: usize = 64_000_000;

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
        let all = local.len().saturating_mul(system.len());
        let cap = if self.decision.window() > 1 {
            MAX_PAIRS / 8
        } else {
            MAX_PAIRS
        };
        if self.decision.gate() == Gate::Off && all > cap {
            return Err(CoreError::CapExceeded {
                what: "track pairs in one scan",
                count: all,
                cap,
                hint:
                    "give a position gate (only pairs within it are scored) for pictures this large",
            });
        }
        let mut pairs = match self.decision.gate() {
            Gate::Off => candidate_pairs(local, system, None),
            Gate::Distance(g) => candidate_pairs(local, system, Some(g)),
            Gate::Auto => auto_gated(local, system, self.decision.max_offset()),
        };
        if let Some(threshold) = self.decision.chi2_gate() {
            pairs = chi2_gated(local, system, &pairs, threshold)?;
        }
        let mut scores = self.scores(local, system, &pairs)?;
        self.history
            .average_in_place(local.ids(), system.ids(), &pairs, &mut scores);
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
                let topology = decide(&pairs, &scores, dims, threshold, Decision::Assignment)?;
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
                fused_pairs(&scan, &self.memory, self.estimate.as_ref(), &self.decision)?
            }
            (_, decision) => decide(&pairs, &scores, dims, threshold, decision)?,
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
