//! Bindings for radar/ESM association (METHODS §5): the coarse gate's hot path. Extract the
//! operator and both sides' coefficients and variances (borrowed, no copy), release the GIL,
//! run the core, move the statistic and the pass flags to NumPy.

use numpy::{PyArrayDyn, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::convert::{row_major, slice2, threads, to_numpy, F64Array};
use super::errors::{value_error, BindResult};
use passive_assoc_core::parallel::with_threads;
use passive_assoc_core::radar_esm::{coarse_gate, CoarseOptions, CoarseTracks, Operator, Side};

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
    let gate =
        py.detach(|| with_threads(n_threads, || coarse_gate(&operator, &radar, &esm, &options)))??;
    let shape = [gate.radar, gate.esm];
    Ok((
        to_numpy(py, gate.statistic, &shape)?,
        to_numpy(py, gate.passed, &shape)?,
    ))
}
