//! Track-to-track association under azimuth bias by reference topology (METHODS §4,
//! paper 002), and the nearest-neighbour baseline with the same interface.
//!
//! Radars with unknown azimuth biases report local tracks whose absolute positions disagree
//! by kilometres, but the layout of each track's neighbours survives a rotation. Per scan
//! and per local source:
//! 1. `vectors` — each track's reference-topology vector (rings × sectors around it,
//!    occupancy by the same source's other tracks, diffusion);
//! 2. `candidates`, `closeness` — the fuzzy closeness W (eq. 3) of every (local, system)
//!    pair, or of those within the position gate;
//! 3. `history` — W averaged over a sliding window of scans, so a wrong pairing is undone;
//! 4. `decision` — one-to-one pairs maximising the total closeness above λ (or the paper's
//!    per-system-track rule); by default `fusion` — topology, then bias, then distance: the
//!    topology pairs register the pictures, and the pairs are decided on the registered
//!    Mahalanobis distance with the closeness (beyond the paper);
//! 5. `bias` — each radar's rotation (and translation) relative to the system picture, fitted
//!    to every scan of the pairs believed so far (`memory`; beyond the paper), with an honest
//!    standard deviation.
//!
//! `associator::Associator` runs the five for one source; `scan::ScanTracks` is its input.

mod associator;
mod bias;
mod candidates;
mod closeness;
mod decision;
mod fusion;
mod history;
mod memory;
mod options;
mod scan;
mod vectors;

#[cfg(test)]
mod tests;

pub use associator::{Associator, ScanPairs, Scoring, MAX_PAIRS, MAX_REMEMBERED_PAIRS};
pub use bias::{student_3sigma, BiasAccumulator, BiasEstimate, MIN_CLUSTERS, TRIM_SIGMAS};
pub use candidates::{auto_gated, candidate_pairs, chi2_gated, gated_pairs, Candidates};
pub use closeness::{closeness, pair_closeness};
pub use decision::decide;
pub use fusion::{
    fused_pairs, reliable, Transform, MAX_HYPOTHESIS_PAIRS, MAX_ROUNDS, RELIABLE_ROTATION_STD,
    TOP_PROPOSALS,
};
pub use history::ScoreHistory;
pub use memory::{Entry, PairMemory, Picture, HISTORY, MAX_FIT_POINTS, RECENT_SCANS};
pub use options::{
    Decision, DecisionOptions, Diffusion, Gate, Reference, TopologyOptions, MAX_CELLS,
    THRESHOLD_FRACTION,
};
pub use scan::ScanTracks;
pub use vectors::topology_vectors;
