//! Static LOS association (METHODS §2) on one thread: candidate enumeration alone and followed
//! by the intensity-ordered search, in the EXPERIMENTS `intensity` geometry — 2-D sensors at
//! (−15, 0), (0, −5), (15, 0) km (S = 5 adds (−7.5, −3.75) and (7.5, −3.75) km), targets uniform
//! in x ∈ [−10, 10], y ∈ [20, 40] km, Pd = 0.95, σ from R = Δ/σ = 15 with Δ = 0.761 rad / M (the
//! square's angular width seen from (0, −5) km, split over M targets), false bearings uniform
//! over each sensor's sector of the square. Target: S = 3, M = 18 in ≤ 2 ms including the
//! enumeration.

use criterion::{criterion_group, criterion_main, Criterion};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use passive_assoc_core::data::{Measurements, Sensors};
use passive_assoc_core::geometry::model::{predict, Space};
use passive_assoc_core::static_los::{
    enumerate, intensity_search, DetectionModel, EnumerateOptions, IntensityOptions,
};

const SENSORS_KM: [[f64; 2]; 5] = [
    [-15.0, 0.0],
    [0.0, -5.0],
    [15.0, 0.0],
    [-7.5, -3.75],
    [7.5, -3.75],
];
const SQUARE_WIDTH_RAD: f64 = 0.761;

struct Scan {
    positions: Vec<f64>,
    sigma: Vec<f64>,
    pd: Vec<f64>,
    density: Vec<f64>,
    sensor: Vec<i64>,
    time: Vec<f64>,
    azimuth: Vec<f64>,
}

fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let (u, v): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// One scan with `m` targets and `false_per_sensor` false bearings per sensor.
fn scan(n_sensors: usize, m: usize, false_per_sensor: usize, seed: u64) -> Scan {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let sigma = SQUARE_WIDTH_RAD / m as f64 / 15.0;
    let targets: Vec<[f64; 3]> = (0..m)
        .map(|_| {
            [
                rng.random_range(-10e3..10e3),
                rng.random_range(20e3..40e3),
                0.0,
            ]
        })
        .collect();
    let mut s = Scan {
        positions: vec![],
        sigma: vec![sigma; n_sensors],
        pd: vec![0.95; n_sensors],
        density: vec![],
        sensor: vec![],
        time: vec![],
        azimuth: vec![],
    };
    for (j, p) in SENSORS_KM[..n_sensors].iter().enumerate() {
        let p = [p[0] * 1e3, p[1] * 1e3, 0.0];
        s.positions.extend_from_slice(&p);
        for t in &targets {
            if rng.random::<f64>() < 0.95 {
                s.sensor.push(j as i64);
                s.azimuth
                    .push(predict(Space::Planar, &p, t)[0] + sigma * gaussian(&mut rng));
            }
        }
        let corners = [[-10e3, 20e3], [10e3, 20e3], [-10e3, 40e3], [10e3, 40e3]];
        let b: Vec<f64> = corners
            .iter()
            .map(|c| (c[1] - p[1]).atan2(c[0] - p[0]))
            .collect();
        let (lo, hi) = b
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                (l.min(x), h.max(x))
            });
        for _ in 0..false_per_sensor {
            s.sensor.push(j as i64);
            s.azimuth.push(rng.random_range(lo..hi));
        }
        s.density
            .push((false_per_sensor as f64).max(0.5) / (hi - lo));
    }
    s.time = vec![0.0; s.sensor.len()];
    s
}

fn bench_case(c: &mut Criterion, name: &str, s: &Scan) {
    let sensors =
        Sensors::new(Space::Planar, &s.positions, &s.sigma, &s.sigma).expect("valid sensors");
    let table =
        Measurements::new(&sensors, &s.sensor, &s.time, &s.azimuth, &[]).expect("valid table");
    let detection = DetectionModel::new(&sensors, &s.pd, &s.density).expect("valid detection");
    let options = EnumerateOptions::default();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let run = || {
        let cands = enumerate(&sensors, &table, &detection, &options).expect("enumerates");
        let input = cands.intensity_input().expect("valid");
        let out = intensity_search(&input, &IntensityOptions::paper()).expect("searches");
        (cands, out)
    };
    let cands =
        pool.install(|| enumerate(&sensors, &table, &detection, &options).expect("enumerates"));
    let full = cands
        .intensity
        .iter()
        .filter(|&&i| i as usize == cands.n_sensors)
        .count();
    eprintln!(
        "{name}: {} reports, {} candidates ({full} of intensity S)",
        s.sensor.len(),
        cands.len()
    );
    if std::env::var_os("STATIC_ASSOC_VERBOSE").is_some() {
        let (_, out) = pool.install(run);
        eprintln!(
            "  {} chosen, {} chains, levels {:?}",
            out.chosen.len(),
            out.chains,
            out.levels
        );
        eprintln!("  stages {:?}", cands.stages.named());
    }
    c.bench_function(&format!("static/{name}/enumerate"), |b| {
        b.iter(|| {
            pool.install(|| {
                enumerate(&sensors, &table, &detection, &options)
                    .expect("enumerates")
                    .len()
            })
        })
    });
    c.bench_function(&format!("static/{name}/enumerate+intensity"), |b| {
        b.iter(|| pool.install(run))
    });
    let input = cands.intensity_input().expect("valid");
    c.bench_function(&format!("static/{name}/intensity"), |b| {
        b.iter(|| {
            pool.install(|| {
                intensity_search(&input, &IntensityOptions::paper())
                    .expect("searches")
                    .chosen
                    .len()
            })
        })
    });
    // The same with at most 64 chains per level (not the paper's rule; for large scans).
    let capped = IntensityOptions::paper()
        .with_max_chains(Some(64))
        .expect("valid");
    c.bench_function(&format!("static/{name}/intensity_max_chains_64"), |b| {
        b.iter(|| {
            pool.install(|| {
                intensity_search(&input, &capped)
                    .expect("searches")
                    .chosen
                    .len()
            })
        })
    });
}

fn benches(c: &mut Criterion) {
    bench_case(c, "S3_M18", &scan(3, 18, 1, 1));
    bench_case(c, "S3_M100_fa5", &scan(3, 100, 5, 2));
    bench_case(c, "S5_M50_fa3", &scan(5, 50, 3, 3));
}

criterion_group! {
    name = static_assoc;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = benches
}
criterion_main!(static_assoc);
