//! Bindings for batched Gauss-Newton fitting and the CRLB: extract, validate, `py.detach`,
//! delegate to the core, return arrays.

use numpy::{PyArrayDyn, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use super::convert::{
    count, layout, slice1, threads, to_numpy, F64Array, MeasurementArrays, SensorArrays,
};
use crate::fisher;
use crate::fit::batch::{fit_batch as core_fit_batch, Problems};
use crate::fit::FitOptions;
use crate::parallel::with_threads;

type FitArrays<'py> = (
    F64Array<'py>,
    F64Array<'py>,
    F64Array<'py>,
    Bound<'py, PyArrayDyn<u32>>,
    Bound<'py, PyArrayDyn<u8>>,
);

/// Batched ML fit; returns (estimates, covariances, chi2, iterations, termination).
#[pyfunction]
#[pyo3(signature = (
    sensor, time, azimuth, elevation, sensor_positions, sigma_azimuth, sigma_elevation,
    indices, offsets, initial=None, *, ndim, motion, t0=0.0, max_iter=50, xtol=1e-10,
    step_sigmas=1e-6, max_halvings=30, n_threads=None
))]
#[allow(clippy::too_many_arguments)]
pub fn fit_batch<'py>(
    py: Python<'py>,
    sensor: PyReadonlyArray1<'py, i64>,
    time: PyReadonlyArray1<'py, f64>,
    azimuth: PyReadonlyArray1<'py, f64>,
    elevation: PyReadonlyArray1<'py, f64>,
    sensor_positions: PyReadonlyArray2<'py, f64>,
    sigma_azimuth: PyReadonlyArray1<'py, f64>,
    sigma_elevation: PyReadonlyArray1<'py, f64>,
    indices: PyReadonlyArray1<'py, i64>,
    offsets: PyReadonlyArray1<'py, i64>,
    initial: Option<PyReadonlyArray2<'py, f64>>,
    ndim: i64,
    motion: &str,
    t0: f64,
    max_iter: i64,
    xtol: f64,
    step_sigmas: f64,
    max_halvings: i64,
    n_threads: Option<i64>,
) -> PyResult<FitArrays<'py>> {
    let layout = layout(ndim, motion, t0)?;
    let options = FitOptions::default()
        .with_max_iter(count("max_iter", max_iter, 1)?)?
        .with_xtol(xtol)?
        .with_step_sigmas(step_sigmas)?
        .with_max_halvings(count("max_halvings", max_halvings, 0)?)?;
    let sensors_arrays = SensorArrays {
        positions: sensor_positions,
        sigma_azimuth,
        sigma_elevation,
    };
    let sensors = sensors_arrays.view(layout.space)?;
    let table = MeasurementArrays {
        sensor,
        time,
        azimuth,
        elevation,
    };
    let measurements = table.view(&sensors)?;
    let initial_slice = match &initial {
        Some(a) => Some(a.as_slice().map_err(|_| {
            pyo3::exceptions::PyValueError::new_err("initial: array must be C-contiguous")
        })?),
        None => None,
    };
    let problems = Problems {
        indices: slice1("indices", &indices)?,
        offsets: slice1("offsets", &offsets)?,
        initial: initial_slice,
    };
    let n_threads = threads(n_threads)?;
    let outcome = py.detach(|| {
        with_threads(n_threads, || {
            core_fit_batch(&measurements, &sensors, &layout, &problems, &options)
        })
    })??;
    let (p, d) = (outcome.chi2.len(), outcome.dim);
    Ok((
        to_numpy(py, outcome.estimates, &[p, d])?,
        to_numpy(py, outcome.covariances, &[p, d, d])?,
        to_numpy(py, outcome.chi2, &[p])?,
        to_numpy(py, outcome.iterations, &[p])?,
        to_numpy(py, outcome.termination, &[p])?,
    ))
}

/// Fisher information and CRLB of `truth`; returns (fisher, crlb), each `dim × dim`.
#[pyfunction]
#[pyo3(signature = (sensor_positions, sigma_azimuth, sigma_elevation, sensor_index, times, truth, *, ndim, motion, t0=0.0))]
#[allow(clippy::too_many_arguments)]
pub fn crlb<'py>(
    py: Python<'py>,
    sensor_positions: PyReadonlyArray2<'py, f64>,
    sigma_azimuth: PyReadonlyArray1<'py, f64>,
    sigma_elevation: PyReadonlyArray1<'py, f64>,
    sensor_index: PyReadonlyArray1<'py, i64>,
    times: PyReadonlyArray1<'py, f64>,
    truth: PyReadonlyArray1<'py, f64>,
    ndim: i64,
    motion: &str,
    t0: f64,
) -> PyResult<(F64Array<'py>, F64Array<'py>)> {
    let layout = layout(ndim, motion, t0)?;
    let sensors_arrays = SensorArrays {
        positions: sensor_positions,
        sigma_azimuth,
        sigma_elevation,
    };
    let sensors = sensors_arrays.view(layout.space)?;
    let (sensor_index, times, truth) = (
        slice1("sensor_index", &sensor_index)?,
        slice1("times", &times)?,
        slice1("truth", &truth)?,
    );
    let bound = py.detach(|| fisher::crlb(&layout, &sensors, sensor_index, times, truth))?;
    let d = layout.dim();
    Ok((
        to_numpy(py, bound.fisher, &[d, d])?,
        to_numpy(py, bound.crlb, &[d, d])?,
    ))
}
