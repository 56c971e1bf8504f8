//! The streaming associator of one local source against the system picture: every scan,
//! score the candidate (local, system) pairs, average the scores over the window, decide the
//! pairs, and pool the pairs' positions for the bias estimate.

use super::bias::{BiasAccumulator, BiasEstimate};
use super::candidates::{gated_pairs, pair_distances, Candidates};
use super::closeness::pair_closeness;
use super::decision::decide;
use super::history::ScoreHistory;
use super::options::{DecisionOptions, Reference, TopologyOptions};
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
    bias: BiasAccumulator,
}

impl Associator {
    pub fn new(scoring: Scoring, decision: DecisionOptions) -> Self {
        Self {
            scoring,
            decision,
            history: ScoreHistory::new(decision.window()),
            bias: BiasAccumulator::default(),
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
        let gates = (self.decision.gate(), self.decision.chi2_gate());
        let pairs = gated_pairs(local, system, gates, cap)?;
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
            (Scoring::Distance, None) => -(1.0 + 2.0 * scores.iter().map(|s| s.abs()).sum::<f64>()),
            _ => self.decision.threshold(),
        };
        let decided = match decide(
            &pairs,
            &scores,
            (local.len(), system.len()),
            threshold,
            self.decision.decision(),
        ) {
            Err(CoreError::Interrupted) => return Err(self.stopped()),
            decided => decided?,
        };
        for &(i, j) in &decided {
            self.bias.add(local.position(i), system.position(j));
        }
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
    /// (the bias estimate, which only decided pairs feed, is kept).
    fn stopped(&mut self) -> CoreError {
        self.history = ScoreHistory::new(self.decision.window());
        CoreError::Interrupted
    }

    /// The rigid bias estimate from every pair decided so far.
    pub fn bias(&self) -> Option<BiasEstimate> {
        self.bias.rigid()
    }

    /// The rotation-only bias estimate about `centre` (the local radar).
    pub fn bias_about(&self, centre: [f64; 2]) -> Option<BiasEstimate> {
        self.bias.about(centre)
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
