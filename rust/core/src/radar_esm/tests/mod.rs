//! Tests of the coarse gate: small cases by hand, agreement with a naive nalgebra
//! implementation (`W (Σ_i + Σ_j) Wᵀ` built whole per pair and solved by LU), thread-count
//! invariance, and bad input; those of the full-covariance gate are `coupled`.

mod coupled;

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::error::{CoreError, CoreResult};
use crate::parallel::with_threads;

/// Random inputs: W (c × T), and per side coefficients (n, ndim, c) and variances (n, ndim, T).
struct Case {
    operator: Vec<f64>,
    c: usize,
    window: usize,
    ndim: usize,
    radar: (Vec<f64>, Vec<f64>),
    esm: (Vec<f64>, Vec<f64>),
}

impl Case {
    fn random(seed: u64, c: usize, window: usize, ndim: usize, n: (usize, usize)) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let operator = (0..c * window)
            .map(|_| rng.random_range(-1.0..1.0))
            .collect();
        let mut side = |n: usize| {
            let a = (0..n * ndim * c)
                .map(|_| rng.random_range(-3.0..3.0))
                .collect();
            let v = (0..n * ndim * window)
                .map(|_| rng.random_range(0.1..2.0))
                .collect();
            (a, v)
        };
        let (radar, esm) = (side(n.0), side(n.1));
        Self {
            operator,
            c,
            window,
            ndim,
            radar,
            esm,
        }
    }

    fn run(&self, options: &CoarseOptions) -> CoreResult<CoarseGate> {
        let op = Operator::new(&self.operator, self.c, self.window)?;
        let radar = CoarseTracks::new(Side::Radar, &self.radar.0, &self.radar.1, self.ndim, &op)?;
        let esm = CoarseTracks::new(Side::Esm, &self.esm.0, &self.esm.1, self.ndim, &op)?;
        coarse_gate(&op, &radar, &esm, options)
    }

    /// The statistic of pair (i, j) the slow, obvious way.
    fn naive(&self, i: usize, j: usize, whitened: bool) -> f64 {
        let (c, t, ndim) = (self.c, self.window, self.ndim);
        let w = DMatrix::from_row_slice(c, t, &self.operator);
        (0..ndim)
            .map(|k| {
                let ai = &self.radar.0[(i * ndim + k) * c..][..c];
                let aj = &self.esm.0[(j * ndim + k) * c..][..c];
                let d = DVector::from_iterator(c, ai.iter().zip(aj).map(|(x, y)| x - y));
                let vi = &self.radar.1[(i * ndim + k) * t..][..t];
                let vj = &self.esm.1[(j * ndim + k) * t..][..t];
                if whitened {
                    let sigma = DMatrix::from_diagonal(&DVector::from_iterator(
                        t,
                        vi.iter().zip(vj).map(|(x, y)| x + y),
                    ));
                    let s = &w * sigma * w.transpose();
                    let x = s.lu().solve(&d).unwrap();
                    d.dot(&x)
                } else {
                    let mean = |v: &[f64]| v.iter().sum::<f64>() / t as f64;
                    d.norm_squared() / (mean(vi) + mean(vj))
                }
            })
            .sum()
    }
}

fn options(threshold: f64, whitened: bool) -> CoarseOptions {
    CoarseOptions::new(threshold)
        .unwrap()
        .with_whitened(whitened)
}

#[test]
fn identity_operator_by_hand() {
    // W = I: C = diag(v); d = (1, 2), C_i + C_j = diag(2, 4) → 1/2 + 4/4.
    let w = [1.0, 0.0, 0.0, 1.0];
    let op = Operator::new(&w, 2, 2).unwrap();
    let radar = CoarseTracks::new(Side::Radar, &[1.0, 2.0], &[1.0, 1.0], 1, &op).unwrap();
    let esm = CoarseTracks::new(Side::Esm, &[0.0, 0.0], &[1.0, 3.0], 1, &op).unwrap();
    let gate = coarse_gate(&op, &radar, &esm, &options(1.5, true)).unwrap();
    assert!((gate.statistic[0] - 1.5).abs() < 1e-14);
    assert!(gate.passed[0], "the threshold itself passes");
    let gate = coarse_gate(&op, &radar, &esm, &options(1.49, true)).unwrap();
    assert!(!gate.passed[0]);
    // Unwhitened: mean variances 1 and 2 → |d|² / 3.
    let gate = coarse_gate(&op, &radar, &esm, &options(1.0, false)).unwrap();
    assert!((gate.statistic[0] - 5.0 / 3.0).abs() < 1e-14);
    assert!(!gate.passed[0]);
}

#[test]
fn two_by_two_operator_by_hand() {
    // W = [[1, 1], [0, 1]], v_i = (1, 1), v_j = 0: S = W Wᵀ = [[2, 1], [1, 1]],
    // S⁻¹ = [[1, −1], [−1, 2]].
    let w = [1.0, 1.0, 0.0, 1.0];
    let op = Operator::new(&w, 2, 2).unwrap();
    let radar = CoarseTracks::new(
        Side::Radar,
        &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        &[1.0; 6],
        1,
        &op,
    )
    .unwrap();
    let esm = CoarseTracks::new(Side::Esm, &[0.0, 0.0], &[0.0, 0.0], 1, &op).unwrap();
    let gate = coarse_gate(&op, &radar, &esm, &options(10.0, true)).unwrap();
    for (got, expected) in gate.statistic.iter().zip([1.0, 2.0, 1.0]) {
        assert!((got - expected).abs() < 1e-13, "{got} vs {expected}");
    }
    assert_eq!((gate.radar, gate.esm), (3, 1));
}

#[test]
fn coordinates_add_up() {
    // Two coordinates with W = I (1 × 1): each contributes d² / (v_i + v_j).
    let w = [1.0];
    let op = Operator::new(&w, 1, 1).unwrap();
    let radar = CoarseTracks::new(Side::Radar, &[1.0, 2.0], &[0.5, 1.0], 2, &op).unwrap();
    let esm = CoarseTracks::new(Side::Esm, &[0.0, 0.0], &[0.5, 1.0], 2, &op).unwrap();
    let gate = coarse_gate(&op, &radar, &esm, &options(10.0, true)).unwrap();
    assert!((gate.statistic[0] - (1.0 + 4.0 / 2.0)).abs() < 1e-14);
}

#[test]
fn agrees_with_the_naive_implementation() {
    // c = 1..8 take the fixed-size kernels, 9 and 12 the heap one; ndim 1 to 3.
    for (seed, c, window, ndim) in [
        (1, 1, 4, 1),
        (2, 3, 10, 2),
        (3, 6, 30, 1),
        (4, 6, 16, 3),
        (5, 8, 8, 2),
        (6, 9, 20, 1),
        (7, 12, 40, 2),
    ] {
        let case = Case::random(seed, c, window, ndim, (7, 5));
        for whitened in [true, false] {
            let gate = case
                .run(&options(3.0 * (ndim * c) as f64, whitened))
                .unwrap();
            for i in 0..7 {
                for j in 0..5 {
                    let (got, expected) = (gate.statistic[i * 5 + j], case.naive(i, j, whitened));
                    assert!(
                        (got - expected).abs() <= 1e-9 * expected.abs().max(1.0),
                        "c={c} ndim={ndim} whitened={whitened} ({i}, {j}): {got} vs {expected}"
                    );
                    assert_eq!(gate.passed[i * 5 + j], got <= 3.0 * (ndim * c) as f64);
                }
            }
        }
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    for c in [6, 10] {
        let case = Case::random(11, c, 24, 2, (300, 40));
        let o = options(20.0, true);
        let one = with_threads(Some(1), || case.run(&o)).unwrap().unwrap();
        let three = with_threads(Some(3), || case.run(&o)).unwrap().unwrap();
        let all = case.run(&o).unwrap();
        assert_eq!(one, three);
        assert_eq!(one, all);
    }
}

#[test]
fn a_pair_does_not_depend_on_the_other_tracks() {
    // 300 × 42 pairs run in parallel, ESM tracks in lane groups of four plus a tail of two;
    // each ESM track alone runs on the calling thread through the one-lane kernel.
    let case = Case::random(13, 6, 30, 2, (300, 42));
    let o = options(20.0, true);
    let all = case.run(&o).unwrap();
    let (c, t, ndim) = (case.c, case.window, case.ndim);
    for j in [0, 5, 39, 40, 41] {
        let alone = Case {
            esm: (
                case.esm.0[j * ndim * c..(j + 1) * ndim * c].to_vec(),
                case.esm.1[j * ndim * t..(j + 1) * ndim * t].to_vec(),
            ),
            operator: case.operator.clone(),
            radar: case.radar.clone(),
            ..case
        };
        let gate = alone.run(&o).unwrap();
        for i in 0..300 {
            assert_eq!(
                gate.statistic[i].to_bits(),
                all.statistic[i * 42 + j].to_bits(),
                "({i}, {j})"
            );
        }
    }
}

#[test]
fn empty_sides_give_empty_results() {
    let case = Case::random(3, 2, 4, 1, (0, 4));
    let gate = case.run(&options(1.0, true)).unwrap();
    assert!(gate.statistic.is_empty() && gate.passed.is_empty());
    assert_eq!((gate.radar, gate.esm), (0, 4));
    let case = Case::random(3, 2, 4, 1, (4, 0));
    assert!(case.run(&options(1.0, true)).unwrap().statistic.is_empty());
}

#[test]
fn a_singular_pair_is_named() {
    // The second radar and first ESM track have zero variance: C_i + C_j = 0.
    let w = [1.0, 0.0, 0.0, 1.0];
    let op = Operator::new(&w, 2, 2).unwrap();
    let radar = CoarseTracks::new(Side::Radar, &[0.0; 4], &[1.0, 1.0, 0.0, 0.0], 1, &op).unwrap();
    let esm = CoarseTracks::new(Side::Esm, &[0.0; 4], &[0.0, 0.0, 1.0, 1.0], 1, &op).unwrap();
    for whitened in [true, false] {
        let err = coarse_gate(&op, &radar, &esm, &options(1.0, whitened)).unwrap_err();
        let message = err.to_string();
        assert!(
            message.contains("radar track 1 and ESM track 0, coordinate 0"),
            "{message}"
        );
    }
    // A rank-deficient W (two equal rows) is singular whatever the variances.
    let w = [1.0, 0.0, 1.0, 0.0];
    let op = Operator::new(&w, 2, 2).unwrap();
    let radar = CoarseTracks::new(Side::Radar, &[0.0; 2], &[1.0; 2], 1, &op).unwrap();
    let esm = CoarseTracks::new(Side::Esm, &[0.0; 2], &[1.0; 2], 1, &op).unwrap();
    assert!(coarse_gate(&op, &radar, &esm, &options(1.0, true)).is_err());
}

#[test]
fn bad_input_is_refused_by_name() {
    let arg = |r: CoreResult<_>| match r {
        Err(CoreError::Shape { arg, .. })
        | Err(CoreError::NonFinite { arg, .. })
        | Err(CoreError::OutOfRange { arg, .. }) => arg,
        Err(other) => panic!("unexpected {other:?}"),
        Ok(()) => "ok",
    };
    let w = [0.5, 0.5, 0.0, 0.0, 0.5, 0.5];
    assert_eq!(arg(Operator::new(&w, 2, 2).map(|_| ())), "operator");
    assert_eq!(arg(Operator::new(&w, 3, 2).map(|_| ())), "operator");
    assert_eq!(arg(Operator::new(&w, 0, 6).map(|_| ())), "operator");
    assert_eq!(
        arg(Operator::new(&[f64::NAN; 6], 2, 3).map(|_| ())),
        "operator"
    );
    assert!(matches!(
        Operator::new(&vec![0.0; 300 * 300], 300, 300),
        Err(CoreError::CapExceeded { .. })
    ));
    let op = Operator::new(&w, 2, 3).unwrap();
    let tracks = |side, a: &[f64], v: &[f64], ndim| {
        arg(CoarseTracks::new(side, a, v, ndim, &op).map(|_| ()))
    };
    assert_eq!(tracks(Side::Radar, &[0.0; 2], &[1.0; 3], 1), "ok");
    assert_eq!(
        tracks(Side::Radar, &[0.0; 3], &[1.0; 3], 1),
        "radar_coefficients"
    );
    assert_eq!(tracks(Side::Esm, &[0.0; 2], &[1.0; 4], 1), "esm_variances");
    assert_eq!(
        tracks(Side::Esm, &[0.0; 2], &[1.0; 3], 0),
        "esm_coefficients"
    );
    assert_eq!(
        tracks(Side::Radar, &[f64::NAN, 0.0], &[1.0; 3], 1),
        "radar_coefficients"
    );
    assert_eq!(
        tracks(Side::Radar, &[0.0; 2], &[1.0, f64::INFINITY, 1.0], 1),
        "radar_variances"
    );
    assert_eq!(
        tracks(Side::Esm, &[0.0; 2], &[1.0, -1.0, 1.0], 1),
        "esm_variances"
    );
    // Different coordinate counts on the two sides.
    let radar = CoarseTracks::new(Side::Radar, &[0.0; 4], &[1.0; 6], 2, &op).unwrap();
    let esm = CoarseTracks::new(Side::Esm, &[0.0; 4], &[1.0; 6], 1, &op).unwrap();
    let mismatch = coarse_gate(&op, &radar, &esm, &options(1.0, true)).map(|_| ());
    assert_eq!(arg(mismatch), "esm_coefficients");
    // Tracks validated against another operator's shape.
    let other = Operator::new(&[1.0; 4], 2, 2).unwrap();
    let esm = CoarseTracks::new(Side::Esm, &[0.0; 4], &[1.0; 6], 2, &op).unwrap();
    let wrong = coarse_gate(&other, &radar, &esm, &options(1.0, true)).map(|_| ());
    assert_eq!(arg(wrong), "operator");
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(CoarseOptions::new(bad).is_err(), "{bad}");
    }
}
