//! Fuzzy track initiation (METHODS §1, paper 000) for ≥ 2 passive sensors, any number of
//! scans, asynchronous sampling and missed detections, in 3-D (azimuth/elevation, 6-D X0) and
//! 2-D (bearing only, 4-D X0) from the same code.
//!
//! The pipeline ([`initiate`]), one private module per stage, from the bottom up; the public
//! API is what this module re-exports:
//!
//! 1. `scans` ([`Scans`]): a scan is the rows of one sensor with one exact time value; each
//!    sensor's first and last scan in the table feed the candidates (and, in a second pass on
//!    the rows the first pass's detection left, the next-outermost scans: `candidate_scans`).
//! 2. `candidates` ([`generate_candidates`]): for each sensor pair (a, b), one measurement
//!    from each of a-first, b-first, a-last, b-last (eq. 20–22). The product is never
//!    materialised: first-scan ray pairs and last-scan ray pairs are formed and pruned
//!    separately, then combined (`combine`, with the motion-corrected ray gate of
//!    `motion_gate`) and fitted by Gauss-Newton in parallel batches (`batch`). One candidate,
//!    its ray pairs and its fit are `candidate` ([`Candidate`]); the fitted candidates wait in
//!    a `pool` ([`Pool`]). Every pruning rule is optional; with all off every 4-tuple is
//!    fitted, which is the paper's unpruned algorithm.
//! 3. `closeness` ([`closeness`]): the fuzzy synthetic closeness R(X0) (eq. 17–18) and its
//!    gradient.
//! 4. `support`: candidates fewer than Nd scans support are dropped (project extension): the
//!    fixed gate there, then the walk of `tracking_gate`.
//! 5. `descent` ([`descend`]): steepest ascent of R from each surviving candidate (eq. 19);
//!    `merge` merges the optima, and `stages` searches in stages when there are many.
//! 6. `detection` and `detection_order`: detection (eq. 23) and ambiguity resolution
//!    (eq. 24).
//! 7. `pipeline` ([`initiate`]): the driver; the end of the pipeline is the Gauss-Newton
//!    refit of each track (`refit`), the join of split tracks (`track_join`) and the track
//!    test (`track_quality`, with the coverage test of `coverage`; its levels come from
//!    `quantiles`).
//!
//! The settings are `options` ([`InitiationOptions`]) and `descent_options`
//! ([`DescentOptions`]); the tests of the whole initiation and their simulator are `tests`.
//!
//! Parallel stages (fits, descents, final fits) run on rayon and collect in input order; the
//! sequential stages are order-defined, so results are bit-identical for any thread count.

mod batch;
mod candidate;
mod candidates;
mod closeness;
mod combine;
mod coverage;
mod descent;
mod descent_options;
mod detection;
mod detection_order;
mod merge;
mod motion_gate;
mod options;
mod pipeline;
mod pool;
mod quantiles;
mod refit;
mod scans;
mod stages;
mod support;
mod track_join;
mod track_quality;
mod tracking_gate;

#[cfg(test)]
mod tests;

pub use candidate::Candidate;
pub use candidates::generate as generate_candidates;
pub use closeness::{closeness, closeness_and_gradient, closeness_batch, Precomputed, Spreads};
pub use descent::{descend, descend_from};
pub use options::{
    DescentOptions, DetectionOrder, InitiationOptions, Scaling, CHI2_2DOF_999, TRACK_TEST,
};
pub use pipeline::{initiate, initiate_reporting};
pub use pool::{CandidateSet, Pool};
pub use quantiles::{chi2_quantile, normal_quantile};
pub use scans::{resolve_pairs, Scans};

use crate::data::{Measurements, Sensors};
use crate::geometry::model::{Observation, StateLayout};
use crate::progress::Progress;

/// The data of one initiation call: the validated views, the constant-velocity layout and
/// its epoch t0.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a> {
    pub sensors: Sensors<'a>,
    pub measurements: Measurements<'a>,
    pub layout: StateLayout,
    pub t0: f64,
    /// Where the stages report how far they are ([`crate::progress`]).
    pub progress: &'a dyn Progress,
}

impl Problem<'_> {
    /// Whether the call should end now: Ctrl-C, or the progress watcher asked.
    pub fn stopped(&self) -> bool {
        crate::parallel::interrupted() || self.progress.cancelled()
    }

    /// Row `m` as the model sees it.
    #[inline]
    pub fn observation(&self, m: usize) -> Observation {
        self.measurements.observation(&self.sensors, m)
    }
}

/// Candidates (4-tuples) left after each stage, for diagnostics. A 4-tuple survives a
/// ray-pair rule when both its first-scan and its last-scan ray pairs survive it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StageCounts {
    /// Σ over pairs of the product of the four scan sizes.
    pub raw: usize,
    pub ray_gate: usize,
    pub behind: usize,
    pub v_max: usize,
    /// Fits that gave a finite estimate and a positive-definite covariance.
    pub fitted: usize,
    pub chi2_gate: usize,
    /// Candidates that more than Nd scans support (see module `support`; = `chi2_gate` when off).
    pub supported: usize,
    /// Descents run: one per supported candidate, or fewer when a pass searched in stages
    /// (see module `stages`).
    pub optima: usize,
    /// Optima left after merging.
    pub merged: usize,
    /// Targets accepted by detection.
    pub detected: usize,
}

impl StageCounts {
    /// Adds the counts of another pass, stage by stage.
    pub fn accumulate(&mut self, other: &StageCounts) {
        let sums = self.entries().map(|(_, n)| n);
        let more = other.entries().map(|(_, n)| n);
        let [raw, ray_gate, behind, v_max, fitted, chi2_gate, supported, optima, merged, detected] =
            std::array::from_fn(|k| sums[k].saturating_add(more[k]));
        *self = StageCounts {
            raw,
            ray_gate,
            behind,
            v_max,
            fitted,
            chi2_gate,
            supported,
            optima,
            merged,
            detected,
        };
    }

    /// `(name, count)` in pipeline order; the names are the binding's dictionary keys.
    pub fn entries(&self) -> [(&'static str, usize); 10] {
        [
            ("raw", self.raw),
            ("ray_gate", self.ray_gate),
            ("behind", self.behind),
            ("v_max", self.v_max),
            ("fitted", self.fitted),
            ("chi2_gate", self.chi2_gate),
            ("supported", self.supported),
            ("optima", self.optima),
            ("merged", self.merged),
            ("detected", self.detected),
        ]
    }
}

/// Wall-clock seconds per stage.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageSeconds {
    pub candidates: f64,
    pub fit: f64,
    /// The support gate (fixed and tracking), run on each chunk of fitted candidates.
    pub support: f64,
    pub descent: f64,
    pub detection: f64,
    pub final_fit: f64,
}

impl StageSeconds {
    /// `(name, seconds)`; the names are the binding's dictionary keys.
    pub fn entries(&self) -> [(&'static str, f64); 6] {
        [
            ("candidates", self.candidates),
            ("fit", self.fit),
            ("support", self.support),
            ("descent", self.descent),
            ("detection", self.detection),
            ("final", self.final_fit),
        ]
    }
}

/// One initiated track.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// X0 at t0, from the Gauss-Newton refit on all the track's measurements.
    pub estimate: Vec<f64>,
    /// Row-major `dim × dim` inverse Fisher information at the estimate.
    pub covariance: Vec<f64>,
    /// R at the final estimate.
    pub closeness: f64,
    pub chi2: f64,
    /// Measurement rows, ascending.
    pub measurements: Vec<usize>,
}

/// The result of [`initiate`].
#[derive(Clone, Debug, PartialEq)]
pub struct Initiation {
    pub dim: usize,
    /// Tracks in the order detection accepted their optima (see `detection_order`).
    pub tracks: Vec<Track>,
    /// Per measurement row: its track index, or −1 for clutter.
    pub labels: Vec<i64>,
    pub stage_counts: StageCounts,
    /// Iterations of each descent, in candidate order.
    pub descent_iterations: Vec<usize>,
    pub stage_seconds: StageSeconds,
}
