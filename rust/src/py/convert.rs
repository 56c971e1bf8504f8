//! NumPy → core views (borrowed, no copy) and core vectors → NumPy arrays (moved, no copy).

use numpy::ndarray::{Array, Dimension, IxDyn};
use numpy::{
    Element, IntoPyArray, PyArrayDyn, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::data::{Measurements, Sensors};
use crate::model::{Motion, Space, StateLayout};

/// The NumPy arrays the bindings return (owned by Python, filled without a copy).
pub type F64Array<'py> = Bound<'py, PyArrayDyn<f64>>;
pub type I64Array<'py> = Bound<'py, PyArrayDyn<i64>>;

/// A contiguous view of a 1-D array, or a `ValueError` naming the argument.
pub fn slice1<'a, T: Element>(name: &str, array: &'a PyReadonlyArray1<'_, T>) -> PyResult<&'a [T]> {
    array
        .as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name}: array must be C-contiguous")))
}

/// A contiguous row-major view of a 2-D array with `cols` columns.
pub fn slice2<'a, T: Element>(
    name: &str,
    array: &'a PyReadonlyArray2<'_, T>,
    cols: usize,
) -> PyResult<&'a [T]> {
    let shape = array.shape();
    if shape[1] != cols {
        return Err(PyValueError::new_err(format!(
            "{name}: expected {cols} columns, got shape ({}, {})",
            shape[0], shape[1]
        )));
    }
    array
        .as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name}: array must be C-contiguous")))
}

/// `ndim` (2 or 3) → the measurement space. Integer arguments are taken as `i64` so that a
/// negative or huge value is a `ValueError` naming it, not PyO3's `OverflowError`.
pub fn space(ndim: i64) -> PyResult<Space> {
    match ndim {
        2 => Ok(Space::Planar),
        3 => Ok(Space::Spatial),
        other => Err(PyValueError::new_err(format!(
            "ndim: must be 2 or 3, got {other}"
        ))),
    }
}

/// A count argument of at least `min`.
pub fn count(name: &str, value: i64, min: usize) -> PyResult<usize> {
    usize::try_from(value)
        .ok()
        .filter(|&v| v >= min)
        .ok_or_else(|| {
            PyValueError::new_err(format!("{name}: must be at least {min}, got {value}"))
        })
}

/// An optional thread count (`None` = all cores).
pub fn threads(n_threads: Option<i64>) -> PyResult<Option<usize>> {
    n_threads.map(|n| count("n_threads", n, 1)).transpose()
}

/// `motion` ("static" or "cv") and `t0` → the state layout.
pub fn layout(ndim: i64, motion: &str, t0: f64) -> PyResult<StateLayout> {
    let motion = match motion {
        "static" => Motion::Static,
        "cv" if t0.is_finite() => Motion::ConstantVelocity { t0 },
        "cv" => {
            return Err(PyValueError::new_err(format!(
                "t0: must be finite, got {t0}"
            )))
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "motion: must be 'static' or 'cv', got {other:?}"
            )))
        }
    };
    Ok(StateLayout::new(space(ndim)?, motion))
}

/// The sensor arrays of one network, as extracted from Python.
pub struct SensorArrays<'py> {
    pub positions: PyReadonlyArray2<'py, f64>,
    pub sigma_azimuth: PyReadonlyArray1<'py, f64>,
    pub sigma_elevation: PyReadonlyArray1<'py, f64>,
}

impl SensorArrays<'_> {
    pub fn view(&self, space: Space) -> PyResult<Sensors<'_>> {
        Ok(Sensors::new(
            space,
            slice2("sensor_positions", &self.positions, 3)?,
            slice1("sigma_azimuth", &self.sigma_azimuth)?,
            slice1("sigma_elevation", &self.sigma_elevation)?,
        )?)
    }
}

/// The measurement columns, as extracted from Python.
pub struct MeasurementArrays<'py> {
    pub sensor: PyReadonlyArray1<'py, i64>,
    pub time: PyReadonlyArray1<'py, f64>,
    pub azimuth: PyReadonlyArray1<'py, f64>,
    pub elevation: PyReadonlyArray1<'py, f64>,
}

impl MeasurementArrays<'_> {
    pub fn view<'a>(&'a self, sensors: &Sensors<'_>) -> PyResult<Measurements<'a>> {
        Ok(Measurements::new(
            sensors,
            slice1("sensor", &self.sensor)?,
            slice1("time", &self.time)?,
            slice1("azimuth", &self.azimuth)?,
            slice1("elevation", &self.elevation)?,
        )?)
    }
}

/// Moves `data` into a NumPy array of `shape` without copying the buffer.
pub fn to_numpy<'py, T: Element>(
    py: Python<'py>,
    data: Vec<T>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let array = Array::from_shape_vec(IxDyn(shape), data).map_err(|e| {
        PyValueError::new_err(format!(
            "internal: result of {} values does not fit shape {shape:?}: {e}",
            IxDyn(shape).size()
        ))
    })?;
    Ok(array.into_pyarray(py))
}
