//! Benchmarks of track-to-track association by reference topology (METHODS §4): one scan of
//! one local source against the system picture — both sources' topology vectors, the
//! closeness matrix and the one-to-one decision — as `Associator::update` runs it.
//!
//! * `topology/scan/20x20`: the paper's picture size (20 targets; small enough that it runs on
//!   the calling thread);
//! * `topology/scan/2000x2000`: a large picture, 2 000 tracks per source in a 2 000 km square
//!   (about as many neighbours per 120 km disc as the paper's), every pair scored, on all
//!   threads; `..._gate_60km` with the paper's suggested 60 km position gate;
//!
//! window 1, λ = 0.6; the local picture is the system's turned by 3° about a radar 250 km away,
//! with ±500 m noise.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use passive_assoc_core::topology::{
    candidate_pairs, decide, pair_closeness, topology_vectors, Associator, Decision,
    DecisionOptions, Gate, ScanTracks, Scoring, TopologyOptions,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// System and local positions of `n` targets in a square of side `side` metres.
fn pictures(n: usize, side: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let system: Vec<f64> = (0..2 * n)
        .map(|_| rng.random_range(-side / 2.0..side / 2.0))
        .collect();
    let (angle, radar): (f64, [f64; 2]) = (3f64.to_radians(), [250e3, 0.0]);
    let (c, s) = (angle.cos(), angle.sin());
    let local = system
        .chunks_exact(2)
        .flat_map(|p| {
            let (x, y) = (p[0] - radar[0], p[1] - radar[1]);
            let noise = [
                rng.random_range(-500.0..500.0),
                rng.random_range(-500.0..500.0),
            ];
            [
                c * x - s * y + radar[0] + noise[0],
                s * x + c * y + radar[1] + noise[1],
            ]
        })
        .collect();
    (system, local)
}

fn associator(gate: Option<f64>) -> Associator {
    let grid = TopologyOptions::default();
    let decision = DecisionOptions::default()
        .with_threshold(0.6 * grid.cells() as f64)
        .and_then(|d| d.with_window(1))
        .and_then(|d| d.with_gate(gate.map_or(Gate::Off, Gate::Distance)))
        .map(|d| d.with_decision(Decision::Assignment))
        .unwrap_or_default();
    Associator::new(Scoring::Topology(grid), decision)
}

fn bench_scan(c: &mut Criterion) {
    let mut group = c.benchmark_group("topology/scan");
    let cases = [
        (20, 200e3, None, "20x20"),
        (2000, 2000e3, None, "2000x2000"),
        (2000, 2000e3, Some(60e3), "2000x2000_gate_60km"),
    ];
    for (n, side, gate, label) in cases {
        let (system, local) = pictures(n, side, 7);
        let ids: Vec<i64> = (0..n as i64).collect();
        let sys = ScanTracks::new("system", &ids, &system, None).expect("valid");
        let loc = ScanTracks::new("local", &ids, &local, None).expect("valid");
        let pairs = associator(gate).update(&loc, &sys).expect("runs");
        eprintln!("{label}: {} pairs of {n}", pairs.pairs.len());
        group.sample_size(if n > 100 { 10 } else { 100 });
        group.bench_function(label, |b| {
            b.iter(|| {
                associator(gate)
                    .update(black_box(&loc), black_box(&sys))
                    .expect("runs")
                    .pairs
                    .len()
            })
        });
    }
    group.finish();
}

/// The stages of one ungated 2 000 × 2 000 scan apart, to show where its time goes: the
/// vectors of both sources, the closeness of all 4 million pairs, and the decision at three
/// thresholds (the share of pairs above λ decides the assignment's size).
fn bench_stages(c: &mut Criterion) {
    let mut group = c.benchmark_group("topology/stage_2000");
    group.sample_size(10);
    let (system, local) = pictures(2000, 2000e3, 7);
    let ids: Vec<i64> = (0..2000).collect();
    let sys = ScanTracks::new("system", &ids, &system, None).expect("valid");
    let loc = ScanTracks::new("local", &ids, &local, None).expect("valid");
    let grid = TopologyOptions::default();
    group.bench_function("vectors", |b| {
        b.iter(|| {
            (
                topology_vectors(&loc, &grid).len(),
                topology_vectors(&sys, &grid).len(),
            )
        })
    });
    let (a, v) = (topology_vectors(&loc, &grid), topology_vectors(&sys, &grid));
    let pairs = candidate_pairs(&loc, &sys, None);
    group.bench_function("closeness", |b| {
        b.iter(|| pair_closeness(&a, &v, grid.cells(), &pairs).len())
    });
    let scores = pair_closeness(&a, &v, grid.cells(), &pairs);
    for fraction in [0.6, 0.7, 0.75, 0.85] {
        let threshold = fraction * grid.cells() as f64;
        let allowed = scores.iter().filter(|&&s| s > threshold).count();
        eprintln!(
            "λ = {fraction}: {allowed} of {} pairs above it",
            scores.len()
        );
        group.bench_function(format!("decide_lambda_{fraction}"), |b| {
            b.iter(|| {
                decide(
                    &pairs,
                    &scores,
                    (2000, 2000),
                    threshold,
                    Decision::Assignment,
                )
                .expect("decides")
                .len()
            })
        });
    }
    group.finish();
}

/// The window's cost: one ungated 2 000 × 2 000 scan at the default λ with a window of 1 and
/// of 6, first as a fresh associator's first scan, then as the sixth scan of a window of 6
/// (the same pictures each scan, so every pair has five earlier scores to average).
fn bench_window(c: &mut Criterion) {
    let mut group = c.benchmark_group("topology/window_2000");
    group.sample_size(10);
    let (system, local) = pictures(2000, 2000e3, 7);
    let ids: Vec<i64> = (0..2000).collect();
    let sys = ScanTracks::new("system", &ids, &system, None).expect("valid");
    let loc = ScanTracks::new("local", &ids, &local, None).expect("valid");
    let fresh = |window: usize| {
        let decision = DecisionOptions::default()
            .with_window(window)
            .unwrap_or_default();
        Associator::new(Scoring::Topology(TopologyOptions::default()), decision)
    };
    for window in [1, 6] {
        group.bench_function(format!("first_scan_window_{window}"), |b| {
            b.iter(|| fresh(window).update(&loc, &sys).expect("runs").pairs.len())
        });
    }
    let mut warmed = fresh(6);
    for _ in 0..5 {
        warmed.update(&loc, &sys).expect("runs");
    }
    group.bench_function("sixth_scan_window_6", |b| {
        b.iter_batched(
            || warmed.clone(),
            |mut a| a.update(&loc, &sys).expect("runs").pairs.len(),
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(benches, bench_scan, bench_stages, bench_window);
criterion_main!(benches);
