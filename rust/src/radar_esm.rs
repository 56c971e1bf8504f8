//! Bindings for radar/ESM association (METHODS §5): the coarse gate's hot path. Extract the
//! operator and both sides' coefficients and variances (borrowed, no copy), release the GIL,
//! run the core, move the statistic and the pass flags to NumPy.

use numpy::{PyArrayDyn, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::convert::{row_major, slice2, threads, to_numpy, F64Array, I64Array};
use super::errors::{value_error, BindResult};
use super::interrupt;
use passive_assoc_core::parallel::with_threads_unless_sequential;
use passive_assoc_core::radar_esm::{
    coarse_gate, coarse_gate_coupled, repeated_maximum as repeated_maximum_core, runs_sequentially,
    CoarseOptions, CoarseTracks, CoupledTracks, Operator, Side,
};

/// `passive_assoc._settings.CoarseGateSettings`, read by attribute.
#[derive(FromPyObject)]
pub struct CoarseGateSettings {
    threshold: f64,
    whitened: bool,
    n_threads: Option<i64>,
}

/// One sensor's tracks: approximation coefficients `(n, ndim, c)` and per-scan position
/// variances `(n, ndim, T)`.
type Tracks<'py> = (PyReadonlyArray3<'py, f64>, PyReadonlyArray3<'py, f64>);

/// The argument names of one side, for the shape errors raised here.
struct Names {
    coefficients: &'static str,
    variances: &'static str,
}

const RADAR: Names = Names {
    coefficients: "radar_coefficients",
    variances: "radar_variances",
};
const ESM: Names = Names {
    coefficients: "esm_coefficients",
    variances: "esm_variances",
};

/// A contiguous row-major view of a 3-D array.
fn slice3<'a>(name: &str, array: &'a PyReadonlyArray3<'_, f64>) -> BindResult<&'a [f64]> {
    row_major(name, array)
}

/// Checks one side's shapes against W (c × T) and returns its validated core view.
fn side<'a>(
    which: Side,
    names: &Names,
    tracks: &'a Tracks<'_>,
    operator: &Operator<'_>,
) -> BindResult<CoarseTracks<'a>> {
    let (c, window) = (operator.coefficients(), operator.window());
    let (a, v) = (tracks.0.shape(), tracks.1.shape());
    if a[2] != c {
        return Err(value_error(
            names.coefficients,
            format!("expected shape (n, ndim, {c}) for an operator of {c} rows, got {a:?}"),
        ));
    }
    if v != [a[0], a[1], window] {
        return Err(value_error(
            names.variances,
            format!(
                "expected shape ({}, {}, {window}) (the coefficients' tracks and coordinates, \
                 the operator's {window} scans), got {v:?}",
                a[0], a[1]
            ),
        ));
    }
    let coefficients = slice3(names.coefficients, &tracks.0)?;
    let variances = slice3(names.variances, &tracks.1)?;
    Ok(CoarseTracks::new(
        which,
        coefficients,
        variances,
        a[1],
        operator,
    )?)
}

/// The coarse gate of every (radar, ESM) pair: `operator` W `(c, T)`, each side
/// `(coefficients (n, ndim, c), variances (n, ndim, T))`. Returns (statistic `(n_radar,
/// n_esm)`, passed `(n_radar, n_esm)` bool).
#[pyfunction]
#[pyo3(signature = (operator, radar, esm, settings))]
pub fn wavelet_coarse_gate<'py>(
    py: Python<'py>,
    operator: PyReadonlyArray2<'py, f64>,
    radar: Tracks<'py>,
    esm: Tracks<'py>,
    settings: CoarseGateSettings,
) -> BindResult<(F64Array<'py>, Bound<'py, PyArrayDyn<bool>>)> {
    let options = CoarseOptions::new(settings.threshold)?.with_whitened(settings.whitened);
    let n_threads = threads(settings.n_threads)?;
    let (c, window) = (operator.shape()[0], operator.shape()[1]);
    let operator = Operator::new(slice2("operator", &operator, window)?, c, window)?;
    let radar = side(Side::Radar, &RADAR, &radar, &operator)?;
    let esm = side(Side::Esm, &ESM, &esm, &operator)?;
    let sequential = runs_sequentially(radar.len(), esm.len());
    let gate = interrupt::detach(py, || {
        with_threads_unless_sequential(sequential, n_threads, || {
            coarse_gate(&operator, &radar, &esm, &options)
        })
    })???;
    let shape = [gate.radar, gate.esm];
    Ok((
        to_numpy(py, gate.statistic, &shape)?,
        to_numpy(py, gate.passed, &shape)?,
    ))
}

/// One sensor's tracks with their coefficients' full covariance: coefficients `(n, m)` and
/// covariances `(n, m, m)`, m = ndim · c, coordinate-major.
type CoupledArrays<'py> = (PyReadonlyArray2<'py, f64>, PyReadonlyArray3<'py, f64>);

fn coupled<'a>(
    which: Side,
    (coefficients, covariances): (&'static str, &'static str),
    tracks: &'a CoupledArrays<'_>,
) -> BindResult<CoupledTracks<'a>> {
    let (a, c) = (tracks.0.shape(), tracks.1.shape());
    if c != [a[0], a[1], a[1]] {
        return Err(value_error(
            covariances,
            format!(
                "expected shape ({}, {m}, {m}) (the coefficients' tracks, m × m), got {c:?}",
                a[0],
                m = a[1]
            ),
        ));
    }
    let values = slice2(coefficients, &tracks.0, a[1])?;
    let cov = slice3(covariances, &tracks.1)?;
    Ok(CoupledTracks::new(which, values, cov, a[1])?)
}

/// The whitened coarse gate of every (radar, ESM) pair when each track brings its
/// coefficients' full covariance: each side `(coefficients (n, m), covariances (n, m, m))`.
/// Returns (statistic `(n_radar, n_esm)`, passed `(n_radar, n_esm)` bool).
#[pyfunction]
#[pyo3(signature = (radar, esm, settings))]
pub fn wavelet_coarse_gate_coupled<'py>(
    py: Python<'py>,
    radar: CoupledArrays<'py>,
    esm: CoupledArrays<'py>,
    settings: CoarseGateSettings,
) -> BindResult<(F64Array<'py>, Bound<'py, PyArrayDyn<bool>>)> {
    let options = CoarseOptions::new(settings.threshold)?.with_whitened(settings.whitened);
    let n_threads = threads(settings.n_threads)?;
    let radar = coupled(
        Side::Radar,
        ("radar_coefficients", "radar_covariances"),
        &radar,
    )?;
    let esm = coupled(Side::Esm, ("esm_coefficients", "esm_covariances"), &esm)?;
    let sequential = runs_sequentially(radar.len(), esm.len());
    let gate = interrupt::detach(py, || {
        with_threads_unless_sequential(sequential, n_threads, || {
            coarse_gate_coupled(&radar, &esm, &options)
        })
    })???;
    let shape = [gate.radar, gate.esm];
    Ok((
        to_numpy(py, gate.statistic, &shape)?,
        to_numpy(py, gate.passed, &shape)?,
    ))
}

/// The one-to-one decision of every scan by repeated maximum: `score`, `allowed` and `tie`
/// `(scans, n_radar, n_esm)`; a pair needs `allowed` and `score > threshold`. Returns the
/// picks' (scan, radar row, ESM row) as three int64 arrays, scan by scan in the order made.
#[pyfunction]
#[pyo3(signature = (score, allowed, tie, threshold, n_threads=None))]
pub fn repeated_maximum<'py>(
    py: Python<'py>,
    score: PyReadonlyArray3<'py, f64>,
    allowed: PyReadonlyArray3<'py, bool>,
    tie: PyReadonlyArray3<'py, f64>,
    threshold: f64,
    n_threads: Option<i64>,
) -> BindResult<(I64Array<'py>, I64Array<'py>, I64Array<'py>)> {
    let shape = score.shape().to_vec();
    for (name, other) in [("allowed", allowed.shape()), ("tie", tie.shape())] {
        if other != shape.as_slice() {
            return Err(value_error(
                name,
                format!("expected the score's shape {shape:?}, got {other:?}"),
            ));
        }
    }
    let n_threads = threads(n_threads)?;
    let (score, allowed, tie) = (
        row_major("score", &score)?,
        row_major("allowed", &allowed)?,
        row_major("tie", &tie)?,
    );
    let dims = (shape[0], shape[1], shape[2]);
    // Per scan the work is a sort of its candidates: worth the pool only for many of them.
    let sequential = dims.0.saturating_mul(dims.1).saturating_mul(dims.2) < 1 << 16;
    let picks = interrupt::detach(py, || {
        with_threads_unless_sequential(sequential, n_threads, || {
            repeated_maximum_core(score, allowed, tie, dims, threshold)
        })
    })???;
    let column = |f: fn(&(usize, usize, usize)) -> usize| -> BindResult<I64Array<'py>> {
        let values = picks.iter().map(|p| f(p) as i64).collect();
        to_numpy(py, values, &[picks.len()])
    };
    Ok((column(|p| p.0)?, column(|p| p.1)?, column(|p| p.2)?))
}
