//! The Lagrangian's settings, built with validated `with_*` setters.

use super::order::SensorOrder;
use std::time::Duration;

use crate::error::{parse_option, CoreError, CoreResult, UnknownOption};

/// Options of [`solve`](super::solve), built with validated `with_*` setters.
///
/// ```
/// use passive_assoc_core::assign::lagrangian::LagrangianOptions;
/// let o = LagrangianOptions::default().with_max_iter(50).unwrap().with_gap_tol(1e-2).unwrap();
/// assert_eq!(o.max_iter(), 50);
/// assert!(LagrangianOptions::default().with_gap_tol(-1.0).is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LagrangianOptions {
    max_iter: usize,
    gap_tol: f64,
    step_scale: f64,
    stall_iters: usize,
    warm_start: WarmStart,
    sensor_order: SensorOrder,
    polish: bool,
    time_limit: Option<Duration>,
}

/// Whether each iteration's inner 2-D assignment starts from the previous iteration's duals
/// and pairs (a square, mirrored form; see the private module `sap::warm`). Either way the
/// 2-D solve is exact, so iterations, bounds and answers are those of an exact solve; only the
/// time differs (and, between optima of equal cost, which one is returned).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WarmStart {
    /// Warm for S = 3 problems whose two sensors kept in the 2-D problem (see
    /// [`SensorOrder`]) have at least [`WARM_MIN_SIZE`] reports between them, cold otherwise:
    /// where it measured faster on `reproduce intensity` scans
    /// (`python benches/bench_warm_start.py`; the figures are in docs/performance.md): a
    /// gain on large S = 3 scans, a loss on small ones and none at S = 4. A likely reason,
    /// not measured: with S >= 4 several multiplier
    /// sets move each iteration, so fewer pairs stay tight, and on small problems the square
    /// form's set-up costs more than the searches it saves. (The synthetic criterion group
    /// `sd_lagrangian_warm` shows the small and S = 4 losses too, but no gain on its S = 3
    /// shape.)
    #[default]
    Auto,
    Always,
    Never,
}

impl std::str::FromStr for WarmStart {
    type Err = UnknownOption;

    /// `"auto"`, `"always"` or `"never"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("auto", Self::Auto),
            ("always", Self::Always),
            ("never", Self::Never),
        ];
        parse_option(value, &choices, "'auto', 'always' or 'never'")
    }
}

/// Reports of the two sensors kept in the 2-D problem, together, from which
/// [`WarmStart::Auto`] starts warm.
pub const WARM_MIN_SIZE: usize = 50;

impl Default for LagrangianOptions {
    /// [`LagrangianOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

/// The step parameter floor: below it the multipliers no longer move usefully.
pub(super) const MIN_STEP_SCALE: f64 = 1e-4;

/// The deflection β of the subgradient direction (Camerini, Fratta & Maffioli 1975): each
/// step moves along `g + β·d_prev`, the previous direction damping the zig-zag of plain
/// subgradients. On 1 000 scans of S = 3, M = 20 (`benches/lagrangian_identity.py`),
/// β = 0.5 with 150 iterations gave a lower mean primal than plain steps with 200 and a mean
/// gap within its Monte-Carlo error; 0.3 and 0.7 did worse (docs/performance.md).
pub(super) const DEFLECTION: f64 = 0.5;

impl LagrangianOptions {
    /// The project's defaults, those of the Python package (`assign_sd`,
    /// `StaticAssociator`): `max_iter = 150`, `gap_tol = 1e-3` (0.1 %, tight enough that the
    /// recovered solution is usually the optimum, see the tests), `step_scale = 1`,
    /// `stall_iters = 10`, automatic warm start and sensor order, the end-of-solve polish on
    /// (on random problems it brings the answer markedly nearer the optimum for little time,
    /// docs/performance.md) and no time limit: the iteration cap is the stop, so the answer
    /// does not depend on the machine's load (a wall-clock limit is an option).
    pub fn recommended() -> Self {
        Self {
            max_iter: 150,
            gap_tol: 1e-3,
            step_scale: 1.0,
            stall_iters: 10,
            warm_start: WarmStart::Auto,
            sensor_order: SensorOrder::Auto,
            polish: true,
            time_limit: None,
        }
    }

    /// Baseline A of METHODS §2 as the papers run it (Pattipati et al. 1992, Deb et al.
    /// 1997): differs from [`recommended`](Self::recommended) in relaxing the sensors as
    /// given (sensors 3..S, [`SensorOrder::Given`]) and in no end-of-solve polish (the
    /// project's addition to the recovery). The papers give no iteration cap, gap, step or
    /// time limit: those are the recommended ones.
    pub fn paper() -> Self {
        Self {
            sensor_order: SensorOrder::Given,
            polish: false,
            ..Self::recommended()
        }
    }

    /// Subgradient iterations, at least 1.
    pub fn with_max_iter(mut self, max_iter: usize) -> CoreResult<Self> {
        if max_iter == 0 {
            return Err(CoreError::out_of_range(
                "max_iter",
                "must be at least 1, got 0",
            ));
        }
        self.max_iter = max_iter;
        Ok(self)
    }

    /// Stop when the relative gap `(primal − dual) / max(1, |primal|)` is at most this
    /// (finite, `>= 0`; 0 means "only a proven optimum stops early").
    pub fn with_gap_tol(mut self, gap_tol: f64) -> CoreResult<Self> {
        if !(gap_tol.is_finite() && gap_tol >= 0.0) {
            return Err(CoreError::out_of_range(
                "gap_tol",
                format!("must be finite and >= 0, got {gap_tol}"),
            ));
        }
        self.gap_tol = gap_tol;
        Ok(self)
    }

    /// Initial Polyak step parameter α in `(0, 2]`; it is halved whenever the dual bound has
    /// not improved for `stall_iters` iterations.
    pub fn with_step_scale(mut self, step_scale: f64) -> CoreResult<Self> {
        if !(step_scale > 0.0 && step_scale <= 2.0) {
            return Err(CoreError::out_of_range(
                "step_scale",
                format!("must be in (0, 2], got {step_scale}"),
            ));
        }
        self.step_scale = step_scale;
        Ok(self)
    }

    /// Iterations without dual improvement before the step parameter is halved, at least 1.
    pub fn with_stall_iters(mut self, stall_iters: usize) -> CoreResult<Self> {
        if stall_iters == 0 {
            return Err(CoreError::out_of_range(
                "stall_iters",
                "must be at least 1, got 0",
            ));
        }
        self.stall_iters = stall_iters;
        Ok(self)
    }

    /// Warm-started inner 2-D solves: automatic (the default), always or never.
    pub fn with_warm_start(mut self, warm_start: WarmStart) -> Self {
        self.warm_start = warm_start;
        self
    }

    /// Which sensors the relaxation keeps and which it relaxes: automatic (the default) or
    /// as given.
    pub fn with_sensor_order(mut self, sensor_order: SensorOrder) -> Self {
        self.sensor_order = sensor_order;
        self
    }

    /// Whether the best solution gets the compound-move polish at the end (on by default):
    /// a markedly better primal on large scans for a large share of the solve's time
    /// (`python benches/bench_sensor_order.py`, docs/performance.md).
    pub fn with_polish(mut self, polish: bool) -> Self {
        self.polish = polish;
        self
    }

    pub fn polish(&self) -> bool {
        self.polish
    }

    /// Wall-clock limit of the subgradient loop (default 10 s; `None`: none; zero is refused).
    /// Reaching it
    /// ends the solve with the best feasible solution found, `NotProven(Limit::Time)`.
    pub fn with_time_limit(mut self, time_limit: Option<Duration>) -> CoreResult<Self> {
        if time_limit.is_some_and(|d| d.is_zero()) {
            return Err(CoreError::out_of_range(
                "time_limit",
                "must be > 0 seconds or None",
            ));
        }
        self.time_limit = time_limit;
        Ok(self)
    }

    pub fn time_limit(&self) -> Option<Duration> {
        self.time_limit
    }

    pub fn sensor_order(&self) -> SensorOrder {
        self.sensor_order
    }

    pub fn warm_start(&self) -> WarmStart {
        self.warm_start
    }

    pub fn max_iter(&self) -> usize {
        self.max_iter
    }

    pub fn gap_tol(&self) -> f64 {
        self.gap_tol
    }

    pub fn step_scale(&self) -> f64 {
        self.step_scale
    }

    pub fn stall_iters(&self) -> usize {
        self.stall_iters
    }
}
