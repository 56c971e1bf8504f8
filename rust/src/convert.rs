//! The typed boundary: the Python `SensorNetwork` and `MeasurementTable` are read once, by
//! attribute, into borrowed views (no copy); core vectors go back to NumPy by move (no copy).
//! Counts arrive as `i64` so that a negative or huge value is a `ValueError` naming it, not
//! PyO3's `OverflowError`.

use numpy::ndarray::{Array, Dimension, IxDyn};
use numpy::{
    Element, IntoPyArray, PyArrayDyn, PyReadonlyArray, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use super::errors::{value_error, BindResult};
use passive_assoc_core::data::{Measurements, ReportOverrides, Sensors};
use passive_assoc_core::geometry::model::{MotionKind, Space, StateLayout};

/// The NumPy arrays the bindings return (owned by Python, filled without a copy).
pub type F64Array<'py> = Bound<'py, PyArrayDyn<f64>>;
pub type I64Array<'py> = Bound<'py, PyArrayDyn<i64>>;

/// The row-major (C-order) memory of any array, or a `ValueError` naming the argument.
/// rust-numpy's `as_slice` also accepts a Fortran-ordered array, whose memory read as
/// row-major would be the transpose: every binding reads arrays through this check.
pub fn row_major<'a, T: Element, D: Dimension>(
    name: &str,
    array: &'a PyReadonlyArray<'_, T, D>,
) -> BindResult<&'a [T]> {
    if array.len() > 1 && !array.is_c_contiguous() {
        return Err(value_error(
            name,
            "array must be C-contiguous (row-major); pass np.ascontiguousarray(...)",
        ));
    }
    array
        .as_slice()
        .map_err(|_| value_error(name, "array must be C-contiguous and aligned"))
}

/// A contiguous view of a 1-D array, or a `ValueError` naming the argument.
pub fn slice1<'a, T: Element>(
    name: &str,
    array: &'a PyReadonlyArray1<'_, T>,
) -> BindResult<&'a [T]> {
    row_major(name, array)
}

/// A contiguous row-major view of a 2-D array with `cols` columns.
pub fn slice2<'a, T: Element>(
    name: &str,
    array: &'a PyReadonlyArray2<'_, T>,
    cols: usize,
) -> BindResult<&'a [T]> {
    let shape = array.shape();
    if shape[1] != cols {
        return Err(value_error(
            name,
            format!(
                "expected {cols} columns, got shape ({}, {})",
                shape[0], shape[1]
            ),
        ));
    }
    row_major(name, array)
}

/// `ndim` (2 or 3) → the measurement space.
pub fn space(ndim: i64) -> BindResult<Space> {
    match ndim {
        2 => Ok(Space::Planar),
        3 => Ok(Space::Spatial),
        other => Err(value_error("ndim", format!("must be 2 or 3, got {other}"))),
    }
}

/// A count argument of at least `min`.
pub fn count(name: &str, value: i64, min: usize) -> BindResult<usize> {
    usize::try_from(value)
        .ok()
        .filter(|&v| v >= min)
        .ok_or_else(|| value_error(name, format!("must be at least {min}, got {value}")))
}

/// An optional thread count (`None` = all cores).
pub fn threads(n_threads: Option<i64>) -> BindResult<Option<usize>> {
    n_threads.map(|n| count("n_threads", n, 1)).transpose()
}

/// `motion` ("static" or "cv", parsed by the core) and `t0` → the state layout.
pub fn layout(space: Space, motion: &str, t0: f64) -> BindResult<StateLayout> {
    let kind: MotionKind = parse("motion", motion)?;
    Ok(StateLayout::new(space, kind.at(t0)?))
}

/// Non-negative int64 → usize, naming the argument and index of the first negative entry.
pub fn to_usize(name: &str, values: &[i64]) -> BindResult<Vec<usize>> {
    values
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            usize::try_from(v)
                .map_err(|_| value_error(name, format!("entry {k} is {v}, must be >= 0")))
        })
        .collect()
}

/// A `SensorNetwork`, read by attribute: positions `(S, 3)`, per-sensor stds, `ndim`.
#[derive(FromPyObject)]
pub struct SensorsArg<'py> {
    positions: PyReadonlyArray2<'py, f64>,
    sigma_azimuth: PyReadonlyArray1<'py, f64>,
    sigma_elevation: PyReadonlyArray1<'py, f64>,
    ndim: i64,
}

impl SensorsArg<'_> {
    pub fn space(&self) -> BindResult<Space> {
        space(self.ndim)
    }

    /// The validated core view.
    pub fn view(&self) -> BindResult<Sensors<'_>> {
        Ok(Sensors::new(
            self.space()?,
            slice2("sensor_positions", &self.positions, 3)?,
            slice1("sigma_azimuth", &self.sigma_azimuth)?,
            slice1("sigma_elevation", &self.sigma_elevation)?,
        )?)
    }
}

/// A `MeasurementTable`, read by attribute: the four core columns, and the optional
/// per-report sensor positions `(N, 3)` and noise stds (None, or absent: the sensors').
#[derive(FromPyObject)]
pub struct MeasurementsArg<'py> {
    sensor: PyReadonlyArray1<'py, i64>,
    time: PyReadonlyArray1<'py, f64>,
    azimuth: PyReadonlyArray1<'py, f64>,
    elevation: PyReadonlyArray1<'py, f64>,
    #[pyo3(default)]
    sensor_position: Option<PyReadonlyArray2<'py, f64>>,
    #[pyo3(default)]
    sigma_azimuth: Option<PyReadonlyArray1<'py, f64>>,
    #[pyo3(default)]
    sigma_elevation: Option<PyReadonlyArray1<'py, f64>>,
}

/// The borrowed per-report columns (the elevation std only in 3-D), validated by the core.
pub fn overrides<'a>(
    space: Space,
    position: &'a Option<PyReadonlyArray2<'_, f64>>,
    sigma_azimuth: &'a Option<PyReadonlyArray1<'_, f64>>,
    sigma_elevation: &'a Option<PyReadonlyArray1<'_, f64>>,
) -> BindResult<ReportOverrides<'a>> {
    Ok(ReportOverrides {
        positions: position
            .as_ref()
            .map(|a| slice2("sensor_position", a, 3))
            .transpose()?,
        sigma_azimuth: sigma_azimuth
            .as_ref()
            .map(|a| slice1("sigma_azimuth", a))
            .transpose()?,
        sigma_elevation: match space {
            Space::Planar => None,
            Space::Spatial => sigma_elevation
                .as_ref()
                .map(|a| slice1("sigma_elevation", a))
                .transpose()?,
        },
    })
}

/// The measurement columns as the core reads them. A planar network's elevation column (NaN
/// in the table) is replaced by zeros: the core ignores it, and zeros keep every code path
/// finite whatever it does with the column.
pub struct Columns<'a> {
    sensor: &'a [i64],
    time: &'a [f64],
    azimuth: &'a [f64],
    elevation: Vec<f64>,
    table_elevation: &'a [f64],
    overrides: ReportOverrides<'a>,
}

impl MeasurementsArg<'_> {
    pub fn columns(&self, space: Space) -> BindResult<Columns<'_>> {
        let sensor = slice1("sensor", &self.sensor)?;
        let elevation = match space {
            Space::Planar => vec![0.0; sensor.len()],
            Space::Spatial => Vec::new(),
        };
        Ok(Columns {
            sensor,
            time: slice1("time", &self.time)?,
            azimuth: slice1("azimuth", &self.azimuth)?,
            elevation,
            table_elevation: slice1("elevation", &self.elevation)?,
            overrides: overrides(
                space,
                &self.sensor_position,
                &self.sigma_azimuth,
                &self.sigma_elevation,
            )?,
        })
    }
}

impl Columns<'_> {
    /// The validated core view against `sensors`.
    pub fn view<'a>(&'a self, sensors: &Sensors<'_>) -> BindResult<Measurements<'a>> {
        self.view_with_time(sensors, self.time)
    }

    /// The view with another time column (one static scan: times play no part).
    pub fn view_with_time<'a>(
        &'a self,
        sensors: &Sensors<'_>,
        time: &'a [f64],
    ) -> BindResult<Measurements<'a>> {
        let elevation = match sensors.space() {
            Space::Planar => &self.elevation,
            Space::Spatial => self.table_elevation,
        };
        Ok(
            Measurements::new(sensors, self.sensor, time, self.azimuth, elevation)?
                .with_overrides(sensors, self.overrides)?,
        )
    }

    pub fn len(&self) -> usize {
        self.sensor.len()
    }
}

/// Moves `data` into a NumPy array of `shape` without copying the buffer.
pub fn to_numpy<'py, T: Element>(
    py: Python<'py>,
    data: Vec<T>,
    shape: &[usize],
) -> BindResult<Bound<'py, PyArrayDyn<T>>> {
    let size = IxDyn(shape).size();
    let array = Array::from_shape_vec(IxDyn(shape), data).map_err(|e| {
        value_error(
            "internal",
            format!("result of {size} values does not fit shape {shape:?}: {e}"),
        )
    })?;
    Ok(array.into_pyarray(py))
}

/// Moves `data` into an owned 1-D NumPy array held by a result object.
pub fn owned<T: Element>(py: Python<'_>, data: Vec<T>) -> BindResult<Py<PyArrayDyn<T>>> {
    let n = data.len();
    Ok(to_numpy(py, data, &[n])?.unbind())
}

/// A string option parsed by the core's `FromStr`, or a `ValueError` naming the argument.
pub fn parse<T>(name: &str, value: &str) -> BindResult<T>
where
    T: std::str::FromStr<Err = passive_assoc_core::error::UnknownOption>,
{
    value.parse().map_err(|err| value_error(name, err))
}
