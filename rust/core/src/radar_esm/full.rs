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
use super::inputs::{Side, MAX_COEFFICIENTS};
use super::options::CoarseOptions;
use super::rows::Sides;
use crate::error::{ensure_finite, CoreError, CoreResult};

/// Relative asymmetry `|C_ab − C_ba| / sqrt(C_aa C_bb)` above which a covariance is refused:
/// a layout mistake (a transposed or mis-strided block) rather than rounding.
const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// One sensor's tracks: `m` coefficients per track (all coordinates, coordinate-major) and
/// their `m × m` covariance, row-major: `(n, m)` and `(n, m, m)`.
///
/// ```
/// use passive_assoc_core::radar_esm::{CoupledTracks, Side};
/// let tracks = CoupledTracks::new(Side::Radar, &[1.0, 2.0], &[2.0, 0.5, 0.5, 1.0], 2).unwrap();
/// assert_eq!((tracks.len(), tracks.width()), (1, 2));
/// assert!(CoupledTracks::new(Side::Esm, &[1.0, 2.0], &[2.0, 0.5, 0.4, 1.0], 2).is_err());
/// ```
#[derive(Debug, Clone, Copy)]
pub struct CoupledTracks<'a> {
    pub(super) coefficients: &'a [f64],
    pub(super) covariances: &'a [f64],
    len: usize,
    width: usize,
}

impl<'a> CoupledTracks<'a> {
    /// Validates the lengths against `width` (m ≥ 1, at most [`MAX_COEFFICIENTS`]), finite
    /// values, non-negative diagonals and symmetric covariances.
    pub fn new(
        side: Side,
        coefficients: &'a [f64],
        covariances: &'a [f64],
        width: usize,
    ) -> CoreResult<Self> {
        let (coefficients_arg, covariances_arg) = names(side);
        if width == 0 || width > MAX_COEFFICIENTS {
            return Err(CoreError::shape(
                coefficients_arg,
                format!("{width} coefficients per track; expected 1 to {MAX_COEFFICIENTS}"),
            ));
        }
        if coefficients.len() % width != 0 {
            return Err(CoreError::shape(
                coefficients_arg,
                format!(
                    "{} values are not whole tracks of {width}",
                    coefficients.len()
                ),
            ));
        }
        let len = coefficients.len() / width;
        if covariances.len() != len * width * width {
            return Err(CoreError::shape(
                covariances_arg,
                format!(
                    "{} values, expected n × m × m = {len} × {width} × {width}",
                    covariances.len()
                ),
            ));
        }
        ensure_finite(coefficients_arg, coefficients)?;
        ensure_finite(covariances_arg, covariances)?;
        for (track, c) in covariances.chunks_exact(width * width).enumerate() {
            check_covariance(covariances_arg, track, c, width)?;
        }
        Ok(Self {
            coefficients,
            covariances,
            len,
            width,
        })
    }

    /// n, the tracks.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// m, the coefficients per track.
    pub fn width(&self) -> usize {
        self.width
    }
}

fn names(side: Side) -> (&'static str, &'static str) {
    match side {
        Side::Radar => ("radar_coefficients", "radar_covariances"),
        Side::Esm => ("esm_coefficients", "esm_covariances"),
    }
}

fn check_covariance(name: &'static str, track: usize, c: &[f64], m: usize) -> CoreResult<()> {
    for a in 0..m {
        let caa = c[a * m + a];
        if caa < 0.0 {
            return Err(CoreError::out_of_range(
                name,
                format!("track {track}: diagonal entry {a} is {caa}, negative"),
            ));
        }
        for b in 0..a {
            let (x, y) = (c[a * m + b], c[b * m + a]);
            let scale = (caa * c[b * m + b]).sqrt();
            if (x - y).abs() > SYMMETRY_TOLERANCE * scale.max(f64::MIN_POSITIVE) {
                return Err(CoreError::ill_posed(
                    name,
                    format!(
                        "track {track}: not symmetric, entry ({a}, {b}) is {x}, ({b}, {a}) is {y}"
                    ),
                ));
            }
        }
    }
    Ok(())
}

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
    if radar.width != esm.width {
        return Err(CoreError::shape(
            "esm_coefficients",
            format!(
                "{} coefficients per track, the radar tracks have {}",
                esm.width, radar.width
            ),
        ));
    }
    let pairs = checked_pairs(radar.len, esm.len)?;
    let sides = Sides::coupled(radar, esm);
    run_pairs(
        &sides,
        (radar.len, esm.len),
        options.threshold(),
        is_parallel(pairs),
    )
    .map_err(|(i, j, _)| {
        CoreError::ill_posed(
            "covariances",
            format!(
                "radar track {i} and ESM track {j}: C_i + C_j is not positive definite \
                     (singular to working precision)"
            ),
        )
    })
}
