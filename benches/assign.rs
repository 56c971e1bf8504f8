//! Benchmarks of the assignment solvers (METHODS.md §2).
//!
//! * dense LAP on uniform [0, 1) costs, 100×100 and 1000×1000 — the target is at most 1.5×
//!   `scipy.optimize.linear_sum_assignment` on the same sizes;
//! * the S-D Lagrangian on S = 3 scans with ~18 and ~100 reports per sensor and a sparse,
//!   gated-looking tuple set (each report in a handful of tuples);
//! * the same on the shape `static_association.enumerate_candidates` produces (~1 200 and
//!   ~38 000 candidates): nearly every report pair of two sensors is a candidate at one shared
//!   cost, and ~0.7·n² triples, many nearly as cheap as the true ones;
//! * warm-started against cold inner 2-D solves on that shape, S = 3 and 4;
//! * the gated shape with the end-of-solve polish on and off (`with_polish`), in one run;
//! * the complete sparse LAP (SciPy sparse input) on 1000² uniform costs with 2 % of the
//!   entries allowed plus the diagonal, as `benches/bench_lap.py`'s gated case.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use passive_assoc_core::assign::lagrangian::{self, LagrangianOptions, WarmStart};
use passive_assoc_core::assign::lap::{solve_dense, solve_sparse_complete, SparseCosts};
use passive_assoc_core::assign::SdProblem;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

fn dense_lap(c: &mut Criterion) {
    let mut group = c.benchmark_group("lap_dense_uniform");
    for n in [100usize, 1000] {
        let mut rng = ChaCha8Rng::seed_from_u64(n as u64);
        let costs: Vec<f64> = (0..n * n).map(|_| rng.random::<f64>()).collect();
        if n == 1000 {
            group.sample_size(10);
        }
        group.bench_with_input(BenchmarkId::from_parameter(n), &costs, |b, costs| {
            b.iter(|| solve_dense(n, n, black_box(costs)))
        });
    }
    group.finish();
}

fn sparse_lap(c: &mut Criterion) {
    let n = 1000usize;
    let (mut keep_rng, mut cost_rng) = (ChaCha8Rng::seed_from_u64(7), ChaCha8Rng::seed_from_u64(8));
    let entries: Vec<(usize, usize, f64)> = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter(|&(i, j)| i == j || keep_rng.random_bool(0.02))
        .map(|(i, j)| (i, j, cost_rng.random::<f64>()))
        .collect();
    let costs = SparseCosts::from_triplets(n, n, &entries).expect("valid triplets");
    let mut group = c.benchmark_group("lap_sparse_gated");
    group.bench_with_input(BenchmarkId::from_parameter(n), &costs, |b, costs| {
        b.iter(|| solve_sparse_complete(black_box(costs)))
    });
    group.finish();
}

/// A synthetic S = 3 scan: `n` reports per sensor, ~90 % of them from `n` targets (sensor s
/// reports target t as report `perm_s[t]`), the rest clutter. Tuples: every target's full
/// triple (strongly negative cost) plus, per report, a few random "ghost" tuples through
/// neighbouring reports with weaker costs, and the intensity-2 sub-tuples — so each report
/// appears in a handful of tuples, as after gating.
fn sd_scan(n: usize, seed: u64) -> SdProblem {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let perms: Vec<Vec<usize>> = (0..3)
        .map(|_| {
            let mut p: Vec<usize> = (1..=n).collect();
            for i in (1..n).rev() {
                p.swap(i, rng.random_range(0..=i));
            }
            p
        })
        .collect();
    let (mut tuples, mut costs) = (Vec::new(), Vec::new());
    let mut push = |t: [usize; 3], c: f64| {
        tuples.extend_from_slice(&t);
        costs.push(c);
    };
    for t in 0..n {
        let full = [perms[0][t], perms[1][t], perms[2][t]];
        let c: f64 = rng.random_range(-25.0..-12.0);
        push(full, c);
        for drop in 0..3 {
            let mut sub = full;
            sub[drop] = 0;
            push(sub, c * rng.random_range(0.4..0.7));
        }
        for _ in 0..3 {
            // A ghost: shares one or two reports with target t, the rest from nearby targets.
            let mut g = full;
            for s in 0..3 {
                if rng.random_bool(0.5) {
                    let near = (t + rng.random_range(1..4)) % n;
                    g[s] = perms[s][near];
                }
            }
            push(g, rng.random_range(-14.0..-2.0));
        }
    }
    SdProblem::new(tuples, 3, costs, vec![n; 3]).expect("the generator builds valid input")
}

/// An S = 3 scan shaped like the enumerated candidates of `static_scan` (ratio 15): `n`
/// reports per sensor from `n` targets; each sensor pair's report pairs are candidates with
/// probability 0.97 at a cost shared by that sensor pair; the true triples cost about -13.7,
/// and ~0.7·n² ghost triples cost between that and -7.
fn sd_gated(n: usize, seed: u64) -> SdProblem {
    sd_gated_s(3, n, seed)
}

/// [`sd_gated`] for `s` sensors: every sensor pair's report pairs, true and ghost s-tuples
/// with costs scaled by s/3 (for s = 3 exactly `sd_gated`'s problem).
fn sd_gated_s(s: usize, n: usize, seed: u64) -> SdProblem {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut tuples, mut costs) = (Vec::new(), Vec::new());
    let pairs: Vec<((usize, usize), f64)> = if s == 3 {
        vec![((0, 1), -6.08), ((0, 2), -6.13), ((1, 2), -6.21)]
    } else {
        let all = (0..s).flat_map(|a| (a + 1..s).map(move |b| (a, b)));
        all.enumerate()
            .map(|(k, p)| (p, -6.08 - 0.03 * k as f64))
            .collect()
    };
    let scale = s as f64 / 3.0;
    for (pair, cost) in pairs {
        for i in 1..=n {
            for j in (1..=n).filter(|_| rng.random_bool(0.97)) {
                let mut t = vec![0; s];
                (t[pair.0], t[pair.1]) = (i, j);
                tuples.extend_from_slice(&t);
                costs.push(cost);
            }
        }
    }
    let perms: Vec<Vec<usize>> = (0..s)
        .map(|_| {
            let mut p: Vec<usize> = (1..=n).collect();
            for i in (1..n).rev() {
                p.swap(i, rng.random_range(0..=i));
            }
            p
        })
        .collect();
    for t in 0..n {
        tuples.extend(perms.iter().map(|p| p[t]));
        costs.push(rng.random_range(-13.71..-13.0) * scale);
    }
    for _ in 0..n * n * 7 / 10 {
        tuples.extend((0..s).map(|_| rng.random_range(1..=n)));
        costs.push(rng.random_range(-13.7..-7.0) * scale);
    }
    SdProblem::new(tuples, s, costs, vec![n; s]).expect("the generator builds valid input")
}

fn sd_lagrangian(c: &mut Criterion) {
    // The subgradient loop as measured (the recommended options add the polish).
    let options = LagrangianOptions::default().with_polish(false);
    for (name, make) in [
        ("sd_lagrangian_s3", sd_scan as fn(usize, u64) -> SdProblem),
        ("sd_lagrangian_s3_gated", sd_gated),
    ] {
        let mut group = c.benchmark_group(name);
        for n in [18usize, 100] {
            let problem = make(n, 42);
            group.bench_with_input(BenchmarkId::from_parameter(n), &problem, |b, p| {
                b.iter(|| lagrangian::solve(black_box(p), &options))
            });
        }
        group.finish();
    }
}

/// The same problems with the inner 2-D solves warm-started and cold, in one run: the
/// evidence for `WarmStart::Auto`'s policy.
fn sd_lagrangian_warm(c: &mut Criterion) {
    let mut group = c.benchmark_group("sd_lagrangian_warm");
    for (s, n) in [(3usize, 18usize), (3, 100), (4, 50)] {
        let problem = sd_gated_s(s, n, 42);
        for (mode, warm) in [("warm", WarmStart::Always), ("cold", WarmStart::Never)] {
            let options = LagrangianOptions::default()
                .with_polish(false)
                .with_warm_start(warm);
            let id = BenchmarkId::new(format!("s{s}_gated_{mode}"), n);
            group.bench_with_input(id, &problem, |b, p| {
                b.iter(|| lagrangian::solve(black_box(p), &options))
            });
        }
    }
    group.finish();
}

/// The gated shape with and without the end-of-solve polish, in one run: what it costs.
fn sd_lagrangian_polish(c: &mut Criterion) {
    let mut group = c.benchmark_group("sd_lagrangian_polish");
    for n in [18usize, 100] {
        let problem = sd_gated(n, 42);
        for (mode, polish) in [("on", true), ("off", false)] {
            let options = LagrangianOptions::default().with_polish(polish);
            let id = BenchmarkId::new(format!("s3_gated_{mode}"), n);
            group.bench_with_input(id, &problem, |b, p| {
                b.iter(|| lagrangian::solve(black_box(p), &options))
            });
        }
    }
    group.finish();
}

criterion_group!(
    benches,
    dense_lap,
    sparse_lap,
    sd_lagrangian,
    sd_lagrangian_warm,
    sd_lagrangian_polish
);
criterion_main!(benches);
