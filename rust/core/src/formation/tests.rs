use super::*;
use crate::data::{Measurements, Sensors};
use crate::error::CoreError;
use crate::evidence::{AttributeGate, AttributeTable, Combination};
use crate::geometry::model::Space;
use crate::parallel::with_threads;

const SENSORS: [[f64; 2]; 3] = [[-80e3, -30e3], [-30e3, -30e3], [20e3, -30e3]];
const TARGETS: [[f64; 2]; 6] = [
    [-27.5e3, 60e3],
    [-22.5e3, 60e3],
    [-17.5e3, 60e3],
    [-60e3, 70e3],
    [-45e3, 70e3],
    [0.0, 70e3],
];
const ATTRIBUTES: [[f64; 4]; 6] = [
    [4008.0, 1005.0, 4.9, 2.2],
    [7991.0, 1488.0, 6.3, 5.2],
    [6011.0, 1211.0, 5.5, 4.3],
    [3987.0, 994.0, 5.1, 1.8],
    [4002.0, 1007.0, 4.6, 1.9],
    [6000.0, 1202.0, 5.3, 4.5],
];
const STD: [f64; 4] = [10.0, 5.0, 0.2, 0.2];

/// The paper's scene, sensor-major rows (row = 6 s + t), bearings perturbed by `noise(row)`.
struct Scene {
    positions: Vec<f64>,
    sigma: Vec<f64>,
    sensor: Vec<i64>,
    time: Vec<f64>,
    azimuth: Vec<f64>,
    values: Vec<f64>,
    stds: Vec<f64>,
}

fn paper_scene(noise: impl Fn(usize) -> f64) -> Scene {
    let mut scene = Scene {
        positions: SENSORS.iter().flat_map(|p| [p[0], p[1], 0.0]).collect(),
        sigma: vec![1e-3; 3],
        sensor: Vec::new(),
        time: Vec::new(),
        azimuth: Vec::new(),
        values: Vec::new(),
        stds: Vec::new(),
    };
    for (s, p) in SENSORS.iter().enumerate() {
        for (t, target) in TARGETS.iter().enumerate() {
            let row = scene.sensor.len();
            scene.sensor.push(s as i64);
            scene.time.push(0.0);
            scene
                .azimuth
                .push((target[1] - p[1]).atan2(target[0] - p[0]) + noise(row));
            scene.values.extend(ATTRIBUTES[t]);
            scene.stds.extend(STD);
        }
    }
    scene
}

fn run(scene: &Scene, attributes: bool, options: &FormationOptions) -> FormationOutput {
    let sensors =
        Sensors::new(Space::Planar, &scene.positions, &scene.sigma, &[]).expect("sensors");
    let meas = Measurements::new(&sensors, &scene.sensor, &scene.time, &scene.azimuth, &[])
        .expect("measurements");
    let n = scene.sensor.len();
    let (values, stds) = (
        attribute_major(&scene.values, 4),
        attribute_major(&scene.stds, 4),
    );
    let gate = attributes.then(|| {
        let table = AttributeTable::new(&values, &stds, n, 4).expect("table");
        AttributeGate::new(table, Combination::SimpleSupport, 0.6).expect("gate")
    });
    locate(&sensors, &meas, gate, options).expect("locate")
}

/// Whether baseline report t chose target t's line at every sensor.
fn correct(out: &FormationOutput, t: usize) -> bool {
    (0..3).all(|s| out.rows[3 * t + s] == (6 * s + t) as i64)
}

#[test]
fn noiseless_paper_scene_with_attributes_is_exact_and_located() {
    let out = run(&paper_scene(|_| 0.0), true, &FormationOptions::default());
    for (t, target) in TARGETS.iter().enumerate() {
        assert!(
            correct(&out, t),
            "target {t}: rows {:?}",
            &out.rows[3 * t..3 * t + 3]
        );
        assert!(out.radius[t] < 1e-6);
        assert!((out.positions[2 * t] - target[0]).abs() < 1e-6);
        assert!((out.positions[2 * t + 1] - target[1]).abs() < 1e-6);
        assert!(out.covariances[4 * t] > 0.0 && out.support[3 * t + 1] == 1.0);
    }
    assert_eq!(out.baseline_rows, vec![0, 1, 2, 3, 4, 5]);
}

#[test]
fn noiseless_azimuth_only_falls_for_the_exact_ghost() {
    // S1→T1, S2→T2, S3→T3 meet where S1→T3, S2→T2, S3→T1 do (METHODS §3): radius 0 twice,
    // so target 1's baseline keeps the first reference point it scores and one of T1/T3 fails.
    let out = run(&paper_scene(|_| 0.0), false, &FormationOptions::default());
    assert!(!(correct(&out, 0) && correct(&out, 2)));
    assert!(correct(&out, 1) && correct(&out, 3) && correct(&out, 4));
    // The one-to-one variant cannot give sensor 1's T2 line to two baselines either way,
    // and every row is used at most once.
    let one = run(
        &paper_scene(|_| 0.0),
        false,
        &FormationOptions::default().with_one_to_one(true),
    );
    let mut used: Vec<i64> = one.rows.iter().copied().filter(|&r| r >= 0).collect();
    used.sort_unstable();
    let before = used.len();
    used.dedup();
    assert_eq!(before, used.len(), "a row chosen twice: {:?}", one.rows);
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let noisy = paper_scene(|row| 0.02 * ((row * 7919 % 13) as f64 / 13.0 - 0.5));
    for one_to_one in [false, true] {
        let o = FormationOptions::default().with_one_to_one(one_to_one);
        let one = with_threads(Some(1), || run(&noisy, true, &o)).expect("pool");
        let two = with_threads(Some(2), || run(&noisy, true, &o)).expect("pool");
        // Debug text compares NaN entries (no association, the baseline's support) as equal.
        assert_eq!(format!("{one:?}"), format!("{two:?}"));
    }
}

#[test]
fn range_region_and_direction_prune_meetings() {
    let scene = paper_scene(|_| 0.0);
    let wide = run(&scene, false, &FormationOptions::default());
    assert_eq!(wide.counts.pairs, 6 * 12);
    let short = FormationOptions::default().with_r_max(50e3).expect("r_max");
    let out = run(&scene, false, &short);
    assert!(out.counts.out_of_range > 0);
    assert!(
        out.radius.iter().all(|r| r.is_nan()),
        "every target is beyond 50 km"
    );
    let region = FormationOptions::default()
        .with_region([-70e3, 10e3, 50e3, 80e3])
        .expect("region");
    let out = run(&scene, true, &region);
    assert!(out.counts.outside_region > 0);
    assert!((0..6).all(|t| correct(&out, t)));
    // Diverging lines meet behind the sensors, ~500 km away: within range only when it is far.
    let far = FormationOptions::default().with_r_max(1e7).expect("r_max");
    let front = run(&scene, false, &far.with_in_front(true));
    assert!(front.counts.behind > 0);
}

#[test]
fn bad_networks_and_options_are_errors_naming_the_argument() {
    let scene = paper_scene(|_| 0.0);
    let sensors =
        Sensors::new(Space::Planar, &scene.positions, &scene.sigma, &[]).expect("sensors");
    let meas = Measurements::new(&sensors, &scene.sensor, &scene.time, &scene.azimuth, &[])
        .expect("measurements");
    let err = |o: FormationOptions| {
        locate(&sensors, &meas, None, &o)
            .expect_err("must fail")
            .to_string()
    };
    assert!(err(FormationOptions::default().with_baseline_sensor(3)).starts_with("baseline_sensor"));
    assert!(
        err(FormationOptions::default().with_reference(Reference::Sensor(0)))
            .starts_with("reference")
    );
    let two =
        Sensors::new(Space::Planar, &scene.positions[..6], &scene.sigma[..2], &[]).expect("2");
    let rows: Vec<i64> = scene.sensor.iter().map(|&s| s.min(1)).collect();
    let meas2 = Measurements::new(&two, &rows, &scene.time, &scene.azimuth, &[]).expect("m");
    let e = locate(&two, &meas2, None, &FormationOptions::default()).expect_err("2 sensors");
    assert!(e.to_string().contains("at least 3 sensors"));
    let short = AttributeTable::new(&scene.values[..8], &scene.stds[..8], 2, 4).expect("table");
    let gate = AttributeGate::new(short, Combination::SimpleSupport, 0.6).expect("gate");
    let e = locate(&sensors, &meas, Some(gate), &FormationOptions::default()).expect_err("rows");
    assert!(e.to_string().starts_with("attributes"));
}

/// Row-major `N × k` → the core's attribute-major `k × N`.
fn attribute_major(row_major: &[f64], k: usize) -> Vec<f64> {
    let n = row_major.len() / k;
    (0..k * n)
        .map(|at| row_major[(at % n) * k + at / n])
        .collect()
}

/// The pairs a location examines are capped before any work (3 sensors × 16 000 reports once
/// ran 90 CPU-s unchecked): the paper's scene has 6 × 12 of them.
#[test]
fn more_pairs_than_the_cap_are_refused_before_any_work() {
    let scene = paper_scene(|_| 0.0);
    let sensors =
        Sensors::new(Space::Planar, &scene.positions, &scene.sigma, &[]).expect("sensors");
    let meas = Measurements::new(&sensors, &scene.sensor, &scene.time, &scene.azimuth, &[])
        .expect("measurements");
    let at = |cap: usize| {
        FormationOptions::default()
            .with_max_pairs(cap)
            .expect("cap")
    };
    assert!(locate(&sensors, &meas, None, &at(72)).is_ok());
    let e = locate(&sensors, &meas, None, &at(71)).expect_err("over the cap");
    assert_eq!(
        e,
        CoreError::CapExceeded {
            what: "(baseline report, other report) pairs",
            count: 72,
            cap: 71,
            hint: "raise max_pairs, or locate a smaller snapshot (the work grows with the pairs)",
        }
    );
    assert!(FormationOptions::default().with_max_pairs(0).is_err());
    assert_eq!(FormationOptions::default().max_pairs(), DEFAULT_MAX_PAIRS);
}

/// A sink that records the reports and cancels from the `cancel_after`-th on.
#[derive(Debug, Default)]
struct Watcher {
    reports: std::sync::Mutex<Vec<(&'static str, f64)>>,
    cancel_after: Option<usize>,
}

impl crate::progress::Progress for Watcher {
    fn report(&self, stage: &'static str, fraction: f64) {
        self.reports.lock().expect("lock").push((stage, fraction));
    }

    fn cancelled(&self) -> bool {
        let seen = self.reports.lock().expect("lock").len();
        self.cancel_after.is_some_and(|n| seen >= n)
    }
}

/// The baseline reports (and the one-to-one pass) are reported as they are decided; the
/// answer does not depend on the watcher; a watcher that cancels stops the call.
#[test]
fn locations_report_progress_and_stop_when_cancelled() {
    let scene = paper_scene(|row| 1e-3 * ((row * 7) % 5) as f64);
    let sensors =
        Sensors::new(Space::Planar, &scene.positions, &scene.sigma, &[]).expect("sensors");
    let meas = Measurements::new(&sensors, &scene.sensor, &scene.time, &scene.azimuth, &[])
        .expect("measurements");
    for one_to_one in [false, true] {
        let options = FormationOptions::default().with_one_to_one(one_to_one);
        let watcher = Watcher::default();
        let watched = locate_reporting(&sensors, &meas, None, &options, &watcher).expect("locate");
        let unwatched = locate(&sensors, &meas, None, &options).expect("locate");
        assert_eq!(format!("{watched:?}"), format!("{unwatched:?}")); // NaN-aware equality
        let reports = watcher.reports.into_inner().expect("lock");
        assert_eq!(reports.first(), Some(&("baseline reports", 0.0)));
        assert!(reports.contains(&("baseline reports", 1.0)));
        assert_eq!(reports.contains(&("one-to-one", 1.0)), one_to_one);
        let cancelling = Watcher {
            cancel_after: Some(2),
            ..Watcher::default()
        };
        let stopped = locate_reporting(&sensors, &meas, None, &options, &cancelling);
        assert_eq!(stopped, Err(CoreError::Interrupted));
    }
}
