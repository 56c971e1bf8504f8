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
//!    per-system-track rule);
//! 5. `bias` — each radar's rotation (and translation) relative to the system picture, from
//!    the pooled pairs (beyond the paper).
//!
//! `associator::Associator` runs the five for one source; `scan::ScanTracks` is its input.

mod associator;
mod bias;
mod candidates;
mod closeness;
mod decision;
mod history;
mod options;
mod scan;
mod vectors;

#[cfg(test)]
mod tests;

pub use associator::{Associator, ScanPairs, Scoring, MAX_PAIRS, MAX_REMEMBERED_PAIRS};
pub use bias::{BiasAccumulator, BiasEstimate, TRIM_SIGMAS};
pub use candidates::{candidate_pairs, chi2_gated, gated_pairs, Candidates};
pub use closeness::{closeness, pair_closeness};
pub use decision::decide;
pub use history::ScoreHistory;
pub use options::{
    Decision, DecisionOptions, Diffusion, Reference, TopologyOptions, MAX_CELLS, THRESHOLD_FRACTION,
};
pub use scan::ScanTracks;
pub use vectors::topology_vectors;
