//! Bindings for static LOS association (METHODS §2): candidate enumeration with eq. 2 costs,
//! and the paper's intensity-ordered search. Extract, validate, `py.detach`, delegate to the
//! core, return a dict of arrays.

use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::convert::{count, slice1, space, threads, to_numpy, SensorArrays};
use crate::data::Measurements;
use crate::parallel::with_threads;
use crate::static_assoc::{
    enumerate, intensity_search as core_intensity_search, DetectionModel, EnumerateOptions,
    IntensityInput, IntensityOptions,
};

/// Enumerates the gated candidate tuples of one scan with ML positions, covariances and eq. 2
/// costs. Times are not needed (one scan); `elevation` is ignored for `ndim=2`.
#[pyfunction]
#[pyo3(signature = (
    sensor, azimuth, elevation, sensor_positions, sigma_azimuth, sigma_elevation, pd,
    false_alarm_density, *, ndim, gate, min_intensity=2, max_candidates=1_000_000, n_threads=None
))]
#[allow(clippy::too_many_arguments)]
pub fn enumerate_static<'py>(
    py: Python<'py>,
    sensor: PyReadonlyArray1<'py, i64>,
    azimuth: PyReadonlyArray1<'py, f64>,
    elevation: PyReadonlyArray1<'py, f64>,
    sensor_positions: PyReadonlyArray2<'py, f64>,
    sigma_azimuth: PyReadonlyArray1<'py, f64>,
    sigma_elevation: PyReadonlyArray1<'py, f64>,
    pd: PyReadonlyArray1<'py, f64>,
    false_alarm_density: PyReadonlyArray1<'py, f64>,
    ndim: i64,
    gate: f64,
    min_intensity: i64,
    max_candidates: i64,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyDict>> {
    let space = space(ndim)?;
    let options = EnumerateOptions {
        gate,
        min_intensity: count("min_intensity", min_intensity, 2)?,
        max_candidates: count("max_candidates", max_candidates, 1)?,
        ..EnumerateOptions::default()
    };
    let threads = threads(n_threads)?;
    let sensors_arrays = SensorArrays {
        positions: sensor_positions,
        sigma_azimuth,
        sigma_elevation,
    };
    let sensors = sensors_arrays.view(space)?;
    // One scan: the table's times play no part, so a zero column stands in for them.
    let time = vec![0.0; sensor.len()];
    let measurements = Measurements::new(
        &sensors,
        slice1("sensor", &sensor)?,
        &time,
        slice1("azimuth", &azimuth)?,
        slice1("elevation", &elevation)?,
    )?;
    let detection = DetectionModel::new(
        &sensors,
        slice1("pd", &pd)?,
        slice1("false_alarm_density", &false_alarm_density)?,
    )?;
    let c = py.detach(|| {
        with_threads(threads, || {
            enumerate(&sensors, &measurements, &detection, &options)
        })
    })??;

    let (k, s, d) = (c.len(), c.n_sensors, c.dim);
    let out = PyDict::new(py);
    out.set_item("tuples", to_numpy(py, c.tuples, &[k, s])?)?;
    out.set_item("rows", to_numpy(py, c.rows, &[k, s])?)?;
    out.set_item("positions", to_numpy(py, c.positions, &[k, d])?)?;
    out.set_item("covariances", to_numpy(py, c.covariances, &[k, d, d])?)?;
    out.set_item("costs", to_numpy(py, c.costs, &[k])?)?;
    out.set_item("intensity", to_numpy(py, c.intensity, &[k])?)?;
    out.set_item("chi2", to_numpy(py, c.chi2, &[k])?)?;
    let sizes: Vec<i64> = c.sizes.iter().map(|&n| n as i64).collect();
    out.set_item("sizes", to_numpy(py, sizes, &[s])?)?;
    let counts = PyDict::new(py);
    for (name, value) in c.stages.named() {
        counts.set_item(name, value)?;
    }
    out.set_item("stage_counts", counts)?;
    Ok(out)
}

/// The paper's intensity-ordered search over enumerated candidates: valid airspace, chains,
/// vote, then the next lower intensity. `chosen` indexes the rows of `tuples`. `max_chains`
/// (not in the paper; default None = one chain per point of H) caps the chains per level.
/// Chains run in parallel blocks of 64 on `n_threads` (None: all cores); with the default
/// τ = 0.5 the vote runs two blocks at a time, so more than two threads help only a vote
/// with τ < 0.5. The result is the same for any thread count.
#[pyfunction]
#[pyo3(signature = (tuples, positions, costs, sizes, *, vote_fraction=0.5, valid_airspace=true, max_chains=None, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn intensity_search<'py>(
    py: Python<'py>,
    tuples: PyReadonlyArray2<'py, i64>,
    positions: PyReadonlyArray2<'py, f64>,
    costs: PyReadonlyArray1<'py, f64>,
    sizes: PyReadonlyArray1<'py, i64>,
    vote_fraction: f64,
    valid_airspace: bool,
    max_chains: Option<i64>,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyDict>> {
    let threads = threads(n_threads)?;
    let max_chains = match max_chains {
        Some(n) => Some(count("max_chains", n, 1)?),
        None => None,
    };
    let (tuple_shape, position_shape) = (tuples.shape().to_vec(), positions.shape().to_vec());
    let (k, n_sensors, dim) = (tuple_shape[0], tuple_shape[1], position_shape[1]);
    if position_shape[0] != k {
        return Err(PyValueError::new_err(format!(
            "positions: has {} rows, tuples has {k}",
            position_shape[0]
        )));
    }
    let contiguous =
        |name: &str| PyValueError::new_err(format!("{name}: array must be C-contiguous"));
    let tuple_slice = tuples.as_slice().map_err(|_| contiguous("tuples"))?;
    let position_slice = positions.as_slice().map_err(|_| contiguous("positions"))?;
    let input = IntensityInput::new(
        tuple_slice,
        n_sensors,
        position_slice,
        dim,
        slice1("costs", &costs)?,
        slice1("sizes", &sizes)?,
    )?;
    let options = IntensityOptions {
        vote_fraction,
        valid_airspace,
        max_chains,
        ..IntensityOptions::default()
    };
    let outcome =
        py.detach(|| with_threads(threads, || core_intensity_search(&input, &options)))??;
    let t = outcome.chosen.len();
    let chosen: Vec<i64> = outcome.chosen.iter().map(|&c| c as i64).collect();
    let out = PyDict::new(py);
    out.set_item("chosen", to_numpy(py, chosen, &[t])?)?;
    out.set_item("airspace_radius", outcome.airspace_radius)?;
    out.set_item("ghosts_dropped", outcome.ghosts_dropped)?;
    out.set_item("chains", outcome.chains)?;
    let levels = PyList::empty(py);
    for level in &outcome.levels {
        let row = PyDict::new(py);
        row.set_item("intensity", level.intensity)?;
        row.set_item("candidates", level.candidates)?;
        row.set_item("starts", level.starts)?;
        row.set_item("chains", level.chains)?;
        row.set_item("confirmed", level.confirmed)?;
        levels.append(row)?;
    }
    out.set_item("levels", levels)?;
    Ok(out)
}
