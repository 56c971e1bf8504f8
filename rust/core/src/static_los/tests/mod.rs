//! Tests of §2: enumeration against brute force, the noiseless truth, thread invariance,
//! the intensity search's rules, and input errors. Geometry of EXPERIMENTS `intensity`:
//! sensors (−15, 0), (0, −5), (15, 0) km, targets uniform in x ∈ [−10, 10], y ∈ [20, 40] km.
//! This file holds the simulated scan shared by `enumeration` and `intensity`.

mod enumeration;
mod intensity;

use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::prepared::{Estimate, Prepared};
use super::*;
use crate::assign::CandidateSet;
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::geometry::model::{predict, Observation, Space};
use crate::parallel::with_threads;

const SENSORS_KM: [[f64; 3]; 5] = [
    [-15.0, 0.0, 0.0],
    [0.0, -5.0, 0.1],
    [15.0, 0.0, 0.05],
    [-7.5, -3.75, 0.0],
    [7.5, -3.75, 0.2],
];

/// An intensity input from `i64` slices, the way the binding layer receives them (a negative
/// entry is an out-of-range error, as there).
fn intensity_input(
    tuples: &[i64],
    n_sensors: usize,
    positions: &[f64],
    dim: usize,
    costs: &[f64],
    sizes: &[i64],
) -> CoreResult<IntensityInput> {
    let unsigned = |name: &'static str, values: &[i64]| {
        values
            .iter()
            .map(|&v| usize::try_from(v).map_err(|_| CoreError::out_of_range(name, "negative")))
            .collect::<CoreResult<Vec<usize>>>()
    };
    let set = CandidateSet::new(
        unsigned("tuples", tuples)?,
        n_sensors,
        costs.to_vec(),
        unsigned("sizes", sizes)?,
    )?;
    IntensityInput::new(set, positions.to_vec(), dim)
}

/// One simulated scan: a measurement table plus each target's true tuple.
struct Scene {
    space: Space,
    positions: Vec<f64>,
    sigma: Vec<f64>,
    sensor: Vec<i64>,
    time: Vec<f64>,
    azimuth: Vec<f64>,
    elevation: Vec<f64>,
    targets: Vec<[f64; 3]>,
    /// Per target, the 1-based index among its sensor's rows (0 = missed).
    truth: Vec<Vec<i64>>,
}

fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let (u, v): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

#[allow(clippy::too_many_arguments)]
fn scene(
    space: Space,
    n_sensors: usize,
    n_targets: usize,
    sigma: f64,
    pd: f64,
    false_per_sensor: usize,
    noisy: bool,
    seed: u64,
) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let sensors: Vec<[f64; 3]> = SENSORS_KM[..n_sensors]
        .iter()
        .map(|p| p.map(|v| v * 1000.0))
        .collect();
    let targets: Vec<[f64; 3]> = (0..n_targets)
        .map(|_| {
            let z = if space == Space::Spatial {
                rng.random_range(1000.0..5000.0)
            } else {
                0.0
            };
            [
                rng.random_range(-10_000.0..10_000.0),
                rng.random_range(20_000.0..40_000.0),
                z,
            ]
        })
        .collect();
    // (sensor, azimuth, elevation, target or −1)
    let mut rows: Vec<(usize, f64, f64, i64)> = Vec::new();
    for (j, s) in sensors.iter().enumerate() {
        for (t, target) in targets.iter().enumerate() {
            if rng.random::<f64>() < pd {
                let [a, e] = predict(space, s, target);
                let (na, ne) = if noisy {
                    (sigma * gaussian(&mut rng), sigma * gaussian(&mut rng))
                } else {
                    (0.0, 0.0)
                };
                rows.push((j, a + na, e + ne, t as i64));
            }
        }
        // False bearings uniform over the sector that covers the square.
        let corners = [[-10e3, 20e3], [10e3, 20e3], [-10e3, 40e3], [10e3, 40e3]];
        let bearings: Vec<f64> = corners
            .iter()
            .map(|c| (c[1] - s[1]).atan2(c[0] - s[0]))
            .collect();
        let (lo, hi) = bearings
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &b| {
                (l.min(b), h.max(b))
            });
        for _ in 0..false_per_sensor {
            rows.push((
                j,
                rng.random_range(lo..hi),
                rng.random_range(0.02..0.25),
                -1,
            ));
        }
    }
    rows.shuffle(&mut rng);
    let mut truth = vec![vec![0i64; n_sensors]; n_targets];
    let mut seen = vec![0i64; n_sensors];
    for &(j, _, _, t) in &rows {
        seen[j] += 1;
        if t >= 0 {
            truth[t as usize][j] = seen[j];
        }
    }
    Scene {
        space,
        positions: sensors.iter().flatten().copied().collect(),
        sigma: vec![sigma; n_sensors],
        sensor: rows.iter().map(|r| r.0 as i64).collect(),
        time: vec![0.0; rows.len()],
        azimuth: rows.iter().map(|r| r.1).collect(),
        elevation: rows.iter().map(|r| r.2).collect(),
        targets,
        truth,
    }
}

impl Scene {
    fn sensors(&self) -> Sensors<'_> {
        Sensors::new(self.space, &self.positions, &self.sigma, &self.sigma).expect("valid sensors")
    }

    fn detection(&self, pd: f64, density: f64) -> DetectionModel {
        let n = self.sigma.len();
        DetectionModel::new(&self.sensors(), &vec![pd; n], &vec![density; n])
            .expect("valid detection")
    }

    fn run(&self, options: &EnumerateOptions, threads: Option<usize>) -> CoreResult<Candidates> {
        let sensors = self.sensors();
        let table = Measurements::new(
            &sensors,
            &self.sensor,
            &self.time,
            &self.azimuth,
            &self.elevation,
        )
        .expect("valid table");
        let detection = self.detection(0.9, 1.0);
        with_threads(threads, || enumerate(&sensors, &table, &detection, options)).expect("pool")
    }

    /// Every tuple of Π(n_s + 1), gated prefix by prefix with the same primitives.
    fn brute_force(&self, options: &EnumerateOptions) -> Vec<(Vec<i64>, Estimate)> {
        let sensors = self.sensors();
        let table = Measurements::new(
            &sensors,
            &self.sensor,
            &self.time,
            &self.azimuth,
            &self.elevation,
        )
        .expect("valid table");
        let detection = self.detection(0.9, 1.0);
        let p = Prepared::new(&sensors, &table, &detection, options).expect("valid");
        let sizes: Vec<usize> = p.rays.iter().map(Vec::len).collect();
        let mut out = Vec::new();
        let mut tuple = vec![0usize; sizes.len()];
        'all: loop {
            let chosen: Vec<_> = tuple
                .iter()
                .enumerate()
                .filter(|(_, &i)| i > 0)
                .map(|(s, &i)| p.rays[s][i - 1])
                .collect();
            if chosen.len() >= options.min_intensity() {
                let obs: Vec<Observation> = chosen.iter().map(|r| r.obs).collect();
                let mut estimate = p.estimate_pair(&chosen[0], &chosen[1]);
                for k in 3..=chosen.len() {
                    estimate = estimate.and_then(|e| p.estimate_extension(&e, &obs[..k]));
                }
                if let Some(e) = estimate {
                    out.push((tuple.iter().map(|&i| i as i64).collect(), e));
                }
            }
            // Odometer, last sensor fastest: lexicographic order.
            for s in (0..sizes.len()).rev() {
                if tuple[s] < sizes[s] {
                    tuple[s] += 1;
                    continue 'all;
                }
                tuple[s] = 0;
            }
            break;
        }
        out
    }
}

fn sizes_i64(c: &Candidates) -> Vec<i64> {
    c.sizes.iter().map(|&n| n as i64).collect()
}
