//! Fuzzy track initiation (METHODS §1, paper 000) for ≥ 2 passive sensors, any number of
//! scans, asynchronous sampling and missed detections, in 3-D (azimuth/elevation, 6-D X0) and
//! 2-D (bearing only, 4-D X0) from the same code.
//!
//! The pipeline ([`initiate`]), one module per stage:
//!
//! 1. [`scans`]: a scan is the rows of one sensor with one exact time value; each sensor's
//!    first and last scan in the table feed the candidates.
//! 2. [`candidates`]: for each sensor pair (a, b), one measurement from each of a-first,
//!    b-first, a-last, b-last (eq. 20–22). The product is never materialised: first-scan ray
//!    pairs and last-scan ray pairs are formed and pruned separately, then combined in chunks
//!    and fitted by Gauss-Newton. Every pruning rule is optional; with all off every 4-tuple is
//!    fitted, which is the paper's unpruned algorithm.
//! 3. [`closeness`](mod@closeness): the fuzzy synthetic closeness R(X0) (eq. 17–18) and its gradient.
//! 4. [`descent`]: steepest ascent of R from each surviving candidate (eq. 19), merged optima.
//! 5. [`detection`]: detection (eq. 23) and ambiguity resolution (eq. 24).
//! 6. [`pipeline`]: the driver and the final Gauss-Newton refit of each track.
//!
//! Parallel stages (fits, descents, final fits) run on rayon and collect in input order; the
//! sequential stages are order-defined, so results are bit-identical for any thread count.

pub mod candidates;
pub mod closeness;
pub mod descent;
pub mod detection;
pub mod pipeline;
pub mod scans;

#[cfg(test)]
mod reference;
#[cfg(test)]
mod sim;
#[cfg(test)]
mod tests;

pub use closeness::{closeness, closeness_and_gradient, Precomputed, Spreads};
pub use pipeline::initiate;

use crate::data::{Measurements, Sensors};
use crate::error::{parse_option, CoreError, CoreResult, UnknownOption};
use crate::geometry::model::{Observation, StateLayout};

/// The data of one initiation call: the validated views, the constant-velocity layout and
/// its epoch t0.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a> {
    pub sensors: Sensors<'a>,
    pub measurements: Measurements<'a>,
    pub layout: StateLayout,
    pub t0: f64,
}

impl Problem<'_> {
    /// Row `m` as the model sees it.
    #[inline]
    pub fn observation(&self, m: usize) -> Observation {
        self.measurements.observation(&self.sensors, m)
    }
}

/// 99.9 % quantile of χ²(2): the default candidate gate in 3-D, where a candidate's 4
/// measurements give 8 equations for 6 unknowns.
pub const CHI2_2DOF_999: f64 = 13.815510557964274;

/// The linear change of variables each descent works in. See [`descent`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scaling {
    /// `x = x_c + L·y` with `L·Lᵀ` the candidate fit's covariance (default).
    Whitened,
    /// `x_k = x_ck + σ_k·y_k` with σ the candidate fit's standard deviations.
    Diagonal,
}

impl std::str::FromStr for Scaling {
    type Err = UnknownOption;

    /// `"whitened"` or `"diagonal"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [("whitened", Self::Whitened), ("diagonal", Self::Diagonal)];
        parse_option(value, &choices, "'whitened' or 'diagonal'")
    }
}

/// Settings of the steepest-ascent search (eq. 19). See [`descent`] for the method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DescentOptions {
    pub scaling: Scaling,
    /// Iteration cap per descent (0 = keep the candidate fits as the optima).
    pub max_iter: usize,
    /// Stop when an accepted step is shorter than this in scaled units (standard deviations
    /// of the candidate fit): far below the estimation noise; the final Gauss-Newton refit
    /// supplies the precision.
    pub step_tol: f64,
    /// Stop when an accepted step raises R by less than `r_tol·R`.
    pub r_tol: f64,
}

impl Default for DescentOptions {
    fn default() -> Self {
        Self {
            scaling: Scaling::Whitened,
            max_iter: 100,
            step_tol: 1e-2,
            r_tol: 1e-9,
        }
    }
}

/// Every parameter of the initiation except the data. `Default` gives the recommended values:
///
/// | field | default | why |
/// |---|---|---|
/// | `gate` | 5 | the paper's g |
/// | `n_detect` | 9 | the paper's Nd (2 sensors × 8 scans) |
/// | `ray_gate` | 5 σ | misses a true ray pair with probability < 10⁻⁵ (3-D only) |
/// | `reject_behind` | on | a passive sensor cannot see a target behind it |
/// | `v_max` | 500 m/s | 2.5× the paper's fastest target; loosening it mostly costs fits |
/// | `chi2_gate` | 13.8155 | χ²(2) 99.9 % (3-D only) |
/// | `one_per_scan` | on | a point target yields one report per scan; see [`detection`] |
/// | `merge_tol` | 1 σ | distinct targets are many σ apart; duplicates converge within 0.1 σ |
/// | `descent` | see [`DescentOptions`] | |
/// | `max_candidates` | 500 000 | ≈ 0.45 kB per stored candidate, ≈ 3 s of fitting per thread |
#[derive(Clone, Debug, PartialEq)]
pub struct InitiationOptions {
    /// Sensor pairs that form candidates; `None` = every pair a < b.
    pub pairs: Option<Vec<[usize; 2]>>,
    /// Relation gate g of eq. 23, in σ (paper 5).
    pub gate: f64,
    /// A detected target needs more than `n_detect` related measurements (paper Nd = 9).
    pub n_detect: usize,
    /// Ray gate in σ units (3-D only; `None` = off). See [`candidates`].
    pub ray_gate: Option<f64>,
    /// Reject ray pairs that meet behind either sensor.
    pub reject_behind: bool,
    /// Largest plausible target speed, m/s (`None` = off). See [`candidates`].
    pub v_max: Option<f64>,
    /// Candidate χ² gate after the 4-measurement fit (3-D only; `None` = off).
    pub chi2_gate: Option<f64>,
    /// A target takes at most one measurement per (sensor, scan). See [`detection`].
    pub one_per_scan: bool,
    /// Optima closer than this scaled distance are one optimum. See [`descent`].
    pub merge_tol: f64,
    pub descent: DescentOptions,
    /// Cap on candidates reaching the fitting stage (and on ray pairs per scan pair): past it
    /// the call fails with [`CoreError::CapExceeded`] instead of exhausting memory.
    pub max_candidates: usize,
    /// Extra classify-and-refit passes after the final fit (project extension, not in the
    /// paper): measurements are re-related (eq. 23–24) to the ML estimates, which are more
    /// accurate than the closeness optima the first classification used, and the targets
    /// refitted; stops early when the partition no longer changes. 0 = the paper's pipeline.
    pub refine_passes: usize,
}

impl Default for InitiationOptions {
    fn default() -> Self {
        Self {
            pairs: None,
            gate: 5.0,
            n_detect: 9,
            ray_gate: Some(5.0),
            reject_behind: true,
            v_max: Some(500.0),
            chi2_gate: Some(CHI2_2DOF_999),
            one_per_scan: true,
            merge_tol: 1.0,
            descent: DescentOptions::default(),
            max_candidates: 500_000,
            refine_passes: 2,
        }
    }
}

impl InitiationOptions {
    /// Checks every scalar setting; the pairs are checked against the data in [`scans`].
    pub fn validate(&self) -> CoreResult<()> {
        positive("gate", Some(self.gate))?;
        positive("ray_gate", self.ray_gate)?;
        positive("v_max", self.v_max)?;
        positive("chi2_gate", self.chi2_gate)?;
        if self.n_detect < 1 {
            return Err(CoreError::out_of_range("n_detect", "must be at least 1"));
        }
        if !(self.merge_tol.is_finite() && self.merge_tol >= 0.0) {
            return Err(CoreError::out_of_range(
                "merge_tol",
                format!("{} must be finite and >= 0", self.merge_tol),
            ));
        }
        positive("descent step_tol", Some(self.descent.step_tol))?;
        if !(self.descent.r_tol.is_finite() && self.descent.r_tol >= 0.0) {
            return Err(CoreError::out_of_range(
                "descent r_tol",
                "must be finite and >= 0",
            ));
        }
        if self.max_candidates < 1 {
            return Err(CoreError::out_of_range(
                "max_candidates",
                "must be at least 1",
            ));
        }
        Ok(())
    }
}

fn positive(arg: &'static str, value: Option<f64>) -> CoreResult<()> {
    match value {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(CoreError::out_of_range(
            arg,
            format!("{v} must be finite and > 0"),
        )),
        _ => Ok(()),
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
    /// Descents run (one per surviving candidate).
    pub optima: usize,
    /// Optima left after merging.
    pub merged: usize,
    /// Targets accepted by detection.
    pub detected: usize,
}

impl StageCounts {
    /// `(name, count)` in pipeline order; the names are the binding's dictionary keys.
    pub fn entries(&self) -> [(&'static str, usize); 9] {
        [
            ("raw", self.raw),
            ("ray_gate", self.ray_gate),
            ("behind", self.behind),
            ("v_max", self.v_max),
            ("fitted", self.fitted),
            ("chi2_gate", self.chi2_gate),
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
    pub descent: f64,
    pub detection: f64,
    pub final_fit: f64,
}

impl StageSeconds {
    /// `(name, seconds)`; the names are the binding's dictionary keys.
    pub fn entries(&self) -> [(&'static str, f64); 5] {
        [
            ("candidates", self.candidates),
            ("fit", self.fit),
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
    /// Tracks in detection order (decreasing R of their optimum).
    pub tracks: Vec<Track>,
    /// Per measurement row: its track index, or −1 for clutter.
    pub labels: Vec<i64>,
    pub stage_counts: StageCounts,
    /// Iterations of each descent, in candidate order.
    pub descent_iterations: Vec<usize>,
    pub stage_seconds: StageSeconds,
}
