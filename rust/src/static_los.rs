//! Bindings for static LOS association (METHODS §2): candidate enumeration with eq. 2 costs,
//! and the paper's intensity-ordered search. Extract, `py.detach`, delegate to the core,
//! return frozen result objects.

use std::borrow::Cow;

use numpy::{PyArrayDyn, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::convert::{
    count, owned, row_major, slice1, threads, to_numpy, to_usize, MeasurementsArg, SensorsArg,
};
use super::errors::{value_error, BindResult};
use super::formation::AttributesArg;
use super::interrupt;
use passive_assoc_core::assign::CandidateSet;
use passive_assoc_core::parallel::with_threads_unless_sequential;
use passive_assoc_core::static_los::false_alarms::{
    check, gate_width, scan_density, table_density, MIN_SPAN,
};
use passive_assoc_core::static_los::{
    enumerate_with_attributes, enumerates_sequentially, intensity_search as core_intensity_search,
    searches_sequentially, Candidates as CoreCandidates, DetectionModel, EnumerateOptions,
    IntensityInput, IntensityOptions,
};

/// The enumeration's settings, read by attribute from `passive_assoc.StaticAssociator`.
#[derive(FromPyObject)]
pub struct EnumerationSettings {
    gate_sigmas: f64,
    min_intensity: i64,
    max_candidates: i64,
    n_threads: Option<i64>,
}

/// Partial tuples the enumeration examined: `tested[k]` / `pruned[k]` for prefixes with k
/// lines of sight (entries 0 and 1 unused).
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct EnumerationStages {
    tested: Vec<u64>,
    pruned: Vec<u64>,
    windowed_out: u64,
    /// Extensions cut by the attribute gate (0 without attributes).
    attribute_pruned: u64,
    candidates: u64,
}

/// The gated candidate tuples of one scan, columnar, `K` rows in lexicographic tuple order.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct Candidates {
    /// `(K, S)`: 0 = missed, else the 1-based index among that sensor's rows.
    tuples: Py<PyArrayDyn<i64>>,
    /// `(K, S)`: the table row of each entry, −1 = missed.
    rows: Py<PyArrayDyn<i64>>,
    positions: Py<PyArrayDyn<f64>>,
    covariances: Py<PyArrayDyn<f64>>,
    costs: Py<PyArrayDyn<f64>>,
    intensity: Py<PyArrayDyn<i64>>,
    chi2: Py<PyArrayDyn<f64>>,
    /// Reports per sensor.
    sizes: Py<PyArrayDyn<i64>>,
    stages: Py<EnumerationStages>,
}

/// The default false-alarm density of one scan's reports (module `false_alarms` of the
/// core), one value per sensor `0..n_sensors`; rows of other sensors are not counted. The
/// elevations are read when given (3-D). `sigma`, `(n_sensors, 2)` angle stds `[σβ, σε]`,
/// sets each span's floor (the default gate's width) as the solvers' default does; without
/// it the floor is 10⁻³ rad.
#[pyfunction]
#[pyo3(signature = (sensor, azimuth, elevation, n_sensors, p_false, sigma=None))]
pub fn default_false_alarm_density<'py>(
    py: Python<'py>,
    sensor: PyReadonlyArray1<'py, i64>,
    azimuth: PyReadonlyArray1<'py, f64>,
    elevation: Option<PyReadonlyArray1<'py, f64>>,
    n_sensors: usize,
    p_false: f64,
    sigma: Option<PyReadonlyArray2<'py, f64>>,
) -> BindResult<Bound<'py, PyArrayDyn<f64>>> {
    check(n_sensors, p_false)?;
    let floors: Vec<[f64; 2]> = match &sigma {
        None => vec![[MIN_SPAN; 2]; n_sensors],
        Some(given) => {
            let values = row_major("sigma", given)?;
            if given.shape() != [n_sensors, 2] {
                return Err(value_error(
                    "sigma",
                    format!("expected shape ({n_sensors}, 2), got {:?}", given.shape()),
                ));
            }
            if let Some(k) = values.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(value_error(
                    "sigma",
                    format!("entry {k} is {}; stds must be finite and > 0", values[k]),
                ));
            }
            values
                .chunks_exact(2)
                .map(|pair| [gate_width(pair[0]), gate_width(pair[1])])
                .collect()
        }
    };
    let (sensor, azimuth) = (slice1("sensor", &sensor)?, slice1("azimuth", &azimuth)?);
    let elevation = match &elevation {
        Some(e) => Some(slice1("elevation", e)?),
        None => None,
    };
    let lengths = [
        ("azimuth", Some(azimuth.len())),
        ("elevation", elevation.map(<[f64]>::len)),
    ];
    if let Some((name, Some(len))) = lengths
        .into_iter()
        .find(|(_, len)| len.is_some_and(|l| l != sensor.len()))
    {
        return Err(value_error(
            name,
            format!("has {len} values, sensor has {}", sensor.len()),
        ));
    }
    if let Some(row) = sensor.iter().position(|&j| j < 0) {
        return Err(value_error(
            "sensor",
            format!("row {row} names sensor {}", sensor[row]),
        ));
    }
    let reports = (0..sensor.len()).map(|m| {
        // Non-negative (checked above); an index past usize would not be a sensor either.
        let j = usize::try_from(sensor[m]).unwrap_or(usize::MAX);
        (j, azimuth[m], elevation.map_or(0.0, |e| e[m]))
    });
    let density = scan_density(reports, &floors, elevation.is_some(), p_false);
    to_numpy(py, density, &[n_sensors])
}

/// Enumerates the gated candidate tuples of one scan with ML positions, covariances and eq. 2
/// costs. Times play no part (one scan); the elevation column is ignored in 2-D.
#[pyfunction]
#[pyo3(signature = (measurements, sensors, pd, false_alarm_density, settings, attributes=None))]
pub fn enumerate_static(
    py: Python<'_>,
    measurements: MeasurementsArg<'_>,
    sensors: SensorsArg<'_>,
    pd: PyReadonlyArray1<'_, f64>,
    false_alarm_density: Option<PyReadonlyArray1<'_, f64>>,
    settings: EnumerationSettings,
    attributes: Option<AttributesArg<'_>>,
) -> BindResult<Candidates> {
    let (options, n_threads) = enumeration_options(&settings)?;
    let network = sensors.view()?;
    let columns = measurements.columns(network.space())?;
    // One scan: the table's times play no part, so a zero column stands in for them.
    let time = vec![0.0; columns.len()];
    let table = columns.view_with_time(&network, &time)?;
    let density = match &false_alarm_density {
        Some(given) => Cow::Borrowed(slice1("false_alarm_density", given)?),
        None => Cow::Owned(table_density(&table, 0..table.len(), &network)),
    };
    let detection = DetectionModel::new(&network, slice1("pd", &pd)?, &density)?;
    let gate = match &attributes {
        Some(a) => Some(a.gate(table.len())?),
        None => None,
    };
    let mut reports = vec![0usize; network.len()];
    for m in 0..table.len() {
        if let Some(count) = reports.get_mut(table.sensor(m)) {
            *count += 1;
        }
    }
    let sequential = enumerates_sequentially(&reports);
    let found = interrupt::detach(py, || {
        with_threads_unless_sequential(sequential, n_threads, || {
            enumerate_with_attributes(&network, &table, &detection, &options, gate)
        })
    })???;
    candidates_output(py, found)
}

fn candidates_output(py: Python<'_>, c: CoreCandidates) -> BindResult<Candidates> {
    let (k, s, d) = (c.len(), c.n_sensors, c.dim);
    let sizes = c.sizes.iter().map(|&n| n as i64).collect();
    let stages = EnumerationStages {
        tested: c.stages.tested.clone(),
        pruned: c.stages.pruned.clone(),
        windowed_out: c.stages.windowed_out,
        attribute_pruned: c.stages.attribute_pruned,
        candidates: c.stages.candidates,
    };
    Ok(Candidates {
        tuples: to_numpy(py, c.tuples, &[k, s])?.unbind(),
        rows: to_numpy(py, c.rows, &[k, s])?.unbind(),
        positions: to_numpy(py, c.positions, &[k, d])?.unbind(),
        covariances: to_numpy(py, c.covariances, &[k, d, d])?.unbind(),
        costs: owned(py, c.costs)?,
        intensity: owned(py, c.intensity)?,
        chi2: owned(py, c.chi2)?,
        sizes: owned(py, sizes)?,
        stages: Py::new(py, stages)?,
    })
}

/// The intensity search's settings, read by attribute from `passive_assoc.StaticAssociator`.
#[derive(FromPyObject)]
pub struct IntensitySettings {
    vote_fraction: f64,
    valid_airspace: bool,
    max_chains: Option<i64>,
    n_threads: Option<i64>,
}

/// The intensity search's options from the Python settings.
pub fn intensity_options(settings: &IntensitySettings) -> BindResult<IntensityOptions> {
    let max_chains = match settings.max_chains {
        Some(n) => Some(count("max_chains", n, 1)?),
        None => None,
    };
    Ok(IntensityOptions::default()
        .with_vote_fraction(settings.vote_fraction)?
        .with_valid_airspace(settings.valid_airspace)
        .with_max_chains(max_chains)?)
}

/// The enumeration's options and thread count from the Python settings.
pub fn enumeration_options(
    settings: &EnumerationSettings,
) -> BindResult<(EnumerateOptions, Option<usize>)> {
    let options = EnumerateOptions::default()
        .with_gate_sigmas(settings.gate_sigmas)?
        .with_min_intensity(count("min_intensity", settings.min_intensity, 2)?)?
        .with_max_candidates(count("max_candidates", settings.max_candidates, 1)?)?;
    Ok((options, threads(settings.n_threads)?))
}

/// One searched level of the intensity search.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct IntensityLevel {
    intensity: usize,
    candidates: usize,
    starts: usize,
    chains: usize,
    confirmed: usize,
}

/// The intensity search's choice (ascending indices into the candidates) and diagnostics.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct IntensityResult {
    chosen: Py<PyArrayDyn<i64>>,
    airspace_radius: f64,
    ghosts_dropped: usize,
    chains: usize,
    levels: Vec<Py<IntensityLevel>>,
}

/// The paper's intensity-ordered search over enumerated candidates: valid airspace, chains,
/// vote, then the next lower intensity. The result is the same for any thread count.
#[pyfunction]
#[pyo3(signature = (tuples, positions, costs, sizes, settings))]
pub fn intensity_search(
    py: Python<'_>,
    tuples: PyReadonlyArray2<'_, i64>,
    positions: PyReadonlyArray2<'_, f64>,
    costs: PyReadonlyArray1<'_, f64>,
    sizes: PyReadonlyArray1<'_, i64>,
    settings: IntensitySettings,
) -> BindResult<IntensityResult> {
    let n_threads = threads(settings.n_threads)?;
    let (k, n_sensors, dim) = (tuples.shape()[0], tuples.shape()[1], positions.shape()[1]);
    if positions.shape()[0] != k {
        return Err(value_error(
            "positions",
            format!("has {} rows, tuples has {k}", positions.shape()[0]),
        ));
    }
    let tuple_slice = row_major("tuples", &tuples)?;
    let position_slice = row_major("positions", &positions)?;
    let set = CandidateSet::new(
        to_usize("tuples", tuple_slice)?,
        n_sensors,
        slice1("costs", &costs)?.to_vec(),
        to_usize("sizes", slice1("sizes", &sizes)?)?,
    )?;
    let input = IntensityInput::new(set, position_slice.to_vec(), dim)?;
    let options = intensity_options(&settings)?;
    let sequential = searches_sequentially(costs.len());
    let outcome = interrupt::detach(py, || {
        with_threads_unless_sequential(sequential, n_threads, || {
            core_intensity_search(&input, &options)
        })
    })???;
    let chosen = outcome.chosen.iter().map(|&c| c as i64).collect();
    let levels = outcome
        .levels
        .iter()
        .map(|level| {
            Py::new(
                py,
                IntensityLevel {
                    intensity: level.intensity,
                    candidates: level.candidates,
                    starts: level.starts,
                    chains: level.chains,
                    confirmed: level.confirmed,
                },
            )
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok(IntensityResult {
        chosen: owned(py, chosen)?,
        airspace_radius: outcome.airspace_radius,
        ghosts_dropped: outcome.ghosts_dropped,
        chains: outcome.chains,
        levels,
    })
}
