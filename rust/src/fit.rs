//! Bindings for batched Gauss-Newton fitting and the CRLB: extract, `py.detach`, delegate to
//! the core, return arrays.

use numpy::{PyArrayDyn, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use super::convert::{
    count, layout, overrides, row_major, slice1, threads, to_numpy, F64Array, MeasurementsArg,
    SensorsArg,
};
use super::errors::BindResult;
use super::interrupt;
use passive_assoc_core::estimation::fisher;
use passive_assoc_core::estimation::fit::batch::{
    fit_batch as core_fit_batch, fits_sequentially, Problems,
};
use passive_assoc_core::estimation::fit::FitOptions;
use passive_assoc_core::parallel::with_threads_unless_sequential;

/// The fit's settings, read by attribute: `fit_ml`'s validated arguments.
#[derive(FromPyObject)]
pub struct FitSettings {
    motion: String,
    t0: f64,
    max_iter: i64,
    xtol: f64,
    step_sigmas: f64,
    max_halvings: i64,
    n_threads: Option<i64>,
}

impl FitSettings {
    fn options(&self) -> BindResult<FitOptions> {
        Ok(FitOptions::default()
            .with_max_iter(count("max_iter", self.max_iter, 1)?)?
            .with_xtol(self.xtol)?
            .with_step_sigmas(self.step_sigmas)?
            .with_max_halvings(count("max_halvings", self.max_halvings, 0)?)?)
    }
}

type FitArrays<'py> = (
    F64Array<'py>,
    F64Array<'py>,
    F64Array<'py>,
    Bound<'py, PyArrayDyn<u32>>,
    Bound<'py, PyArrayDyn<u8>>,
);

/// Batched ML fit of the groups `indices[offsets[p]..offsets[p + 1]]`; returns (estimates,
/// covariances, chi2, iterations, termination codes).
#[pyfunction]
#[pyo3(signature = (measurements, sensors, indices, offsets, initial, settings))]
pub fn fit_batch<'py>(
    py: Python<'py>,
    measurements: MeasurementsArg<'py>,
    sensors: SensorsArg<'py>,
    indices: PyReadonlyArray1<'py, i64>,
    offsets: PyReadonlyArray1<'py, i64>,
    initial: Option<PyReadonlyArray2<'py, f64>>,
    settings: FitSettings,
) -> BindResult<FitArrays<'py>> {
    let layout = layout(sensors.space()?, &settings.motion, settings.t0)?;
    let options = settings.options()?;
    let network = sensors.view()?;
    let columns = measurements.columns(layout.space)?;
    let table = columns.view(&network)?;
    let initial = match &initial {
        Some(a) => Some(row_major("initial", a)?),
        None => None,
    };
    let problems = Problems {
        indices: slice1("indices", &indices)?,
        offsets: slice1("offsets", &offsets)?,
        initial,
    };
    let n_threads = threads(settings.n_threads)?;
    let sequential = fits_sequentially(problems.len());
    let outcome = interrupt::detach(py, || {
        with_threads_unless_sequential(sequential, n_threads, || {
            core_fit_batch(&table, &network, &layout, &problems, &options)
        })
    })???;
    let (p, d) = (outcome.chi2.len(), outcome.dim);
    Ok((
        to_numpy(py, outcome.estimates, &[p, d])?,
        to_numpy(py, outcome.covariances, &[p, d, d])?,
        to_numpy(py, outcome.chi2, &[p])?,
        to_numpy(py, outcome.iterations, &[p])?,
        to_numpy(py, outcome.termination, &[p])?,
    ))
}

/// Fisher information and CRLB of `truth` seen by `sensor_index` at `times`; returns
/// (fisher, crlb), each `dim × dim`.
/// The optional per-report `sensor_position` `(N, 3)`, `sigma_azimuth` and `sigma_elevation`
/// (a moving sensor, the reports' own noise) are read as a table's.
#[pyfunction]
#[pyo3(signature = (
    sensors, truth, sensor_index, times, motion, t0,
    sensor_position=None, sigma_azimuth=None, sigma_elevation=None
))]
#[allow(clippy::too_many_arguments)]
pub fn crlb<'py>(
    py: Python<'py>,
    sensors: SensorsArg<'py>,
    truth: PyReadonlyArray1<'py, f64>,
    sensor_index: PyReadonlyArray1<'py, i64>,
    times: PyReadonlyArray1<'py, f64>,
    motion: &str,
    t0: f64,
    sensor_position: Option<PyReadonlyArray2<'py, f64>>,
    sigma_azimuth: Option<PyReadonlyArray1<'py, f64>>,
    sigma_elevation: Option<PyReadonlyArray1<'py, f64>>,
) -> BindResult<(F64Array<'py>, F64Array<'py>)> {
    let layout = layout(sensors.space()?, motion, t0)?;
    let network = sensors.view()?;
    let (sensor_index, times, truth) = (
        slice1("sensor_index", &sensor_index)?,
        slice1("times", &times)?,
        slice1("truth", &truth)?,
    );
    let overrides = overrides(
        layout.space,
        &sensor_position,
        &sigma_azimuth,
        &sigma_elevation,
    )?;
    let bound =
        py.detach(|| fisher::crlb(&layout, &network, sensor_index, times, &overrides, truth))?;
    let d = layout.dim();
    Ok((
        to_numpy(py, bound.fisher, &[d, d])?,
        to_numpy(py, bound.crlb, &[d, d])?,
    ))
}
