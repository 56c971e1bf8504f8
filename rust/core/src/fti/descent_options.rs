//! The steepest-ascent search's settings ([`DescentOptions`]) and its coordinates
//! ([`Scaling`]), built with validated `with_*` setters.

use crate::error::{ensure_positive, parse_option, CoreError, CoreResult, UnknownOption};

/// The linear change of variables each descent works in. See module `descent`.
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

/// Settings of the steepest-ascent search (eq. 19), built with validated `with_*` setters.
/// See module `descent` for the method.
///
/// ```
/// use passive_assoc_core::fti::{DescentOptions, Scaling};
/// let o = DescentOptions::default().with_max_iter(20).with_scaling(Scaling::Diagonal)
///     .with_step_tol(1e-3).unwrap();
/// assert_eq!((o.max_iter(), o.scaling(), o.step_tol()), (20, Scaling::Diagonal, 1e-3));
/// assert!(DescentOptions::default().with_step_tol(0.0).is_err());
/// assert!(DescentOptions::default().with_r_tol(-1.0).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DescentOptions {
    scaling: Scaling,
    max_iter: usize,
    step_tol: f64,
    r_tol: f64,
}

impl Default for DescentOptions {
    /// [`DescentOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl DescentOptions {
    /// The project's defaults, those of the Python package (`maximize_closeness`, and
    /// `FuzzyTrackInitiator`'s `descent_*`): whitened scaling, `max_iter = 100`,
    /// `step_tol = 1e-2` (scaled units), `r_tol = 1e-9`.
    pub fn recommended() -> Self {
        Self {
            scaling: Scaling::Whitened,
            max_iter: 100,
            step_tol: 1e-2,
            r_tol: 1e-9,
        }
    }

    /// The published method (METHODS §1 eq. 19): differs from
    /// [`recommended`](Self::recommended) only in the diagonal scaling, the candidate fit's
    /// per-component standard deviations that METHODS names (whitened removes the
    /// position–velocity correlation and converges in fewer steps). The paper gives no
    /// iteration cap or tolerances: those are the recommended ones.
    pub fn paper() -> Self {
        Self {
            scaling: Scaling::Diagonal,
            ..Self::recommended()
        }
    }

    /// The change of variables: whitened (the default) or diagonal.
    pub fn with_scaling(mut self, scaling: Scaling) -> Self {
        self.scaling = scaling;
        self
    }

    /// Iteration cap per descent (0 = keep the candidate fits as the optima).
    pub fn with_max_iter(mut self, max_iter: usize) -> Self {
        self.max_iter = max_iter;
        self
    }

    /// Stop when an accepted step is shorter than this in scaled units (standard deviations
    /// of the candidate fit; finite, `> 0`): far below the estimation noise; the final
    /// Gauss-Newton refit supplies the precision.
    pub fn with_step_tol(mut self, step_tol: f64) -> CoreResult<Self> {
        ensure_positive("descent step_tol", Some(step_tol))?;
        self.step_tol = step_tol;
        Ok(self)
    }

    /// Stop when an accepted step raises R by less than `r_tol·R` (finite, `>= 0`).
    pub fn with_r_tol(mut self, r_tol: f64) -> CoreResult<Self> {
        if !(r_tol.is_finite() && r_tol >= 0.0) {
            return Err(CoreError::out_of_range(
                "descent r_tol",
                "must be finite and >= 0",
            ));
        }
        self.r_tol = r_tol;
        Ok(self)
    }

    pub fn scaling(&self) -> Scaling {
        self.scaling
    }

    pub fn max_iter(&self) -> usize {
        self.max_iter
    }

    pub fn step_tol(&self) -> f64 {
        self.step_tol
    }

    pub fn r_tol(&self) -> f64 {
        self.r_tol
    }
}
