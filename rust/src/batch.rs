//! Binding of the many-scan static association: the whole table and the scans' rows in,
//! each scan enumerated and solved in the core with the GIL released, the scans in parallel.

use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use super::assign::{branch_bound_options, lagrangian_options, SdSettings};
use super::convert::{
    row_major, slice1, to_numpy, to_usize, F64Array, I64Array, MeasurementsArg, SensorsArg,
};
use super::errors::{value_error, BindResult};
use super::interrupt;
use super::progress::Sink;
use super::static_los::{
    enumeration_options, intensity_options, EnumerationSettings, IntensitySettings,
};
use passive_assoc_core::parallel::with_threads;
use passive_assoc_core::static_los::{associate_scans as core_associate_scans, ScanSolver, Scans};

/// Associates every scan: `rows` (the table's rows scan by scan) and `offsets` (CSR over
/// scans), `pd` per sensor, `false_alarm_density` per scan and sensor (`None`: each scan's
/// default). `method` picks the solver ("intensity", "lagrangian", or "exact": the
/// branch-and-bound). Returns (labels per entry of `rows`: target index within its scan or −1;
/// targets per scan; positions of every target, scan by scan, `(targets, dim)`; per scan,
/// whether the branch-and-bound stopped at `max_nodes` unproven). `progress`, when given, is
/// called `("scans", fraction)` as scans finish (module `progress`).
#[pyfunction]
#[pyo3(signature = (measurements, sensors, rows, offsets, pd, false_alarm_density, associator, progress=None))]
#[allow(clippy::too_many_arguments)] // the table, its scans, the per-sensor arrays, the settings
pub fn associate_scans<'py>(
    py: Python<'py>,
    measurements: MeasurementsArg<'py>,
    sensors: SensorsArg<'py>,
    rows: PyReadonlyArray1<'py, i64>,
    offsets: PyReadonlyArray1<'py, i64>,
    pd: PyReadonlyArray1<'py, f64>,
    false_alarm_density: Option<PyReadonlyArray2<'py, f64>>,
    associator: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
) -> BindResult<(I64Array<'py>, I64Array<'py>, F64Array<'py>, Vec<bool>)> {
    let enumeration: EnumerationSettings = associator.extract()?;
    let sd: SdSettings = associator.extract()?;
    let intensity: IntensitySettings = associator.extract()?;
    let method: String = associator.getattr("method")?.extract()?;
    let (enumerate, n_threads) = enumeration_options(&enumeration)?;
    let solver = match method.as_str() {
        "intensity" => ScanSolver::Intensity(intensity_options(&intensity)?),
        "lagrangian" => ScanSolver::Lagrangian(lagrangian_options(&sd)?),
        "exact" => ScanSolver::Exact(branch_bound_options(&sd, lagrangian_options(&sd)?)?),
        other => {
            return Err(value_error(
                "method",
                format!("must be 'intensity', 'lagrangian' or 'exact', got {other:?}"),
            ))
        }
    };
    let network = sensors.view()?;
    let columns = measurements.columns(network.space())?;
    let time = vec![0.0; columns.len()];
    let table = columns.view_with_time(&network, &time)?;
    let rows = to_usize("rows", slice1("rows", &rows)?)?;
    let offsets = to_usize("offsets", slice1("offsets", &offsets)?)?;
    let density = match &false_alarm_density {
        Some(given) => Some(row_major("false_alarm_density", given)?),
        None => None,
    };
    let pd = slice1("pd", &pd)?;
    let scans = Scans {
        rows: &rows,
        offsets: &offsets,
    };
    let sink = Sink::new(progress);
    let reported = sink.progress();
    let results = interrupt::detach(py, || {
        with_threads(n_threads, || {
            let settings = (&enumerate, &solver);
            core_associate_scans(&network, &table, scans, (pd, density), settings, reported)
        })
    })??;
    let results = sink.settle(results)?;
    let dim =
        usize::from(network.space() == passive_assoc_core::geometry::model::Space::Spatial) + 2;
    let labels: Vec<i64> = results
        .iter()
        .flat_map(|r| r.labels.iter().copied())
        .collect();
    let targets: Vec<i64> = results.iter().map(|r| r.targets as i64).collect();
    let positions: Vec<f64> = results
        .iter()
        .flat_map(|r| r.positions.iter().copied())
        .collect();
    let node_limited: Vec<bool> = results.iter().map(|r| r.node_limited).collect();
    let (n_labels, n_scans, n_targets) = (labels.len(), targets.len(), positions.len() / dim);
    Ok((
        to_numpy(py, labels, &[n_labels])?,
        to_numpy(py, targets, &[n_scans])?,
        to_numpy(py, positions, &[n_targets, dim])?,
        node_limited,
    ))
}
