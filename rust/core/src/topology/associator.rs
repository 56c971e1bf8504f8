//! The streaming associator of one local source against the system picture: every scan,
//! score every (local, system) pair, average the scores over the window, decide the pairs,
//! and pool the pairs' positions for the bias estimate.

use super::bias::{BiasAccumulator, BiasEstimate};
use super::closeness::closeness_matrix;
use super::decision::decide;
use super::history::ScoreHistory;
use super::options::{DecisionOptions, TopologyOptions};
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

/// Pairs remembered at most, per source, with a window longer than one scan: the history is
/// a few words per pair, so this bounds it near 1 GB; beyond it a position gate (which
/// forgets distant pairs) or `window = 1` is needed.
pub const MAX_HISTORY_PAIRS: usize = 4_000_000;

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
        let mut scores = self.scores(local, system)?;
        self.apply_gate(local, system, &mut scores);
        if self.decision.window() > 1 {
            let live = scores.iter().filter(|s| !s.is_nan()).count();
            if live > MAX_HISTORY_PAIRS {
                return Err(CoreError::CapExceeded {
                    what: "pairs in the window's history",
                    count: live,
                    cap: MAX_HISTORY_PAIRS,
                    hint: "give a position gate or window = 1 for pictures this large",
                });
            }
        }
        self.history
            .average_in_place(local.ids(), system.ids(), &mut scores);
        let n_system = system.len();
        let pairs = decide(
            &scores,
            local.len(),
            n_system,
            self.decision.threshold(),
            self.decision.decision(),
        )?;
        for &(i, j) in &pairs {
            self.bias.add(local.position(i), system.position(j));
        }
        let scores = pairs
            .iter()
            .map(|&(i, j)| scores[i * n_system + j])
            .collect();
        Ok(ScanPairs { pairs, scores })
    }

    /// The rigid bias estimate from every pair decided so far.
    pub fn bias(&self) -> Option<BiasEstimate> {
        self.bias.rigid()
    }

    /// The rotation-only bias estimate about `centre` (the local radar).
    pub fn bias_about(&self, centre: [f64; 2]) -> Option<BiasEstimate> {
        self.bias.about(centre)
    }

    fn scores(&self, local: &ScanTracks<'_>, system: &ScanTracks<'_>) -> CoreResult<Vec<f64>> {
        match &self.scoring {
            Scoring::Topology(options) => {
                if options.reference() == super::options::Reference::Heading
                    && !(local.has_velocities() && system.has_velocities())
                {
                    return Err(CoreError::ill_posed(
                        "velocities",
                        "the heading-referenced grid needs both sides' velocities",
                    ));
                }
                let a = topology_vectors(local, options);
                let b = topology_vectors(system, options);
                Ok(closeness_matrix(&a, &b, options.cells()))
            }
            Scoring::Distance => Ok(distances(local, system).into_iter().map(|d| -d).collect()),
        }
    }

    /// NaN-out the pairs beyond the position gate.
    fn apply_gate(&self, local: &ScanTracks<'_>, system: &ScanTracks<'_>, scores: &mut [f64]) {
        let Some(gate) = self.decision.gate() else {
            return;
        };
        for (score, d) in scores.iter_mut().zip(distances(local, system)) {
            if d > gate {
                *score = f64::NAN;
            }
        }
    }
}

/// Euclidean distances, `(n_local, n_system)` row-major.
fn distances(local: &ScanTracks<'_>, system: &ScanTracks<'_>) -> Vec<f64> {
    let mut out = Vec::with_capacity(local.len() * system.len());
    for i in 0..local.len() {
        let p = local.position(i);
        out.extend((0..system.len()).map(|j| {
            let q = system.position(j);
            (p[0] - q[0]).hypot(p[1] - q[1])
        }));
    }
    out
}
