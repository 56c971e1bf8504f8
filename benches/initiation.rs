//! Benchmarks of fuzzy track initiation (METHODS §1) on the paper's scenario with 2× clutter
//! (8 clutter reports per sensor per scan, azimuth U[0, π], elevation U[0, π/2], σ = 5 mrad;
//! 2 sensors × 8 scans × 12 reports = 192 rows):
//!
//! * `closeness/value_and_gradient`: R and ∇R at 64 states near the targets; the throughput
//!   line is measurement-evaluations per second (ns per evaluation = 1e3 / Melem/s).
//! * `descent/one`: one steepest-ascent search from the candidate nearest target 1.
//! * `pipeline/paper_2x_clutter_1_thread`: the whole initiation on one thread.
//! * `pipeline_dense/planar_8_targets_1_thread`: the whole initiation on one thread of a dense
//!   2-D scene like `benches/bench_initiation_2d.py`'s (3 sensors 15 km apart, 8 targets
//!   20–40 km out, 16 clutter bearings per sensor and scan over [0, π], 8 scans; 576 rows),
//!   where the support and tracking gates are most of the time.

use std::f64::consts::PI;
use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use passive_assoc_core::data::{Measurements, Sensors};
use passive_assoc_core::fti::{
    closeness_and_gradient, descend, generate_candidates, initiate, resolve_pairs,
    InitiationOptions, Precomputed, Problem, Scans, Slot, Spreads,
};
use passive_assoc_core::geometry::model::{predict, Motion, Space, StateLayout};
use passive_assoc_core::parallel::with_threads;
use passive_assoc_core::progress::Silent;

const TARGETS: [[f64; 6]; 4] = [
    [1340.0, 15000.0, 1000.0, 173.2, -100.0, 0.0],
    [1340.0, 5000.0, 1000.0, 173.2, 100.0, 0.0],
    [6000.0, 1000.0, 1000.0, 0.0, 200.0, 0.0],
    [1340.0, 16000.0, 1000.0, 173.2, -100.0, 0.0],
];
const SIGMA: f64 = 5e-3;

/// SplitMix64 with Box-Muller normals: a fixed, crate-independent stream.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.uniform();
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * self.uniform()).cos()
    }
}

/// The measurement table of one run: (sensor, time, azimuth, elevation).
#[derive(Default)]
struct Table {
    sensor: Vec<i64>,
    time: Vec<f64>,
    azimuth: Vec<f64>,
    elevation: Vec<f64>,
}

impl Table {
    fn push(&mut self, sensor: usize, time: f64, [azimuth, elevation]: [f64; 2]) {
        self.sensor.push(sensor as i64);
        self.time.push(time);
        self.azimuth.push(azimuth);
        self.elevation.push(elevation);
    }
}

const POSITIONS: [f64; 6] = [0.0, 0.0, 0.0, 20_000.0, 0.0, 0.0];
const SIGMAS: [f64; 2] = [SIGMA, SIGMA];
const SPREADS: [f64; 2] = [2.0 * SIGMA, 2.0 * SIGMA];

fn paper_run(seed: u64) -> Table {
    let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
    let mut rng = Rng(seed);
    let mut table = Table::default();
    for k in 0..8 {
        for j in 0..2usize {
            let time = 15.0 * k as f64 + 5.0 * j as f64;
            let s = [POSITIONS[3 * j], POSITIONS[3 * j + 1], POSITIONS[3 * j + 2]];
            for target in &TARGETS {
                let [a, e] = predict(Space::Spatial, &s, &layout.position(target, time));
                table.push(
                    j,
                    time,
                    [a + SIGMA * rng.normal(), e + SIGMA * rng.normal()],
                );
            }
            for _ in 0..8 {
                table.push(j, time, [PI * rng.uniform(), 0.5 * PI * rng.uniform()]);
            }
        }
    }
    table
}

const PLANAR_POSITIONS: [f64; 9] = [-15_000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 15_000.0, 0.0, 0.0];
const PLANAR_SIGMAS: [f64; 3] = [SIGMA; 3];
const PLANAR_SPREADS: [f64; 3] = [2.0 * SIGMA; 3];

/// A dense 2-D scene: 8 constant-velocity targets at random (x in ±10 km, y in 20–40 km,
/// 100–200 m/s), 3 synchronous sensors, 8 scans 10 s apart, 16 clutter bearings a scan.
fn planar_run(seed: u64) -> Table {
    let layout = StateLayout::new(Space::Planar, Motion::ConstantVelocity { t0: 0.0 });
    let mut rng = Rng(seed);
    let targets: Vec<[f64; 4]> = (0..8)
        .map(|_| {
            let (speed, heading) = (100.0 + 100.0 * rng.uniform(), 2.0 * PI * rng.uniform());
            let x = -10_000.0 + 20_000.0 * rng.uniform();
            let y = 20_000.0 + 20_000.0 * rng.uniform();
            [x, y, speed * heading.cos(), speed * heading.sin()]
        })
        .collect();
    let mut table = Table::default();
    for k in 0..8 {
        for j in 0..3usize {
            let time = 10.0 * k as f64;
            let s = [PLANAR_POSITIONS[3 * j], 0.0, 0.0];
            let mut bearings: Vec<f64> = targets
                .iter()
                .map(|t| predict(Space::Planar, &s, &layout.position(t, time))[0])
                .map(|a| a + SIGMA * rng.normal())
                .collect();
            bearings.extend((0..16).map(|_| PI * rng.uniform()));
            for a in bearings {
                table.push(j, time, [a, 0.0]);
            }
        }
    }
    table
}

fn views(table: &Table) -> (Sensors<'_>, Measurements<'_>, Spreads<'_>) {
    views_in(table, Space::Spatial, &POSITIONS, &SIGMAS, &SPREADS)
}

/// The validated views of `table` for sensors at `positions` (3 per sensor) with equal angle
/// stds and spreads in both angles.
fn views_in<'a>(
    table: &'a Table,
    space: Space,
    positions: &'a [f64],
    sigmas: &'a [f64],
    spreads: &'a [f64],
) -> (Sensors<'a>, Measurements<'a>, Spreads<'a>) {
    let sensors = Sensors::new(space, positions, sigmas, sigmas).expect("valid sensors");
    let rows = Measurements::new(
        &sensors,
        &table.sensor,
        &table.time,
        &table.azimuth,
        &table.elevation,
    )
    .expect("valid table");
    let spreads = Spreads::new(space, sigmas.len(), spreads, spreads).expect("valid spreads");
    (sensors, rows, spreads)
}

fn bench_closeness(c: &mut Criterion) {
    let table = paper_run(2024);
    let (sensors, rows, spreads) = views(&table);
    let pre = Precomputed::new(&sensors, &rows, &spreads, 0.0).expect("valid");
    let mut rng = Rng(5);
    let states: Vec<[f64; 6]> = (0..64)
        .map(|i| {
            let t = TARGETS[i % 4];
            std::array::from_fn(|k| t[k] + if k < 3 { 80.0 } else { 2.0 } * rng.normal())
        })
        .collect();
    let mut group = c.benchmark_group("closeness");
    group.throughput(Throughput::Elements((states.len() * pre.len()) as u64));
    group.bench_function("value_and_gradient", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for x in &states {
                let (r, g) = closeness_and_gradient(&pre, black_box(x));
                acc += r + g[0];
            }
            acc
        })
    });
    group.finish();
}

fn bench_descent(c: &mut Criterion) {
    let table = paper_run(2024);
    let (sensors, rows, spreads) = views(&table);
    let pre = Precomputed::new(&sensors, &rows, &spreads, 0.0).expect("valid");
    let options = InitiationOptions::default();
    let problem = Problem {
        sensors,
        measurements: rows,
        layout: StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 }),
        t0: 0.0,
        progress: &Silent,
    };
    let scans = Scans::new(&rows, 2);
    let pairs = resolve_pairs(None, &scans).expect("two sensors with scans");
    let outer: Vec<Slot> = pairs
        .iter()
        .flat_map(|&p| scans.scan_slots(p, 1, false))
        .map(Slot::untested)
        .collect();
    let set =
        generate_candidates(&problem, &scans, &outer, None, &options, None).expect("candidates");
    let truth = TARGETS[0];
    let candidates = set.candidates.into_whole(&problem);
    let nearest = candidates
        .iter()
        .min_by(|a, b| {
            let d = |c: &passive_assoc_core::fti::Candidate| {
                (0..6)
                    .map(|k| ((c.estimate[k] - truth[k]) / c.scale[k]).powi(2))
                    .sum::<f64>()
            };
            d(a).total_cmp(&d(b))
        })
        .expect("some candidate");
    let probe = descend(&pre, &nearest.estimate, &nearest.factor, options.descent());
    println!(
        "descent/one: {} iterations, {} evaluations",
        probe.iterations, probe.evaluations
    );
    c.bench_function("descent/one", |b| {
        b.iter(|| {
            descend(
                &pre,
                black_box(&nearest.estimate),
                &nearest.factor,
                options.descent(),
            )
        })
    });
}

fn bench_pipeline(c: &mut Criterion) {
    let table = paper_run(2024);
    let (sensors, rows, spreads) = views(&table);
    let options = InitiationOptions::default();
    let run = || {
        with_threads(Some(1), || {
            initiate(&sensors, &rows, &spreads, 0.0, &options)
        })
    };
    let probe = run().expect("pool").expect("runs");
    println!(
        "pipeline: {} tracks; counts {:?}; seconds {:?}; descent iterations total {}",
        probe.tracks.len(),
        probe.stage_counts,
        probe.stage_seconds,
        probe.descent_iterations.iter().sum::<usize>()
    );
    let mut group = c.benchmark_group("pipeline");
    group.sample_size(20);
    // One pool for all iterations: the bench measures the algorithm, not thread start-up.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    group.bench_function("paper_2x_clutter_1_thread", |b| {
        b.iter(|| pool.install(|| initiate(&sensors, &rows, &spreads, 0.0, black_box(&options))))
    });
    group.finish();

    let table = planar_run(16);
    let (sensors, rows, spreads) = views_in(
        &table,
        Space::Planar,
        &PLANAR_POSITIONS,
        &PLANAR_SIGMAS,
        &PLANAR_SPREADS,
    );
    let probe = pool
        .install(|| initiate(&sensors, &rows, &spreads, 0.0, &options))
        .expect("runs");
    println!(
        "pipeline_dense: {} tracks; counts {:?}; seconds {:?}",
        probe.tracks.len(),
        probe.stage_counts,
        probe.stage_seconds
    );
    let mut group = c.benchmark_group("pipeline_dense");
    group.sample_size(10);
    group.bench_function("planar_8_targets_1_thread", |b| {
        b.iter(|| pool.install(|| initiate(&sensors, &rows, &spreads, 0.0, black_box(&options))))
    });
    group.finish();
}

criterion_group!(benches, bench_closeness, bench_descent, bench_pipeline);
criterion_main!(benches);
