//! What an initiation returns ([`Initiation`]): the tracks, the label of every row, and the
//! candidates left and seconds spent after each stage.

use super::formation_choice::Formation;

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

/// Where the candidate formation stopped at its limit (`stop_at_limit`): what was reached, and
/// how far through its scan slots the formation had got.
#[derive(Clone, Debug, PartialEq)]
pub struct FormationLimit {
    /// The limit reached, as the error it would otherwise have been.
    pub reached: String,
    /// The formation's scan slots formed in full before it stopped, and all its slots (those
    /// of every pass it could have run; the rounds formation may end before its last).
    pub slots_formed: usize,
    pub slots: usize,
}

/// The result of [`initiate`](super::initiate).
#[derive(Clone, Debug, PartialEq)]
pub struct Initiation {
    pub dim: usize,
    /// The formation that ran: `Auto` resolved to `Paper` or `Rounds`.
    pub formation: Formation,
    /// What ended the formation early (`stop_at_limit`); `None` when it ran to its end. The
    /// tracks are those the candidates formed until then found.
    pub limit: Option<FormationLimit>,
    /// Tracks in the order detection accepted their optima (see `detection_order`).
    pub tracks: Vec<Track>,
    /// Per measurement row: its track index, or −1 for clutter.
    pub labels: Vec<i64>,
    pub stage_counts: StageCounts,
    /// Iterations of each descent, in candidate order.
    pub descent_iterations: Vec<usize>,
    pub stage_seconds: StageSeconds,
}
