//! Benchmarks of formation location with emitter attributes (METHODS §3).
//!
//! * `formation/paper_scene`: one association of the paper's scene (3 sensors × 6 emitters,
//!   σθ = 1°, attributes on), all threads and `..._1_thread`.
//! * `formation/large_5x200`: 5 sensors × 200 emitters with attributes (σθ = 0.5°), the
//!   layout of `passive_assoc.simulation.formation_scene`: sensors along 100 km at y = −30 km,
//!   emitters in x ∈ [−60, 60] km, y ∈ [20, 120] km, 8 emitter types whose members look alike.
//!   Independent and one-to-one.
//!
//! Figures go to docs/performance.md.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use passive_assoc_core::data::{Measurements, Sensors};
use passive_assoc_core::evidence::{AttributeGate, AttributeTable, Combination};
use passive_assoc_core::formation::{locate, FormationOptions};
use passive_assoc_core::geometry::model::Space;
use passive_assoc_core::parallel::with_threads;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const STD: [f64; 4] = [10.0, 5.0, 0.2, 0.2];

struct Scene {
    positions: Vec<f64>,
    sigma: Vec<f64>,
    sensor: Vec<i64>,
    time: Vec<f64>,
    azimuth: Vec<f64>,
    values: Vec<f64>,
    stds: Vec<f64>,
}

fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    // Box-Muller: the benchmark needs plausible noise, not a particular generator.
    let (u, v): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random_range(0.0..1.0));
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// `sensors` (x, y), `targets` (x, y) and their attributes, every report seen, bearing noise
/// `sigma` (rad) and attribute noise `STD`.
fn scene(
    sensors: &[[f64; 2]],
    targets: &[[f64; 2]],
    attrs: &[[f64; 4]],
    sigma: f64,
    seed: u64,
) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut s = Scene {
        positions: sensors.iter().flat_map(|p| [p[0], p[1], 0.0]).collect(),
        sigma: vec![sigma; sensors.len()],
        sensor: Vec::new(),
        time: Vec::new(),
        azimuth: Vec::new(),
        values: Vec::new(),
        stds: Vec::new(),
    };
    for (j, p) in sensors.iter().enumerate() {
        for (t, target) in targets.iter().enumerate() {
            s.sensor.push(j as i64);
            s.time.push(0.0);
            let bearing = (target[1] - p[1]).atan2(target[0] - p[0]);
            s.azimuth.push(bearing + sigma * gaussian(&mut rng));
            for k in 0..4 {
                s.values.push(attrs[t][k] + STD[k] * gaussian(&mut rng));
            }
            s.stds.extend(STD);
        }
    }
    s
}

fn paper() -> Scene {
    let sensors = [[-80e3, -30e3], [-30e3, -30e3], [20e3, -30e3]];
    let targets = [
        [-27.5e3, 60e3],
        [-22.5e3, 60e3],
        [-17.5e3, 60e3],
        [-60e3, 70e3],
        [-45e3, 70e3],
        [0.0, 70e3],
    ];
    let attrs = [
        [4008.0, 1005.0, 4.9, 2.2],
        [7991.0, 1488.0, 6.3, 5.2],
        [6011.0, 1211.0, 5.5, 4.3],
        [3987.0, 994.0, 5.1, 1.8],
        [4002.0, 1007.0, 4.6, 1.9],
        [6000.0, 1202.0, 5.3, 4.5],
    ];
    scene(&sensors, &targets, &attrs, 1f64.to_radians(), 1)
}

fn large() -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let sensors: Vec<[f64; 2]> = (0..5).map(|j| [-50e3 + 25e3 * j as f64, -30e3]).collect();
    let types: Vec<[f64; 4]> = (0..8)
        .map(|_| {
            [
                rng.random_range(2000.0..10000.0),
                rng.random_range(500.0..3000.0),
                rng.random_range(1.0..20.0),
                rng.random_range(1.0..10.0),
            ]
        })
        .collect();
    let mut targets = Vec::new();
    let mut attrs = Vec::new();
    for _ in 0..200 {
        targets.push([rng.random_range(-60e3..60e3), rng.random_range(20e3..120e3)]);
        let centre = types[rng.random_range(0..types.len())];
        attrs.push(std::array::from_fn(|k| {
            centre[k] + 2.0 * STD[k] * gaussian(&mut rng)
        }));
    }
    scene(&sensors, &targets, &attrs, 0.5f64.to_radians(), 3)
}

fn run(s: &Scene, options: &FormationOptions) -> usize {
    let sensors = Sensors::new(Space::Planar, &s.positions, &s.sigma, &[]).expect("sensors");
    let meas = Measurements::new(&sensors, &s.sensor, &s.time, &s.azimuth, &[]).expect("table");
    let (values, stds) = (attribute_major(&s.values, 4), attribute_major(&s.stds, 4));
    let table = AttributeTable::new(&values, &stds, s.sensor.len(), 4).expect("attributes");
    let gate = AttributeGate::new(table, Combination::SimpleSupport, 0.6).expect("gate");
    let out = locate(&sensors, &meas, Some(gate), options).expect("locates");
    out.radius.iter().filter(|r| !r.is_nan()).count()
}

fn bench_formation(c: &mut Criterion) {
    let (paper, large) = (paper(), large());
    let independent = FormationOptions::default();
    let one_to_one = independent.with_one_to_one(true);
    let mut group = c.benchmark_group("formation");
    group.sample_size(30);
    group.bench_function("paper_scene", |b| {
        b.iter(|| black_box(run(&paper, &independent)))
    });
    group.bench_function("paper_scene_1_thread", |b| {
        b.iter(|| with_threads(Some(1), || black_box(run(&paper, &independent))).expect("pool"))
    });
    group.bench_function("large_5x200", |b| {
        b.iter(|| black_box(run(&large, &independent)))
    });
    group.bench_function("large_5x200_1_thread", |b| {
        b.iter(|| with_threads(Some(1), || black_box(run(&large, &independent))).expect("pool"))
    });
    group.bench_function("large_5x200_one_to_one", |b| {
        b.iter(|| black_box(run(&large, &one_to_one)))
    });
    group.finish();
}

criterion_group!(benches, bench_formation);
criterion_main!(benches);

/// Row-major `N × k` → the core's attribute-major `k × N`.
fn attribute_major(row_major: &[f64], k: usize) -> Vec<f64> {
    let n = row_major.len() / k;
    (0..k * n)
        .map(|at| row_major[(at % n) * k + at / n])
        .collect()
}
