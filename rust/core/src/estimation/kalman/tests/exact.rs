//! Noiseless tracks are reproduced exactly once the filter has started; the rows before are
//! NaN; a numerical failure leaves the rest of its track NaN.

use super::*;

/// A noiseless version of `spec` (zero process noise in the truth, measurements exact, the
/// filter still told about noise).
fn noiseless(spec: Spec) -> Scenario {
    let mut sc = simulate(&Spec { q: 0.0, ..spec });
    let n = sc.state_dim;
    let polar = spec.model.is_polar();
    for row in 0..sc.len() {
        let x = &sc.truth[row * n..(row + 1) * n];
        if polar {
            let s = sc.sensors.as_ref().expect("polar");
            let (dx, dy) = (x[0] - s[2 * row], x[1] - s[2 * row + 1]);
            sc.measurements[2 * row] = dx.hypot(dy);
            sc.measurements[2 * row + 1] = dy.atan2(dx);
        } else {
            let m = sc.columns;
            sc.measurements[row * m..(row + 1) * m].copy_from_slice(&x[..m]);
        }
    }
    sc
}

fn assert_reproduced(sc: &Scenario, out: &KalmanOutcome, first: usize, tol: f64) {
    let n = sc.state_dim;
    for p in 0..sc.offsets.len() - 1 {
        let (lo, hi) = (sc.offsets[p] as usize, sc.offsets[p + 1] as usize);
        for (k, row) in (lo..hi).enumerate() {
            let got = &out.states[row * n..(row + 1) * n];
            let want = &sc.truth[row * n..(row + 1) * n];
            if k < first {
                assert!(got.iter().all(|v| v.is_nan()), "row {row} before the start");
                assert!(out.nis[row].is_nan());
                continue;
            }
            for i in 0..n {
                assert!(
                    (got[i] - want[i]).abs() <= tol * (1.0 + want[i].abs()),
                    "row {row} component {i}: {} vs {}",
                    got[i],
                    want[i]
                );
            }
            if k > first {
                assert!(out.nis[row] < 1e-12, "row {row}: nis {}", out.nis[row]);
            }
        }
    }
}

#[test]
fn noiseless_cv_tracks_are_reproduced_in_every_dimension() {
    for dims in 1..=3 {
        let sc = noiseless(Spec {
            tracks: 5,
            ..Spec::new(
                MotionModel::ConstantVelocity,
                MeasurementModel::Position,
                dims,
            )
        });
        let options = KalmanOptions::new(MotionModel::ConstantVelocity, 3.0).expect("q");
        assert_reproduced(&sc, &sc.run(&options), 1, 1e-9);
    }
}

#[test]
fn noiseless_ca_recovers_the_acceleration() {
    for dims in [1, 2, 3] {
        let sc = noiseless(Spec {
            tracks: 5,
            ..Spec::new(
                MotionModel::ConstantAcceleration,
                MeasurementModel::Position,
                dims,
            )
        });
        let options = KalmanOptions::new(MotionModel::ConstantAcceleration, 0.1).expect("q");
        let out = sc.run(&options);
        assert_eq!(out.state_dim, 3 * dims);
        // Three-point start: the third row already has the exact acceleration.
        assert_reproduced(&sc, &out, 2, 1e-8);
    }
}

#[test]
fn noiseless_polar_tracks_are_reproduced_by_both_polar_models() {
    for model in [MeasurementModel::Polar, MeasurementModel::PolarConverted] {
        for motion in [
            MotionModel::ConstantVelocity,
            MotionModel::ConstantAcceleration,
        ] {
            // Targets west of the sensors, so some azimuths cross ±π.
            let sc = noiseless(Spec {
                tracks: 8,
                centre: [-20_000.0, 0.0, 0.0],
                spread: 2_000.0,
                ..Spec::new(motion, model, 2)
            });
            let options = KalmanOptions::new(motion, 1.0)
                .expect("q")
                .with_measurement(model);
            assert_reproduced(&sc, &sc.run(&options), motion.order() - 1, 1e-8);
        }
    }
}

#[test]
fn single_point_starts_at_the_first_row() {
    let sc = simulate(&Spec {
        tracks: 3,
        ..Spec::new(MotionModel::ConstantVelocity, MeasurementModel::Position, 2)
    });
    let options = KalmanOptions::new(MotionModel::ConstantVelocity, 1.0)
        .expect("q")
        .with_init(Init::SinglePoint)
        .with_init_velocity_std(300.0)
        .expect("std");
    let out = sc.run(&options);
    for &start in &sc.offsets[..3] {
        let row = start as usize;
        assert_eq!(
            &out.states[row * 4..row * 4 + 2],
            &sc.measurements[row * 2..row * 2 + 2]
        );
        assert_eq!(&out.states[row * 4 + 2..row * 4 + 4], &[0.0, 0.0]);
        assert_eq!(out.covariances[row * 16 + 2 * 4 + 2], 300.0 * 300.0);
        assert!(out.nis[row].is_nan() && out.nis[row + 1].is_finite());
    }
}

#[test]
fn a_short_track_gets_no_state_and_a_failed_update_ends_its_track() {
    // Track 0: a target on the x axis at 10, 15, 20, 25 m (t = 0..3) seen from the origin,
    // except that the third range is taken from (20, 0), where the filter predicts the
    // target exactly: no bearing there, so rows 2 and 3 stay NaN. Track 1: one row only.
    let input = KalmanInput {
        times: &[0.0, 1.0, 2.0, 3.0, 0.0],
        measurements: &[10.0, 0.0, 15.0, 0.0, 0.0, 0.0, 25.0, 0.0, 5.0, 1.0],
        columns: 2,
        noise: Noise::Std(&[1.0, 1e-3, 1.0, 1e-3, 1.0, 1e-3, 1.0, 1e-3, 1.0, 1e-3]),
        sensor_positions: Some(&[0.0, 0.0, 0.0, 0.0, 20.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
    };
    let tracks = Tracks {
        indices: &[0, 1, 2, 3, 4],
        offsets: &[0, 4, 5],
    };
    let options = KalmanOptions::new(MotionModel::ConstantVelocity, 1.0)
        .expect("q")
        .with_measurement(MeasurementModel::Polar);
    let out = kalman_filter(&input, &tracks, &options).expect("valid input");
    assert_eq!(&out.states[4..8], &[15.0, 0.0, 5.0, 0.0]);
    let has_state: Vec<bool> = (0..5).map(|r| !out.states[r * 4].is_nan()).collect();
    assert_eq!(has_state, [false, true, false, false, false]);
    assert!(out.covariances[16..32].iter().all(|v| v.is_finite()));
    assert!(out.covariances[32..].iter().all(|v| v.is_nan()));
}
