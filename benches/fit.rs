//! Batched Gauss-Newton fitting: 10 000 problems of 4 az/el measurements with a 6-D
//! constant-velocity state (the fuzzy-initiation candidate fit), and 2-D static bearing fixes.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use passive_assoc_core::data::{Measurements, Sensors};
use passive_assoc_core::estimation::fit::batch::{fit_batch, Problems};
use passive_assoc_core::estimation::fit::FitOptions;
use passive_assoc_core::geometry::model::{predict, Motion, Space, StateLayout};
use passive_assoc_core::parallel::with_threads;

/// Columnar measurement table plus CSR groups and initial states for `n` problems.
struct Batch {
    sensor: Vec<i64>,
    time: Vec<f64>,
    azimuth: Vec<f64>,
    elevation: Vec<f64>,
    indices: Vec<i64>,
    offsets: Vec<i64>,
    initial: Vec<f64>,
}

fn make_batch(
    layout: &StateLayout,
    positions: &[[f64; 3]],
    times: &[(usize, f64)],
    n: usize,
    sigma: f64,
) -> Batch {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let dim = layout.dim();
    let mut b = Batch {
        sensor: vec![],
        time: vec![],
        azimuth: vec![],
        elevation: vec![],
        indices: vec![],
        offsets: vec![0],
        initial: vec![],
    };
    for _ in 0..n {
        let mut truth = [0.0; 6];
        truth[0] = rng.random_range(-5e3..25e3);
        truth[1] = rng.random_range(2e3..30e3);
        if layout.space == Space::Spatial {
            truth[2] = rng.random_range(500.0..3000.0);
        }
        if dim > 3 {
            let p = layout.space.position_dim();
            truth[p] = rng.random_range(-250.0..250.0);
            truth[p + 1] = rng.random_range(-250.0..250.0);
        }
        for &(j, t) in times {
            let [a, e] = predict(layout.space, &positions[j], &layout.position(&truth, t));
            b.indices.push(b.sensor.len() as i64);
            b.sensor.push(j as i64);
            b.time.push(t);
            b.azimuth.push(a + sigma * rng.random_range(-1.7..1.7));
            b.elevation.push(e + sigma * rng.random_range(-1.7..1.7));
        }
        b.offsets.push(b.indices.len() as i64);
        b.initial
            .extend(truth[..dim].iter().map(|v| v * 1.01 + 20.0));
    }
    b
}

fn bench_batch(
    c: &mut Criterion,
    name: &str,
    layout: StateLayout,
    positions: &[[f64; 3]],
    times: &[(usize, f64)],
) {
    let flat: Vec<f64> = positions.iter().flatten().copied().collect();
    let sigmas = vec![5e-3; positions.len()];
    let sensors = Sensors::new(layout.space, &flat, &sigmas, &sigmas).expect("valid sensors");
    let b = make_batch(&layout, positions, times, 10_000, 5e-3);
    let table = Measurements::new(&sensors, &b.sensor, &b.time, &b.azimuth, &b.elevation)
        .expect("valid table");
    let problems = Problems {
        indices: &b.indices,
        offsets: &b.offsets,
        initial: Some(&b.initial),
    };
    let options = FitOptions::default();
    for threads in [1usize, 2] {
        c.bench_function(
            &format!("{name}/10000 problems/{threads} thread(s)"),
            |bencher| {
                bencher.iter_batched(
                    || (),
                    |_| {
                        with_threads(Some(threads), || {
                            fit_batch(&table, &sensors, &layout, &problems, &options)
                        })
                    },
                    BatchSize::SmallInput,
                )
            },
        );
    }
}

fn fits(c: &mut Criterion) {
    let cv3 = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
    let pair = [[0.0, 0.0, 0.0], [20_000.0, 0.0, 0.0]];
    bench_batch(
        c,
        "cv_6d_4_azel",
        cv3,
        &pair,
        &[(0, 0.0), (1, 5.0), (0, 105.0), (1, 110.0)],
    );
    let static2 = StateLayout::new(Space::Planar, Motion::Static);
    let trio = [
        [-15_000.0, 0.0, 0.0],
        [0.0, -5_000.0, 0.0],
        [15_000.0, 0.0, 0.0],
    ];
    bench_batch(
        c,
        "static_2d_3_bearings",
        static2,
        &trio,
        &[(0, 0.0), (1, 0.0), (2, 0.0)],
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = fits
}
criterion_main!(benches);
