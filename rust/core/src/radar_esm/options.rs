//! The coarse gate's settings, built with validated `with_*` setters.

use crate::error::{CoreError, CoreResult};

/// What the coarse gate computes and where it cuts (METHODS §5 step 2).
///
/// ```
/// use passive_assoc_core::radar_esm::CoarseOptions;
/// let o = CoarseOptions::new(16.81).unwrap().with_whitened(false);
/// assert_eq!(o.threshold(), 16.81);
/// assert!(!o.whitened());
/// assert!(CoarseOptions::new(f64::NAN).is_err());
/// assert!(CoarseOptions::new(0.0).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoarseOptions {
    threshold: f64,
    whitened: bool,
}

impl CoarseOptions {
    /// The gate `threshold` (the caller's χ² quantile: the core does not know the gate
    /// probability, nor the degrees of freedom the Python `gate_probability` needs), whitened
    /// statistic: the same as [`recommended`](Self::recommended).
    pub fn new(threshold: f64) -> CoreResult<Self> {
        Self {
            threshold: 1.0,
            whitened: true,
        }
        .with_threshold(threshold)
    }

    /// The project's defaults, those of the Python package (`coarse_gate`,
    /// `WaveletFuzzyAssociator`), at χ² threshold `threshold` (Python computes it from
    /// `gate_probability`, default 0.99): the whitened statistic. There is no `Default`: the
    /// threshold depends on the coefficients' count.
    pub fn recommended(threshold: f64) -> CoreResult<Self> {
        Self::new(threshold)
    }

    /// The coarse gate of METHODS §5 step 2 at χ² threshold `threshold`: the same as
    /// [`recommended`](Self::recommended), whitened, as METHODS requires (the paper's printed
    /// scalar statistic rejects ~24 % of true pairs at a nominal 1 %; it is
    /// [`with_whitened(false)`](Self::with_whitened), an ablation).
    pub fn paper(threshold: f64) -> CoreResult<Self> {
        Self::new(threshold)
    }

    /// A pair passes when its statistic is at most this: finite and > 0.
    pub fn with_threshold(mut self, threshold: f64) -> CoreResult<Self> {
        if !(threshold.is_finite() && threshold > 0.0) {
            return Err(CoreError::out_of_range(
                "threshold",
                format!("{threshold} must be finite and > 0"),
            ));
        }
        self.threshold = threshold;
        Ok(self)
    }

    /// `true` (default): `dᵀ (C_i + C_j)⁻¹ d` with `C = W diag(variances) Wᵀ`, χ²-distributed
    /// on true pairs. `false`: the paper's literal statistic `|d|² / (σ_i² + σ_j²)`, σ² the
    /// track's mean per-scan variance over the window, per coordinate — an ablation: the
    /// boundary coefficients' larger variances make it reject far more true pairs than the
    /// nominal level.
    pub fn with_whitened(mut self, whitened: bool) -> Self {
        self.whitened = whitened;
        self
    }

    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    pub fn whitened(&self) -> bool {
        self.whitened
    }
}
