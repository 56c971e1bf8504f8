//! The one candidate-set type of the S-D methods: K tuples over S sensors with their costs
//! and the number of reports per sensor. The Lagrangian and branch and bound read it through
//! [`SdProblem`](super::SdProblem); the intensity search of `static_los` reads it directly.

use crate::error::{ensure_finite, CoreError, CoreResult};

/// Validated candidate tuples. A tuple is a row of `n_sensors` entries; entry `s` is `0`
/// ("sensor s missed it") or `1..=sizes[s]`, a report of sensor `s`.
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateSet {
    n_sensors: usize,
    sizes: Vec<usize>,
    tuples: Vec<usize>,
    costs: Vec<f64>,
}

impl CandidateSet {
    /// Validates and builds a set. `tuples` is `K × n_sensors` row-major with
    /// `K = costs.len()`; `sizes[s]` is the number of reports of sensor `s` (may be 0; no
    /// memory is sized by it here).
    ///
    /// Errors: `OutOfRange` if `n_sensors < 2` or an entry exceeds its sensor's size, `Shape`
    /// for mismatched lengths, `NonFinite` for a NaN/inf cost.
    pub fn new(
        tuples: Vec<usize>,
        n_sensors: usize,
        costs: Vec<f64>,
        sizes: Vec<usize>,
    ) -> CoreResult<Self> {
        check_sensors(n_sensors, &sizes)?;
        let k = costs.len();
        if Some(tuples.len()) != k.checked_mul(n_sensors) {
            let got = tuples.len();
            return Err(CoreError::shape(
                "tuples",
                format!("length {got} is not len(costs) × n_sensors = {k} × {n_sensors}"),
            ));
        }
        if let Some(at) = (0..tuples.len()).find(|&at| tuples[at] > sizes[at % n_sensors]) {
            let (row, col) = (at / n_sensors, at % n_sensors);
            return Err(CoreError::out_of_range(
                "tuples",
                format!(
                    "row {row} column {col} is {} but sensor {col} has {} reports",
                    tuples[at], sizes[col]
                ),
            ));
        }
        ensure_finite("costs", &costs)?;
        super::check_cost_range("costs", &costs)?;
        Ok(Self {
            n_sensors,
            sizes,
            tuples,
            costs,
        })
    }

    /// Number of sensors S.
    pub fn n_sensors(&self) -> usize {
        self.n_sensors
    }

    /// Reports per sensor.
    pub fn sizes(&self) -> &[usize] {
        &self.sizes
    }

    /// Number of candidate tuples K.
    pub fn n_tuples(&self) -> usize {
        self.costs.len()
    }

    /// Tuple `k` (panics if `k >= n_tuples()`, like slice indexing).
    pub fn tuple(&self, k: usize) -> &[usize] {
        &self.tuples[k * self.n_sensors..(k + 1) * self.n_sensors]
    }

    /// All tuple costs.
    pub fn costs(&self) -> &[f64] {
        &self.costs
    }

    /// Lines of sight through tuple `k`: its non-zero entries.
    pub fn intensity(&self, k: usize) -> usize {
        self.tuple(k).iter().filter(|&&i| i > 0).count()
    }

    /// The same set with its sensors in `order` (sensor `s` of the result is sensor
    /// `order[s]` of `self`); tuple indices and costs are unchanged.
    pub(crate) fn reordered(&self, order: &[usize]) -> Self {
        let tuples = (0..self.n_tuples())
            .flat_map(|k| order.iter().map(move |&s| (k, s)))
            .map(|(k, s)| self.tuple(k)[s])
            .collect();
        Self {
            n_sensors: self.n_sensors,
            sizes: order.iter().map(|&s| self.sizes[s]).collect(),
            tuples,
            costs: self.costs.clone(),
        }
    }
}

/// At least two sensors, one size per sensor.
pub(crate) fn check_sensors(n_sensors: usize, sizes: &[usize]) -> CoreResult<()> {
    if n_sensors < 2 {
        return Err(CoreError::out_of_range(
            "n_sensors",
            format!("S-D assignment needs at least 2 sensors, got {n_sensors}"),
        ));
    }
    if sizes.len() != n_sensors {
        let got = sizes.len();
        return Err(CoreError::shape(
            "sizes",
            format!("length {got} is not n_sensors = {n_sensors}"),
        ));
    }
    Ok(())
}
