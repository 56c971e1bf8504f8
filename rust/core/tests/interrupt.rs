//! A stop request (Ctrl-C, through the binding's SIGINT handler) ends the batched fit and the
//! batched Kalman filter with `Interrupted` instead of running every problem, and reaches
//! every call running when it came, however the calls overlap. The requests are process-wide,
//! so these checks live in their own test binary (one process) and in one test, where no
//! other test can see them.

use passive_assoc_core::data::{Measurements, Sensors};
use passive_assoc_core::error::CoreError;
use passive_assoc_core::estimation::fit::batch::{fit_batch, Problems};
use passive_assoc_core::estimation::fit::FitOptions;
use passive_assoc_core::estimation::kalman::{
    kalman_filter, KalmanInput, KalmanOptions, MotionModel, Noise, Tracks,
};
use passive_assoc_core::geometry::model::{predict, Motion, Space, StateLayout};
use passive_assoc_core::parallel::{begin_call, clear_interrupt, interrupted, request_interrupt};
use passive_assoc_core::topology::{
    Associator, DecisionOptions, ScanTracks, Scoring, TopologyOptions,
};

#[test]
fn a_stop_request_ends_the_fit_and_the_filter() {
    // The fit: one 6-state problem of four az/el measurements from two sensors.
    let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
    let positions = [0.0, 0.0, 0.0, 20_000.0, 0.0, 0.0];
    let truth = [5e3, 20e3, 1e3, 100.0, -50.0, 0.0];
    let (sensor, time) = ([0i64, 1, 0, 1], [0.0, 5.0, 105.0, 110.0]);
    let (mut az, mut el) = (vec![], vec![]);
    for (&j, &t) in sensor.iter().zip(&time) {
        let at = &positions[3 * j as usize..3 * j as usize + 3];
        let [a, e] = predict(
            Space::Spatial,
            &[at[0], at[1], at[2]],
            &layout.position(&truth, t),
        );
        az.push(a);
        el.push(e);
    }
    let sigma = [5e-3; 2];
    let sensors = Sensors::new(Space::Spatial, &positions, &sigma, &sigma).unwrap();
    let table = Measurements::new(&sensors, &sensor, &time, &az, &el).unwrap();
    let problems = Problems {
        indices: &[0, 1, 2, 3],
        offsets: &[0, 4],
        initial: Some(&truth),
    };
    let fit = || fit_batch(&table, &sensors, &layout, &problems, &FitOptions::default());

    // The filter: one 1-D track of three exact positions.
    let input = KalmanInput {
        times: &[0.0, 1.0, 2.0],
        measurements: &[5.0, 15.0, 25.0],
        columns: 1,
        noise: Noise::Std(&[1.0, 1.0, 1.0]),
        sensor_positions: None,
    };
    let tracks = Tracks {
        indices: &[0, 1, 2],
        offsets: &[0, 3],
    };
    let options = KalmanOptions::new(MotionModel::ConstantVelocity, 0.0).unwrap();
    let filter = || kalman_filter(&input, &tracks, &options);

    request_interrupt();
    assert!(matches!(fit(), Err(CoreError::Interrupted)));
    assert!(matches!(filter(), Err(CoreError::Interrupted)));
    clear_interrupt();
    let fitted = fit().unwrap();
    assert!(
        (fitted.estimates[0] - truth[0]).abs() < 1.0,
        "{:?}",
        fitted.estimates
    );
    assert_eq!(&filter().unwrap().states[4..6], &[25.0, 10.0]);

    // Overlapping calls: a request made while a call runs reaches it even when a second call
    // starts and ends in the meantime (each call used to clear a shared flag on entry, so the
    // second swallowed the first's Ctrl-C), and the second call sees it too.
    let first = begin_call();
    assert!(!interrupted());
    request_interrupt();
    let second = begin_call();
    assert!(
        interrupted(),
        "the second call's start cleared the first's request"
    );
    assert!(matches!(fit(), Err(CoreError::Interrupted)));
    drop(second);
    assert!(
        interrupted(),
        "the second call's end cleared the first's request"
    );
    drop(first);
    // A call that starts once they are over does not answer to their request, nor to one
    // made while no call ran (the program's to handle).
    let later = begin_call();
    assert!(!interrupted());
    drop(later);
    request_interrupt();
    let after_idle = begin_call();
    assert!(!interrupted());
    assert!(fit().is_ok());
    drop(after_idle);

    // A track-to-track scan stops on a request, and the associator goes on pairing later
    // scans as one that never saw the stopped scan.
    let ids = [0_i64, 1, 2];
    let positions = [0.0, 0.0, 30e3, 0.0, 0.0, 45e3];
    let scan = ScanTracks::new("local", &ids, &positions, None).unwrap();
    let options = TopologyOptions::default();
    let decision = DecisionOptions::default()
        .with_threshold(0.5 * options.cells() as f64)
        .unwrap()
        .with_window(3)
        .unwrap();
    let mut used = Associator::new(Scoring::Topology(options), decision);
    let mut fresh = Associator::new(Scoring::Topology(options), decision);
    used.update(&scan, &scan).unwrap();
    request_interrupt();
    assert!(matches!(
        used.update(&scan, &scan),
        Err(CoreError::Interrupted)
    ));
    clear_interrupt();
    for _ in 0..2 {
        assert_eq!(
            used.update(&scan, &scan).unwrap(),
            fresh.update(&scan, &scan).unwrap()
        );
    }
}
