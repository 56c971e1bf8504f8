//! The intensity search's input: the shared [`CandidateSet`] plus each candidate's point.
//! Its own module so that the search's helpers (`airspace`, `chains`, `measurement_ids`) and
//! the search itself all depend on it, and not on each other.

use crate::assign::CandidateSet;
use crate::error::{ensure_finite, CoreError, CoreResult};

/// Validated input: a candidate set of `K` tuples over `S` sensors and one point per tuple.
#[derive(Clone, Debug)]
pub struct IntensityInput {
    set: CandidateSet,
    positions: Vec<f64>,
    dim: usize,
}

impl IntensityInput {
    /// `positions` is `K × dim` row-major, `dim` in 1..=3 (the airspace index is built for
    /// points on a line, in the plane or in space).
    pub fn new(set: CandidateSet, positions: Vec<f64>, dim: usize) -> CoreResult<Self> {
        let k = set.n_tuples();
        if !(1..=3).contains(&dim) || Some(positions.len()) != k.checked_mul(dim) {
            return Err(CoreError::shape(
                "positions",
                format!(
                    "expected shape ({k}, d) with d in 1..=3, got {} values in {dim} columns",
                    positions.len()
                ),
            ));
        }
        ensure_finite("positions", &positions)?;
        Ok(Self {
            set,
            positions,
            dim,
        })
    }

    /// The candidate tuples and their costs.
    pub fn candidates(&self) -> &CandidateSet {
        &self.set
    }

    pub fn n_sensors(&self) -> usize {
        self.set.n_sensors()
    }

    pub fn dim(&self) -> usize {
        self.dim
    }

    pub fn len(&self) -> usize {
        self.set.n_tuples()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub(super) fn costs(&self) -> &[f64] {
        self.set.costs()
    }

    pub(super) fn tuple(&self, k: usize) -> &[usize] {
        self.set.tuple(k)
    }

    pub(super) fn point(&self, k: usize) -> &[f64] {
        &self.positions[k * self.dim..(k + 1) * self.dim]
    }

    /// Reports of sensor s.
    pub(super) fn size(&self, s: usize) -> usize {
        self.set.sizes()[s]
    }

    /// Reports over all sensors (saturating: counts near `usize::MAX` are legal input).
    pub(super) fn sizes_total(&self) -> usize {
        self.set
            .sizes()
            .iter()
            .fold(0usize, |acc, &n| acc.saturating_add(n))
    }

    pub(super) fn intensity(&self, k: usize) -> usize {
        self.set.intensity(k)
    }

    pub(super) fn distance(&self, a: usize, b: usize) -> f64 {
        self.distance_squared(a, b).sqrt()
    }

    pub(super) fn distance_squared(&self, a: usize, b: usize) -> f64 {
        self.point(a)
            .iter()
            .zip(self.point(b))
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
    }
}
