//! Bindings for fuzzy track initiation (METHODS §1) and its closeness function: extract,
//! `py.detach`, delegate to the core, return arrays or a frozen result object.

use numpy::{PyArrayDyn, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;

use super::convert::{
    count, owned, parse, row_major, slice1, slice2, threads, to_numpy, to_usize, F64Array,
    I64Array, MeasurementsArg, SensorsArg,
};
use super::errors::{value_error, BindError, BindResult};
use super::interrupt;
use super::progress::Sink;
use passive_assoc_core::data::Sensors;
use passive_assoc_core::error::ensure_finite;
use passive_assoc_core::fti::{
    closeness_batch, descend_from, initiate_reporting, DescentOptions, Initiation,
    InitiationOptions, Neighbourhood, Precomputed, Spreads, StageCounts as CoreCounts,
    StageSeconds as CoreSeconds,
};
use passive_assoc_core::parallel::with_threads;

/// The membership spreads per sensor, (azimuth, elevation), radians.
type SpreadArrays<'py> = (PyReadonlyArray1<'py, f64>, PyReadonlyArray1<'py, f64>);

/// The initiation's settings, read by attribute from `passive_assoc.FuzzyTrackInitiator`
/// (the fields it declares).
#[derive(FromPyObject)]
pub struct InitiationSettings {
    candidates: String,
    prefit_gates: bool,
    sweep: bool,
    untangle: bool,
    on_limit: String,
    gate_sigmas: f64,
    n_detect: Option<i64>,
    ray_gate_sigmas: Option<f64>,
    reject_behind: bool,
    v_max: Option<f64>,
    chi2_gate: Option<f64>,
    one_per_scan: bool,
    detection_order: String,
    merge_tol: f64,
    descent_scaling: String,
    descent_max_iter: i64,
    max_candidates: i64,
    refine_passes: i64,
    candidate_scans: i64,
    support_gate: bool,
    track_test: Option<f64>,
    gate_pd: Option<f64>,
    search_stage: Option<i64>,
    n_threads: Option<i64>,
}

impl InitiationSettings {
    fn options(&self, pairs: Option<Vec<[usize; 2]>>) -> BindResult<InitiationOptions> {
        let descent = DescentOptions::default()
            .with_max_iter(count("descent_max_iter", self.descent_max_iter, 0)?)
            .with_scaling(parse("descent_scaling", &self.descent_scaling)?);
        Ok(InitiationOptions::default()
            .with_candidates(parse("candidates", &self.candidates)?)
            .with_prefit_gates(self.prefit_gates)
            .with_sweep(self.sweep)
            .with_untangle(self.untangle)
            .with_stop_at_limit(stop_at_limit(&self.on_limit)?)
            .with_pairs(pairs)
            .with_gate_sigmas(self.gate_sigmas)?
            .with_n_detect(self.n_detect.map(|n| count("n_detect", n, 1)).transpose()?)?
            .with_ray_gate_sigmas(self.ray_gate_sigmas)?
            .with_reject_behind(self.reject_behind)
            .with_v_max(self.v_max)?
            .with_chi2_gate(self.chi2_gate)?
            .with_one_per_scan(self.one_per_scan)
            .with_detection_order(parse("detection_order", &self.detection_order)?)
            .with_merge_tol(self.merge_tol)?
            .with_descent(descent)
            .with_max_candidates(count("max_candidates", self.max_candidates, 1)?)?
            .with_refine_passes(count("refine_passes", self.refine_passes, 0)?)
            .with_candidate_scans(count("candidate_scans", self.candidate_scans, 1)?)?
            .with_support_gate(self.support_gate)
            .with_track_test(self.track_test)?
            .with_gate_pd(self.gate_pd)?
            .with_search_stage(
                (self.search_stage)
                    .map(|n| count("search_stage", n, 1))
                    .transpose()?,
            )?)
    }
}

/// `on_limit`'s spelling: `"warn"` goes on with the tracks found (the Python package warns),
/// `"raise"` fails.
fn stop_at_limit(on_limit: &str) -> BindResult<bool> {
    match on_limit {
        "warn" => Ok(true),
        "raise" => Ok(false),
        other => Err(value_error(
            "on_limit",
            format!("expected 'warn' or 'raise', got {other:?}"),
        )),
    }
}

/// Candidates and optima surviving each stage of one initiation.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct StageCounts {
    raw: usize,
    ray_gate: usize,
    behind: usize,
    v_max: usize,
    fitted: usize,
    chi2_gate: usize,
    supported: usize,
    optima: usize,
    merged: usize,
    detected: usize,
}

/// Seconds spent in each stage of one initiation.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct StageSeconds {
    candidates: f64,
    fit: f64,
    support: f64,
    descent: f64,
    detection: f64,
    final_fit: f64,
}

/// What one initiation returns: per track its state, covariance, closeness and χ², and per
/// measurement row its track index (−1 = clutter).
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct InitiationOutput {
    estimates: Py<PyArrayDyn<f64>>,
    covariances: Py<PyArrayDyn<f64>>,
    closeness: Py<PyArrayDyn<f64>>,
    chi2: Py<PyArrayDyn<f64>>,
    labels: Py<PyArrayDyn<i64>>,
    descent_iterations: Py<PyArrayDyn<i64>>,
    stage_counts: Py<StageCounts>,
    stage_seconds: Py<StageSeconds>,
    /// The formation that ran, `"paper"`, `"rounds"` or `"witnessed"`.
    formation: &'static str,
    /// The limit that ended the formation early, or `None`.
    limit: Option<String>,
    /// With `limit`: the formation's scan slots formed in full before it stopped, and all of
    /// its slots.
    limit_slots: Option<(usize, usize)>,
}

/// Fuzzy track initiation. `pairs` is (K, 2) sensor indices; an empty (0, 2) array means every
/// pair a < b; `spreads` is (azimuth, elevation), one per sensor. `progress`, when given, is
/// called `(stage, fraction)` as the passes go (module `progress`); what it raises is raised.
#[pyfunction]
#[pyo3(signature = (measurements, sensors, pairs, spreads, t0, settings, progress=None))]
#[allow(clippy::too_many_arguments)] // the data, the pairs and spreads, the epoch, the settings
pub fn initiate(
    py: Python<'_>,
    measurements: MeasurementsArg<'_>,
    sensors: SensorsArg<'_>,
    pairs: PyReadonlyArray2<'_, i64>,
    spreads: SpreadArrays<'_>,
    t0: f64,
    settings: InitiationSettings,
    progress: Option<Py<PyAny>>,
) -> BindResult<InitiationOutput> {
    let network = sensors.view()?;
    let columns = measurements.columns(network.space())?;
    let table = columns.view(&network)?;
    let spreads = spreads_of(&network, &spreads)?;
    let options = settings.options(pair_list(slice2("pairs", &pairs, 2)?)?)?;
    let n_threads = threads(settings.n_threads)?;
    let sink = Sink::new(progress);
    let reported = sink.progress();
    let result = interrupt::detach(py, || {
        with_threads(n_threads, || {
            initiate_reporting(&network, &table, &spreads, t0, &options, reported)
        })
    })??;
    initiation_output(py, sink.settle(result)?)
}

fn initiation_output(py: Python<'_>, result: Initiation) -> BindResult<InitiationOutput> {
    let (t, d) = (result.tracks.len(), result.dim);
    let mut estimates = Vec::with_capacity(t * d);
    let mut covariances = Vec::with_capacity(t * d * d);
    for track in &result.tracks {
        estimates.extend_from_slice(&track.estimate);
        covariances.extend_from_slice(&track.covariance);
    }
    let iterations = result
        .descent_iterations
        .iter()
        .map(|&i| i as i64)
        .collect();
    let CoreCounts {
        raw,
        ray_gate,
        behind,
        v_max,
        fitted,
        chi2_gate,
        supported,
        optima,
        merged,
        detected,
    } = result.stage_counts;
    let CoreSeconds {
        candidates,
        fit,
        support,
        descent,
        detection,
        final_fit,
    } = result.stage_seconds;
    Ok(InitiationOutput {
        formation: result.formation.name(),
        limit_slots: (result.limit.as_ref()).map(|l| (l.slots_formed, l.slots)),
        limit: result.limit.map(|l| l.reached),
        estimates: to_numpy(py, estimates, &[t, d])?.unbind(),
        covariances: to_numpy(py, covariances, &[t, d, d])?.unbind(),
        closeness: owned(py, result.tracks.iter().map(|r| r.closeness).collect())?,
        chi2: owned(py, result.tracks.iter().map(|r| r.chi2).collect())?,
        labels: owned(py, result.labels)?,
        descent_iterations: owned(py, iterations)?,
        stage_counts: Py::new(
            py,
            StageCounts {
                raw,
                ray_gate,
                behind,
                v_max,
                fitted,
                chi2_gate,
                supported,
                optima,
                merged,
                detected,
            },
        )?,
        stage_seconds: Py::new(
            py,
            StageSeconds {
                candidates,
                fit,
                support,
                descent,
                detection,
                final_fit,
            },
        )?,
    })
}

/// Regrouping's neighbourhood (core `fti::Neighbourhood`): a 3-D table's rows as lines of
/// sight with the ray gate's settings, built once; `of(rows, free)` gives the free rows
/// meeting any of `rows`, ascending.
#[pyclass(frozen, module = "passive_assoc._core")]
pub struct RayNeighbourhood {
    inner: Neighbourhood,
}

#[pymethods]
impl RayNeighbourhood {
    #[new]
    #[pyo3(signature = (measurements, sensors, ray_gate_sigmas, v_max))]
    fn new(
        py: Python<'_>,
        measurements: MeasurementsArg<'_>,
        sensors: SensorsArg<'_>,
        ray_gate_sigmas: Option<f64>,
        v_max: Option<f64>,
    ) -> BindResult<Self> {
        let network = sensors.view()?;
        let columns = measurements.columns(network.space())?;
        let table = columns.view(&network)?;
        let options = InitiationOptions::default()
            .with_ray_gate_sigmas(ray_gate_sigmas)?
            .with_v_max(v_max)?;
        let inner = interrupt::detach(py, || Neighbourhood::new(&network, &table, &options))??;
        Ok(Self { inner })
    }

    /// The free rows (`free`: one flag per row) meeting any of `rows`, ascending.
    fn of(
        &self,
        py: Python<'_>,
        rows: PyReadonlyArray1<'_, i64>,
        free: PyReadonlyArray1<'_, bool>,
    ) -> BindResult<Py<PyArrayDyn<i64>>> {
        let rows = to_usize("rows", slice1("rows", &rows)?)?;
        let free = slice1("free", &free)?;
        let inner = &self.inner;
        let met = interrupt::detach(py, || inner.of(&rows, free))??;
        owned(py, met.into_iter().map(|m| m as i64).collect())
    }
}

/// R and ∂R/∂X0 (METHODS §1 eq. 17–18) at each row of `states` (P, 4 or 6); returns
/// (R: (P,), gradient: (P, D)).
#[pyfunction]
#[pyo3(signature = (measurements, sensors, spreads, states, t0, n_threads))]
pub fn closeness<'py>(
    py: Python<'py>,
    measurements: MeasurementsArg<'py>,
    sensors: SensorsArg<'py>,
    spreads: SpreadArrays<'py>,
    states: PyReadonlyArray2<'py, f64>,
    t0: f64,
    n_threads: Option<i64>,
) -> BindResult<(F64Array<'py>, F64Array<'py>)> {
    let (pre, d) = precompute(&measurements, &sensors, &spreads, t0)?;
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

/// The descent's settings, read by attribute: `maximize_closeness`'s validated arguments.
#[derive(FromPyObject)]
pub struct DescentSettings {
    t0: f64,
    scaling: String,
    max_iter: i64,
    n_threads: Option<i64>,
}

type Optima<'py> = (F64Array<'py>, F64Array<'py>, I64Array<'py>, I64Array<'py>);

/// Steepest ascent of R (METHODS §1 eq. 19) from each row of `starts`, scaled by the matching
/// covariance; returns (optima (P, D), R (P,), iterations (P,), evaluations (P,)).
#[pyfunction]
#[pyo3(signature = (measurements, sensors, spreads, starts, covariances, settings))]
pub fn maximize_closeness<'py>(
    py: Python<'py>,
    measurements: MeasurementsArg<'py>,
    sensors: SensorsArg<'py>,
    spreads: SpreadArrays<'py>,
    starts: PyReadonlyArray2<'py, f64>,
    covariances: PyReadonlyArray3<'py, f64>,
    settings: DescentSettings,
) -> BindResult<Optima<'py>> {
    let (pre, d) = precompute(&measurements, &sensors, &spreads, settings.t0)?;
    let starts = slice2("starts", &starts, d)?;
    let covariances = row_major("covariances", &covariances)?;
    let options = DescentOptions::default()
        .with_max_iter(count("max_iter", settings.max_iter, 0)?)
        .with_scaling(parse("scaling", &settings.scaling)?);
    let threads = threads(settings.n_threads)?;
    let optima = interrupt::detach(py, || {
        with_threads(threads, || {
            descend_from(&pre, starts, covariances, &options)
        })
    })???;
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

/// The validated closeness table of one call (owned: the array views end here) and the
/// state dimension.
fn precompute(
    measurements: &MeasurementsArg<'_>,
    sensors: &SensorsArg<'_>,
    spreads: &SpreadArrays<'_>,
    t0: f64,
) -> BindResult<(Precomputed, usize)> {
    let network = sensors.view()?;
    let columns = measurements.columns(network.space())?;
    let table = columns.view(&network)?;
    let spreads = spreads_of(&network, spreads)?;
    let pre = Precomputed::new(&network, &table, &spreads, t0)?;
    Ok((pre, 2 * network.space().position_dim()))
}

/// The per-sensor membership spreads, validated against the network.
fn spreads_of<'a>(network: &Sensors<'_>, spreads: &'a SpreadArrays<'_>) -> BindResult<Spreads<'a>> {
    Ok(Spreads::new(
        network.space(),
        network.len(),
        slice1("spread_azimuth", &spreads.0)?,
        slice1("spread_elevation", &spreads.1)?,
    )?)
}

/// Row-major (K, 2) sensor indices → pairs; an empty array means "every pair".
fn pair_list(flat: &[i64]) -> BindResult<Option<Vec<[usize; 2]>>> {
    if flat.is_empty() {
        return Ok(None);
    }
    flat.chunks_exact(2)
        .enumerate()
        .map(
            |(k, p)| match (usize::try_from(p[0]), usize::try_from(p[1])) {
                (Ok(a), Ok(b)) => Ok([a, b]),
                _ => Err(value_error(
                    "pairs",
                    format!("pair {k} is ({}, {}); indices must be >= 0", p[0], p[1]),
                )),
            },
        )
        .collect::<Result<Vec<_>, BindError>>()
        .map(Some)
}
