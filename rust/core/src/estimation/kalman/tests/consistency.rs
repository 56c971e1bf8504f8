//! Consistency: over many seeded runs (one track each) the filter's covariance matches its
//! actual errors — the average NEES at every step lies in the two-sided 99 % χ² band of
//! `runs × state_dim` degrees of freedom, and the average over all steps is close to the state
//! dimension. For the linear models with the exact start the NEES is χ²-distributed exactly;
//! the polar models are held to a looser overall band.

use super::*;

/// NEES figures of one scenario: the mean over all runs and steps, and how many steps'
/// run-averages fell outside the 99 % band.
struct Nees {
    mean: f64,
    mean_nis: f64,
    outside: usize,
    steps: usize,
}

fn measure(sc: &Scenario, out: &KalmanOutcome, runs: usize, steps: usize) -> Nees {
    let n = sc.state_dim as f64;
    let (low, high) = (
        chi2_quantile(runs as f64 * n, -2.575_829) / runs as f64,
        chi2_quantile(runs as f64 * n, 2.575_829) / runs as f64,
    );
    let (mut total, mut count, mut outside, mut measured) = (0.0, 0usize, 0, 0);
    for k in 0..steps {
        let values: Vec<f64> = (0..runs)
            .filter_map(|p| nees(out, &sc.truth, sc.offsets[p] as usize + k))
            .collect();
        if values.is_empty() {
            continue;
        }
        assert_eq!(values.len(), runs, "step {k}: some runs have no state");
        let mean = values.iter().sum::<f64>() / runs as f64;
        measured += 1;
        if !(low..=high).contains(&mean) {
            outside += 1;
        }
        total += values.iter().sum::<f64>();
        count += runs;
    }
    let nis: Vec<f64> = out.nis.iter().copied().filter(|v| v.is_finite()).collect();
    Nees {
        mean: total / count as f64,
        mean_nis: nis.iter().sum::<f64>() / nis.len() as f64,
        outside,
        steps: measured,
    }
}

/// Runs `spec` through `options` and checks the NEES: overall mean within `tolerance`
/// (relative) of the state dimension, NIS within it of the measurement dimension, and at
/// most 3 steps (of ~40, 0.4 expected at 99 %) outside the band.
fn check(label: &str, spec: Spec, options: KalmanOptions, tolerance: f64) {
    let sc = simulate(&spec);
    let out = sc.run(&options);
    let nees = measure(&sc, &out, spec.tracks, spec.steps);
    let (n, m) = (sc.state_dim as f64, sc.columns as f64);
    eprintln!(
        "NEES {label}: mean {:.3} for dimension {n} ({:+.1} %), NIS {:.3} for {m}, {} of {} steps outside the 99 % band of {} runs",
        nees.mean,
        100.0 * (nees.mean / n - 1.0),
        nees.mean_nis,
        nees.outside,
        nees.steps,
        spec.tracks
    );
    assert!(
        ((nees.mean / n) - 1.0).abs() < tolerance,
        "{label}: NEES {}",
        nees.mean
    );
    assert!(
        ((nees.mean_nis / m) - 1.0).abs() < tolerance,
        "{label}: NIS {}",
        nees.mean_nis
    );
    assert!(nees.outside <= 3, "{label}: {} steps outside", nees.outside);
}

#[test]
fn linear_models_are_consistent() {
    let cv = MotionModel::ConstantVelocity;
    let ca = MotionModel::ConstantAcceleration;
    let position = MeasurementModel::Position;
    check(
        "cv 2-D position, differencing",
        Spec {
            tracks: 400,
            ..Spec::new(cv, position, 2)
        },
        KalmanOptions::new(cv, 0.5).expect("q"),
        0.05,
    );
    check(
        "ca 1-D position, differencing",
        Spec {
            tracks: 400,
            q: 0.05,
            seed: 2,
            ..Spec::new(ca, position, 1)
        },
        KalmanOptions::new(ca, 0.05).expect("q"),
        0.05,
    );
    check(
        "ca 3-D position, differencing",
        Spec {
            tracks: 400,
            q: 0.05,
            seed: 3,
            ..Spec::new(ca, position, 3)
        },
        KalmanOptions::new(ca, 0.05).expect("q"),
        0.05,
    );
    // Initial velocities drawn from the single-point prior: the start is then exact too.
    check(
        "cv 3-D position, single_point",
        Spec {
            prior: Some((80.0, 0.0)),
            seed: 4,
            ..Spec::new(cv, position, 3)
        },
        KalmanOptions::new(cv, 0.5)
            .expect("q")
            .with_init(Init::SinglePoint)
            .with_init_velocity_std(80.0)
            .expect("std"),
        0.05,
    );
}

#[test]
fn polar_models_are_consistent() {
    let cv = MotionModel::ConstantVelocity;
    for (label, model, centre, seed) in [
        ("polar EKF, east", MeasurementModel::Polar, 20_000.0, 5),
        (
            "polar EKF, west (azimuth ±π)",
            MeasurementModel::Polar,
            -20_000.0,
            6,
        ),
        (
            "polar converted, east",
            MeasurementModel::PolarConverted,
            20_000.0,
            7,
        ),
    ] {
        check(
            label,
            Spec {
                centre: [centre, 0.0, 0.0],
                seed,
                ..Spec::new(cv, model, 2)
            },
            KalmanOptions::new(cv, 0.5)
                .expect("q")
                .with_measurement(model),
            0.10,
        );
    }
    let ca = MotionModel::ConstantAcceleration;
    check(
        "polar EKF, ca",
        Spec {
            q: 0.05,
            seed: 8,
            ..Spec::new(ca, MeasurementModel::Polar, 2)
        },
        KalmanOptions::new(ca, 0.05)
            .expect("q")
            .with_measurement(MeasurementModel::Polar),
        0.10,
    );
}

/// The polar EKF against a linear filter on the same truth and the same noise draws,
/// linearised at the truth (full covariances per row): the estimates agree to a small
/// fraction of their error.
#[test]
fn polar_ekf_agrees_with_the_cartesian_filter_on_the_same_truth() {
    let cv = MotionModel::ConstantVelocity;
    let spec = Spec::new(cv, MeasurementModel::Polar, 2);
    let sc = simulate(&spec);
    let sensors = sc.sensors.as_ref().expect("polar");
    let (mut points, mut covariances) = (vec![], vec![]);
    for row in 0..sc.len() {
        let (x, y) = (sc.truth[row * 4], sc.truth[row * 4 + 1]);
        let (dx, dy) = (x - sensors[2 * row], y - sensors[2 * row + 1]);
        let (range, azimuth) = (dx.hypot(dy), dy.atan2(dx));
        let n_r = sc.measurements[2 * row] - range;
        let n_a = wrap(sc.measurements[2 * row + 1] - azimuth);
        let (s, c) = azimuth.sin_cos();
        let j = [[c, -range * s], [s, range * c]];
        points.extend([
            x + j[0][0] * n_r + j[0][1] * n_a,
            y + j[1][0] * n_r + j[1][1] * n_a,
        ]);
        let var = [spec.std[0].powi(2), spec.std[1].powi(2)];
        for a in 0..2 {
            for b in 0..2 {
                covariances.push(j[a][0] * j[b][0] * var[0] + j[a][1] * j[b][1] * var[1]);
            }
        }
    }
    let cartesian = KalmanInput {
        times: &sc.times,
        measurements: &points,
        columns: 2,
        noise: Noise::Covariance(&covariances),
        sensor_positions: None,
    };
    let options = KalmanOptions::new(cv, spec.q).expect("q");
    let linear = kalman_filter(&cartesian, &sc.tracks(), &options).expect("valid input");
    let ekf = sc.run(&options.with_measurement(MeasurementModel::Polar));
    let (mut diff, mut err) = (0.0, 0.0);
    for row in (0..sc.len()).filter(|&r| !ekf.states[r * 4].is_nan()) {
        for a in 0..2 {
            diff += (ekf.states[row * 4 + a] - linear.states[row * 4 + a]).powi(2);
            err += (linear.states[row * 4 + a] - sc.truth[row * 4 + a]).powi(2);
        }
    }
    let ratio = (diff / err).sqrt();
    eprintln!("polar EKF vs linearised-at-truth filter: RMS difference / RMS error = {ratio:.4}");
    assert!(ratio < 0.05, "{ratio}");
}
