//! The initiation's settings, built with validated `with_*` setters: [`InitiationOptions`]
//! (the steepest-ascent search's own are module `descent_options`), and the hint that names
//! them when the candidates outgrow memory.

use super::descent_options::DescentOptions;
use super::formation_choice::Formation;
use super::quantiles::upper_normal_level;
use crate::error::{ensure_positive, parse_option, CoreError, CoreResult, UnknownOption};

/// 99.9 % quantile of χ²(2): the default candidate gate in 3-D, where a candidate's 4
/// measurements give 8 equations for 6 unknowns.
pub const CHI2_2DOF_999: f64 = 13.815510557964274;

/// The final track test's default tail probability: a true track fails it once in 10⁶.
pub const TRACK_TEST: f64 = 1e-6;

/// What to do when the candidates outgrow memory (max_candidates bounds them only by count).
pub(super) const OOM_HINT: &str =
    "lower max_candidates, set v_max, tighten ray_gate_sigmas or enable reject_behind";

/// How detection orders the optima: see module `detection_order`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DetectionOrder {
    /// Decreasing R over every row, computed once (the paper's eq. 23).
    Closeness,
    /// Decreasing membership of the rows each optimum would take, rescored as rows are taken
    /// (default).
    Membership,
}

impl std::str::FromStr for DetectionOrder {
    type Err = UnknownOption;

    /// `"membership"` or `"closeness"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("membership", Self::Membership),
            ("closeness", Self::Closeness),
        ];
        parse_option(value, &choices, "'membership' or 'closeness'")
    }
}

/// Every parameter of the initiation except the data, built with validated `with_*` setters.
/// The names are `FuzzyTrackInitiator`'s parameters (the descent's are its `descent_*`).
/// `Default` is [`recommended`](Self::recommended), the values below, which are the Python
/// package's defaults; [`paper`](Self::paper) is the published method:
///
/// | field | recommended | why |
/// |---|---|---|
/// | `candidates` | auto | where a third sensor can reject ghosts (≥ 3 sensors), the rounds formation in 3-D and the witnessed in 2-D; with fewer, the witnessed on the pair's own scans; see [`Formation`] |
/// | `prefit_gates` | on | the rounds and witnessed formations test their candidates before fitting them; see [`with_prefit_gates`](Self::with_prefit_gates) |
/// | `sweep` | on | after the rounds, the paper's formation on the rows left as clutter, under a budget; see [`with_sweep`](Self::with_sweep) |
/// | `stop_at_limit` | on | reaching `max_candidates` ends the formation with the tracks it found, and says so; see [`with_stop_at_limit`](Self::with_stop_at_limit) |
/// | `pairs` | every pair a < b | |
/// | `gate_sigmas` | 5 | the paper's g |
/// | `n_detect` | auto | ⌈0.6·N⌉ − 1 for N scans in the table: the paper's Nd = 9 at N = 16; see [`n_detect_for`](Self::n_detect_for) |
/// | `ray_gate_sigmas` | 5 σ | misses a true ray pair with probability < 10⁻⁵ (3-D only) |
/// | `reject_behind` | on | a passive sensor cannot see a target behind it |
/// | `v_max` | 500 m/s | 2.5× the paper's fastest target; loosening it mostly costs fits |
/// | `chi2_gate` | 13.8155 | χ²(2) 99.9 % (3-D only) |
/// | `one_per_scan` | on | a point target yields one report per scan; see module `detection` |
/// | `detection_order` | membership | R favours ghosts between targets; see module `detection_order` |
/// | `merge_tol` | 1 σ | distinct targets are many σ apart; duplicates converge within 0.1 σ |
/// | `descent` | see [`DescentOptions`] | |
/// | `max_candidates` | 500 000 | bounds the work: fitting and gating 465 152 candidates takes ≈ 1.4 s on one thread (the 8-target 2-D scene of `benches/bench_initiation_2d.py` with `candidates="paper"`); with the support gate off every candidate is stored (≈ 0.45 kB each) |
/// | `refine_passes` | 2 | see [`with_refine_passes`](Self::with_refine_passes) |
/// | `untangle` | on | two tracks that took each other's rows at one sensor exchange them; see [`with_untangle`](Self::with_untangle) |
/// | `track_test` | 10⁻⁶ (z = 4.753) | see [`with_track_test`](Self::with_track_test) |
/// | `support_gate` | on | see module `support` |
/// | `candidate_scans` | 4 | see [`with_candidate_scans`](Self::with_candidate_scans) |
/// | `gate_pd` | `None` | misses not priced; see [`with_gate_pd`](Self::with_gate_pd) |
/// | `search_stage` | 8 192 | see [`with_search_stage`](Self::with_search_stage) |
///
/// Every scalar is checked by its setter; the pairs need the data and are checked by
/// [`initiate`](super::initiate).
///
/// ```
/// use passive_assoc_core::fti::{DescentOptions, InitiationOptions};
/// let o = InitiationOptions::default()
///     .with_pairs(Some(vec![[0, 1]]))
///     .with_gate_sigmas(4.0).unwrap()
///     .with_v_max(None).unwrap()
///     .with_descent(DescentOptions::default().with_max_iter(50));
/// assert_eq!((o.gate_sigmas(), o.v_max(), o.descent().max_iter()), (4.0, None, 50));
/// assert_eq!(o.pairs(), Some(&[[0, 1]][..]));
/// assert!(InitiationOptions::default().with_gate_sigmas(0.0).is_err());
/// assert!(InitiationOptions::default().with_n_detect(Some(0)).is_err());
/// assert_eq!(InitiationOptions::default().n_detect_for(16), 9);
/// assert!(InitiationOptions::default().with_gate_pd(Some(1.0)).is_err());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct InitiationOptions {
    candidates: Formation,
    prefit_gates: bool,
    sweep: bool,
    stop_at_limit: bool,
    pairs: Option<Vec<[usize; 2]>>,
    gate_sigmas: f64,
    n_detect: Option<usize>,
    ray_gate_sigmas: Option<f64>,
    reject_behind: bool,
    v_max: Option<f64>,
    chi2_gate: Option<f64>,
    one_per_scan: bool,
    detection_order: DetectionOrder,
    merge_tol: f64,
    descent: DescentOptions,
    max_candidates: usize,
    refine_passes: usize,
    untangle: bool,
    candidate_scans: usize,
    support_gate: bool,
    track_test: Option<f64>,
    gate_pd: Option<f64>,
    search_stage: Option<usize>,
}

impl Default for InitiationOptions {
    /// [`InitiationOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl InitiationOptions {
    /// The project's defaults, the Python package's: the formation chosen by the scene, its
    /// pre-fit gates on, a formation that stops at its limit, every pair, `gate_sigmas = 5`,
    /// `n_detect` automatic, `ray_gate_sigmas = Some(5)`, `reject_behind`,
    /// `v_max = Some(500)`, `chi2_gate = Some(`[`CHI2_2DOF_999`]`)`, `one_per_scan`, the
    /// membership detection order, `merge_tol = 1`, the recommended descent,
    /// `max_candidates = 500_000`, `refine_passes = 2`, untangling on, `candidate_scans = 4`,
    /// the support gate on, `track_test = Some(`[`TRACK_TEST`]`)`, misses not priced,
    /// `search_stage = Some(8192)` (the table of [`InitiationOptions`] says why).
    pub fn recommended() -> Self {
        Self {
            candidates: Formation::Auto,
            prefit_gates: true,
            sweep: true,
            stop_at_limit: true,
            pairs: None,
            gate_sigmas: 5.0,
            n_detect: None,
            ray_gate_sigmas: Some(5.0),
            reject_behind: true,
            v_max: Some(500.0),
            chi2_gate: Some(CHI2_2DOF_999),
            one_per_scan: true,
            detection_order: DetectionOrder::Membership,
            merge_tol: 1.0,
            descent: DescentOptions::default(),
            max_candidates: 500_000,
            refine_passes: 2,
            untangle: true,
            candidate_scans: 4,
            support_gate: true,
            track_test: Some(TRACK_TEST),
            gate_pd: None,
            search_stage: Some(8192),
        }
    }

    /// The published method (METHODS §1, paper 000): the paper's unpruned algorithm and
    /// pipeline. It differs from [`recommended`](Self::recommended) in:
    ///
    /// * `n_detect = Some(9)`, the paper's Nd (recommended: from the table's scans, which is 9
    ///   at the paper's 16 scans and grows with them);
    /// * `ray_gate_sigmas`, `v_max` and `chi2_gate` `None` and `reject_behind` off: the paper
    ///   fits every 4-tuple (12⁴ ≈ 21 000 a pair in its run); the rules are the
    ///   restatement's pruning, conservative but not the paper's;
    /// * `one_per_scan` off and the closeness detection order: eq. 23 as printed;
    /// * the diagonal descent scaling ([`DescentOptions::paper`]): per-component standard
    ///   deviations, the scaling METHODS names;
    /// * `candidates = Paper`, `refine_passes = 0`, untangling off, `candidate_scans = 1`, the
    ///   support gate off, `track_test` `None`, `search_stage` `None`: the project extensions, each off, so
    ///   candidates come from the first and last scans only and every candidate is descended
    ///   before detection.
    ///
    /// Where the paper is silent (`merge_tol`, `max_candidates` and what reaching it does,
    /// `gate_pd`, the descent's iteration cap and tolerances) the values are the recommended
    /// ones.
    pub fn paper() -> Self {
        Self {
            n_detect: Some(9),
            ray_gate_sigmas: None,
            reject_behind: false,
            v_max: None,
            chi2_gate: None,
            one_per_scan: false,
            detection_order: DetectionOrder::Closeness,
            descent: DescentOptions::paper(),
            refine_passes: 0,
            untangle: false,
            candidate_scans: 1,
            candidates: Formation::Paper,
            support_gate: false,
            track_test: None,
            search_stage: None,
            ..Self::recommended()
        }
    }

    /// Where the candidates come from ([`Formation`]).
    pub fn with_candidates(mut self, candidates: Formation) -> Self {
        self.candidates = candidates;
        self
    }

    pub fn candidates(&self) -> Formation {
        self.candidates
    }

    /// Test the rounds and witnessed formations' candidates against their pair's other rounds
    /// and the other sensors' scans before fitting them (modules `round_gate`,
    /// `witness_gate`; on by default). Without the tests every candidate that passes `v_max`
    /// is fitted. The witness test reads the support gate's tables, so it runs only with the
    /// support gate on; the witnessed formation without it is the paper's, and says so.
    pub fn with_prefit_gates(mut self, prefit_gates: bool) -> Self {
        self.prefit_gates = prefit_gates;
        self
    }

    pub fn prefit_gates(&self) -> bool {
        self.prefit_gates
    }

    /// After the rounds formation, run the paper's formation on the rows its tracks leave as
    /// clutter, with a twentieth of `max_candidates` as its budget (on by default; the
    /// pipeline's `sweep`). It finds the targets a miss left without a slot of rounds.
    /// Reaching its budget ends it with what it found, not reported as a limit.
    pub fn with_sweep(mut self, sweep: bool) -> Self {
        self.sweep = sweep;
        self
    }

    pub fn sweep(&self) -> bool {
        self.sweep
    }

    /// At the end of the pipeline, exchange one sensor's rows between two competing tracks
    /// when both then fit better (on by default; module `track_swap`): where two targets fly
    /// close, each track can hold the other's rows at one sensor.
    pub fn with_untangle(mut self, untangle: bool) -> Self {
        self.untangle = untangle;
        self
    }

    pub fn untangle(&self) -> bool {
        self.untangle
    }

    /// What reaching `max_candidates` (or the test cap it sets) does: `true` ends the
    /// formation there and goes on with the candidates fitted so far, the result saying so
    /// ([`crate::fti::Initiation::limit`]); `false` fails with [`CoreError::CapExceeded`].
    /// The sweep after the rounds ([`Self::with_sweep`]) has a budget of its own, a twentieth
    /// of `max_candidates`, which ends it silently either way.
    pub fn with_stop_at_limit(mut self, stop_at_limit: bool) -> Self {
        self.stop_at_limit = stop_at_limit;
        self
    }

    pub fn stop_at_limit(&self) -> bool {
        self.stop_at_limit
    }

    /// Sensor pairs that form candidates; `None` = every pair a < b. Checked against the data
    /// (sensor indices, a ≠ b, no repeats, first and last scans) when the initiation runs.
    pub fn with_pairs(mut self, pairs: Option<Vec<[usize; 2]>>) -> Self {
        self.pairs = pairs;
        self
    }

    /// Relation gate g of eq. 23, in σ (paper 5; finite, `> 0`).
    pub fn with_gate_sigmas(mut self, gate_sigmas: f64) -> CoreResult<Self> {
        ensure_positive("gate_sigmas", Some(gate_sigmas))?;
        self.gate_sigmas = gate_sigmas;
        Ok(self)
    }

    /// A detected target needs more than `n_detect` related measurements (paper Nd = 9; at
    /// least 1); `None` derives it from the data ([`n_detect_for`](Self::n_detect_for)).
    pub fn with_n_detect(mut self, n_detect: Option<usize>) -> CoreResult<Self> {
        if n_detect == Some(0) {
            return Err(CoreError::out_of_range("n_detect", "must be at least 1"));
        }
        self.n_detect = n_detect;
        Ok(self)
    }

    /// Ray gate in σ units (3-D only; finite, `> 0`; `None` = off). See
    /// module `candidates`.
    pub fn with_ray_gate_sigmas(mut self, ray_gate_sigmas: Option<f64>) -> CoreResult<Self> {
        ensure_positive("ray_gate_sigmas", ray_gate_sigmas)?;
        self.ray_gate_sigmas = ray_gate_sigmas;
        Ok(self)
    }

    /// Reject ray pairs that meet behind either sensor (on by default).
    pub fn with_reject_behind(mut self, reject_behind: bool) -> Self {
        self.reject_behind = reject_behind;
        self
    }

    /// Largest plausible target speed, m/s (finite, `> 0`; `None` = off). See
    /// module `candidates`.
    pub fn with_v_max(mut self, v_max: Option<f64>) -> CoreResult<Self> {
        ensure_positive("v_max", v_max)?;
        self.v_max = v_max;
        Ok(self)
    }

    /// Candidate χ² gate after the 4-measurement fit (3-D only; finite, `> 0`; `None` = off).
    pub fn with_chi2_gate(mut self, chi2_gate: Option<f64>) -> CoreResult<Self> {
        ensure_positive("chi2_gate", chi2_gate)?;
        self.chi2_gate = chi2_gate;
        Ok(self)
    }

    /// A target takes at most one measurement per (sensor, scan) (on by default). See
    /// module `detection`.
    pub fn with_one_per_scan(mut self, one_per_scan: bool) -> Self {
        self.one_per_scan = one_per_scan;
        self
    }

    /// The order in which detection visits the optima: [`DetectionOrder::Membership`]
    /// (default) or the paper's [`DetectionOrder::Closeness`]. See
    /// module `detection_order`.
    pub fn with_detection_order(mut self, detection_order: DetectionOrder) -> Self {
        self.detection_order = detection_order;
        self
    }

    /// Optima closer than this scaled distance are one optimum (finite, `>= 0`). See
    /// module `descent`.
    pub fn with_merge_tol(mut self, merge_tol: f64) -> CoreResult<Self> {
        if !(merge_tol.is_finite() && merge_tol >= 0.0) {
            return Err(CoreError::out_of_range(
                "merge_tol",
                format!("{merge_tol} must be finite and >= 0"),
            ));
        }
        self.merge_tol = merge_tol;
        Ok(self)
    }

    /// Settings of the steepest-ascent search (already validated by its own setters).
    pub fn with_descent(mut self, descent: DescentOptions) -> Self {
        self.descent = descent;
        self
    }

    /// Cap on candidates reaching the fitting stage (and on ray pairs per scan pair; at least
    /// 1): past it the formation stops, or the call fails with [`CoreError::CapExceeded`]
    /// ([`Self::with_stop_at_limit`]), instead of exhausting memory.
    pub fn with_max_candidates(mut self, max_candidates: usize) -> CoreResult<Self> {
        if max_candidates < 1 {
            return Err(CoreError::out_of_range(
                "max_candidates",
                "must be at least 1",
            ));
        }
        self.max_candidates = max_candidates;
        Ok(self)
    }

    /// Extra classify-and-refit passes after the final fit (project extension, not in the
    /// paper): measurements are re-related (eq. 23–24) to the ML estimates, which are more
    /// accurate than the closeness optima the first classification used, and the targets
    /// refitted; stops early when the partition no longer changes. 0 = the paper's pipeline.
    pub fn with_refine_passes(mut self, refine_passes: usize) -> Self {
        self.refine_passes = refine_passes;
        self
    }

    /// Candidates searched before detection runs (project extension; at least 1): a pass
    /// with more candidates than this searches them in stages, by decreasing tracking-gate
    /// score, and later stages only search candidates the gates still keep on the rows
    /// detection has left (module `stages`). `None`: every candidate is
    /// searched before detection, as in the paper, whatever their number.
    pub fn with_search_stage(mut self, search_stage: Option<usize>) -> CoreResult<Self> {
        if search_stage == Some(0) {
            return Err(CoreError::out_of_range(
                "search_stage",
                "must be at least 1",
            ));
        }
        self.search_stage = search_stage;
        Ok(self)
    }

    /// How deep into each end of the window candidates reach (project extension for missed
    /// detections; at least 1). 1 is the paper: each sensor's first and last scan. With k > 1
    /// a second pass, on the rows the first pass's detection left, also combines each sensor's
    /// i-th scan from the start with its j-th from the end for every other i, j < k (see
    /// [`Scans::scan_slots`](super::Scans::scan_slots)), so a target missed in an outer
    /// scan is still initiated.
    pub fn with_candidate_scans(mut self, candidate_scans: usize) -> CoreResult<Self> {
        if candidate_scans < 1 {
            return Err(CoreError::out_of_range(
                "candidate_scans",
                "must be at least 1",
            ));
        }
        self.candidate_scans = candidate_scans;
        Ok(self)
    }

    /// Descend only from candidates that more than Nd scans support (on by default; off = the
    /// paper, every candidate is descended). See module `support`.
    pub fn with_support_gate(mut self, support_gate: bool) -> Self {
        self.support_gate = support_gate;
        self
    }

    /// Dissolve a final track whose refit χ² exceeds the χ²(dof) quantile at this upper tail
    /// probability (dof = angles − state dimension), its rows becoming clutter (project
    /// extension; in (0, 0.5), `None` = off). The quantile is Wilson–Hilferty's at the
    /// standard-normal level `z = −Φ⁻¹(track_test)` ([`track_test_level`](Self::track_test_level)).
    /// A track of clutter reports threads them at residuals spread over the whole gate
    /// (χ²/dof ≈ 8 for a uniform ±5σ spread); a target's is χ²-distributed. Default
    /// [`TRACK_TEST`] = 10⁻⁶ (z = 4.753).
    pub fn with_track_test(mut self, track_test: Option<f64>) -> CoreResult<Self> {
        if let Some(p) = track_test.filter(|p| !(*p > 0.0 && *p < 0.5)) {
            return Err(CoreError::out_of_range(
                "track_test",
                format!("{p} must be in (0, 0.5)"),
            ));
        }
        self.track_test = track_test;
        Ok(self)
    }

    /// The detection probability the tracking gate assumes when it prices a scan whose gate
    /// holds no row (project extension, opt-in; in (0, 1), `None` = misses are not priced).
    /// Each such scan then adds `ln(1 − pd)` to the candidate's score: a target is missed
    /// there with probability 1 − pd, clutter always "misses". See
    /// module `tracking_gate` and docs/methods.md §1.
    pub fn with_gate_pd(mut self, pd: Option<f64>) -> CoreResult<Self> {
        if let Some(p) = pd.filter(|p| !(*p > 0.0 && *p < 1.0)) {
            return Err(CoreError::out_of_range(
                "gate_pd",
                format!("{p} must be in (0, 1)"),
            ));
        }
        self.gate_pd = pd;
        Ok(self)
    }

    pub fn gate_pd(&self) -> Option<f64> {
        self.gate_pd
    }

    /// The track test's tail probability (`None`: off).
    pub fn track_test(&self) -> Option<f64> {
        self.track_test
    }

    /// The track test's standard-normal level `z = −Φ⁻¹(track_test)` (AS 241: SciPy's
    /// `-ndtri` to the last bit or two; to the bit at the default 10⁻⁶).
    pub fn track_test_level(&self) -> Option<f64> {
        self.track_test.map(upper_normal_level)
    }

    pub fn support_gate(&self) -> bool {
        self.support_gate
    }

    pub fn candidate_scans(&self) -> usize {
        self.candidate_scans
    }

    pub fn search_stage(&self) -> Option<usize> {
        self.search_stage
    }

    pub fn pairs(&self) -> Option<&[[usize; 2]]> {
        self.pairs.as_deref()
    }

    pub fn gate_sigmas(&self) -> f64 {
        self.gate_sigmas
    }

    /// Nd for a table of `n_scans` scans (over all sensors): the explicit value, or
    /// `⌈0.6·n_scans⌉ − 1` (at least 1). With one report per target and scan, N scans are the
    /// most a target can be related to; the rule asks for 60 % of them, which is the paper's
    /// Nd = 9 at its N = 16 and grows with the scans and sensors, where a fixed Nd lets
    /// clutter optima through (docs/methods.md §1, "Detection threshold").
    pub fn n_detect_for(&self, n_scans: usize) -> usize {
        self.n_detect
            .unwrap_or_else(|| ((3 * n_scans).div_ceil(5)).saturating_sub(1).max(1))
    }

    pub fn n_detect(&self) -> Option<usize> {
        self.n_detect
    }

    pub fn ray_gate_sigmas(&self) -> Option<f64> {
        self.ray_gate_sigmas
    }

    pub fn reject_behind(&self) -> bool {
        self.reject_behind
    }

    pub fn v_max(&self) -> Option<f64> {
        self.v_max
    }

    pub fn chi2_gate(&self) -> Option<f64> {
        self.chi2_gate
    }

    pub fn one_per_scan(&self) -> bool {
        self.one_per_scan
    }

    pub fn detection_order(&self) -> DetectionOrder {
        self.detection_order
    }

    pub fn merge_tol(&self) -> f64 {
        self.merge_tol
    }

    pub fn descent(&self) -> &DescentOptions {
        &self.descent
    }

    pub fn max_candidates(&self) -> usize {
        self.max_candidates
    }

    pub fn refine_passes(&self) -> usize {
        self.refine_passes
    }
}
