//! Bindings for batched Kalman filtering of measurements into local tracks: extract,
//! `py.detach`, delegate to the core, return arrays aligned to the input rows.

use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::convert::{parse, row_major, slice1, slice2, threads, to_numpy, F64Array};
use super::errors::{value_error, BindResult};
use super::interrupt;
use passive_assoc_core::estimation::kalman::{
    filters_sequentially, kalman_filter as core_kalman_filter, Init, KalmanInput, KalmanOptions,
    MeasurementModel, MotionModel, Noise, Tracks,
};
use passive_assoc_core::parallel::with_threads_unless_sequential;

/// The filter's settings, read by attribute from `passive_assoc.KalmanFilter`.
#[derive(FromPyObject)]
pub struct KalmanSettings {
    motion: String,
    measurement: String,
    process_noise: f64,
    init: String,
    init_velocity_std: f64,
    init_acceleration_std: f64,
    n_threads: Option<i64>,
}

impl KalmanSettings {
    fn options(&self) -> BindResult<KalmanOptions> {
        let motion: MotionModel = parse("motion", &self.motion)?;
        let measurement: MeasurementModel = parse("measurement", &self.measurement)?;
        let init: Init = parse("init", &self.init)?;
        Ok(KalmanOptions::new(motion, self.process_noise)?
            .with_measurement(measurement)
            .with_init(init)
            .with_init_velocity_std(self.init_velocity_std)?
            .with_init_acceleration_std(self.init_acceleration_std)?)
    }
}

/// The CSR track groups: `(indices, offsets)`.
type Groups<'py> = (PyReadonlyArray1<'py, i64>, PyReadonlyArray1<'py, i64>);

/// Filters the tracks `indices[offsets[p]..offsets[p + 1]]` (rows sorted by time) of the
/// measurement table `times` (n,), `measurements` (n, m), `noise` — standard deviations
/// (n, m) or covariances (n, m, m) — and, for polar models, `sensor_positions` (n, 2).
/// Returns (states (n, D), covariances (n, D, D), nis (n,)), NaN where a row has no state.
#[pyfunction]
#[pyo3(signature = (times, measurements, groups, noise, sensor_positions, settings))]
pub fn kalman_filter<'py>(
    py: Python<'py>,
    times: PyReadonlyArray1<'py, f64>,
    measurements: PyReadonlyArray2<'py, f64>,
    groups: Groups<'py>,
    noise: PyReadonlyArrayDyn<'py, f64>,
    sensor_positions: Option<PyReadonlyArray2<'py, f64>>,
    settings: KalmanSettings,
) -> BindResult<(F64Array<'py>, F64Array<'py>, F64Array<'py>)> {
    let options = settings.options()?;
    let times = slice1("times", &times)?;
    let (rows, columns) = (measurements.shape()[0], measurements.shape()[1]);
    if rows != times.len() {
        return Err(value_error(
            "measurements",
            format!("has {rows} rows, times has {}", times.len()),
        ));
    }
    let values = slice2("measurements", &measurements, columns)?;
    let noise_values = row_major("noise", &noise)?;
    let noise = match noise.shape() {
        [r, c] if (*r, *c) == (rows, columns) => Noise::Std(noise_values),
        [r, c, k] if (*r, *c, *k) == (rows, columns, columns) => Noise::Covariance(noise_values),
        shape => {
            return Err(value_error(
                "noise",
                format!(
                    "expected standard deviations of shape ({rows}, {columns}) or covariances of shape ({rows}, {columns}, {columns}), got {shape:?}"
                ),
            ))
        }
    };
    let sensor_positions = match &sensor_positions {
        Some(s) => Some(slice2("sensor_positions", s, 2)?),
        None => None,
    };
    let input = KalmanInput {
        times,
        measurements: values,
        columns,
        noise,
        sensor_positions,
    };
    let tracks = Tracks {
        indices: slice1("indices", &groups.0)?,
        offsets: slice1("offsets", &groups.1)?,
    };
    let n_threads = threads(settings.n_threads)?;
    let sequential = filters_sequentially(tracks.offsets.len().saturating_sub(1));
    let outcome = interrupt::detach(py, || {
        with_threads_unless_sequential(sequential, n_threads, || {
            core_kalman_filter(&input, &tracks, &options)
        })
    })???;
    let d = outcome.state_dim;
    Ok((
        to_numpy(py, outcome.states, &[rows, d])?,
        to_numpy(py, outcome.covariances, &[rows, d, d])?,
        to_numpy(py, outcome.nis, &[rows])?,
    ))
}
