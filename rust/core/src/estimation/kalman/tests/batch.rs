//! The batch: identical results for any thread count and any row order, and every bad input
//! an error naming its argument.

use super::*;
use crate::error::{CoreError, CoreResult};
use crate::parallel::with_threads;

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// `sc` with its rows interleaved scan by scan (track-major → a shuffled-looking order), and
/// one extra row that no track uses.
fn interleaved(sc: &Scenario) -> (Scenario, Vec<usize>) {
    let mut order: Vec<usize> = (0..sc.len()).collect();
    order.sort_by_key(|&row| {
        let track = sc.offsets.partition_point(|&o| o as usize <= row) - 1;
        (row - sc.offsets[track] as usize, track)
    });
    let (m, n) = (sc.columns, sc.state_dim);
    let mut out = Scenario {
        times: order.iter().map(|&r| sc.times[r]).collect(),
        measurements: order
            .iter()
            .flat_map(|&r| sc.measurements[r * m..(r + 1) * m].to_vec())
            .collect(),
        noise: order
            .iter()
            .flat_map(|&r| sc.noise[r * m..(r + 1) * m].to_vec())
            .collect(),
        sensors: sc.sensors.as_ref().map(|s| {
            order
                .iter()
                .flat_map(|&r| s[2 * r..2 * r + 2].to_vec())
                .collect()
        }),
        truth: order
            .iter()
            .flat_map(|&r| sc.truth[r * n..(r + 1) * n].to_vec())
            .collect(),
        ..sc.clone()
    };
    let mut new_row = vec![0; sc.len()];
    for (new, &old) in order.iter().enumerate() {
        new_row[old] = new;
    }
    out.indices = (0..sc.len()).map(|old| new_row[old] as i64).collect();
    out.times.push(0.0);
    out.measurements.extend(vec![1.0; m]);
    out.noise.extend(vec![1.0; m]);
    if let Some(s) = out.sensors.as_mut() {
        s.extend([0.0, 0.0]);
    }
    (out, new_row)
}

/// Keeps only the first `p % 7 + 1` rows of every third track `p`.
fn shorten(sc: &mut Scenario) {
    let (mut indices, mut offsets) = (vec![], vec![0]);
    for (p, w) in sc.offsets.windows(2).enumerate() {
        let rows = &sc.indices[w[0] as usize..w[1] as usize];
        let keep = if p % 3 == 0 { p % 7 + 1 } else { rows.len() };
        indices.extend(&rows[..keep]);
        offsets.push(indices.len() as i64);
    }
    (sc.indices, sc.offsets) = (indices, offsets);
}

#[test]
fn results_do_not_depend_on_threads_or_row_order() {
    let cv = MotionModel::ConstantVelocity;
    let mut spec = Spec::new(cv, MeasurementModel::Polar, 2);
    spec.tracks = 300;
    let mut sc = simulate(&spec);
    let options = KalmanOptions::new(cv, 0.5)
        .expect("q")
        .with_measurement(MeasurementModel::Polar);
    let (mut shuffled, new_row) = interleaved(&sc);
    // Tracks of different lengths (1 to 7 rows, or all 40), the cut rows in no track.
    shorten(&mut sc);
    shorten(&mut shuffled);
    let runs: Vec<KalmanOutcome> = [Some(1), Some(3), None]
        .into_iter()
        .map(|threads| with_threads(threads, || shuffled.run(&options)).expect("pool"))
        .collect();
    for other in &runs[1..] {
        assert_eq!(bits(&runs[0].states), bits(&other.states));
        assert_eq!(bits(&runs[0].covariances), bits(&other.covariances));
        assert_eq!(bits(&runs[0].nis), bits(&other.nis));
    }
    let sorted = sc.run(&options);
    let (n, last) = (sc.state_dim, shuffled.len() - 1);
    for (old, &new) in new_row.iter().enumerate() {
        assert_eq!(
            bits(&sorted.states[old * n..(old + 1) * n]),
            bits(&runs[0].states[new * n..(new + 1) * n])
        );
        assert_eq!(sorted.nis[old].to_bits(), runs[0].nis[new].to_bits());
    }
    assert!(runs[0].states[last * n..].iter().all(|v| v.is_nan()));
    assert!(runs[0].covariances[last * n * n..]
        .iter()
        .all(|v| v.is_nan()));
}

/// The smallest valid input: one 2-D position track of three rows.
struct Case {
    times: Vec<f64>,
    measurements: Vec<f64>,
    columns: usize,
    noise: Vec<f64>,
    covariance: bool,
    sensors: Option<Vec<f64>>,
    indices: Vec<i64>,
    offsets: Vec<i64>,
    options: KalmanOptions,
}

impl Case {
    fn new() -> Self {
        Self {
            times: vec![0.0, 1.0, 2.0],
            measurements: vec![0.0, 0.0, 10.0, 5.0, 20.0, 10.0],
            columns: 2,
            noise: vec![1.0; 6],
            covariance: false,
            sensors: None,
            indices: vec![0, 1, 2],
            offsets: vec![0, 3],
            options: KalmanOptions::new(MotionModel::ConstantVelocity, 1.0).expect("q"),
        }
    }

    fn polar() -> Self {
        Self {
            measurements: vec![100.0, 0.1, 110.0, 0.1, 120.0, 0.1],
            sensors: Some(vec![0.0; 6]),
            options: Case::new()
                .options
                .with_measurement(MeasurementModel::Polar),
            ..Self::new()
        }
    }

    fn run(&self) -> CoreResult<KalmanOutcome> {
        let input = KalmanInput {
            times: &self.times,
            measurements: &self.measurements,
            columns: self.columns,
            noise: if self.covariance {
                Noise::Covariance(&self.noise)
            } else {
                Noise::Std(&self.noise)
            },
            sensor_positions: self.sensors.as_deref(),
        };
        let tracks = Tracks {
            indices: &self.indices,
            offsets: &self.offsets,
        };
        kalman_filter(&input, &tracks, &self.options)
    }
}

#[test]
fn the_base_cases_are_valid() {
    assert!(Case::new().run().is_ok());
    assert!(Case::polar().run().is_ok());
    let empty = Case {
        indices: vec![],
        offsets: vec![0],
        ..Case::new()
    };
    assert_eq!(empty.run().expect("no tracks").states.len(), 3 * 4);
}

#[test]
fn bad_input_is_an_error_naming_the_argument() {
    type Edit = fn(&mut Case);
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "nan time",
            |c| c.times[1] = f64::NAN,
            "times: non-finite value at index 1",
        ),
        (
            "inf measurement",
            |c| c.measurements[3] = f64::INFINITY,
            "measurements: non-finite value at index 3",
        ),
        (
            "nan noise",
            |c| c.noise[0] = f64::NAN,
            "noise: non-finite value at index 0",
        ),
        (
            "zero std",
            |c| c.noise[2] = 0.0,
            "noise: row 1 has std 0, must be > 0",
        ),
        (
            "short measurements",
            |c| c.measurements.truncate(5),
            "measurements: expected 3 rows of 2 values",
        ),
        (
            "short noise",
            |c| c.noise.truncate(4),
            "noise: expected 3 rows of 2 values",
        ),
        (
            "four columns",
            |c| {
                c.columns = 4;
                c.measurements = vec![0.0; 12];
                c.noise = vec![1.0; 12]
            },
            "measurements: position measurements have 1 to 3 columns, got 4",
        ),
        (
            "empty track",
            |c| c.offsets = vec![0, 0, 3],
            "offsets: track 0 has no rows",
        ),
        (
            "offsets start",
            |c| c.offsets = vec![1, 3],
            "offsets: must start with 0",
        ),
        (
            "offsets end",
            |c| c.offsets = vec![0, 2],
            "offsets: last entry must equal len(indices) = 3",
        ),
        (
            "offsets decrease",
            |c| {
                c.indices = vec![0, 1, 2];
                c.offsets = vec![0, 2, 1, 3]
            },
            "offsets: decreases between entries 1 and 2",
        ),
        (
            "index out of range",
            |c| c.indices[2] = 3,
            "indices: entry 2 is 3 but the table has 3 rows",
        ),
        (
            "negative index",
            |c| c.indices[0] = -1,
            "indices: entry 0 is -1",
        ),
        (
            "row twice",
            |c| {
                c.indices = vec![0, 1, 2, 1];
                c.offsets = vec![0, 3, 4]
            },
            "indices: row 1 is in entries 1 and 3",
        ),
        (
            "decreasing times",
            |c| c.times = vec![0.0, 2.0, 1.0],
            "times: track 0 goes back in time at row 2 (1 after 2)",
        ),
        (
            "equal start times",
            |c| c.times = vec![1.0, 1.0, 2.0],
            "times: track 0's first 2 measurements need distinct times",
        ),
        (
            "sensors with positions",
            |c| c.sensors = Some(vec![0.0; 6]),
            "sensor_positions: only polar measurements use sensor positions",
        ),
        (
            "asymmetric covariance",
            |c| {
                c.covariance = true;
                c.noise = [1.0, 0.5, 0.0, 1.0].repeat(3)
            },
            "noise: row 0's covariance is not symmetric",
        ),
        (
            "indefinite covariance",
            |c| {
                c.covariance = true;
                c.noise = [1.0, 2.0, 2.0, 1.0].repeat(3)
            },
            "noise: row 0's covariance is not positive definite",
        ),
        (
            "covariance shape",
            |c| {
                c.covariance = true;
                c.noise = vec![1.0; 6]
            },
            "noise: expected 3 rows of 4 values",
        ),
    ];
    for (label, edit, message) in cases {
        let mut case = Case::new();
        edit(&mut case);
        let err = case.run().expect_err(label);
        assert!(err.to_string().starts_with(message), "{label}: {err}");
    }
    let polar: Vec<(&str, Edit, &str)> = vec![
        (
            "no sensors",
            |c| c.sensors = None,
            "sensor_positions: polar measurements need the sensor position of every row",
        ),
        (
            "nan sensor",
            |c| c.sensors = Some(vec![0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0]),
            "sensor_positions: non-finite value at index 1",
        ),
        (
            "short sensors",
            |c| c.sensors = Some(vec![0.0; 4]),
            "sensor_positions: expected 3 rows of 2 values",
        ),
        (
            "negative range",
            |c| c.measurements[2] = -1.0,
            "measurements: row 1 has a negative range -1",
        ),
        (
            "three columns",
            |c| {
                c.columns = 3;
                c.measurements = vec![1.0; 9];
                c.noise = vec![1.0; 9]
            },
            "measurements: polar measurements have 2 columns (range, azimuth), got 3",
        ),
    ];
    for (label, edit, message) in polar {
        let mut case = Case::polar();
        edit(&mut case);
        let err = case.run().expect_err(label);
        assert!(err.to_string().starts_with(message), "{label}: {err}");
    }
    // The option setters.
    assert!(matches!(
        KalmanOptions::new(MotionModel::ConstantVelocity, f64::NAN),
        Err(CoreError::OutOfRange {
            arg: "process_noise",
            ..
        })
    ));
    assert!(Case::new().options.with_init_velocity_std(0.0).is_err());
    assert!(Case::new()
        .options
        .with_init_acceleration_std(-1.0)
        .is_err());
}

#[test]
fn absurd_finite_values_give_nan_rows_not_a_panic() {
    for value in [1e300_f64, -1e300, 1e-300] {
        let mut case = Case::polar();
        case.measurements = vec![value.abs(), 0.1, value.abs(), 3.0, value.abs(), -3.0];
        case.noise = vec![value.abs(), 1.0, 1e-300, 1.0, 1e300, 1.0];
        let out = case.run().expect("valid input");
        assert_eq!(out.states.len(), 12);
        let mut case = Case::new();
        case.measurements = vec![value; 6];
        case.noise = vec![value.abs(); 6];
        case.options = case.options.with_process_noise(1e300).expect("q");
        assert!(case.run().is_ok());
    }
}

/// Time steps of 10¹² s scale a constant-acceleration prediction by 10⁶⁰: the update then
/// keeps no digits and once wrote negative variances on rows reported as having a state. Such
/// a row and the rest of its track are NaN now, like any numerical failure.
#[test]
fn a_row_with_a_state_never_has_a_negative_variance() {
    let times = [-1e12, 1e12 - 2.0, 1e12 - 1.0, 1e12];
    let measurements: Vec<f64> = (0..4).flat_map(|k| [10.0 * k as f64, k as f64]).collect();
    let input = KalmanInput {
        times: &times,
        measurements: &measurements,
        columns: 2,
        noise: Noise::Std(&[1.0; 8]),
        sensor_positions: None,
    };
    let tracks = Tracks {
        indices: &[0, 1, 2, 3],
        offsets: &[0, 4],
    };
    for init in [Init::Differencing, Init::SinglePoint] {
        for q in [0.0, 1.0, 1e3] {
            let options = KalmanOptions::new(MotionModel::ConstantAcceleration, q)
                .unwrap()
                .with_init(init);
            let out = kalman_filter(&input, &tracks, &options).unwrap();
            let n = out.state_dim;
            for row in 0..times.len() {
                let p = &out.covariances[row * n * n..(row + 1) * n * n];
                if !out.states[row * n].is_nan() {
                    assert!(
                        (0..n).all(|k| p[k * n + k] >= 0.0),
                        "{init:?} q {q} row {row}"
                    );
                }
            }
        }
    }
}
