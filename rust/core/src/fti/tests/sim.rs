//! A tiny deterministic simulator for the tests: the paper's scenario (METHODS §1, EXPERIMENTS
//! `fti`) and a 2-D bearing-only one, with a self-contained PRNG so results never depend on a
//! crate's stream.

use std::f64::consts::PI;

use crate::data::{Measurements, Sensors};
use crate::fti::{Problem, Spreads};
use crate::geometry::model::{predict, Motion, Space, StateLayout};

/// Table 1 of the paper: X0 = (x0, y0, z0, vx, vy, vz) at t0 = 0.
pub const PAPER_TARGETS: [[f64; 6]; 4] = [
    [1340.0, 15000.0, 1000.0, 173.2, -100.0, 0.0],
    [1340.0, 5000.0, 1000.0, 173.2, 100.0, 0.0],
    [6000.0, 1000.0, 1000.0, 0.0, 200.0, 0.0],
    [1340.0, 16000.0, 1000.0, 173.2, -100.0, 0.0],
];

/// SplitMix64 with Box-Muller normals.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn normal(&mut self) -> f64 {
        let u = 1.0 - self.uniform();
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * self.uniform()).cos()
    }
}

/// A simulated network and measurement table (rows shuffled), with the hidden truth.
pub struct Scenario {
    pub space: Space,
    pub positions: Vec<f64>,
    pub sigma_az: Vec<f64>,
    pub sigma_el: Vec<f64>,
    pub spread_az: Vec<f64>,
    pub spread_el: Vec<f64>,
    pub sensor: Vec<i64>,
    pub time: Vec<f64>,
    pub azimuth: Vec<f64>,
    pub elevation: Vec<f64>,
    /// Target index or −1 for clutter.
    pub truth: Vec<i64>,
    pub targets: Vec<Vec<f64>>,
}

impl Scenario {
    pub fn sensors(&self) -> Sensors<'_> {
        Sensors::new(self.space, &self.positions, &self.sigma_az, &self.sigma_el)
            .expect("valid sensors")
    }

    pub fn measurements<'a>(&'a self, sensors: &Sensors<'_>) -> Measurements<'a> {
        Measurements::new(
            sensors,
            &self.sensor,
            &self.time,
            &self.azimuth,
            &self.elevation,
        )
        .expect("valid table")
    }

    /// The rows of target `i`, ascending.
    pub fn rows_of(&self, i: i64) -> Vec<usize> {
        (0..self.truth.len())
            .filter(|&m| self.truth[m] == i)
            .collect()
    }

    /// Drops the rows whose `keep` flag is false (a missed detection or a removed report).
    pub fn keep_rows(&mut self, keep: &[bool]) {
        fn kept<T: Copy>(v: &[T], keep: &[bool]) -> Vec<T> {
            v.iter()
                .zip(keep)
                .filter(|(_, k)| **k)
                .map(|(x, _)| *x)
                .collect()
        }
        self.time = kept(&self.time, keep);
        self.azimuth = kept(&self.azimuth, keep);
        self.elevation = kept(&self.elevation, keep);
        self.sensor = kept(&self.sensor, keep);
        self.truth = kept(&self.truth, keep);
    }

    pub fn spreads(&self) -> Spreads<'_> {
        Spreads::new(
            self.space,
            self.sigma_az.len(),
            &self.spread_az,
            &self.spread_el,
        )
        .expect("valid spreads")
    }

    fn push(&mut self, sensor: usize, time: f64, angles: [f64; 2], truth: i64) {
        self.sensor.push(sensor as i64);
        self.time.push(time);
        self.azimuth.push(angles[0]);
        self.elevation.push(if self.space == Space::Spatial {
            angles[1]
        } else {
            f64::NAN
        });
        self.truth.push(truth);
    }

    fn shuffle(&mut self, rng: &mut Rng) {
        for i in (1..self.sensor.len()).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            self.sensor.swap(i, j);
            self.time.swap(i, j);
            self.azimuth.swap(i, j);
            self.elevation.swap(i, j);
            self.truth.swap(i, j);
        }
    }
}

fn empty(space: Space, positions: Vec<f64>, sigma: f64, targets: Vec<Vec<f64>>) -> Scenario {
    let s = positions.len() / 3;
    Scenario {
        space,
        positions,
        sigma_az: vec![sigma; s],
        sigma_el: vec![sigma; s],
        spread_az: vec![2.0 * sigma; s],
        spread_el: vec![2.0 * sigma; s],
        sensor: Vec::new(),
        time: Vec::new(),
        azimuth: Vec::new(),
        elevation: Vec::new(),
        truth: Vec::new(),
        targets,
    }
}

/// The paper's run: sensors (0,0,0) and (20 km,0,0), σ = 5 mrad (0 noise if `!noisy`),
/// scans at kT (sensor 1) and 5 + kT (sensor 2), T = 15 s; `clutter` reports per sensor and
/// scan with azimuth U[0, π], elevation U[0, π/2].
pub fn paper(seed: u64, noisy: bool, clutter: usize, n_scans: usize) -> Scenario {
    let sigma = 5e-3;
    let mut sc = empty(
        Space::Spatial,
        vec![0.0, 0.0, 0.0, 20_000.0, 0.0, 0.0],
        sigma,
        PAPER_TARGETS.iter().map(|t| t.to_vec()).collect(),
    );
    let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
    let mut rng = Rng::new(seed);
    let noise = if noisy { sigma } else { 0.0 };
    for k in 0..n_scans {
        for j in 0..2 {
            let time = 15.0 * k as f64 + 5.0 * j as f64;
            let p = [
                sc.positions[3 * j],
                sc.positions[3 * j + 1],
                sc.positions[3 * j + 2],
            ];
            for (i, target) in PAPER_TARGETS.iter().enumerate() {
                let [a, e] = predict(Space::Spatial, &p, &layout.position(target, time));
                sc.push(
                    j,
                    time,
                    [a + noise * rng.normal(), e + noise * rng.normal()],
                    i as i64,
                );
            }
            for _ in 0..clutter {
                let angles = [PI * rng.uniform(), 0.5 * PI * rng.uniform()];
                sc.push(j, time, angles, -1);
            }
        }
    }
    sc.shuffle(&mut rng);
    sc
}

/// 2-D bearing-only: three sensors on the x axis, two targets, synchronous scans every 10 s.
pub fn planar(seed: u64, noisy: bool, clutter: usize, n_scans: usize) -> Scenario {
    let sigma = 2e-3;
    let targets = vec![
        vec![-4000.0, 25_000.0, 150.0, -60.0],
        vec![5000.0, 32_000.0, -120.0, -90.0],
    ];
    let positions = vec![-15_000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 15_000.0, 0.0, 0.0];
    let mut sc = empty(Space::Planar, positions, sigma, targets.clone());
    let layout = StateLayout::new(Space::Planar, Motion::ConstantVelocity { t0: 0.0 });
    let mut rng = Rng::new(seed);
    let noise = if noisy { sigma } else { 0.0 };
    for k in 0..n_scans {
        for j in 0..3 {
            let time = 10.0 * k as f64;
            let p = [sc.positions[3 * j], sc.positions[3 * j + 1], 0.0];
            for (i, target) in targets.iter().enumerate() {
                let [a, _] = predict(Space::Planar, &p, &layout.position(target, time));
                sc.push(j, time, [a + noise * rng.normal(), 0.0], i as i64);
            }
            for _ in 0..clutter {
                sc.push(j, time, [PI * rng.uniform(), 0.0], -1);
            }
        }
    }
    sc.shuffle(&mut rng);
    sc
}

/// Three sensors on a 30 km ring (not colinear, 0–400 m high), σ = 4 mrad, asynchronous scans
/// every 15 s (offsets 0, 5, 10 s), `n_targets` targets spread over a 3-D box, detected with
/// probability `pd`, `clutter` rays per sensor and scan over the whole sky.
pub fn ring(seed: u64, n_targets: usize, pd: f64, clutter: usize, n_scans: usize) -> Scenario {
    let sigma = 4e-3;
    let mut rng = Rng::new(seed);
    let mut positions = Vec::new();
    for j in 0..3 {
        let angle = 2.0 * PI * j as f64 / 3.0 + 0.3 * (rng.uniform() - 0.5);
        positions.extend([
            30e3 * angle.cos(),
            30e3 * angle.sin(),
            400.0 * rng.uniform(),
        ]);
    }
    let targets: Vec<Vec<f64>> = (0..n_targets)
        .map(|_| {
            let speed = 100.0 + 200.0 * rng.uniform();
            let heading = 2.0 * PI * rng.uniform();
            let climb = 0.2 * (rng.uniform() - 0.5);
            vec![
                40e3 * (rng.uniform() - 0.5),
                40e3 * (rng.uniform() - 0.5),
                500.0 + 9500.0 * rng.uniform(),
                speed * heading.cos(),
                speed * heading.sin(),
                speed * climb,
            ]
        })
        .collect();
    let mut sc = empty(Space::Spatial, positions, sigma, targets.clone());
    let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
    for k in 0..n_scans {
        for j in 0..3 {
            let time = 15.0 * k as f64 + 5.0 * j as f64;
            let p = [
                sc.positions[3 * j],
                sc.positions[3 * j + 1],
                sc.positions[3 * j + 2],
            ];
            for (i, target) in targets.iter().enumerate() {
                if rng.uniform() >= pd {
                    continue;
                }
                let [a, e] = predict(Space::Spatial, &p, &layout.position(target, time));
                let angles = [a + sigma * rng.normal(), e + sigma * rng.normal()];
                sc.push(j, time, angles, i as i64);
            }
            for _ in 0..clutter {
                let angles = [PI * (2.0 * rng.uniform() - 1.0), 0.5 * PI * rng.uniform()];
                sc.push(j, time, angles, -1);
            }
        }
    }
    sc.shuffle(&mut rng);
    sc
}

/// The constant-velocity problem of a table in its sensors' space, epoch 0 (the simulations'
/// t0).
pub fn problem<'a>(sensors: Sensors<'a>, measurements: Measurements<'a>) -> Problem<'a> {
    Problem {
        sensors,
        measurements,
        layout: StateLayout::new(sensors.space(), Motion::ConstantVelocity { t0: 0.0 }),
        t0: 0.0,
        progress: &crate::progress::Silent,
    }
}
