//! Bindings for the assignment solvers: the sparse S-D assignment (`assign_sd`, like MATLAB's
//! `assignsd` but sparse) and the dense 2-D linear assignment.

use std::time::Duration;

use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::convert::{count, slice1, to_numpy, I64Array};
use crate::assign::{branch_bound, lagrangian, lap, SdProblem, SdSolution};

/// Non-negative int64 → usize, naming the argument and index of the first negative entry.
fn to_usize(name: &str, values: &[i64]) -> PyResult<Vec<usize>> {
    values
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            usize::try_from(v).map_err(|_| {
                PyValueError::new_err(format!("{name}: entry {k} is {v}, must be >= 0"))
            })
        })
        .collect()
}

/// Solve a sparse S-D assignment; see `passive_assoc.assign_sd` for the Python-level docs.
#[pyfunction]
#[pyo3(signature = (tuples, costs, sizes, *, method="lagrangian", max_iter=200, gap_tol=1e-3, max_nodes=10_000_000, time_limit=10.0, warm_start="auto", sensor_order="auto", polish=false))]
#[allow(clippy::too_many_arguments)]
pub fn assign_sd<'py>(
    py: Python<'py>,
    tuples: PyReadonlyArray2<'py, i64>,
    costs: PyReadonlyArray1<'py, f64>,
    sizes: PyReadonlyArray1<'py, i64>,
    method: &str,
    max_iter: i64,
    gap_tol: f64,
    max_nodes: i64,
    time_limit: Option<f64>,
    warm_start: &str,
    sensor_order: &str,
    polish: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let warm_start = match warm_start {
        "auto" => lagrangian::WarmStart::Auto,
        "always" => lagrangian::WarmStart::Always,
        "never" => lagrangian::WarmStart::Never,
        other => {
            return Err(PyValueError::new_err(format!(
                "warm_start: must be 'auto', 'always' or 'never', got {other:?}"
            )))
        }
    };
    let sensor_order = match sensor_order {
        "auto" => lagrangian::SensorOrder::Auto,
        "given" => lagrangian::SensorOrder::Given,
        other => {
            return Err(PyValueError::new_err(format!(
                "sensor_order: must be 'auto' or 'given', got {other:?}"
            )))
        }
    };
    let n_sensors = tuples.shape()[1];
    let tuple_values = to_usize(
        "tuples",
        tuples
            .as_slice()
            .map_err(|_| PyValueError::new_err("tuples: array must be C-contiguous"))?,
    )?;
    let problem = SdProblem::new(
        tuple_values,
        n_sensors,
        slice1("costs", &costs)?.to_vec(),
        to_usize("sizes", slice1("sizes", &sizes)?)?,
    )?;
    let root = lagrangian::LagrangianOptions::default()
        .with_max_iter(count("max_iter", max_iter, 1)?)?
        .with_gap_tol(gap_tol)?
        .with_warm_start(warm_start)
        .with_sensor_order(sensor_order)
        .with_polish(polish);
    let solution: SdSolution = match method {
        "lagrangian" => py.detach(|| lagrangian::solve(&problem, &root)),
        "exact" => {
            let mut options = branch_bound::BranchBoundOptions::default()
                .with_max_nodes(count("max_nodes", max_nodes, 1)?)?
                .with_root(root);
            options = match time_limit {
                Some(seconds) if seconds.is_finite() && seconds > 0.0 => {
                    options.with_time_limit(Duration::from_secs_f64(seconds))?
                }
                Some(seconds) => {
                    return Err(PyValueError::new_err(format!(
                        "time_limit: must be > 0 seconds or None, got {seconds}"
                    )))
                }
                None => options.without_time_limit(),
            };
            py.detach(|| branch_bound::solve(&problem, &options))
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "method: must be 'lagrangian' or 'exact', got {other:?}"
            )))
        }
    };
    let out = PyDict::new(py);
    let chosen: Vec<i64> = solution.chosen.iter().map(|&k| k as i64).collect();
    let n = chosen.len();
    out.set_item("chosen", to_numpy(py, chosen, &[n])?)?;
    out.set_item("primal_cost", solution.primal_cost)?;
    out.set_item("dual_bound", solution.dual_bound)?;
    out.set_item("gap", solution.gap)?;
    out.set_item("iterations", solution.iterations)?;
    out.set_item("termination", solution.termination.as_str())?;
    out.set_item("optimal", solution.termination.is_optimal())?;
    Ok(out)
}

/// Dense rectangular min-cost 2-D assignment; returns (row_ind, col_ind, cost) like
/// `scipy.optimize.linear_sum_assignment` plus the total.
#[pyfunction]
pub fn assign_2d<'py>(
    py: Python<'py>,
    costs: PyReadonlyArray2<'py, f64>,
) -> PyResult<(I64Array<'py>, I64Array<'py>, f64)> {
    let (n_rows, n_cols) = (costs.shape()[0], costs.shape()[1]);
    let values = costs
        .as_slice()
        .map_err(|_| PyValueError::new_err("costs: array must be C-contiguous"))?;
    let solved = py.detach(|| lap::solve_dense(n_rows, n_cols, values))?;
    let (rows, cols): (Vec<i64>, Vec<i64>) = solved
        .row_to_col
        .iter()
        .enumerate()
        .filter_map(|(r, c)| c.map(|c| (r as i64, c as i64)))
        .unzip();
    let n = rows.len();
    Ok((
        to_numpy(py, rows, &[n])?,
        to_numpy(py, cols, &[n])?,
        solved.cost,
    ))
}
