//! Motion models: constant velocity and constant acceleration, discretised exactly.
//!
//! The state holds, per time derivative, one block of `d` axes (d = 1, 2 or 3): `[x, y, vx,
//! vy]` (CV, 2-D) or `[x, y, z, vx, vy, vz, ax, ay, az]` (CA, 3-D), the library's block order.
//! Every axis moves independently, so the transition and the process noise are a per-axis
//! `order × order` matrix repeated on the axes (`F = F₁ ⊗ I_d`, `Q = Q₁ ⊗ I_d`).
//!
//! Process noise is continuous white noise on the highest derivative — acceleration for CV,
//! jerk for CA — with spectral density `q` (m²/s³ resp. m²/s⁵) on every axis. Integrated
//! exactly over a step of `Δt`:
//!
//! * CV: `Q₁ = q [[Δt³/3, Δt²/2], [Δt²/2, Δt]]`;
//! * CA: `Q₁ = q [[Δt⁵/20, Δt⁴/8, Δt³/6], [Δt⁴/8, Δt³/3, Δt²/2], [Δt³/6, Δt²/2, Δt]]`.
//!
//! Being exact, two steps of `Δt₁` and `Δt₂` give the same prediction as one of `Δt₁ + Δt₂`,
//! so time steps may vary from step to step (a test checks it).

use nalgebra::{SMatrix, SVector};

use super::linalg::{mul, mul_t};
use crate::error::{parse_option, UnknownOption};

/// The kinematic model of every track.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionModel {
    /// `"cv"`: position and velocity; white-noise acceleration.
    ConstantVelocity,
    /// `"ca"`: position, velocity and acceleration; white-noise jerk.
    ConstantAcceleration,
}

impl std::str::FromStr for MotionModel {
    type Err = UnknownOption;

    /// `"cv"` or `"ca"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("cv", Self::ConstantVelocity),
            ("ca", Self::ConstantAcceleration),
        ];
        parse_option(value, &choices, "'cv' or 'ca'")
    }
}

impl MotionModel {
    /// Blocks per axis: 2 (position, velocity) or 3 (and acceleration).
    pub fn order(self) -> usize {
        match self {
            Self::ConstantVelocity => 2,
            Self::ConstantAcceleration => 3,
        }
    }

    /// State dimension for `dims` position axes.
    pub fn state_dim(self, dims: usize) -> usize {
        self.order() * dims
    }

    /// The per-axis transition `F₁(Δt)` in the top-left `order × order` corner.
    pub fn transition(self, dt: f64) -> [[f64; 3]; 3] {
        match self {
            Self::ConstantVelocity => [[1.0, dt, 0.0], [0.0, 1.0, 0.0], [0.0; 3]],
            Self::ConstantAcceleration => {
                [[1.0, dt, 0.5 * dt * dt], [0.0, 1.0, dt], [0.0, 0.0, 1.0]]
            }
        }
    }

    /// The per-axis process noise `Q₁(Δt)` for spectral density `q`, in the top-left
    /// `order × order` corner.
    pub fn process_noise(self, dt: f64, q: f64) -> [[f64; 3]; 3] {
        let (t2, t3) = (dt * dt, dt * dt * dt);
        match self {
            Self::ConstantVelocity => [
                [q * t3 / 3.0, q * t2 / 2.0, 0.0],
                [q * t2 / 2.0, q * dt, 0.0],
                [0.0; 3],
            ],
            Self::ConstantAcceleration => {
                let (t4, t5) = (t3 * dt, t3 * t2);
                [
                    [q * t5 / 20.0, q * t4 / 8.0, q * t3 / 6.0],
                    [q * t4 / 8.0, q * t3 / 3.0, q * t2 / 2.0],
                    [q * t3 / 6.0, q * t2 / 2.0, q * dt],
                ]
            }
        }
    }
}

/// `F₁ ⊗ I_D` (or `Q₁ ⊗ I_D`) as a full `N × N` matrix, `N = order · D`. Both sizes are
/// compile-time constants, so the loops unroll into straight stores.
fn kron_identity<const D: usize, const N: usize>(block: &[[f64; 3]; 3]) -> SMatrix<f64, N, N> {
    let order = N / D;
    let mut out = SMatrix::<f64, N, N>::zeros();
    for (j, row) in block.iter().enumerate().take(order) {
        for (l, &value) in row.iter().enumerate().take(order) {
            for a in 0..D {
                out[(j * D + a, l * D + a)] = value;
            }
        }
    }
    out
}

/// Predicts the state `x` and covariance `p` (block order, `D` axes, `N = order · D`) over
/// `dt ≥ 0` with spectral density `q`. A zero step leaves both unchanged.
pub(crate) fn predict<const D: usize, const N: usize>(
    motion: MotionModel,
    dt: f64,
    q: f64,
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
) {
    if dt == 0.0 {
        return;
    }
    let f = kron_identity::<D, N>(&motion.transition(dt));
    let noise = kron_identity::<D, N>(&motion.process_noise(dt, q));
    *x = f * *x;
    *p = mul_t(&mul(&f, p), &f) + noise;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &SMatrix<f64, 6, 6>, b: &SMatrix<f64, 6, 6>, tol: f64) -> bool {
        (a - b).amax() <= tol * a.amax().max(1.0)
    }

    #[test]
    fn option_strings() {
        assert_eq!("cv".parse(), Ok(MotionModel::ConstantVelocity));
        assert_eq!("ca".parse(), Ok(MotionModel::ConstantAcceleration));
        let err = "singer".parse::<MotionModel>().unwrap_err();
        assert_eq!(err.to_string(), "must be 'cv' or 'ca', got \"singer\"");
    }

    /// Exact discretisation: two steps equal one step of the summed length, for the state
    /// and the covariance, whatever the split.
    #[test]
    fn two_steps_equal_one() {
        for motion in [
            MotionModel::ConstantVelocity,
            MotionModel::ConstantAcceleration,
        ] {
            let x0 = SVector::<f64, 6>::from_fn(|i, _| (i as f64 + 1.0) * 3.5);
            let p0 =
                SMatrix::<f64, 6, 6>::from_fn(|i, j| if i == j { 10.0 + i as f64 } else { 0.5 });
            // Six state components: three axes (CV) or two (CA).
            let step = |dt: f64, x: &mut SVector<f64, 6>, p: &mut SMatrix<f64, 6, 6>| match motion {
                MotionModel::ConstantVelocity => predict::<3, 6>(motion, dt, 2.5, x, p),
                MotionModel::ConstantAcceleration => predict::<2, 6>(motion, dt, 2.5, x, p),
            };
            let (mut x1, mut p1) = (x0, p0);
            step(0.7, &mut x1, &mut p1);
            step(2.3, &mut x1, &mut p1);
            let (mut x2, mut p2) = (x0, p0);
            step(3.0, &mut x2, &mut p2);
            assert!((x1 - x2).amax() < 1e-12 * x2.amax(), "{motion:?}");
            assert!(close(&p1, &p2, 1e-12), "{motion:?}: {p1} vs {p2}");
        }
    }

    /// `Q₁` against a numerical integral of `Φ(s) G Gᵀ Φ(s)ᵀ q` over the step.
    #[test]
    fn process_noise_is_the_integral() {
        for motion in [
            MotionModel::ConstantVelocity,
            MotionModel::ConstantAcceleration,
        ] {
            let (dt, q, k) = (1.7, 0.9, motion.order());
            let steps = 20_000;
            let mut integral = [[0.0; 3]; 3];
            for s in 0..steps {
                let tau = (s as f64 + 0.5) * dt / steps as f64;
                let phi = motion.transition(tau);
                for i in 0..k {
                    for j in 0..k {
                        integral[i][j] += phi[i][k - 1] * phi[j][k - 1] * q * dt / steps as f64;
                    }
                }
            }
            let exact = motion.process_noise(dt, q);
            for i in 0..k {
                for j in 0..k {
                    assert!(
                        (integral[i][j] - exact[i][j]).abs() < 1e-6 * exact[i][j].abs().max(1.0)
                    );
                }
            }
        }
    }

    #[test]
    fn state_blocks_are_per_axis() {
        let mut x = SVector::<f64, 4>::new(1.0, 2.0, 10.0, -5.0);
        let mut p = SMatrix::<f64, 4, 4>::identity();
        predict::<2, 4>(MotionModel::ConstantVelocity, 2.0, 0.0, &mut x, &mut p);
        assert_eq!(x, SVector::<f64, 4>::new(21.0, -8.0, 10.0, -5.0));
        assert_eq!(p[(0, 2)], 2.0);
        assert_eq!(p[(0, 3)], 0.0);
        assert_eq!(p[(0, 0)], 5.0);
    }
}
