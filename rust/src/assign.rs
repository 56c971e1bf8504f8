//! Bindings for the assignment solvers: the sparse S-D assignment (`assign_sd`, like MATLAB's
//! `assignsd` but sparse) and the dense 2-D linear assignment.

use std::time::Duration;

use numpy::{
    PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use super::convert::{count, owned, parse, row_major, slice1, to_usize, I64Array};
use super::errors::{type_error, value_error, BindError, BindResult};
use super::interrupt;
use passive_assoc_core::assign::lagrangian::LagrangianOptions;
use passive_assoc_core::assign::{branch_bound, lagrangian, lap, SdMethod, SdProblem};

/// The S-D solvers' settings, read by attribute from the object that declares them
/// (`passive_assoc.StaticAssociator`, or `assign_sd`'s validated arguments).
#[derive(FromPyObject)]
pub struct SdSettings {
    max_iter: i64,
    gap_tol: f64,
    max_nodes: i64,
    time_limit: Option<f64>,
    warm_start: String,
    sensor_order: String,
    polish: bool,
}

/// What an S-D solver returns: the chosen tuples, costs, bound, and why it stopped.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct SdResult {
    /// Indices into the problem's tuples, ascending.
    chosen: Py<PyArrayDyn<i64>>,
    primal_cost: f64,
    dual_bound: f64,
    gap: f64,
    iterations: usize,
    termination: &'static str,
    optimal: bool,
}

/// Solve a sparse S-D assignment; see `passive_assoc.assign_sd` for the Python-level docs.
#[pyfunction]
#[pyo3(signature = (tuples, costs, sizes, method, settings))]
pub fn assign_sd(
    py: Python<'_>,
    tuples: PyReadonlyArray2<'_, i64>,
    costs: PyReadonlyArray1<'_, f64>,
    sizes: PyReadonlyArray1<'_, i64>,
    method: &str,
    settings: SdSettings,
) -> BindResult<SdResult> {
    let method: SdMethod = parse("method", method)?;
    let root = lagrangian_options(&settings)?;
    let n_sensors = tuples.shape()[1];
    let tuple_values = row_major("tuples", &tuples)?;
    let problem = SdProblem::new(
        to_usize("tuples", tuple_values)?,
        n_sensors,
        slice1("costs", &costs)?.to_vec(),
        to_usize("sizes", slice1("sizes", &sizes)?)?,
    )?;
    let solution = match method {
        SdMethod::Lagrangian => interrupt::detach(py, || lagrangian::solve(&problem, &root))?,
        SdMethod::Exact => {
            let options = branch_bound_options(&settings, root)?;
            interrupt::detach(py, || branch_bound::solve(&problem, &options))?
        }
    };
    let chosen = solution.chosen.iter().map(|&k| k as i64).collect();
    Ok(SdResult {
        chosen: owned(py, chosen)?,
        primal_cost: solution.primal_cost,
        dual_bound: solution.dual_bound,
        gap: solution.gap,
        iterations: solution.iterations,
        termination: solution.termination.as_str(),
        optimal: solution.termination.is_optimal(),
    })
}

/// Dense rectangular min-cost 2-D assignment; returns (row_ind, col_ind, cost) like
/// `scipy.optimize.linear_sum_assignment` plus the total. `costs` is a 2-D float64 array, or
/// a float32 one, solved without a float64 copy (exactly, in double precision:
/// [`lap::Entry`]). The dtype is tested by a cast, which unlike a failed extraction builds
/// no error, so a small float32 call costs what a float64 one does.
#[pyfunction]
pub fn assign_2d<'py>(
    py: Python<'py>,
    costs: &Bound<'py, PyAny>,
) -> BindResult<(I64Array<'py>, I64Array<'py>, f64)> {
    if let Ok(costs) = costs.cast::<PyArray2<f64>>() {
        return assign_dense(py, costs);
    }
    if let Ok(costs) = costs.cast::<PyArray2<f32>>() {
        return assign_dense(py, costs);
    }
    Err(type_error(
        "costs",
        "expected a 2-D float64 or float32 NumPy array",
    ))
}

/// [`assign_2d`] on one entry type.
fn assign_dense<'py, C: lap::Entry + numpy::Element>(
    py: Python<'py>,
    costs: &Bound<'py, PyArray2<C>>,
) -> BindResult<(I64Array<'py>, I64Array<'py>, f64)> {
    let (n_rows, n_cols) = (costs.shape()[0], costs.shape()[1]);
    if costs.len() > 1 && !costs.is_c_contiguous() {
        return Err(value_error(
            "costs",
            "array must be C-contiguous (row-major); pass np.ascontiguousarray(...)",
        ));
    }
    if n_rows == 0 || n_cols == 0 {
        // Nothing to assign; answered here, not by a solve sized by the other side (a
        // (0, 10⁹) array holds no memory, its solve's work vectors would).
        let empty = || PyArray1::from_slice(py, &[] as &[i64]).to_dyn().clone();
        return Ok((empty(), empty(), 0.0));
    }
    // SAFETY: the slice is read while this thread holds the GIL, and no Python code runs
    // between here and its last read (the small solve below, or the read that prepares a
    // large one, made before it is solved without the GIL), so neither Python code nor
    // native code that holds the GIL can write to the array meanwhile. Native code that
    // writes to it after releasing the GIL (another extension, a NumPy operation on a large
    // array) races with any reader, as it would with NumPy's own functions: that is the
    // caller's to avoid.
    let values = unsafe { costs.as_slice() }
        .map_err(|_| value_error("costs", "array must be C-contiguous and aligned"))?;
    // A small matrix is solved in place, holding the GIL (faster than releasing it, and no
    // Python code can write to the array meanwhile). A larger one is read once holding it,
    // keeping what the solve needs (its allowed entries if mostly forbidden, else a copy), and
    // solved without the GIL, so another thread writing to the caller's array cannot reach
    // the solve.
    let solved = if values.len() <= SMALL_DENSE {
        lap::solve_dense(n_rows, n_cols, values)?
    } else {
        let prepared = lap::prepare_dense(n_rows, n_cols, values)?;
        py.detach(move || prepared.solve())?
    };
    pairs_output(py, &solved)
}

/// Entries of a dense matrix up to which `assign_2d` keeps the GIL: a 16 × 16 solve takes a
/// few microseconds, about what releasing and retaking the thread state costs.
const SMALL_DENSE: usize = 256;

/// `(row_ind, col_ind, total)` of an assignment, as `scipy.optimize.linear_sum_assignment`
/// gives the pairs, by increasing row.
fn pairs_output<'py>(
    py: Python<'py>,
    solved: &lap::DenseAssignment,
) -> BindResult<(I64Array<'py>, I64Array<'py>, f64)> {
    // Sized once: an unzip of the filtered pairs would grow each vector step by step.
    let n = solved.row_to_col.iter().flatten().count();
    let (mut rows, mut cols) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for (r, c) in solved.row_to_col.iter().enumerate() {
        if let Some(c) = c {
            rows.push(r as i64);
            cols.push(*c as i64);
        }
    }
    // Copied into arrays NumPy allocates: cheaper than handing NumPy the vectors (one owner
    // object each), which shows in a small call; the copy is O(n) beside an O(n³) solve.
    Ok((
        PyArray1::from_slice(py, &rows).to_dyn().clone(),
        PyArray1::from_slice(py, &cols).to_dyn().clone(),
        solved.cost,
    ))
}

/// Sparse complete min-cost 2-D assignment of a CSR matrix (`indptr`, `indices`, `data`, shape
/// `(n_rows, n_cols)`), absent entries forbidden; returns what [`assign_2d`] returns.
#[pyfunction]
pub fn assign_2d_sparse<'py>(
    py: Python<'py>,
    shape: (i64, i64),
    indptr: PyReadonlyArray1<'py, i64>,
    indices: PyReadonlyArray1<'py, i64>,
    data: PyReadonlyArray1<'py, f64>,
) -> BindResult<(I64Array<'py>, I64Array<'py>, f64)> {
    let (n_rows, n_cols) = (count("shape", shape.0, 0)?, count("shape", shape.1, 0)?);
    let offsets = to_usize("indptr", row_major("indptr", &indptr)?)?;
    let columns = to_usize("indices", row_major("indices", &indices)?)?;
    let values = row_major("data", &data)?.to_vec();
    let costs = lap::SparseCosts::new(n_rows, n_cols, offsets, columns, values)?;
    let solved = py.detach(|| lap::solve_sparse_complete(&costs))?;
    pairs_output(py, &solved)
}

/// The Lagrangian's options from the Python settings.
pub fn lagrangian_options(settings: &SdSettings) -> BindResult<LagrangianOptions> {
    Ok(LagrangianOptions::default()
        .with_max_iter(count("max_iter", settings.max_iter, 1)?)?
        .with_gap_tol(settings.gap_tol)?
        .with_warm_start(parse("warm_start", &settings.warm_start)?)
        .with_sensor_order(parse("sensor_order", &settings.sensor_order)?)
        .with_polish(settings.polish)
        .with_time_limit(time_limit(settings.time_limit)?)?)
}

/// The branch-and-bound's options from the Python settings and the Lagrangian's at its root.
pub fn branch_bound_options(
    settings: &SdSettings,
    root: LagrangianOptions,
) -> BindResult<branch_bound::BranchBoundOptions> {
    let options = branch_bound::BranchBoundOptions::default()
        .with_max_nodes(count("max_nodes", settings.max_nodes, 1)?)?
        .with_root(root);
    Ok(match time_limit(settings.time_limit)? {
        Some(limit) => options.with_time_limit(limit)?,
        None => options.without_time_limit(),
    })
}

/// `time_limit` in seconds (None: none) as a `Duration`; both methods honour it.
fn time_limit(seconds: Option<f64>) -> BindResult<Option<Duration>> {
    match seconds {
        None => Ok(None),
        // try_from: a huge value (≳ 1.8e19 s) has no Duration and must not panic.
        Some(s) if s > 0.0 => Duration::try_from_secs_f64(s)
            .map(Some)
            .map_err(|_| time_limit_error(s)),
        Some(s) => Err(time_limit_error(s)),
    }
}

fn time_limit_error(seconds: f64) -> BindError {
    value_error(
        "time_limit",
        format!("must be a finite number of seconds > 0 (at most ~1.8e19), or None; got {seconds}"),
    )
}
