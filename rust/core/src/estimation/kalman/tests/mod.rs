//! Tests of the Kalman filter: noiseless tracks reproduced exactly ([`exact`]), consistency
//! (NEES) over many seeded runs ([`consistency`]), and the batch: thread-count invariance,
//! row order, bad input ([`batch`]). This file holds the simulator they share: tracks with
//! exactly discretised process noise and Gaussian measurement noise, so the linear models'
//! NEES is χ²-distributed exactly.

mod batch;
mod consistency;
mod exact;

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::geometry::angles::wrap;

/// What to simulate.
#[derive(Clone, Copy, Debug)]
pub(super) struct Spec {
    pub motion: MotionModel,
    pub model: MeasurementModel,
    /// Position axes (polar models: 2).
    pub dims: usize,
    pub tracks: usize,
    pub steps: usize,
    /// Spectral density of the true process noise.
    pub q: f64,
    /// Measurement noise std per column (position: every axis the first value; polar: σr, σθ).
    pub std: [f64; 2],
    /// Initial velocity (and acceleration) drawn from N(0, σ²) with these σ when set
    /// (the single-point prior), else uniform in ±150 m/s (±5 m/s²).
    pub prior: Option<(f64, f64)>,
    /// Where the targets start: centre and half-width of the box, per axis.
    pub centre: [f64; 3],
    pub spread: f64,
    pub seed: u64,
}

impl Spec {
    pub fn new(motion: MotionModel, model: MeasurementModel, dims: usize) -> Self {
        Self {
            motion,
            model,
            dims,
            tracks: 200,
            steps: 40,
            q: 0.5,
            std: [25.0, 2e-3],
            prior: None,
            centre: [20_000.0, 0.0, 3_000.0],
            spread: 5_000.0,
            seed: 1,
        }
    }
}

/// A simulated table, one track after the other (so `indices` is the identity), with the
/// true state of every row.
#[derive(Clone, Debug)]
pub(super) struct Scenario {
    pub times: Vec<f64>,
    pub measurements: Vec<f64>,
    pub columns: usize,
    pub noise: Vec<f64>,
    pub sensors: Option<Vec<f64>>,
    pub indices: Vec<i64>,
    pub offsets: Vec<i64>,
    pub state_dim: usize,
    pub truth: Vec<f64>,
}

impl Scenario {
    pub fn input(&self) -> KalmanInput<'_> {
        KalmanInput {
            times: &self.times,
            measurements: &self.measurements,
            columns: self.columns,
            noise: Noise::Std(&self.noise),
            sensor_positions: self.sensors.as_deref(),
        }
    }

    pub fn tracks(&self) -> Tracks<'_> {
        Tracks {
            indices: &self.indices,
            offsets: &self.offsets,
        }
    }

    pub fn run(&self, options: &KalmanOptions) -> KalmanOutcome {
        kalman_filter(&self.input(), &self.tracks(), options).expect("valid input")
    }

    pub fn len(&self) -> usize {
        self.times.len()
    }
}

pub(super) fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.random_range(f64::EPSILON..1.0);
    let v: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// Tracks with random time steps in [0.5, 2] s, process noise drawn from the exact `Q(Δt)`.
pub(super) fn simulate(spec: &Spec) -> Scenario {
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let (order, d) = (spec.motion.order(), spec.dims);
    let n_state = order * d;
    let polar = spec.model.is_polar();
    let mut sc = Scenario {
        times: vec![],
        measurements: vec![],
        columns: if polar { 2 } else { d },
        noise: vec![],
        sensors: polar.then(Vec::new),
        indices: vec![],
        offsets: vec![0],
        state_dim: n_state,
        truth: vec![],
    };
    for _ in 0..spec.tracks {
        let mut x = vec![0.0; n_state];
        for a in 0..d {
            x[a] = spec.centre[a] + rng.random_range(-spec.spread..spec.spread);
            for j in 1..order {
                x[j * d + a] = match spec.prior {
                    Some((sv, sa)) => [sv, sa][j - 1] * normal(&mut rng),
                    None if j == 1 => rng.random_range(-150.0..150.0),
                    None => rng.random_range(-5.0..5.0),
                };
            }
        }
        let mut t = rng.random_range(0.0..10.0);
        let sensor = [
            rng.random_range(-1_000.0..1_000.0),
            rng.random_range(-1_000.0..1_000.0),
        ];
        for step in 0..spec.steps {
            if step > 0 {
                let dt = rng.random_range(0.5..2.0);
                t += dt;
                let f = spec.motion.transition(dt);
                let q = spec.motion.process_noise(dt, spec.q);
                let q1 = DMatrix::from_fn(order, order, |i, j| q[i][j]);
                let l = match q1.cholesky() {
                    Some(chol) => chol.l(),
                    None => DMatrix::zeros(order, order), // q = 0: no process noise
                };
                for a in 0..d {
                    let old: Vec<f64> = (0..order).map(|j| x[j * d + a]).collect();
                    let w = &l * DVector::from_fn(order, |_, _| normal(&mut rng));
                    for j in 0..order {
                        x[j * d + a] = (0..order).map(|m| f[j][m] * old[m]).sum::<f64>() + w[j];
                    }
                }
            }
            sc.indices.push(sc.times.len() as i64);
            sc.times.push(t);
            sc.truth.extend(&x);
            if polar {
                let (dx, dy) = (x[0] - sensor[0], x[1] - sensor[1]);
                sc.measurements
                    .push(dx.hypot(dy) + spec.std[0] * normal(&mut rng));
                sc.measurements
                    .push(wrap(dy.atan2(dx) + spec.std[1] * normal(&mut rng)));
                sc.noise.extend(spec.std);
                if let Some(s) = sc.sensors.as_mut() {
                    s.extend(sensor);
                }
            } else {
                for &position in &x[..d] {
                    sc.measurements
                        .push(position + spec.std[0] * normal(&mut rng));
                    sc.noise.push(spec.std[0]);
                }
            }
        }
        sc.offsets.push(sc.indices.len() as i64);
    }
    sc
}

/// `(x̂ − x)ᵀ P⁻¹ (x̂ − x)` of row `row`, or `None` where the row has no state.
pub(super) fn nees(out: &KalmanOutcome, truth: &[f64], row: usize) -> Option<f64> {
    let n = out.state_dim;
    let state = &out.states[row * n..(row + 1) * n];
    if state[0].is_nan() {
        return None;
    }
    let e = DVector::from_fn(n, |i, _| state[i] - truth[row * n + i]);
    let p = DMatrix::from_row_slice(n, n, &out.covariances[row * n * n..(row + 1) * n * n]);
    let chol = p.cholesky().expect("covariance positive definite");
    Some(e.dot(&chol.solve(&e)))
}

/// χ² quantile by Wilson–Hilferty (ample for the ≥ 100 degrees of freedom used here).
pub(super) fn chi2_quantile(dof: f64, z: f64) -> f64 {
    let c = 2.0 / (9.0 * dof);
    dof * (1.0 - c + z * c.sqrt()).powi(3)
}
