//! Bindings for formation location with emitter attributes (METHODS §3) and the attribute
//! evidence the static association's gate shares. Extract, `py.detach`, delegate, return a
//! frozen result.

use numpy::{PyArrayDyn, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::convert::{
    count, owned, parse, row_major, threads, to_numpy, MeasurementsArg, SensorsArg,
};
use super::errors::{value_error, BindResult};
use super::interrupt;
use super::progress::Sink;
use passive_assoc_core::evidence::{AttributeGate, AttributeTable};
use passive_assoc_core::formation::{
    locate_reporting, FormationOptions, FormationOutput, Reference,
};
use passive_assoc_core::parallel::with_threads;

/// `passive_assoc._settings.AttributeEvidence`, read by attribute: the attribute columns
/// stacked `(K, N)` float64, their stds `(K, N)` or one per attribute `(K, 1)`, and the gate.
#[derive(FromPyObject)]
pub struct AttributesArg<'py> {
    values: PyReadonlyArray2<'py, f64>,
    stds: PyReadonlyArray2<'py, f64>,
    eta: f64,
    combination: String,
}

impl AttributesArg<'_> {
    /// The gate over the table's rows (`n_rows` must match the measurements).
    pub fn gate(&self, n_rows: usize) -> BindResult<AttributeGate<'_>> {
        let (k, rows) = (self.values.shape()[0], self.values.shape()[1]);
        let std_shape = self.stds.shape();
        if rows != n_rows || std_shape[0] != k || !(std_shape[1] == rows || std_shape[1] == 1) {
            return Err(value_error(
                "attributes",
                format!(
                    "values {:?} must be (K, {n_rows}) and stds (K, {n_rows}) or (K, 1), got stds {std_shape:?}",
                    self.values.shape()
                ),
            ));
        }
        let values = row_major("attributes", &self.values)?;
        let stds = row_major("attribute_std", &self.stds)?;
        let table = AttributeTable::new(values, stds, rows, k)?;
        Ok(AttributeGate::new(
            table,
            parse("combination", &self.combination)?,
            self.eta,
        )?)
    }
}

/// The subset that seeds the candidates: a sensor index, or `"smallest"`.
#[derive(FromPyObject)]
enum ReferenceArg {
    Sensor(i64),
    Named(String),
}

/// The formation method's settings, read by attribute from `passive_assoc.FormationLocator`.
#[derive(FromPyObject)]
pub struct FormationSettings {
    baseline_sensor: i64,
    reference: ReferenceArg,
    cluster_radius: String,
    one_to_one: bool,
    r_max: f64,
    region: Option<[f64; 4]>,
    in_front: bool,
    max_pairs: i64,
    n_threads: Option<i64>,
}

impl FormationSettings {
    fn options(&self) -> BindResult<FormationOptions> {
        let reference = match &self.reference {
            ReferenceArg::Named(name) if name == "smallest" => Reference::Smallest,
            ReferenceArg::Named(other) => {
                return Err(value_error(
                    "reference",
                    format!("must be 'smallest' or a sensor index, got {other:?}"),
                ))
            }
            ReferenceArg::Sensor(r) => Reference::Sensor(count("reference", *r, 0)?),
        };
        let mut options = FormationOptions::default()
            .with_baseline_sensor(count("baseline_sensor", self.baseline_sensor, 0)?)
            .with_reference(reference)
            .with_cluster_radius(parse("cluster_radius", &self.cluster_radius)?)
            .with_one_to_one(self.one_to_one)
            .with_r_max(self.r_max)?
            .with_in_front(self.in_front)
            .with_max_pairs(count("max_pairs", self.max_pairs, 1)?)?;
        if let Some(region) = self.region {
            options = options.with_region(region)?;
        }
        Ok(options)
    }
}

/// Why baseline meetings were dropped, summed over the baseline reports.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct FormationCounts {
    pairs: u64,
    parallel: u64,
    low_support: u64,
    out_of_range: u64,
    outside_region: u64,
    behind: u64,
    candidates: u64,
}

/// One entry per report of the baseline sensor, in table order (`B` of them).
#[pyclass(
    frozen,
    get_all,
    name = "FormationOutput",
    module = "passive_assoc._core"
)]
pub struct FormationOutputPy {
    baseline_rows: Py<PyArrayDyn<i64>>,
    /// `(B, S)`: chosen table row per sensor, −1 where none.
    rows: Py<PyArrayDyn<i64>>,
    /// `(B, S)`: `m(assoc)` with the baseline report (NaN at the baseline and where none).
    support: Py<PyArrayDyn<f64>>,
    radius: Py<PyArrayDyn<f64>>,
    positions: Py<PyArrayDyn<f64>>,
    covariances: Py<PyArrayDyn<f64>>,
    chi2: Py<PyArrayDyn<f64>>,
    /// `(N,)`: the group each input row ends in, −1 for none.
    labels: Py<PyArrayDyn<i64>>,
    /// `(N,)`: how many chosen sets hold each row.
    times_chosen: Py<PyArrayDyn<i64>>,
    counts: Py<FormationCounts>,
}

/// The modified baseline least-distance method on one snapshot of 2-D bearings, with the
/// attribute gate when `attributes` is given. Identical results for any thread count.
/// `progress`, when given, is called `(stage, fraction)` as baseline reports are decided
/// (module `progress`).
#[pyfunction]
#[pyo3(signature = (measurements, sensors, attributes, settings, progress=None))]
pub fn locate_formation(
    py: Python<'_>,
    measurements: MeasurementsArg<'_>,
    sensors: SensorsArg<'_>,
    attributes: Option<AttributesArg<'_>>,
    settings: FormationSettings,
    progress: Option<Py<PyAny>>,
) -> BindResult<FormationOutputPy> {
    let options = settings.options()?;
    let n_threads = threads(settings.n_threads)?;
    let network = sensors.view()?;
    let columns = measurements.columns(network.space())?;
    // One snapshot: the table's times play no part, so a zero column stands in for them.
    let time = vec![0.0; columns.len()];
    let table = columns.view_with_time(&network, &time)?;
    let gate = match &attributes {
        Some(a) => Some(a.gate(table.len())?),
        None => None,
    };
    let sink = Sink::new(progress);
    let reported = sink.progress();
    let out = interrupt::detach(py, || {
        with_threads(n_threads, || {
            locate_reporting(&network, &table, gate, &options, reported)
        })
    })??;
    output(py, sink.settle(out)?)
}

fn output(py: Python<'_>, out: FormationOutput) -> BindResult<FormationOutputPy> {
    let (b, s) = (out.baseline_rows.len(), out.n_sensors);
    let c = out.counts;
    let counts = FormationCounts {
        pairs: c.pairs,
        parallel: c.parallel,
        low_support: c.low_support,
        out_of_range: c.out_of_range,
        outside_region: c.outside_region,
        behind: c.behind,
        candidates: c.candidates,
    };
    Ok(FormationOutputPy {
        baseline_rows: owned(py, out.baseline_rows)?,
        rows: to_numpy(py, out.rows, &[b, s])?.unbind(),
        support: to_numpy(py, out.support, &[b, s])?.unbind(),
        radius: owned(py, out.radius)?,
        positions: to_numpy(py, out.positions, &[b, 2])?.unbind(),
        covariances: to_numpy(py, out.covariances, &[b, 2, 2])?.unbind(),
        chi2: owned(py, out.chi2)?,
        labels: owned(py, out.labels)?,
        times_chosen: owned(py, out.times_chosen)?,
        counts: Py::new(py, counts)?,
    })
}
