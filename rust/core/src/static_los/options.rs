//! The settings of static association, built with validated `with_*` setters:
//! [`EnumerateOptions`] for [`enumerate`](fn@super::enumerate) and [`IntensityOptions`] for
//! [`intensity_search`](super::intensity_search). The setters check every value on its own;
//! the checks that need the network (the sensor count) run when the options are used.

use crate::error::{CoreError, CoreResult};
use crate::estimation::fit::FitOptions;

/// The default per-angle gate of eq. 3 in standard deviations: the two-sided 99 % point
/// 2.576σ, whose square is the χ²(1 dof) 99 % quantile γ = 6.6349 exactly.
pub const DEFAULT_GATE_SIGMAS: f64 = 2.5758293035489004;

/// The largest gate accepted, in standard deviations: beyond it every ray passes and the
/// gate's square overflows nothing but means nothing.
pub const MAX_GATE_SIGMAS: f64 = 1e6;

/// Default lowest intensity kept: two lines of sight are the fewest that fix a point.
pub const DEFAULT_MIN_INTENSITY: usize = 2;

/// Default cap on the number of candidates (≈ 120 MB of output at S = 3 in 2-D, 170 MB in 3-D).
pub const DEFAULT_MAX_CANDIDATES: usize = 1_000_000;

/// Settings of [`enumerate`](fn@super::enumerate), built with validated `with_*` setters.
/// `min_intensity` is also checked against the number of sensors when the enumeration runs.
///
/// ```
/// use passive_assoc_core::static_los::EnumerateOptions;
/// let o = EnumerateOptions::default().with_gate_sigmas(3.0).unwrap()
///     .with_min_intensity(3).unwrap()
///     .with_max_candidates(10_000).unwrap();
/// assert_eq!((o.gate_sigmas(), o.min_intensity(), o.max_candidates()), (3.0, 3, 10_000));
/// assert!(o.use_window());
/// assert!(EnumerateOptions::default().with_gate_sigmas(f64::NAN).is_err());
/// assert!(EnumerateOptions::default().with_min_intensity(1).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnumerateOptions {
    gate_sigmas: f64,
    min_intensity: usize,
    max_candidates: usize,
    fit: FitOptions,
    use_window: bool,
}

impl Default for EnumerateOptions {
    /// [`EnumerateOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

/// The Gauss-Newton settings of the enumeration: the library defaults, except that a step
/// shorter than 10⁻³ standard deviations of the estimate ends the fit (the default is 10⁻⁶).
/// The point is then within ~10⁻³σ of the ML point and χ² within ~10⁻⁶ of its minimum —
/// immaterial to the gate and the cost — and the typical three-ray fit takes 2–3 iterations
/// instead of 5–8.
pub fn enumeration_fit_options() -> FitOptions {
    let defaults = FitOptions::default();
    defaults.with_step_sigmas(1e-3).unwrap_or(defaults)
}

impl EnumerateOptions {
    /// The project's defaults, those of the Python package (`StaticAssociator`):
    /// `gate_sigmas = `[`DEFAULT_GATE_SIGMAS`] (χ²(1) 99 %), `min_intensity = `[`DEFAULT_MIN_INTENSITY`],
    /// `max_candidates = `[`DEFAULT_MAX_CANDIDATES`], `fit = `[`enumeration_fit_options`]`()`,
    /// the bearing window on.
    pub fn recommended() -> Self {
        Self {
            gate_sigmas: DEFAULT_GATE_SIGMAS,
            min_intensity: DEFAULT_MIN_INTENSITY,
            max_candidates: DEFAULT_MAX_CANDIDATES,
            fit: enumeration_fit_options(),
            use_window: true,
        }
    }

    /// The published enumeration (METHODS §2, paper 001): the same as
    /// [`recommended`](Self::recommended). The gate γ = `gate_sigmas`² is the χ² 99 % point
    /// METHODS names,
    /// intensity-1 tuples are not targets, and the cap, the fit's tolerance and the exact
    /// bearing-window shortcut change no candidate the paper's enumeration would keep.
    pub fn paper() -> Self {
        Self::recommended()
    }

    /// The per-angle gate of eq. 3 in standard deviations: every angle's normalised residual
    /// must be at most this (`> 0`, at most [`MAX_GATE_SIGMAS`]); γ of eq. 3 is its square.
    pub fn with_gate_sigmas(mut self, gate_sigmas: f64) -> CoreResult<Self> {
        if !(gate_sigmas > 0.0 && gate_sigmas <= MAX_GATE_SIGMAS) {
            return Err(CoreError::out_of_range(
                "gate_sigmas",
                format!(
                    "{gate_sigmas} must be > 0 and at most {MAX_GATE_SIGMAS:e} (standard deviations of each angle)"
                ),
            ));
        }
        self.gate_sigmas = gate_sigmas;
        Ok(self)
    }

    /// Keep tuples with at least this many lines of sight: at least 2 here, and at most the
    /// number of sensors, which the enumeration checks.
    pub fn with_min_intensity(mut self, min_intensity: usize) -> CoreResult<Self> {
        if min_intensity < 2 {
            return Err(CoreError::out_of_range(
                "min_intensity",
                format!("{min_intensity} must be at least 2 (two rays fix a point)"),
            ));
        }
        self.min_intensity = min_intensity;
        Ok(self)
    }

    /// Fail with [`CoreError::CapExceeded`] when more candidates than this (at least 1)
    /// survive.
    pub fn with_max_candidates(mut self, max_candidates: usize) -> CoreResult<Self> {
        if max_candidates == 0 {
            return Err(CoreError::out_of_range(
                "max_candidates",
                "must be at least 1",
            ));
        }
        self.max_candidates = max_candidates;
        Ok(self)
    }

    /// The Gauss-Newton settings of every fit (default [`enumeration_fit_options`]).
    pub fn with_fit(mut self, fit: FitOptions) -> Self {
        self.fit = fit;
        self
    }

    /// Use the exact bearing-window shortcut (on by default; off only to test that it is
    /// exact).
    pub fn with_use_window(mut self, use_window: bool) -> Self {
        self.use_window = use_window;
        self
    }

    pub fn gate_sigmas(&self) -> f64 {
        self.gate_sigmas
    }

    /// γ of eq. 3: the gate on each angle's normalised squared residual, `gate_sigmas`².
    pub fn chi2_per_angle(&self) -> f64 {
        self.gate_sigmas * self.gate_sigmas
    }

    pub fn min_intensity(&self) -> usize {
        self.min_intensity
    }

    pub fn max_candidates(&self) -> usize {
        self.max_candidates
    }

    pub fn fit(&self) -> &FitOptions {
        &self.fit
    }

    pub fn use_window(&self) -> bool {
        self.use_window
    }

    /// The checks that need the network: at least 2 sensors, and `min_intensity` at most
    /// their number.
    pub(super) fn check_sensor_count(&self, n_sensors: usize) -> CoreResult<()> {
        if n_sensors < 2 {
            return Err(CoreError::out_of_range(
                "sensor_positions",
                format!("static association needs at least 2 sensors, got {n_sensors}"),
            ));
        }
        if self.min_intensity > n_sensors {
            return Err(CoreError::out_of_range(
                "min_intensity",
                format!("{} must be in 2..={n_sensors} (two rays fix a point; there are {n_sensors} sensors)", self.min_intensity),
            ));
        }
        Ok(())
    }
}

/// Settings of [`intensity_search`](super::intensity_search), built with validated `with_*`
/// setters. `lowest_intensity` is also checked against the number of sensors when the search
/// runs.
///
/// ```
/// use passive_assoc_core::static_los::IntensityOptions;
/// let o = IntensityOptions::default().with_vote_fraction(0.4).unwrap()
///     .with_max_chains(Some(64)).unwrap()
///     .with_valid_airspace(false);
/// assert_eq!((o.vote_fraction(), o.max_chains(), o.valid_airspace()), (0.4, Some(64), false));
/// assert!(IntensityOptions::default().with_vote_fraction(1.0).is_err());
/// assert!(IntensityOptions::default().with_max_chains(Some(0)).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntensityOptions {
    vote_fraction: f64,
    valid_airspace: bool,
    lowest_intensity: Option<usize>,
    max_chains: Option<usize>,
}

impl Default for IntensityOptions {
    /// [`IntensityOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl IntensityOptions {
    /// The project's defaults, those of the Python package (`StaticAssociator`):
    /// `vote_fraction = 0.5` (a strict majority), the valid airspace off (it assumes
    /// clustered targets and drops isolated real ones; its measured gain on spread-out targets
    /// is within Monte-Carlo noise, docs/methods.md §2), lowest intensity S − 1 (at least 2),
    /// at most 64 chains per level (where ghosts are dense the paper's vote is quadratic in
    /// the candidates).
    pub fn recommended() -> Self {
        Self {
            vote_fraction: 0.5,
            valid_airspace: false,
            lowest_intensity: None,
            max_chains: Some(64),
        }
    }

    /// The paper's intensity-ordered search (METHODS §2, paper 001): differs from
    /// [`recommended`](Self::recommended) in the valid airspace on (step 1) and one chain
    /// from every point of H (`max_chains = None`, step 3). The paper's τ is "the vast
    /// majority", no number: the recommended strict majority.
    pub fn paper() -> Self {
        Self {
            valid_airspace: true,
            max_chains: None,
            ..Self::recommended()
        }
    }

    /// τ: confirmed when accepted by more than this fraction of the chains; in [0, 1).
    pub fn with_vote_fraction(mut self, vote_fraction: f64) -> CoreResult<Self> {
        if !(vote_fraction.is_finite() && (0.0..1.0).contains(&vote_fraction)) {
            return Err(CoreError::out_of_range(
                "vote_fraction",
                format!("{vote_fraction} must be in [0, 1)"),
            ));
        }
        self.vote_fraction = vote_fraction;
        Ok(self)
    }

    /// Drop ghosts outside the valid airspace (step 1; off by default, on in the paper).
    pub fn with_valid_airspace(mut self, valid_airspace: bool) -> Self {
        self.valid_airspace = valid_airspace;
        self
    }

    /// Lowest intensity searched; `None` = S − 1 (at least 2). At least 2 here, and at most
    /// the number of sensors S, which the search checks.
    pub fn with_lowest_intensity(mut self, lowest_intensity: Option<usize>) -> CoreResult<Self> {
        if let Some(lowest) = lowest_intensity.filter(|&v| v < 2) {
            return Err(CoreError::out_of_range(
                "lowest_intensity",
                format!("{lowest} must be at least 2"),
            ));
        }
        self.lowest_intensity = lowest_intensity;
        Ok(self)
    }

    /// Run at most this many chains per level (at least 1; default 64; `None` = one from
    /// every point of H, the paper's rule). When H is larger, its best points by (cost, index) start the
    /// chains and the vote threshold is τ times `max_chains` (the starts, even when the vote
    /// stops early).
    pub fn with_max_chains(mut self, max_chains: Option<usize>) -> CoreResult<Self> {
        if max_chains == Some(0) {
            return Err(CoreError::out_of_range(
                "max_chains",
                "must be at least 1 (or None for one chain per point of H)",
            ));
        }
        self.max_chains = max_chains;
        Ok(self)
    }

    pub fn vote_fraction(&self) -> f64 {
        self.vote_fraction
    }

    pub fn valid_airspace(&self) -> bool {
        self.valid_airspace
    }

    pub fn lowest_intensity(&self) -> Option<usize> {
        self.lowest_intensity
    }

    pub fn max_chains(&self) -> Option<usize> {
        self.max_chains
    }

    /// The lowest intensity searched for `n_sensors` sensors: the set value or S − 1 (at
    /// least 2); an error when it exceeds `n_sensors`, the check that needs the data.
    pub(super) fn lowest_for(&self, n_sensors: usize) -> CoreResult<usize> {
        let lowest = self
            .lowest_intensity
            .unwrap_or(n_sensors.saturating_sub(1).max(2));
        if lowest < 2 || lowest > n_sensors {
            return Err(CoreError::out_of_range(
                "lowest_intensity",
                format!("{lowest} must be in 2..={n_sensors}"),
            ));
        }
        Ok(lowest)
    }
}
