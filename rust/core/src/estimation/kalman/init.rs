//! Starting a track: the first state and its covariance.
//!
//! * `differencing` (default): the polynomial through the first `order` measurement
//!   positions (2 for CV: two-point differencing; 3 for CA: position, velocity and
//!   acceleration from three points), differentiated at the last of them. Times may be
//!   unequal but must differ. The covariance is exact for the linear-Gaussian model: the
//!   measurement noise propagated through the interpolation weights plus the process noise
//!   accumulated between the points (the interpolant misses the random part of the motion;
//!   for CV that adds `q Δt / 3` to the velocity variance). Being exact, the filter's
//!   covariance is honest from its first output on, with no prior to guess; the price is that
//!   the first `order − 1` rows of a track get no state.
//! * `single_point`: the first measurement's position, zero velocity (and acceleration) with
//!   the caller's standard deviations. A state from the first row on, but only as honest as
//!   those prior standard deviations are large enough for the targets.
//!
//! Polar measurements enter the initialisation converted to Cartesian positions
//! (see [`measurement`](super::measurement)).

use nalgebra::{SMatrix, SVector};

use super::measurement::Point;
use super::motion::MotionModel;
use crate::error::{parse_option, UnknownOption};

/// How a track's first state is obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Init {
    /// `"differencing"`: from the first 2 (CV) or 3 (CA) measurements, exactly.
    Differencing,
    /// `"single_point"`: from the first measurement and a zero-mean velocity (acceleration)
    /// prior.
    SinglePoint,
}

impl std::str::FromStr for Init {
    type Err = UnknownOption;

    /// `"differencing"` or `"single_point"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("differencing", Self::Differencing),
            ("single_point", Self::SinglePoint),
        ];
        parse_option(value, &choices, "'differencing' or 'single_point'")
    }
}

impl Init {
    /// Measurements consumed before the first state.
    pub fn points(self, motion: MotionModel) -> usize {
        match self {
            Self::Differencing => motion.order(),
            Self::SinglePoint => 1,
        }
    }
}

/// 3-point Gauss-Legendre nodes and weights on [−1, 1]: exact to degree 5, and the process
/// noise integrands below have degree ≤ 4.
const GAUSS: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// `w[j][i]`: the j-th derivative at the last time `τ = 0` of the Lagrange basis polynomial of
/// point `i`, times shifted to `τ_i = t_i − t_last` (`k ≤ 3` points with distinct times).
fn lagrange_derivatives(tau: &[f64]) -> [[f64; 3]; 3] {
    let k = tau.len();
    let mut w = [[0.0; 3]; 3];
    for i in 0..k {
        // Coefficients of Π_{m≠i} (τ − τ_m) / (τ_i − τ_m) in powers of τ.
        let mut coef = [1.0, 0.0, 0.0];
        for m in (0..k).filter(|&m| m != i) {
            let den = tau[i] - tau[m];
            let mut next = [0.0; 3];
            for c in 0..k {
                let shifted = if c > 0 { coef[c - 1] } else { 0.0 };
                next[c] = (shifted - tau[m] * coef[c]) / den;
            }
            coef = next;
        }
        let mut factorial = 1.0;
        for (j, row) in w.iter_mut().enumerate().take(k) {
            if j > 0 {
                factorial *= j as f64;
            }
            row[i] = factorial * coef[j];
        }
    }
    w
}

/// `g_j(σ)`: how white noise on the k-th derivative at time `σ` (shifted like `tau`) enters
/// the error of the j-th estimated derivative — the interpolation weights applied to the
/// noise's effect on each point, minus its effect on the true j-th derivative at `τ = 0`.
fn noise_gain(w: &[[f64; 3]; 3], tau: &[f64], j: usize, sigma: f64) -> f64 {
    let k = tau.len();
    // (τ − σ)₊^m / m!
    let ramp = |t: f64, m: usize| -> f64 {
        let d = (t - sigma).max(0.0);
        match m {
            0 => 1.0,
            1 => d,
            _ => 0.5 * d * d,
        }
    };
    let interpolated: f64 = (0..k).map(|i| w[j][i] * ramp(tau[i], k - 1)).sum();
    interpolated - ramp(0.0, k - 1 - j)
}

/// The differencing start from `points` (Cartesian, `k = order` of them) at distinct times
/// `times`, for spectral density `q`: state and covariance at the last time.
pub(crate) fn differencing<const D: usize, const N: usize>(
    motion: MotionModel,
    q: f64,
    times: &[f64],
    points: &[Point<D>],
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    let k = motion.order();
    let last = times[k - 1];
    let mut tau = [0.0; 3];
    for (t, &time) in tau.iter_mut().zip(times) {
        *t = time - last;
    }
    let tau = &tau[..k];
    let w = lagrange_derivatives(tau);
    let mut x = SVector::<f64, N>::zeros();
    let mut p = SMatrix::<f64, N, N>::zeros();
    for j in 0..k {
        for (i, point) in points.iter().enumerate().take(k) {
            for a in 0..D {
                x[j * D + a] += w[j][i] * point.z[a];
            }
        }
    }
    // Measurement noise through the weights: P[(j,a),(l,b)] = Σ_i w_ji w_li R_i[a][b].
    for j in 0..k {
        for l in 0..k {
            for (i, point) in points.iter().enumerate().take(k) {
                let weight = w[j][i] * w[l][i];
                for a in 0..D {
                    for b in 0..D {
                        p[(j * D + a, l * D + b)] += weight * point.r[(a, b)];
                    }
                }
            }
        }
    }
    // Process noise between the points: q ∫ g_j g_l over [τ_0, 0], interval by interval.
    let mut integral = [[0.0; 3]; 3];
    for span in tau.windows(2) {
        let (mid, half) = (0.5 * (span[0] + span[1]), 0.5 * (span[1] - span[0]));
        for &(node, weight) in &GAUSS {
            let sigma = mid + half * node;
            let g = [0, 1, 2].map(|j| {
                if j < k {
                    noise_gain(&w, tau, j, sigma)
                } else {
                    0.0
                }
            });
            for j in 0..k {
                for l in 0..k {
                    integral[j][l] += half * weight * g[j] * g[l];
                }
            }
        }
    }
    for j in 0..k {
        for l in 0..k {
            for a in 0..D {
                p[(j * D + a, l * D + a)] += q * integral[j][l];
            }
        }
    }
    (x, (p + p.transpose()) * 0.5)
}

/// The single-point start: `point`'s position, zero velocity and acceleration with standard
/// deviations `velocity_std`, `acceleration_std` on every axis.
pub(crate) fn single_point<const D: usize, const N: usize>(
    point: &Point<D>,
    velocity_std: f64,
    acceleration_std: f64,
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    let mut x = SVector::<f64, N>::zeros();
    let mut p = SMatrix::<f64, N, N>::zeros();
    for a in 0..D {
        x[a] = point.z[a];
        for b in 0..D {
            p[(a, b)] = point.r[(a, b)];
        }
    }
    let stds = [velocity_std, acceleration_std];
    for k in D..N {
        let std = stds[k / D - 1];
        p[(k, k)] = std * std;
    }
    (x, p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lagrange_weights_differentiate_polynomials() {
        // p(t) = 2 + 3t − 0.5t² at unequal times; derivatives at the last time t = 4.
        let times = [0.5, 1.75, 4.0];
        let tau: Vec<f64> = times.iter().map(|t| t - 4.0).collect();
        let w = lagrange_derivatives(&tau);
        let values: Vec<f64> = times.iter().map(|t| 2.0 + 3.0 * t - 0.5 * t * t).collect();
        let d: Vec<f64> = (0..3)
            .map(|j| (0..3).map(|i| w[j][i] * values[i]).sum())
            .collect();
        assert!((d[0] - (2.0 + 12.0 - 8.0)).abs() < 1e-12);
        assert!((d[1] - (3.0 - 4.0)).abs() < 1e-12);
        assert!((d[2] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn two_point_covariance_is_the_textbook_one_plus_process_noise() {
        let r = SMatrix::<f64, 1, 1>::new(4.0);
        let points = [
            Point {
                z: SVector::<f64, 1>::new(10.0),
                r,
            },
            Point {
                z: SVector::<f64, 1>::new(30.0),
                r,
            },
        ];
        let (x, p) = differencing::<1, 2>(MotionModel::ConstantVelocity, 3.0, &[1.0, 3.0], &points);
        assert_eq!((x[0], x[1]), (30.0, 10.0));
        // [[R, R/T], [R/T, 2R/T²]] + [[0, 0], [0, qT/3]], T = 2.
        assert!((p[(0, 0)] - 4.0).abs() < 1e-12);
        assert!((p[(0, 1)] - 2.0).abs() < 1e-12 && p[(0, 1)] == p[(1, 0)]);
        assert!((p[(1, 1)] - (2.0 + 2.0)).abs() < 1e-12);
    }
}
