//! Benchmarks of radar/ESM association (METHODS §5).
//!
//! * `radar_esm/coarse/500x500`: the coarse gate's hot path — the whitened statistic and the
//!   pass flags of 500 radar × 500 ESM tracks, x axis only, a 30-scan window and 6
//!   approximation coefficients per track (what sym2 at 3 levels gives 30 scans in
//!   PyWavelets' symmetric mode), on all threads; `..._1_thread` on one; `..._unwhitened`
//!   the paper's scalar statistic; `..._full_covariance` the same pairs when each track brings
//!   its coefficients' full 6 × 6 covariance (Σ with cross-time terms, the wavelet-fuzzy
//!   associator's default when given the filter's q).
//!
//! The operator is a random 6 × 30 matrix: the work depends only on its shape, and the core
//! never sees PyWavelets (`benches/bench_coarse_gate.py` times the same gate with the real
//! sym2 operator against NumPy).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use passive_assoc_core::parallel::with_threads;
use passive_assoc_core::radar_esm::{
    coarse_gate, coarse_gate_coupled, CoarseOptions, CoarseTracks, CoupledTracks, Operator, Side,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const COEFFICIENTS: usize = 6;
const WINDOW: usize = 30;
/// χ²(6) at 0.99.
const THRESHOLD: f64 = 16.811893829770927;

/// Coefficients `(n, 1, c)` and per-scan variances `(n, 1, T)` of `n` tracks.
fn side(rng: &mut ChaCha8Rng, n: usize) -> (Vec<f64>, Vec<f64>) {
    let coefficients = (0..n * COEFFICIENTS)
        .map(|_| rng.random_range(-20e3..20e3))
        .collect();
    let variances = (0..n * WINDOW)
        .map(|_| rng.random_range(0.2e6..0.8e6))
        .collect();
    (coefficients, variances)
}

fn bench_coarse(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let operator: Vec<f64> = (0..COEFFICIENTS * WINDOW)
        .map(|_| rng.random_range(-0.5..0.5))
        .collect();
    let (radar_data, esm_data) = (side(&mut rng, 500), side(&mut rng, 500));
    let op = Operator::new(&operator, COEFFICIENTS, WINDOW).expect("valid operator");
    let radar =
        CoarseTracks::new(Side::Radar, &radar_data.0, &radar_data.1, 1, &op).expect("valid");
    let esm = CoarseTracks::new(Side::Esm, &esm_data.0, &esm_data.1, 1, &op).expect("valid");
    let whitened = CoarseOptions::new(THRESHOLD).expect("valid threshold");
    let unwhitened = whitened.with_whitened(false);
    let gate = coarse_gate(&op, &radar, &esm, &whitened).expect("runs");
    let passed = gate.passed.iter().filter(|&&p| p).count();
    eprintln!("500x500: {passed} of {} pairs pass", gate.passed.len());

    let mut group = c.benchmark_group("radar_esm/coarse");
    group.sample_size(20);
    let cases = [
        ("500x500", whitened, None),
        ("500x500_1_thread", whitened, Some(1)),
        ("500x500_unwhitened", unwhitened, None),
    ];
    for (label, options, threads) in cases {
        group.bench_function(label, |b| {
            b.iter(|| {
                with_threads(threads, || {
                    coarse_gate(black_box(&op), black_box(&radar), black_box(&esm), &options)
                })
                .expect("threads")
                .expect("runs")
                .statistic
                .len()
            })
        });
    }
    // Full covariances: C = W diag(v) Wᵀ plus a rank-one cross-time term, symmetric positive
    // definite, row-major (n, 6, 6).
    let full = |a: &[f64], v: &[f64]| -> Vec<f64> {
        let n = a.len() / COEFFICIENTS;
        let mut out = vec![0.0; n * COEFFICIENTS * COEFFICIENTS];
        for (k, cov) in out
            .chunks_exact_mut(COEFFICIENTS * COEFFICIENTS)
            .enumerate()
        {
            for x in 0..COEFFICIENTS {
                for y in 0..COEFFICIENTS {
                    let diagonal: f64 = (0..WINDOW)
                        .map(|t| {
                            operator[x * WINDOW + t] * v[k * WINDOW + t] * operator[y * WINDOW + t]
                        })
                        .sum();
                    cov[x * COEFFICIENTS + y] = diagonal + 0.3e6;
                }
            }
        }
        out
    };
    let (radar_full, esm_full) = (
        full(radar_data.0.as_slice(), &radar_data.1),
        full(&esm_data.0, &esm_data.1),
    );
    let radar_coupled =
        CoupledTracks::new(Side::Radar, &radar_data.0, &radar_full, COEFFICIENTS).expect("valid");
    let esm_coupled =
        CoupledTracks::new(Side::Esm, &esm_data.0, &esm_full, COEFFICIENTS).expect("valid");
    group.bench_function("500x500_full_covariance", |b| {
        b.iter(|| {
            coarse_gate_coupled(
                black_box(&radar_coupled),
                black_box(&esm_coupled),
                &whitened,
            )
            .expect("runs")
            .statistic
            .len()
        })
    });
    group.finish();
}

criterion_group!(benches, bench_coarse);
criterion_main!(benches);
