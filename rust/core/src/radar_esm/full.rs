//! The coarse gate with each track's full coefficient covariance (METHODS §5 step 2, Σ
//! not diagonal in time).
//!
//! A Kalman-filtered position sequence has errors correlated from scan to scan, so the
//! covariance of its approximation coefficients is `W Σ Wᵀ` with Σ the *whole* window's
//! covariance, not its per-scan diagonal; with the diagonal alone the gate keeps far fewer
//! true pairs than nominal (docs/experiments.md, wavelet). The caller builds each track's
//! `C = (I ⊗ W) Σ (I ⊗ W)ᵀ` over all its coordinates at once (a 2-D passive fix couples x
//! and y), an O(n) task per side; the O(n²) part — per pair `dᵀ (C_i + C_j)⁻¹ d` — runs here,
//! through the same lane kernel and row loop as the per-scan-variance gate.

use super::coarse::{checked_pairs, is_parallel, run_pairs, CoarseGate};
use super::inputs::CoupledTracks;
use super::options::CoarseOptions;
use super::rows::Sides;
use crate::error::{CoreError, CoreResult};

/// The whitened coarse gate `dᵀ (C_i + C_j)⁻¹ d` of every (radar, ESM) pair, row-major.
///
/// Fails if the sides have different widths, if there are more than
/// [`MAX_PAIRS`](super::MAX_PAIRS) pairs, if `options` asks for the unwhitened statistic (it
/// reads per-scan variances: [`coarse_gate`](super::coarse_gate)), or if a pair's
/// `C_i + C_j` is not positive definite — naming the pair.
///
/// ```
/// use passive_assoc_core::radar_esm::{coarse_gate_coupled, CoarseOptions, CoupledTracks, Side};
/// // C_i + C_j = [[2, 1], [1, 1]], whose inverse is [[1, −1], [−1, 2]].
/// let radar = CoupledTracks::new(Side::Radar, &[0.0, 0.0], &[1.0, 0.5, 0.5, 0.5], 2).unwrap();
/// let esm = CoupledTracks::new(Side::Esm, &[1.0, 1.0, 0.0, 1.0], &[1.0, 0.5, 0.5, 0.5, 1.0, 0.5, 0.5, 0.5], 2).unwrap();
/// let gate = coarse_gate_coupled(&radar, &esm, &CoarseOptions::new(1.5).unwrap()).unwrap();
/// assert!((gate.statistic[0] - 1.0).abs() < 1e-12 && (gate.statistic[1] - 2.0).abs() < 1e-12);
/// assert_eq!(gate.passed, vec![true, false]);
/// ```
pub fn coarse_gate_coupled(
    radar: &CoupledTracks<'_>,
    esm: &CoupledTracks<'_>,
    options: &CoarseOptions,
) -> CoreResult<CoarseGate> {
    if !options.whitened() {
        return Err(CoreError::out_of_range(
            "whitened",
            "the unwhitened statistic reads per-scan variances, not a full covariance",
        ));
    }
    if radar.width() != esm.width() {
        return Err(CoreError::shape(
            "esm_coefficients",
            format!(
                "{} coefficients per track, the radar tracks have {}",
                esm.width(),
                radar.width()
            ),
        ));
    }
    let pairs = checked_pairs(radar.len(), esm.len())?;
    let sides = Sides::coupled(radar, esm);
    let gate = run_pairs(
        &sides,
        (radar.len(), esm.len()),
        options.threshold(),
        is_parallel(pairs),
    );
    if crate::parallel::interrupted() {
        return Err(CoreError::Interrupted); // rows were skipped: no gate to report
    }
    gate.map_err(|(i, j, _)| {
        CoreError::ill_posed(
            "covariances",
            format!(
                "radar track {i} and ESM track {j}: C_i + C_j is not positive definite \
                     (singular to working precision)"
            ),
        )
    })
}
