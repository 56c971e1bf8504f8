//! Maximum-likelihood fitting of a state to angle measurements by Gauss-Newton (METHODS §1
//! "Candidates" and "Final estimate"). One solver ([`gauss_newton`]), one batch driver
//! ([`batch`]) that runs many independent problems in parallel.

pub mod batch;
pub mod gauss_newton;

use crate::error::{CoreError, CoreResult};

/// Why a fit stopped. The numeric codes are what the Python layer sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Termination {
    /// The step became smaller than `xtol` relative to the state, or than `step_sigmas`
    /// standard deviations of the estimate.
    Converged = 0,
    /// `max_iter` iterations without convergence; the estimate is the last iterate. A state
    /// that stands still (its accepted step rounds to nothing, so every later iteration would
    /// repeat the same one) ends here at once, reporting `max_iter` iterations.
    MaxIterations = 1,
    /// No step length along the Gauss-Newton direction lowered χ²: a minimum to rounding.
    Stalled = 2,
    /// The information matrix is not positive definite: the measurements do not determine the
    /// state (e.g. all rays from one sensor). Estimate and covariance are NaN.
    Singular = 3,
    /// The iterate reached a point where the model is undefined (a target on a sensor's
    /// vertical axis) or non-finite.
    NonFinite = 4,
}

/// Gauss-Newton settings, validated by the `with_*` builders.
///
/// ```
/// use passive_assoc_core::estimation::fit::FitOptions;
/// let opts = FitOptions::default().with_max_iter(100).unwrap().with_xtol(1e-12).unwrap();
/// assert_eq!(opts.max_iter(), 100);
/// assert!(FitOptions::default().with_xtol(-1.0).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    max_iter: usize,
    xtol: f64,
    step_sigmas: f64,
    max_halvings: usize,
}

impl Default for FitOptions {
    /// [`FitOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl FitOptions {
    /// The project's defaults, those of the Python package (`fit_ml`): `max_iter = 50`,
    /// `xtol = 1e-10`, `step_sigmas = 1e-6`, `max_halvings = 30`.
    pub fn recommended() -> Self {
        Self {
            max_iter: 50,
            xtol: 1e-10,
            step_sigmas: 1e-6,
            max_halvings: 30,
        }
    }

    /// The Gauss-Newton fit the papers name (METHODS §1–§3: Gauss-Newton with a
    /// step-halving safeguard): the same as [`recommended`](Self::recommended), since no
    /// paper gives an iteration cap or tolerance.
    pub fn paper() -> Self {
        Self::recommended()
    }

    pub fn with_max_iter(mut self, max_iter: usize) -> CoreResult<Self> {
        if max_iter == 0 {
            return Err(CoreError::out_of_range("max_iter", "must be at least 1"));
        }
        self.max_iter = max_iter;
        Ok(self)
    }

    /// Convergence when `‖δ‖ ≤ xtol·(‖x‖ + xtol)`.
    pub fn with_xtol(mut self, xtol: f64) -> CoreResult<Self> {
        if !(xtol.is_finite() && xtol > 0.0) {
            return Err(CoreError::out_of_range(
                "xtol",
                format!("{xtol} must be finite and > 0"),
            ));
        }
        self.xtol = xtol;
        Ok(self)
    }

    /// Convergence when the Gauss-Newton step is shorter than this many standard deviations
    /// of the estimate (`sqrt(δᵀHδ)`, H the information matrix).
    pub fn with_step_sigmas(mut self, step_sigmas: f64) -> CoreResult<Self> {
        if !(step_sigmas.is_finite() && step_sigmas >= 0.0) {
            return Err(CoreError::out_of_range(
                "step_sigmas",
                format!("{step_sigmas} must be finite and >= 0"),
            ));
        }
        self.step_sigmas = step_sigmas;
        Ok(self)
    }

    /// How many times a step that raises χ² is halved before the fit is declared stalled.
    pub fn with_max_halvings(mut self, max_halvings: usize) -> CoreResult<Self> {
        if max_halvings > 200 {
            return Err(CoreError::out_of_range(
                "max_halvings",
                "at most 200 (2^-200 is below any useful step)",
            ));
        }
        self.max_halvings = max_halvings;
        Ok(self)
    }

    pub fn max_iter(&self) -> usize {
        self.max_iter
    }

    pub fn xtol(&self) -> f64 {
        self.xtol
    }

    pub fn step_sigmas(&self) -> f64 {
        self.step_sigmas
    }

    pub fn max_halvings(&self) -> usize {
        self.max_halvings
    }
}

/// The result of one fit. `covariance` is row-major `dim × dim`, the inverse Fisher
/// information (NaN when singular). On convergence it and `chi2` are evaluated at the last
/// iterate, which the final, untested step moved by less than `step_sigmas` standard
/// deviations (or `xtol`): re-evaluating would cost an evaluation for no visible change.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOutcome {
    pub estimate: Vec<f64>,
    pub covariance: Vec<f64>,
    pub chi2: f64,
    pub iterations: usize,
    pub termination: Termination,
}
