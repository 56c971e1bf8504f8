//! Bindings for fuzzy track initiation (METHODS §1) and its closeness function: extract,
//! validate, `py.detach`, delegate to the core, return arrays.

use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::convert::{
    count, slice1, slice2, space, threads, to_numpy, F64Array, I64Array, MeasurementArrays,
    SensorArrays,
};
use crate::error::ensure_finite;
use crate::initiation::closeness::closeness_batch;
use crate::initiation::descent::descend_from;
use crate::initiation::{
    initiate as core_initiate, DescentOptions, InitiationOptions, Precomputed, Scaling, Spreads,
};
use crate::parallel::with_threads;

/// Fuzzy track initiation. `pairs` is (K, 2) sensor indices; an empty (0, 2) array means every
/// pair a < b. Returns a dict (see the keys below and `_core.pyi`).
#[pyfunction]
#[pyo3(signature = (
    sensor, time, azimuth, elevation, sensor_positions, sigma_azimuth, sigma_elevation, pairs,
    spread_azimuth, spread_elevation, *, ndim, t0, gate, n_detect, ray_gate, reject_behind,
    v_max, chi2_gate, one_per_scan, merge_tol, descent_max_iter, max_candidates, n_threads,
    descent_scaling="whitened", refine_passes=2
))]
#[allow(clippy::too_many_arguments)]
pub fn initiate<'py>(
    py: Python<'py>,
    sensor: PyReadonlyArray1<'py, i64>,
    time: PyReadonlyArray1<'py, f64>,
    azimuth: PyReadonlyArray1<'py, f64>,
    elevation: PyReadonlyArray1<'py, f64>,
    sensor_positions: PyReadonlyArray2<'py, f64>,
    sigma_azimuth: PyReadonlyArray1<'py, f64>,
    sigma_elevation: PyReadonlyArray1<'py, f64>,
    pairs: PyReadonlyArray2<'py, i64>,
    spread_azimuth: PyReadonlyArray1<'py, f64>,
    spread_elevation: PyReadonlyArray1<'py, f64>,
    ndim: i64,
    t0: f64,
    gate: f64,
    n_detect: i64,
    ray_gate: Option<f64>,
    reject_behind: bool,
    v_max: Option<f64>,
    chi2_gate: Option<f64>,
    one_per_scan: bool,
    merge_tol: f64,
    descent_max_iter: i64,
    max_candidates: i64,
    n_threads: Option<i64>,
    descent_scaling: &str,
    refine_passes: i64,
) -> PyResult<Bound<'py, PyDict>> {
    let space = space(ndim)?;
    let scaling = scaling_of(descent_scaling)?;
    let sensors_arrays = SensorArrays {
        positions: sensor_positions,
        sigma_azimuth,
        sigma_elevation,
    };
    let sensors = sensors_arrays.view(space)?;
    let table = MeasurementArrays {
        sensor,
        time,
        azimuth,
        elevation,
    };
    let measurements = table.view(&sensors)?;
    let spreads = Spreads::new(
        space,
        sensors.len(),
        slice1("spread_azimuth", &spread_azimuth)?,
        slice1("spread_elevation", &spread_elevation)?,
    )?;
    let options = InitiationOptions {
        pairs: pair_list(slice2("pairs", &pairs, 2)?)?,
        gate,
        n_detect: count("n_detect", n_detect, 1)?,
        ray_gate,
        reject_behind,
        v_max,
        chi2_gate,
        one_per_scan,
        merge_tol,
        descent: DescentOptions {
            max_iter: count("descent_max_iter", descent_max_iter, 0)?,
            scaling,
            ..DescentOptions::default()
        },
        max_candidates: count("max_candidates", max_candidates, 1)?,
        refine_passes: count("refine_passes", refine_passes, 0)?,
    };
    let threads = threads(n_threads)?;
    let result = py.detach(|| {
        with_threads(threads, || {
            core_initiate(&sensors, &measurements, &spreads, t0, &options)
        })
    })??;

    let (t, d, n) = (result.tracks.len(), result.dim, result.labels.len());
    let mut estimates = Vec::with_capacity(t * d);
    let mut covariances = Vec::with_capacity(t * d * d);
    for track in &result.tracks {
        estimates.extend_from_slice(&track.estimate);
        covariances.extend_from_slice(&track.covariance);
    }
    let out = PyDict::new(py);
    out.set_item("estimates", to_numpy(py, estimates, &[t, d])?)?;
    out.set_item("covariances", to_numpy(py, covariances, &[t, d, d])?)?;
    out.set_item(
        "closeness",
        to_numpy(
            py,
            result.tracks.iter().map(|r| r.closeness).collect(),
            &[t],
        )?,
    )?;
    out.set_item(
        "chi2",
        to_numpy(py, result.tracks.iter().map(|r| r.chi2).collect(), &[t])?,
    )?;
    out.set_item("labels", to_numpy(py, result.labels, &[n])?)?;
    let counts = PyDict::new(py);
    for (name, value) in result.stage_counts.entries() {
        counts.set_item(name, value)?;
    }
    out.set_item("stage_counts", counts)?;
    let iterations: Vec<i64> = result
        .descent_iterations
        .iter()
        .map(|&i| i as i64)
        .collect();
    out.set_item(
        "descent_iterations",
        to_numpy(py, iterations.clone(), &[iterations.len()])?,
    )?;
    let seconds = PyDict::new(py);
    for (name, value) in result.stage_seconds.entries() {
        seconds.set_item(name, value)?;
    }
    out.set_item("stage_seconds", seconds)?;
    Ok(out)
}

/// R and ∂R/∂X0 (METHODS §1 eq. 17–18) at each row of `states` (P, 4 or 6); returns
/// (R: (P,), gradient: (P, D)).
#[pyfunction]
#[pyo3(signature = (
    sensor, time, azimuth, elevation, sensor_positions, sigma_azimuth, sigma_elevation,
    spread_azimuth, spread_elevation, states, *, ndim, t0, n_threads=None
))]
#[allow(clippy::too_many_arguments)]
pub fn closeness<'py>(
    py: Python<'py>,
    sensor: PyReadonlyArray1<'py, i64>,
    time: PyReadonlyArray1<'py, f64>,
    azimuth: PyReadonlyArray1<'py, f64>,
    elevation: PyReadonlyArray1<'py, f64>,
    sensor_positions: PyReadonlyArray2<'py, f64>,
    sigma_azimuth: PyReadonlyArray1<'py, f64>,
    sigma_elevation: PyReadonlyArray1<'py, f64>,
    spread_azimuth: PyReadonlyArray1<'py, f64>,
    spread_elevation: PyReadonlyArray1<'py, f64>,
    states: PyReadonlyArray2<'py, f64>,
    ndim: i64,
    t0: f64,
    n_threads: Option<i64>,
) -> PyResult<(F64Array<'py>, F64Array<'py>)> {
    let space = space(ndim)?;
    let pre = precompute(
        space,
        t0,
        SensorArrays {
            positions: sensor_positions,
            sigma_azimuth,
            sigma_elevation,
        },
        MeasurementArrays {
            sensor,
            time,
            azimuth,
            elevation,
        },
        (&spread_azimuth, &spread_elevation),
    )?;
    let d = 2 * space.position_dim();
    let states = slice2("states", &states, d)?;
    ensure_finite("states", states)?;
    let threads = threads(n_threads)?;
    let (values, gradients) =
        py.detach(|| with_threads(threads, || closeness_batch(&pre, states)))?;
    let p = values.len();
    Ok((
        to_numpy(py, values, &[p])?,
        to_numpy(py, gradients, &[p, d])?,
    ))
}

/// Steepest ascent of R (METHODS §1 eq. 19) from each row of `starts`, scaled by the matching
/// covariance; returns (optima (P, D), R (P,), iterations (P,), evaluations (P,)).
#[pyfunction]
#[pyo3(signature = (
    sensor, time, azimuth, elevation, sensor_positions, sigma_azimuth, sigma_elevation,
    spread_azimuth, spread_elevation, starts, covariances, *, ndim, t0, scaling="whitened",
    max_iter=100, n_threads=None
))]
#[allow(clippy::too_many_arguments)]
pub fn maximize_closeness<'py>(
    py: Python<'py>,
    sensor: PyReadonlyArray1<'py, i64>,
    time: PyReadonlyArray1<'py, f64>,
    azimuth: PyReadonlyArray1<'py, f64>,
    elevation: PyReadonlyArray1<'py, f64>,
    sensor_positions: PyReadonlyArray2<'py, f64>,
    sigma_azimuth: PyReadonlyArray1<'py, f64>,
    sigma_elevation: PyReadonlyArray1<'py, f64>,
    spread_azimuth: PyReadonlyArray1<'py, f64>,
    spread_elevation: PyReadonlyArray1<'py, f64>,
    starts: PyReadonlyArray2<'py, f64>,
    covariances: PyReadonlyArray3<'py, f64>,
    ndim: i64,
    t0: f64,
    scaling: &str,
    max_iter: i64,
    n_threads: Option<i64>,
) -> PyResult<(F64Array<'py>, F64Array<'py>, I64Array<'py>, I64Array<'py>)> {
    let space = space(ndim)?;
    let pre = precompute(
        space,
        t0,
        SensorArrays {
            positions: sensor_positions,
            sigma_azimuth,
            sigma_elevation,
        },
        MeasurementArrays {
            sensor,
            time,
            azimuth,
            elevation,
        },
        (&spread_azimuth, &spread_elevation),
    )?;
    let d = 2 * space.position_dim();
    let starts = slice2("starts", &starts, d)?;
    let covariances = covariances
        .as_slice()
        .map_err(|_| PyValueError::new_err("covariances: array must be C-contiguous"))?;
    let options = DescentOptions {
        max_iter: count("max_iter", max_iter, 0)?,
        scaling: scaling_of(scaling)?,
        ..DescentOptions::default()
    };
    let threads = threads(n_threads)?;
    let optima = py.detach(|| {
        with_threads(threads, || {
            descend_from(&pre, starts, covariances, &options)
        })
    })??;
    let p = optima.len();
    let states: Vec<f64> = optima.iter().flat_map(|o| o.x[..d].to_vec()).collect();
    Ok((
        to_numpy(py, states, &[p, d])?,
        to_numpy(py, optima.iter().map(|o| o.closeness).collect(), &[p])?,
        to_numpy(
            py,
            optima.iter().map(|o| o.iterations as i64).collect(),
            &[p],
        )?,
        to_numpy(
            py,
            optima.iter().map(|o| o.evaluations as i64).collect(),
            &[p],
        )?,
    ))
}

fn scaling_of(name: &str) -> PyResult<Scaling> {
    match name {
        "whitened" => Ok(Scaling::Whitened),
        "diagonal" => Ok(Scaling::Diagonal),
        other => Err(PyValueError::new_err(format!(
            "scaling: must be 'whitened' or 'diagonal', got {other:?}"
        ))),
    }
}

/// The validated closeness table of one call (owned: the array views end here).
fn precompute(
    space: crate::model::Space,
    t0: f64,
    sensors: SensorArrays<'_>,
    table: MeasurementArrays<'_>,
    spreads: (&PyReadonlyArray1<'_, f64>, &PyReadonlyArray1<'_, f64>),
) -> PyResult<Precomputed> {
    let sensors = sensors.view(space)?;
    let measurements = table.view(&sensors)?;
    let spreads = Spreads::new(
        space,
        sensors.len(),
        slice1("spread_azimuth", spreads.0)?,
        slice1("spread_elevation", spreads.1)?,
    )?;
    Ok(Precomputed::new(&sensors, &measurements, &spreads, t0)?)
}

/// Row-major (K, 2) sensor indices → pairs; an empty array means "every pair".
fn pair_list(flat: &[i64]) -> PyResult<Option<Vec<[usize; 2]>>> {
    if flat.is_empty() {
        return Ok(None);
    }
    flat.chunks_exact(2)
        .enumerate()
        .map(
            |(k, p)| match (usize::try_from(p[0]), usize::try_from(p[1])) {
                (Ok(a), Ok(b)) => Ok([a, b]),
                _ => Err(PyValueError::new_err(format!(
                    "pairs: pair {k} is ({}, {}); indices must be >= 0",
                    p[0], p[1]
                ))),
            },
        )
        .collect::<PyResult<Vec<_>>>()
        .map(Some)
}
