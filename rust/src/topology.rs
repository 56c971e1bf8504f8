//! Bindings for track-to-track association by reference topology (METHODS §4) and its
//! nearest-neighbour baseline: a `#[pyclass]` handle per local source keeps the window's
//! history between scans; each update extracts the two scans, releases the GIL and runs the
//! core.

use numpy::{
    PyArrayDyn, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use super::convert::{count, owned, parse, row_major, slice1, slice2, threads, to_numpy, F64Array};
use super::errors::{value_error, BindResult};
use super::interrupt;
use passive_assoc_core::parallel::with_threads;
use passive_assoc_core::topology::{
    topology_vectors as core_vectors, Associator, BiasEstimate, DecisionOptions, Gate, ScanTracks,
    Scoring, TopologyOptions,
};

/// `passive_assoc._settings.TopologySettings`, read by attribute.
#[derive(FromPyObject)]
pub struct TopologySettings {
    scoring: String,
    rings: i64,
    sectors: i64,
    radius: f64,
    delta: f64,
    delta_prime: f64,
    diffusion: String,
    reference: String,
    threshold: f64,
    window: i64,
    gate: Option<f64>,
    auto_gate: bool,
    chi2_gate: Option<f64>,
    decision: String,
    max_bias_deg: f64,
    max_range: f64,
    gate_probability: f64,
    topology_weight: f64,
    n_threads: Option<i64>,
}

impl TopologySettings {
    fn grid(&self) -> BindResult<TopologyOptions> {
        Ok(TopologyOptions::default()
            .with_rings(count("rings", self.rings, 1)?)?
            .with_sectors(count("sectors", self.sectors, 1)?)?
            .with_radius(self.radius)?
            .with_delta(self.delta)?
            .with_delta_prime(self.delta_prime)?
            .with_diffusion(parse("diffusion", &self.diffusion)?)
            .with_reference(parse("reference", &self.reference)?))
    }

    fn associator(&self) -> BindResult<Associator> {
        let scoring = match self.scoring.as_str() {
            "topology" => Scoring::Topology(self.grid()?),
            "distance" => Scoring::Distance,
            other => {
                return Err(value_error(
                    "scoring",
                    format!("must be 'topology' or 'distance', got {other:?}"),
                ))
            }
        };
        let gate = match (self.auto_gate, self.gate) {
            (true, _) => Gate::Auto,
            (false, Some(g)) => Gate::Distance(g),
            (false, None) => Gate::Off,
        };
        let decision = DecisionOptions::default()
            .with_threshold(self.threshold)?
            .with_window(count("window", self.window, 1)?)?
            .with_gate(gate)?
            .with_chi2_gate(self.chi2_gate)?
            .with_decision(parse("decision", &self.decision)?)
            .with_max_bias_deg(self.max_bias_deg)?
            .with_max_range(self.max_range)?
            .with_gate_probability(self.gate_probability)?
            .with_topology_weight(self.topology_weight)?;
        Ok(Associator::new(scoring, decision))
    }
}

/// One side of a scan: track ids `(n,)`, planar positions `(n, 2)`, and optionally planar
/// velocities `(n, 2)`, heights `(n,)` and position covariances `(n, d, d)` (d = 3 with
/// heights, else 2).
type Side<'py> = (
    PyReadonlyArray1<'py, i64>,
    PyReadonlyArray2<'py, f64>,
    Option<PyReadonlyArray2<'py, f64>>,
    Option<PyReadonlyArray1<'py, f64>>,
    Option<PyReadonlyArray3<'py, f64>>,
);

fn scan_tracks<'a>(name: &'static str, side: &'a Side<'_>) -> BindResult<ScanTracks<'a>> {
    let velocities = match &side.2 {
        Some(v) => Some(slice2(name, v, 2)?),
        None => None,
    };
    let mut tracks = ScanTracks::new(
        name,
        slice1(name, &side.0)?,
        slice2(name, &side.1, 2)?,
        velocities,
    )?;
    if let Some(h) = &side.3 {
        tracks = tracks.with_heights(name, slice1(name, h)?)?;
    }
    if let Some(c) = &side.4 {
        let d = tracks.dim();
        if c.shape()[1..] != [d, d] {
            return Err(value_error(
                name,
                format!(
                    "covariances: expected shape (n, {d}, {d}), got {:?}",
                    c.shape()
                ),
            ));
        }
        tracks = tracks.with_covariances(name, row_major(name, c)?)?;
    }
    Ok(tracks)
}

/// The pairs of one scan as rows into that scan's local and system arrays.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct ScanPairs {
    /// `(k, 2)`: local row, system row.
    pairs: Py<PyArrayDyn<i64>>,
    /// The window-averaged score of each pair.
    scores: Py<PyArrayDyn<f64>>,
}

/// A bias estimate: rotation (rad) with its standard deviation, translation (m), pairs
/// (points) and track pairs used, and whether it is reliable.
#[pyclass(frozen, get_all, module = "passive_assoc._core")]
pub struct Bias {
    rotation: f64,
    rotation_std: f64,
    translation: (f64, f64),
    pairs: usize,
    tracks: usize,
    reliable: bool,
}

impl From<BiasEstimate> for Bias {
    fn from(b: BiasEstimate) -> Self {
        Self {
            rotation: b.rotation,
            rotation_std: b.rotation_std,
            translation: (b.translation[0], b.translation[1]),
            pairs: b.pairs,
            tracks: b.clusters,
            reliable: b.reliable,
        }
    }
}

/// One local source's streaming association with the system picture.
#[pyclass(module = "passive_assoc._core")]
pub struct AssociatorState {
    inner: Associator,
    n_threads: Option<usize>,
}

#[pymethods]
impl AssociatorState {
    #[new]
    fn new(settings: TopologySettings) -> BindResult<Self> {
        Ok(Self {
            inner: settings.associator()?,
            n_threads: threads(settings.n_threads)?,
        })
    }

    /// Associates one scan (`local` and `system` are `(ids, positions, velocities, heights,
    /// covariances)`).
    fn update(
        &mut self,
        py: Python<'_>,
        local: Side<'_>,
        system: Side<'_>,
    ) -> BindResult<ScanPairs> {
        let (local, system) = (
            scan_tracks("local", &local)?,
            scan_tracks("system", &system)?,
        );
        let (inner, n_threads) = (&mut self.inner, self.n_threads);
        let out = interrupt::detach(py, || {
            with_threads(n_threads, || inner.update(&local, &system))
        })???;
        let k = out.pairs.len();
        let flat = out
            .pairs
            .iter()
            .flat_map(|&(i, j)| [i as i64, j as i64])
            .collect();
        Ok(ScanPairs {
            pairs: to_numpy(py, flat, &[k, 2])?.unbind(),
            scores: owned(py, out.scores)?,
        })
    }

    /// The rigid bias estimate from every pair so far (None before the first pair).
    fn bias(&self) -> Option<Bias> {
        self.inner.bias().map(Bias::from)
    }

    /// The rotation-only bias estimate about `centre` (x, y).
    fn bias_about(&self, centre: (f64, f64)) -> Option<Bias> {
        self.inner.bias_about([centre.0, centre.1]).map(Bias::from)
    }
}

/// Every track's topology vector, `(n, rings · sectors)`.
#[pyfunction]
pub fn topology_vectors<'py>(
    py: Python<'py>,
    tracks: Side<'py>,
    settings: TopologySettings,
) -> BindResult<F64Array<'py>> {
    let grid = settings.grid()?;
    let tracks = scan_tracks("tracks", &tracks)?;
    let n_threads = threads(settings.n_threads)?;
    let vectors = py.detach(|| with_threads(n_threads, || core_vectors(&tracks, &grid)))?;
    let values = vectors.into_iter().map(f64::from).collect();
    to_numpy(py, values, &[tracks.len(), grid.cells()])
}
