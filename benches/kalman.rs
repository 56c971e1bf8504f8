//! Batched Kalman filtering: 2 000 constant-velocity tracks × 90 scans of range/azimuth from
//! one of four sensors, polar EKF (180 000 predict/update steps), on one thread and on all.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use passive_assoc_core::estimation::kalman::{
    kalman_filter, KalmanInput, KalmanOptions, MeasurementModel, MotionModel, Noise, Tracks,
};
use passive_assoc_core::parallel::with_threads;

const TRACKS: usize = 2_000;
const SCANS: usize = 90;
const SENSORS: [[f64; 2]; 4] = [[0.0, 0.0], [40e3, 0.0], [0.0, 40e3], [40e3, 40e3]];

/// The table scan by scan (all tracks' rows of a scan together, as a radar reports them).
struct Table {
    times: Vec<f64>,
    measurements: Vec<f64>,
    noise: Vec<f64>,
    sensors: Vec<f64>,
    indices: Vec<i64>,
    offsets: Vec<i64>,
}

fn table() -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let states: Vec<[f64; 4]> = (0..TRACKS)
        .map(|_| {
            [
                rng.random_range(-20e3..60e3),
                rng.random_range(-20e3..60e3),
                rng.random_range(-300.0..300.0),
                rng.random_range(-300.0..300.0),
            ]
        })
        .collect();
    let sensor_of: Vec<usize> = (0..TRACKS).map(|_| rng.random_range(0..4)).collect();
    let (sigma_r, sigma_a) = (50.0, 2e-3);
    let mut t = Table {
        times: vec![],
        measurements: vec![],
        noise: vec![],
        sensors: vec![],
        indices: vec![0; TRACKS * SCANS],
        offsets: (0..=TRACKS).map(|p| (p * SCANS) as i64).collect(),
    };
    for scan in 0..SCANS {
        for (p, x) in states.iter().enumerate() {
            let time = scan as f64 * 10.0 + p as f64 * 1e-3;
            let s = SENSORS[sensor_of[p]];
            let (dx, dy) = (x[0] + x[2] * time - s[0], x[1] + x[3] * time - s[1]);
            t.indices[p * SCANS + scan] = t.times.len() as i64;
            t.times.push(time);
            t.measurements
                .push(dx.hypot(dy) + sigma_r * rng.random_range(-1.7..1.7));
            t.measurements
                .push(dy.atan2(dx) + sigma_a * rng.random_range(-1.7..1.7));
            t.noise.extend([sigma_r, sigma_a]);
            t.sensors.extend(s);
        }
    }
    t
}

fn filter(c: &mut Criterion) {
    let t = table();
    let input = KalmanInput {
        times: &t.times,
        measurements: &t.measurements,
        columns: 2,
        noise: Noise::Std(&t.noise),
        sensor_positions: Some(&t.sensors),
    };
    let tracks = Tracks {
        indices: &t.indices,
        offsets: &t.offsets,
    };
    let options = KalmanOptions::new(MotionModel::ConstantVelocity, 1.0)
        .expect("valid q")
        .with_measurement(MeasurementModel::Polar);
    let mut group = c.benchmark_group("kalman_cv_polar_ekf");
    group.throughput(Throughput::Elements((TRACKS * SCANS) as u64));
    for (label, threads) in [("1 thread", Some(1)), ("all threads", None)] {
        group.bench_function(format!("{TRACKS} tracks x {SCANS} scans/{label}"), |b| {
            b.iter(|| {
                with_threads(threads, || {
                    black_box(kalman_filter(&input, &tracks, &options).expect("valid input"))
                })
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = filter
}
criterion_main!(benches);
