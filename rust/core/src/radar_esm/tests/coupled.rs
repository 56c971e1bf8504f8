//! Tests of the full-covariance coarse gate: agreement with a naive nalgebra solve and with
//! the per-scan-variance gate when Σ is diagonal, thread-count invariance, bad input.

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::error::CoreError;
use crate::parallel::with_threads;
use crate::radar_esm::*;

/// `n` tracks of `m` coefficients with random symmetric positive-definite covariances
/// `A Aᵀ + 0.1 I`.
fn side(rng: &mut ChaCha8Rng, n: usize, m: usize) -> (Vec<f64>, Vec<f64>) {
    let coefficients = (0..n * m).map(|_| rng.random_range(-3.0..3.0)).collect();
    let mut covariances = Vec::with_capacity(n * m * m);
    for _ in 0..n {
        let a = DMatrix::from_fn(m, m, |_, _| rng.random_range(-1.0..1.0));
        let c = &a * a.transpose() + DMatrix::identity(m, m) * 0.1;
        // Row-major; C is symmetric, so nalgebra's column-major storage reads the same.
        covariances.extend(c.iter().copied());
    }
    (coefficients, covariances)
}

fn naive(
    radar: &(Vec<f64>, Vec<f64>),
    esm: &(Vec<f64>, Vec<f64>),
    m: usize,
    i: usize,
    j: usize,
) -> f64 {
    let d = DVector::from_iterator(m, (0..m).map(|a| radar.0[i * m + a] - esm.0[j * m + a]));
    let s = DMatrix::from_fn(m, m, |a, b| {
        radar.1[(i * m + a) * m + b] + esm.1[(j * m + a) * m + b]
    });
    d.dot(&s.lu().solve(&d).unwrap())
}

fn options(threshold: f64) -> CoarseOptions {
    CoarseOptions::new(threshold).unwrap()
}

#[test]
fn agrees_with_the_naive_solve() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for (m, n) in [
        (1, (3, 4)),
        (6, (5, 9)),
        (7, (2, 3)),
        (12, (6, 5)),
        (20, (3, 2)),
    ] {
        let (radar, esm) = (side(&mut rng, n.0, m), side(&mut rng, n.1, m));
        let r = CoupledTracks::new(Side::Radar, &radar.0, &radar.1, m).unwrap();
        let e = CoupledTracks::new(Side::Esm, &esm.0, &esm.1, m).unwrap();
        let gate = coarse_gate_coupled(&r, &e, &options(m as f64)).unwrap();
        for i in 0..n.0 {
            for j in 0..n.1 {
                let (got, expected) = (gate.statistic[i * n.1 + j], naive(&radar, &esm, m, i, j));
                assert!(
                    (got - expected).abs() <= 1e-9 * expected.max(1.0),
                    "m {m} ({i}, {j}): {got} vs {expected}"
                );
                assert_eq!(gate.passed[i * n.1 + j], got <= m as f64);
            }
        }
    }
}

#[test]
fn a_diagonal_sigma_gives_the_per_scan_gate() {
    // C = W diag(v) Wᵀ built by hand, one coordinate: both paths compute the same form.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (c, t, n) = (4, 9, 5);
    let w: Vec<f64> = (0..c * t).map(|_| rng.random_range(-1.0..1.0)).collect();
    let mut sides = Vec::new();
    for _ in 0..2 {
        let a: Vec<f64> = (0..n * c).map(|_| rng.random_range(-3.0..3.0)).collect();
        let v: Vec<f64> = (0..n * t).map(|_| rng.random_range(0.1..2.0)).collect();
        let full: Vec<f64> = (0..n)
            .flat_map(|k| {
                let (w, v) = (&w, &v);
                (0..c * c).map(move |e| {
                    (0..t)
                        .map(|s| w[e / c * t + s] * v[k * t + s] * w[e % c * t + s])
                        .sum()
                })
            })
            .collect();
        sides.push((a, v, full));
    }
    let op = Operator::new(&w, c, t).unwrap();
    let per_scan = coarse_gate(
        &op,
        &CoarseTracks::new(Side::Radar, &sides[0].0, &sides[0].1, 1, &op).unwrap(),
        &CoarseTracks::new(Side::Esm, &sides[1].0, &sides[1].1, 1, &op).unwrap(),
        &options(9.0),
    )
    .unwrap();
    let full = coarse_gate_coupled(
        &CoupledTracks::new(Side::Radar, &sides[0].0, &sides[0].2, c).unwrap(),
        &CoupledTracks::new(Side::Esm, &sides[1].0, &sides[1].2, c).unwrap(),
        &options(9.0),
    )
    .unwrap();
    for (x, y) in per_scan.statistic.iter().zip(&full.statistic) {
        assert!((x - y).abs() <= 1e-10 * x.max(1.0), "{x} vs {y}");
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    // 100 × 100 pairs take the parallel path.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (radar, esm) = (side(&mut rng, 100, 6), side(&mut rng, 100, 6));
    let r = CoupledTracks::new(Side::Radar, &radar.0, &radar.1, 6).unwrap();
    let e = CoupledTracks::new(Side::Esm, &esm.0, &esm.1, 6).unwrap();
    let run = |threads| {
        with_threads(threads, || coarse_gate_coupled(&r, &e, &options(16.8)))
            .unwrap()
            .unwrap()
    };
    let one = run(Some(1));
    for threads in [Some(2), Some(3), None] {
        let other = run(threads);
        let bits = |g: &CoarseGate| g.statistic.iter().map(|s| s.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&one), bits(&other), "{threads:?}");
    }
}

#[test]
fn bad_input_is_refused_by_name() {
    let arg = |e: CoreError| e.to_string();
    let err = CoupledTracks::new(Side::Esm, &[0.0, 0.0], &[1.0, 0.2, 0.3, 1.0], 2).unwrap_err();
    assert!(arg(err).contains("esm_covariances"));
    let err = CoupledTracks::new(Side::Radar, &[0.0], &[-1.0], 1).unwrap_err();
    assert!(arg(err).contains("radar_covariances"));
    let err =
        CoupledTracks::new(Side::Radar, &[0.0, f64::NAN], &[1.0, 0.0, 0.0, 1.0], 2).unwrap_err();
    assert!(arg(err).contains("radar_coefficients"));
    assert!(CoupledTracks::new(Side::Radar, &[0.0; 3], &[1.0; 4], 2).is_err());
    assert!(CoupledTracks::new(Side::Radar, &[0.0; 2], &[1.0; 3], 2).is_err());
    assert!(CoupledTracks::new(Side::Radar, &[], &[], 0).is_err());

    let one = CoupledTracks::new(Side::Radar, &[0.0], &[1.0], 1).unwrap();
    let two = CoupledTracks::new(Side::Esm, &[0.0, 0.0], &[1.0, 0.0, 0.0, 1.0], 2).unwrap();
    assert!(
        arg(coarse_gate_coupled(&one, &two, &options(1.0)).unwrap_err())
            .contains("esm_coefficients")
    );
    let unwhitened = options(1.0).with_whitened(false);
    assert!(arg(coarse_gate_coupled(&one, &one, &unwhitened).unwrap_err()).contains("whitened"));

    // Zero covariance on both sides: the pair is named.
    let zero = CoupledTracks::new(Side::Esm, &[0.0, 1.0], &[1.0, 0.0], 1).unwrap();
    let none = CoupledTracks::new(Side::Radar, &[0.0], &[0.0], 1).unwrap();
    let err = arg(coarse_gate_coupled(&none, &zero, &options(1.0)).unwrap_err());
    assert!(err.contains("radar track 0 and ESM track 1"), "{err}");
}

#[test]
fn empty_sides_give_empty_results() {
    let none = CoupledTracks::new(Side::Radar, &[], &[], 3).unwrap();
    let gate = coarse_gate_coupled(&none, &none, &options(1.0)).unwrap();
    assert!(gate.statistic.is_empty() && gate.passed.is_empty());
}
