//! Measurement models and the update step.
//!
//! * `position`: Cartesian position in the state's `d` axes, `z = H x + w`, linear.
//! * `polar`: 2-D range and azimuth from a sensor at `s` (one position per measurement, so a
//!   sensor may move), `z = (|p − s|, atan2(p_y − s_y, p_x − s_x)) + w` — azimuth counter-
//!   clockwise from +x (METHODS §0) — as an extended Kalman filter: `H` is the Jacobian at the
//!   prediction and the azimuth residual is wrapped to (−π, π] before it is used.
//! * `polar_converted`: the same measurement turned into a Cartesian position first,
//!   `z = s + r (cos θ, sin θ)` with the linearised covariance `J R Jᵀ`, `J = ∂z/∂(r, θ)` at
//!   the measured values — the classic converted-measurement filter, linear after conversion.
//!   The conversion is biased and its covariance optimistic when the cross-range error is
//!   large against the range error (`r σθ² / σr` beyond about 0.4, Bar-Shalom's rule); the
//!   EKF has no such bias, hence it is the default polar model.
//!
//! The update is the standard Kalman update with the covariance in Joseph form,
//! `P = (I − KH) P (I − KH)ᵀ + K R Kᵀ`, which stays symmetric positive semi-definite under
//! rounding where `P − K S Kᵀ` need not (a long EKF run with small `R` is where that shows).

use nalgebra::{SMatrix, SVector};

use super::linalg::{mul, mul_t};
use crate::error::{parse_option, UnknownOption};
use crate::geometry::angles::wrap;

/// What each measurement row holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeasurementModel {
    /// `"position"`: Cartesian position, 1 to 3 columns (the state's axes).
    Position,
    /// `"polar"`: range and azimuth (2 columns, 2-D only), extended Kalman filter.
    Polar,
    /// `"polar_converted"`: range and azimuth converted to a Cartesian position.
    PolarConverted,
}

impl std::str::FromStr for MeasurementModel {
    type Err = UnknownOption;

    /// `"position"`, `"polar"` or `"polar_converted"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("position", Self::Position),
            ("polar", Self::Polar),
            ("polar_converted", Self::PolarConverted),
        ];
        parse_option(value, &choices, "'position', 'polar' or 'polar_converted'")
    }
}

impl MeasurementModel {
    /// Whether rows are (range, azimuth) from a sensor position.
    pub fn is_polar(self) -> bool {
        !matches!(self, Self::Position)
    }
}

/// A measurement as a Cartesian position with its covariance (`d` axes).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Point<const D: usize> {
    pub z: SVector<f64, D>,
    pub r: SMatrix<f64, D, D>,
}

/// `(r, θ)` from `sensor`, with covariance `cov` of `(r, θ)`, as a Cartesian point with the
/// linearised covariance `J cov Jᵀ`.
pub(crate) fn polar_to_point(
    sensor: [f64; 2],
    range: f64,
    azimuth: f64,
    cov: &SMatrix<f64, 2, 2>,
) -> Point<2> {
    let (sin, cos) = azimuth.sin_cos();
    let z = SVector::<f64, 2>::new(sensor[0] + range * cos, sensor[1] + range * sin);
    let j = SMatrix::<f64, 2, 2>::new(cos, -range * sin, sin, range * cos);
    Point {
        z,
        r: j * cov * j.transpose(),
    }
}

/// Updates `x`, `p` with a linear(ised) measurement: innovation `nu`, model `h`, noise `r`.
/// Returns the normalised innovation squared `νᵀ S⁻¹ ν`, or `None` when the innovation
/// covariance is not positive definite (non-finite arithmetic from absurd inputs).
pub(crate) fn update<const D: usize, const N: usize>(
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
    nu: &SVector<f64, D>,
    h: &SMatrix<f64, D, N>,
    r: &SMatrix<f64, D, D>,
) -> Option<f64> {
    let ph = mul_t(p, h);
    let s = mul(h, &ph) + r;
    let chol = s.cholesky()?;
    // K = P Hᵀ S⁻¹ = (S⁻¹ H P)ᵀ, S and P symmetric.
    let gain = chol.solve(&ph.transpose()).transpose();
    let nis = nu.dot(&chol.solve(nu));
    *x += gain * nu;
    let ikh = SMatrix::<f64, N, N>::identity() - mul(&gain, h);
    let joseph = mul_t(&mul(&ikh, p), &ikh) + mul_t(&mul(&gain, r), &gain);
    *p = (joseph + joseph.transpose()) * 0.5;
    Some(nis)
}

/// The position update: `H = [I_d 0 …]`.
pub(crate) fn update_position<const D: usize, const N: usize>(
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
    point: &Point<D>,
) -> Option<f64> {
    let h = SMatrix::<f64, D, N>::from_fn(|i, j| if i == j { 1.0 } else { 0.0 });
    let nu = point.z - h * *x;
    update(x, p, &nu, &h, &point.r)
}

/// The polar EKF update (2-D: the first two state components are x, y). `None` where the
/// prediction sits on the sensor (no bearing) or the update fails.
pub(crate) fn update_polar<const N: usize>(
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
    sensor: [f64; 2],
    measured: [f64; 2],
    cov: &SMatrix<f64, 2, 2>,
) -> Option<f64> {
    let (dx, dy) = (x[0] - sensor[0], x[1] - sensor[1]);
    let range = dx.hypot(dy);
    if !(range > 0.0 && range.is_finite()) {
        return None;
    }
    let r2 = range * range;
    let mut h = SMatrix::<f64, 2, N>::zeros();
    h[(0, 0)] = dx / range;
    h[(0, 1)] = dy / range;
    h[(1, 0)] = -dy / r2;
    h[(1, 1)] = dx / r2;
    let nu = SVector::<f64, 2>::new(measured[0] - range, wrap(measured[1] - dy.atan2(dx)));
    update(x, p, &nu, &h, cov)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn option_strings() {
        assert_eq!("polar".parse(), Ok(MeasurementModel::Polar));
        assert_eq!(
            "polar_converted".parse(),
            Ok(MeasurementModel::PolarConverted)
        );
        assert!("bearing".parse::<MeasurementModel>().is_err());
    }

    /// A scalar update against the textbook formulas.
    #[test]
    fn scalar_update() {
        let mut x = SVector::<f64, 2>::new(1.0, 0.5);
        let mut p = SMatrix::<f64, 2, 2>::new(4.0, 1.0, 1.0, 2.0);
        let point = Point {
            z: SVector::<f64, 1>::new(3.0),
            r: SMatrix::<f64, 1, 1>::new(1.0),
        };
        let nis = update_position(&mut x, &mut p, &point).unwrap();
        // S = 5, K = (0.8, 0.2), ν = 2.
        assert!((nis - 0.8).abs() < 1e-15);
        assert!((x[0] - 2.6).abs() < 1e-15 && (x[1] - 0.9).abs() < 1e-15);
        assert!((p[(0, 0)] - 0.8).abs() < 1e-14 && (p[(1, 1)] - 1.8).abs() < 1e-14);
        assert!((p[(0, 1)] - 0.2).abs() < 1e-14 && p[(0, 1)] == p[(1, 0)]);
    }

    /// The azimuth residual across ±π is small, not 2π.
    #[test]
    fn polar_residual_is_wrapped() {
        let sensor = [0.0, 0.0];
        let mut x = SVector::<f64, 4>::new(-1000.0, -1.0, 0.0, 0.0);
        let mut p = SMatrix::<f64, 4, 4>::identity() * 100.0;
        let cov = SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, 1e-6);
        let measured = [1000.0, std::f64::consts::PI - 0.0005];
        let nis = update_polar(&mut x, &mut p, sensor, measured, &cov).unwrap();
        assert!(nis < 10.0, "{nis}");
        assert!(x[1] > 0.0 && x[1] < 1.0, "{x}");
        assert!(update_polar(
            &mut SVector::<f64, 4>::zeros(),
            &mut p,
            sensor,
            measured,
            &cov
        )
        .is_none());
    }

    #[test]
    fn conversion_of_a_small_error_matches_the_geometry() {
        let cov = SMatrix::<f64, 2, 2>::new(4.0, 0.0, 0.0, 1e-6);
        let point = polar_to_point([10.0, 20.0], 1000.0, std::f64::consts::FRAC_PI_2, &cov);
        assert!((point.z[0] - 10.0).abs() < 1e-9 && (point.z[1] - 1020.0).abs() < 1e-9);
        // Cross-range (x) variance r² σθ² = 1, down-range (y) σr² = 4.
        assert!((point.r[(0, 0)] - 1.0).abs() < 1e-9 && (point.r[(1, 1)] - 4.0).abs() < 1e-9);
    }
}
