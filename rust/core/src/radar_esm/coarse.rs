//! The coarse gate (METHODS §5 step 2): for every (radar, ESM) pair, the statistic of the
//! difference of their wavelet approximation coefficients and whether it passes the χ² gate.
//!
//! Whitened (default): per coordinate, `C = W diag(variances) Wᵀ` once per track, then per
//! pair `dᵀ (C_i + C_j)⁻¹ d` by a c × c Cholesky solve, summed over coordinates; on a true
//! pair with Gaussian noise it is χ² with ndim · c degrees of freedom. Unwhitened (ablation):
//! `|d|² / (σ_i² + σ_j²)` per coordinate, σ² the track's mean per-scan variance.
//!
//! Radar rows run in parallel (small problems on the calling thread); each pair is computed
//! by the same sequential code whatever the thread count, so the results are identical for
//! any count. `rows` holds the pair loop, `cholesky` its linear algebra.

use rayon::prelude::*;

use super::inputs::{CoarseTracks, Operator};
use super::options::CoarseOptions;
use super::rows::Sides;
use crate::error::{CoreError, CoreResult};

/// The largest number of pairs (n_radar × n_esm) one call may ask for: the statistic alone
/// takes 8 bytes a pair.
pub const MAX_PAIRS: usize = 64_000_000;

/// Pairs per parallel task at least: below this, rayon's scheduling costs more than the work.
const PAIRS_PER_TASK: usize = 2048;

/// Fewer pairs than this run on the calling thread: a per-scan gate of a few dozen tracks
/// takes microseconds, less than handing work to the pool and waking its threads.
const PARALLEL_PAIRS: usize = 4 * PAIRS_PER_TASK;

/// The coarse gate of every pair, row-major `(radar, esm)`.
#[derive(Debug, Clone, PartialEq)]
pub struct CoarseGate {
    /// The statistic of pair (i, j) at `i · esm + j`.
    pub statistic: Vec<f64>,
    /// `statistic ≤ threshold`.
    pub passed: Vec<bool>,
    pub radar: usize,
    pub esm: usize,
}

/// The coarse gate of every (radar, ESM) pair.
///
/// Fails if the two sides have different coordinate counts or were built for another
/// operator, if there are more than [`MAX_PAIRS`] pairs, or if a pair's `C_i + C_j` (or
/// `σ_i² + σ_j²`) is not positive — naming the pair and the coordinate.
///
/// ```
/// use passive_assoc_core::radar_esm::{coarse_gate, CoarseOptions, CoarseTracks, Operator, Side};
/// // W = I (2 × 2): the coefficients are the positions; variances ½ on both sides, so
/// // C_i + C_j = I and the statistic is |d|².
/// let w = [1.0, 0.0, 0.0, 1.0];
/// let op = Operator::new(&w, 2, 2).unwrap();
/// let radar = CoarseTracks::new(Side::Radar, &[0.0, 0.0], &[0.5; 2], 1, &op).unwrap();
/// let esm = CoarseTracks::new(Side::Esm, &[1.0, 1.0, 3.0, 0.0], &[0.5; 4], 1, &op).unwrap();
/// let gate = coarse_gate(&op, &radar, &esm, &CoarseOptions::new(2.0).unwrap()).unwrap();
/// assert_eq!(gate.statistic, vec![2.0, 9.0]);
/// assert_eq!(gate.passed, vec![true, false]);
/// ```
pub fn coarse_gate(
    operator: &Operator<'_>,
    radar: &CoarseTracks<'_>,
    esm: &CoarseTracks<'_>,
    options: &CoarseOptions,
) -> CoreResult<CoarseGate> {
    if radar.ndim() != esm.ndim() {
        return Err(CoreError::shape(
            "esm_coefficients",
            format!(
                "{} coordinates per track, the radar tracks have {}",
                esm.ndim(),
                radar.ndim()
            ),
        ));
    }
    if !(radar.fits(operator) && esm.fits(operator)) {
        return Err(CoreError::shape(
            "operator",
            "the tracks were validated against an operator of another shape",
        ));
    }
    let (n_radar, n_esm) = (radar.len(), esm.len());
    let pairs = checked_pairs(n_radar, n_esm)?;
    let parallel = is_parallel(pairs);
    let sides = Sides::new(operator, (radar, esm), options.whitened(), parallel);
    let gate = run_pairs(&sides, (n_radar, n_esm), options.threshold(), parallel);
    if crate::parallel::interrupted() {
        return Err(CoreError::Interrupted); // rows were skipped: no gate to report
    }
    gate.map_err(|(i, j, k)| not_positive(i, j, k, options.whitened()))
}

/// `n_radar × n_esm`, or the cap's error.
pub(super) fn checked_pairs(n_radar: usize, n_esm: usize) -> CoreResult<usize> {
    let pairs = n_radar.saturating_mul(n_esm);
    if pairs > MAX_PAIRS {
        return Err(CoreError::CapExceeded {
            what: "radar × ESM track pairs",
            count: pairs,
            cap: MAX_PAIRS,
            hint: "gate the tracks in blocks of radar tracks",
        });
    }
    Ok(pairs)
}

/// Whether `pairs` pairs are worth the thread pool.
pub(super) fn is_parallel(pairs: usize) -> bool {
    pairs >= PARALLEL_PAIRS
}

/// Whether a gate of `n_radar × n_esm` pairs runs on the calling thread alone (so a caller
/// can skip handing it to a thread pool).
pub fn runs_sequentially(n_radar: usize, n_esm: usize) -> bool {
    !is_parallel(n_radar.saturating_mul(n_esm))
}

/// The statistic and pass flags of every pair of prepared `sides`; on failure the
/// (radar, ESM, coordinate) of the first pair in row order whose summed covariance is not
/// positive, whichever thread found it. On a stop request the rows not yet begun are
/// skipped: the caller polls it (`parallel::interrupted`) before using the gate.
pub(super) fn run_pairs(
    sides: &Sides<'_>,
    (n_radar, n_esm): (usize, usize),
    threshold: f64,
    parallel: bool,
) -> Result<CoarseGate, (usize, usize, usize)> {
    let mut statistic = vec![0.0; n_radar * n_esm];
    if !statistic.is_empty() {
        let row = sides.row_kernel();
        let failed = |(i, out): (usize, &mut [f64])| -> Option<(usize, usize, usize)> {
            if crate::parallel::interrupted() {
                return None;
            }
            row(sides, i, out).err().map(|(j, k)| (i, j, k))
        };
        let failure = if parallel {
            let rows_per_task = (PAIRS_PER_TASK / n_esm).max(1);
            statistic
                .par_chunks_mut(n_esm)
                .with_min_len(rows_per_task)
                .enumerate()
                .filter_map(failed)
                .min()
        } else {
            statistic.chunks_mut(n_esm).enumerate().find_map(failed)
        };
        if let Some(first) = failure {
            return Err(first);
        }
    }
    let passes = |&s: &f64| s <= threshold;
    let passed = if parallel {
        statistic.par_iter().map(passes).collect()
    } else {
        statistic.iter().map(passes).collect()
    };
    Ok(CoarseGate {
        statistic,
        passed,
        radar: n_radar,
        esm: n_esm,
    })
}

fn not_positive(i: usize, j: usize, k: usize, whitened: bool) -> CoreError {
    let what = if whitened {
        "C_i + C_j = W (Σ_i + Σ_j) Wᵀ is not positive definite"
    } else {
        "σ_i² + σ_j² is not positive"
    };
    CoreError::ill_posed(
        "variances",
        format!(
            "radar track {i} and ESM track {j}, coordinate {k}: {what} \
             (both tracks' variances zero, or too small for the operator)"
        ),
    )
}
