//! Radar/ESM track association of maneuvering targets with wavelets and fuzzy factors
//! (METHODS §5, paper 003).
//!
//! A radar and a passive (ESM) sensor track the same targets; each track is filtered on its
//! own measurements. The method compares the tracks' shapes first and their kinematics second:
//! 1. *coarse gate* (§5 step 2) — every track's filtered position sequence over the window is
//!    reduced to its wavelet approximation coefficients `a = W x` (W the transform's linear
//!    approximation operator, built in Python with PyWavelets); a (radar, ESM) pair passes if
//!    the coefficient difference is inside a χ² gate, whitened by `W (Σ_i + Σ_j) Wᵀ`;
//! 2. the fine stage (fuzzy factors) and the decision.
//!
//! Files:
//! * `options` — [`CoarseOptions`]: the χ² threshold and whitened / scalar statistic;
//! * `inputs` — [`Operator`], [`CoarseTracks`] and [`CoupledTracks`]: validated borrowed
//!   views of W and of one side's coefficients with per-scan variances or with their full
//!   covariance;
//! * `coarse` — [`coarse_gate`]: the statistic and the pass flags of every pair, in parallel
//!   over radar tracks (the hot path);
//! * `decision` — [`repeated_maximum`]: the one-to-one decision of every scan (step 4);
//! * `full` — [`coarse_gate_coupled`]: the same gate when each track brings its
//!   coefficients' full covariance ([`CoupledTracks`]; a filtered track's errors are
//!   correlated in time);
//! * `rows` — the pair loop: both sides prepared once, one radar track's row at a time;
//! * `cholesky` — the hand-rolled small-matrix Cholesky solve the pair loop runs, several
//!   pairs at once.

mod cholesky;
mod coarse;
mod decision;
mod full;
mod inputs;
mod options;
mod rows;

#[cfg(test)]
mod tests;

pub use coarse::{coarse_gate, runs_sequentially, CoarseGate, MAX_PAIRS};
pub use decision::repeated_maximum;
pub use full::coarse_gate_coupled;
pub use inputs::{CoarseTracks, CoupledTracks, Operator, Side, MAX_COEFFICIENTS};
pub use options::CoarseOptions;
