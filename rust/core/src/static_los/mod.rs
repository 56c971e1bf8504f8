//! Static (one-scan) association of angle-only reports by line-of-sight intersections
//! (METHODS §2, paper 001): candidate enumeration with S-D pruning, the tuple cost of eq. 2, and
//! the paper's intensity-ordered search. The assignment baselines (Lagrangian relaxation,
//! branch and bound) live in [`crate::assign`] and consume the same tuples.
//!
//! # Tuples
//! A candidate is a tuple `(i_1, …, i_S)` with `i_s ∈ {0, 1, …, n_s}`: `0` means "sensor s
//! missed it", `i ≥ 1` is the i-th report of sensor s, counting that sensor's rows in table
//! order from 1 (the [`crate::assign::SdProblem`] convention). Its *intensity* is the number of
//! non-zero entries (lines of sight through the point).
//!
//! # The gate (eq. 3) and what exactly is enumerated
//! Tuples are grown sensor by sensor (sensor 0 first). Every *prefix* with at least two lines of
//! sight — the tuple restricted to its first k contributing sensors, k = 2..intensity — gets a
//! point estimate:
//! * two rays: the closed-form intersection (2-D; it is the ML point, both residuals are 0, so
//!   the gate reduces to "in front of both sensors") or, for az/el, the midpoint of the rays'
//!   closest points refined by Gauss-Newton ML;
//! * more rays: Gauss-Newton ML started from the previous prefix's estimate (static layout);
//!
//! and the prefix is pruned, with everything that extends it, unless
//! * the two-ray closed form exists (rays not parallel) and lies in front of both sensors,
//! * Gauss-Newton ends with a finite, non-singular estimate,
//! * every normalised squared residual `(wrap(z − ĥ)/σ)²` — one per angle — is ≤ `gate`, and
//! * the point is in front of every contributing sensor.
//!
//! Every Gauss-Newton fit uses [`enumeration_fit_options`] (stop when a step is shorter than
//! 10⁻³ standard deviations). A tuple is a candidate iff all its prefixes pass and its
//! intensity is ≥ `min_intensity`.
//! This is the definition the brute-force check in the tests applies to all `Π(n_s + 1)`
//! tuples. It depends (for borderline tuples only) on the sensor order, because the per-angle
//! gate is not monotone when a ray is added. The survivor's final estimate is the last
//! prefix's ML point, with the inverse Fisher information as covariance.
//!
//! The default gate is 2.576σ, [`DEFAULT_GATE_SIGMAS`], whose square is the 99 % point of χ²(1 dof), 6.635, applied *per
//! angle* (eq. 3 gates each bearing separately; for az/el both angles are gated): a true tuple
//! then survives with probability ≈ 0.99 per angle (slightly more, because the ML fit absorbs
//! part of the noise).
//!
//! Besides the gate, the enumeration uses one exact shortcut (see `window`): a report of the
//! next sensor is only fitted when its azimuth falls in the bearing window under which that
//! sensor sees the region where the first two rays' gates overlap. The window never excludes a
//! report the gate would accept.
//!
//! # Modules
//! * `enumerate` — the pruned depth-first enumeration, parallel over the first two sensors;
//!   `prepared` — its per-prefix primitives (point estimates, gate, covariance); `window` —
//!   the exact bearing window.
//! * [`cost`] — eq. 2 and its units.
//! * [`intensity`] — the intensity-ordered search: the project's reading of eq. 11–13, rule by
//!   rule; `airspace` (eq. 12–13) and `chains` (probability-intensity chains) implement it.

mod airspace;
mod batch;
mod chain_block;
mod chains;
pub mod cost;
mod enumerate;
pub mod false_alarms;
pub mod intensity;
mod intensity_input;
mod measurement_ids;
mod options;
mod prepared;
mod window;

#[cfg(test)]
mod tests;

pub use batch::{associate_scans, ScanResult, ScanSolver, Scans};
pub use cost::DetectionModel;
pub use enumerate::{enumerate, enumerate_with_attributes, enumerates_sequentially};
pub use intensity::{intensity_search, searches_sequentially, IntensityInput, IntensityOutcome};
pub use options::{
    enumeration_fit_options, EnumerateOptions, IntensityOptions, DEFAULT_GATE_SIGMAS,
    DEFAULT_MAX_CANDIDATES, DEFAULT_MIN_INTENSITY, MAX_GATE_SIGMAS,
};

use crate::assign::CandidateSet;
use crate::error::{CoreError, CoreResult};

/// Partial tuples examined by the enumeration, for diagnostics. `tested[k]` / `pruned[k]`
/// count prefixes with k lines of sight whose point was estimated / that failed the gate
/// (entries 0 and 1 are always 0). Identical for any thread count.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct StageCounts {
    pub tested: Vec<u64>,
    pub pruned: Vec<u64>,
    /// (prefix, report) extensions skipped by the exact bearing window, without a fit.
    pub windowed_out: u64,
    /// (prefix, report) extensions cut by the attribute gate, without a fit.
    pub attribute_pruned: u64,
    /// Candidates returned.
    pub candidates: u64,
}

impl StageCounts {
    pub(crate) fn new(n_sensors: usize) -> Self {
        Self {
            tested: vec![0; n_sensors + 1],
            pruned: vec![0; n_sensors + 1],
            windowed_out: 0,
            attribute_pruned: 0,
            candidates: 0,
        }
    }

    pub(crate) fn add(&mut self, other: &StageCounts) {
        for (a, b) in self.tested.iter_mut().zip(&other.tested) {
            *a += b;
        }
        for (a, b) in self.pruned.iter_mut().zip(&other.pruned) {
            *a += b;
        }
        self.windowed_out += other.windowed_out;
        self.attribute_pruned += other.attribute_pruned;
        self.candidates += other.candidates;
    }

    /// `("tested_2", n), ("pruned_2", n), …, ("windowed_out", n), ("final", n)`.
    pub fn named(&self) -> Vec<(String, u64)> {
        let mut out = Vec::new();
        for k in 2..self.tested.len() {
            out.push((format!("tested_{k}"), self.tested[k]));
            out.push((format!("pruned_{k}"), self.pruned[k]));
        }
        out.push(("windowed_out".to_string(), self.windowed_out));
        out.push(("attribute_pruned".to_string(), self.attribute_pruned));
        out.push(("final".to_string(), self.candidates));
        out
    }
}

/// The candidates of one scan, columnar, `K` rows in lexicographic tuple order.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidates {
    pub n_sensors: usize,
    /// Position dimension (2 or 3).
    pub dim: usize,
    /// `K × S`: 0 = missed, else the 1-based index among that sensor's rows in table order.
    pub tuples: Vec<i64>,
    /// `K × S`: the table row of each entry, −1 = missed.
    pub rows: Vec<i64>,
    /// `K × dim` ML positions.
    pub positions: Vec<f64>,
    /// `K × dim × dim` inverse Fisher information at the ML position.
    pub covariances: Vec<f64>,
    /// Eq. 2 cost of each tuple.
    pub costs: Vec<f64>,
    /// Lines of sight per tuple.
    pub intensity: Vec<i64>,
    /// χ² (sum of normalised squared residuals) at the ML position.
    pub chi2: Vec<f64>,
    /// Reports per sensor.
    pub sizes: Vec<usize>,
    pub stages: StageCounts,
}

impl Candidates {
    pub fn len(&self) -> usize {
        self.costs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.costs.is_empty()
    }

    /// Tuple `k` (caller guarantees `k < len()`).
    pub fn tuple(&self, k: usize) -> &[i64] {
        &self.tuples[k * self.n_sensors..(k + 1) * self.n_sensors]
    }

    /// The tuples and costs as the shared [`CandidateSet`], which the S-D solvers (through
    /// [`crate::assign::SdProblem::from_set`]) and the intensity search read.
    pub fn candidate_set(&self) -> CoreResult<CandidateSet> {
        // Enumerated entries are 0 (missed) or a 1-based report index: never negative.
        let tuples = self
            .tuples
            .iter()
            .map(|&t| usize::try_from(t).map_err(|_| CoreError::out_of_range("tuples", "negative")))
            .collect::<CoreResult<Vec<usize>>>()?;
        CandidateSet::new(
            tuples,
            self.n_sensors,
            self.costs.clone(),
            self.sizes.clone(),
        )
    }

    /// The intensity search's input: the candidate set and the ML positions.
    pub fn intensity_input(&self) -> CoreResult<IntensityInput> {
        IntensityInput::new(self.candidate_set()?, self.positions.clone(), self.dim)
    }
}
