//! The validated input of the S-D assignment problem (METHODS.md §2, baselines A and B).

use super::candidates::{check_sensors, CandidateSet};
use crate::error::{CoreError, CoreResult};

/// Upper bound on reports per sensor accepted by [`SdProblem::new`].
pub const MAX_REPORTS_PER_SENSOR: usize = 10_000_000;

/// An S-D assignment problem: choose candidate tuples minimising the sum of their costs so that
/// every real report is used by at most one chosen tuple (unused reports are false alarms,
/// cost 0).
///
/// A tuple is a row of `n_sensors` entries; entry `s` is `0` ("sensor s missed it") or
/// `1..=sizes[s]`, a report of sensor `s`. Conventions the solvers rely on:
/// * an all-zero tuple (the dummy, cost 0 by definition) is accepted and ignored;
/// * a tuple with cost `>= 0` is never chosen: dropping it never raises the objective;
/// * duplicate tuples are allowed; the solvers simply never need more than the cheapest.
#[derive(Debug, Clone, PartialEq)]
pub struct SdProblem {
    set: CandidateSet,
    /// Tuples worth choosing: not all-zero and with negative cost, ascending.
    active: Vec<usize>,
    /// Prefix sums of `sizes`: sensor `s`'s report `i > 0` has flat id `report_offs[s] + i − 1`.
    report_offs: Vec<usize>,
}

/// Prefix sums of the sizes, from 0: the first flat report id of each sensor, then the total.
fn prefix_sums(sizes: &[usize]) -> Vec<usize> {
    std::iter::once(0)
        .chain(sizes.iter().scan(0, |total, &n| {
            *total += n;
            Some(*total)
        }))
        .collect()
}

impl SdProblem {
    /// Validates and builds a problem. `tuples` is `K × n_sensors` row-major with
    /// `K = costs.len()`; `sizes[s]` is the number of reports of sensor `s` (may be 0).
    ///
    /// Errors: `OutOfRange` if `n_sensors < 2` or an entry exceeds its sensor's size, `Shape`
    /// for mismatched lengths, `CapExceeded` for a size above [`MAX_REPORTS_PER_SENSOR`],
    /// `NonFinite` for a NaN/inf cost.
    ///
    /// ```
    /// use passive_assoc_core::assign::SdProblem;
    /// // Two tuples over 3 sensors that share report 1 of sensor 0.
    /// let p = SdProblem::new(vec![1, 1, 1, 1, 2, 0], 3, vec![-5.0, -3.0], vec![1, 2, 1]).unwrap();
    /// assert_eq!(p.n_tuples(), 2);
    /// assert!(p.evaluate(&[0, 1]).is_err());
    /// assert_eq!(p.evaluate(&[0]).unwrap(), -5.0);
    /// ```
    pub fn new(
        tuples: Vec<usize>,
        n_sensors: usize,
        costs: Vec<f64>,
        sizes: Vec<usize>,
    ) -> CoreResult<Self> {
        check_sensors(n_sensors, &sizes)?;
        check_cap(&sizes)?;
        Self::from_set(CandidateSet::new(tuples, n_sensors, costs, sizes)?)
    }

    /// The problem over a validated candidate set (the report-count cap checked here: the
    /// solvers allocate per report).
    pub fn from_set(set: CandidateSet) -> CoreResult<Self> {
        check_cap(set.sizes())?;
        let active = (0..set.n_tuples())
            .filter(|&t| set.costs()[t] < 0.0 && set.tuple(t).iter().any(|&i| i > 0))
            .collect();
        Ok(Self {
            report_offs: prefix_sums(set.sizes()),
            set,
            active,
        })
    }

    /// The candidate set this problem chooses from.
    pub fn candidates(&self) -> &CandidateSet {
        &self.set
    }

    /// Number of sensors S.
    pub fn n_sensors(&self) -> usize {
        self.set.n_sensors()
    }

    /// Reports per sensor.
    pub fn sizes(&self) -> &[usize] {
        self.set.sizes()
    }

    /// Number of candidate tuples K (including ignored ones).
    pub fn n_tuples(&self) -> usize {
        self.set.n_tuples()
    }

    /// Tuple `k` (panics if `k >= n_tuples()`, like slice indexing).
    pub fn tuple(&self, k: usize) -> &[usize] {
        self.set.tuple(k)
    }

    /// All tuple costs.
    pub fn costs(&self) -> &[f64] {
        self.set.costs()
    }

    /// Indices of the tuples a solver may choose (non-dummy, negative cost), ascending.
    pub fn active(&self) -> &[usize] {
        &self.active
    }

    /// All sensors' reports together: flat report ids are `0..n_reports()`.
    pub(crate) fn n_reports(&self) -> usize {
        self.report_offs[self.n_sensors()]
    }

    /// Sensor `s`'s report `i > 0` has flat id `report_offsets()[s] + i − 1`.
    pub(crate) fn report_offsets(&self) -> &[usize] {
        &self.report_offs
    }

    /// The flat ids of tuple `k`'s real reports (see [`Self::report_offsets`]).
    pub(crate) fn flat_reports(&self, k: usize) -> impl Iterator<Item = usize> + Clone + '_ {
        let t = self.tuple(k);
        (0..t.len())
            .filter(move |&s| t[s] > 0)
            .map(move |s| self.report_offs[s] + t[s] - 1)
    }

    /// The active tuples by ascending cost, ties by index: the local searches' scan order.
    pub(crate) fn active_by_cost(&self) -> Vec<usize> {
        let c = self.costs();
        let mut by_cost = self.active.clone();
        by_cost.sort_by(|&a, &b| c[a].total_cmp(&c[b]).then(a.cmp(&b)));
        by_cost
    }

    /// The same problem with only the tuples of `active` (ascending, drawn from
    /// [`Self::active`]) worth choosing: the Lagrangian solver's, once it has proven the
    /// others out of every solution better than its incumbent (module `lagrangian`).
    pub(crate) fn with_active(&self, active: Vec<usize>) -> Self {
        debug_assert!(active.windows(2).all(|w| w[0] < w[1]));
        Self {
            set: self.set.clone(),
            active,
            report_offs: self.report_offs.clone(),
        }
    }

    /// The same problem with its sensors in `order` (sensor `s` of the result is sensor
    /// `order[s]` of `self`); tuple indices, costs and hence every solution are unchanged.
    /// `order` must be a permutation of `0..n_sensors` (the solvers compute it themselves).
    pub(crate) fn reordered(&self, order: &[usize]) -> Self {
        debug_assert!({
            let mut seen = order.to_vec();
            seen.sort_unstable();
            seen == (0..self.n_sensors()).collect::<Vec<_>>()
        });
        let set = self.set.reordered(order);
        Self {
            report_offs: prefix_sums(set.sizes()),
            set,
            active: self.active.clone(),
        }
    }

    /// Total cost of `chosen` after checking it is feasible: indices in range, no duplicates,
    /// no real report used twice. Errors name the offending position.
    pub fn evaluate(&self, chosen: &[usize]) -> CoreResult<f64> {
        let mut owner: Vec<Vec<Option<usize>>> =
            self.sizes().iter().map(|&n| vec![None; n + 1]).collect();
        let mut total = 0.0;
        for (pos, &k) in chosen.iter().enumerate() {
            if k >= self.n_tuples() {
                let n = self.n_tuples();
                return Err(CoreError::out_of_range(
                    "chosen",
                    format!("entry {pos} is {k} but there are {n} tuples"),
                ));
            }
            for (s, &i) in self.tuple(k).iter().enumerate().filter(|e| *e.1 > 0) {
                if let Some(prev) = owner[s][i].replace(k) {
                    return Err(CoreError::ill_posed(
                        "chosen",
                        format!("entry {pos} (tuple {k}) reuses report {i} of sensor {s}, already used by tuple {prev}"),
                    ));
                }
            }
            total += self.costs()[k];
        }
        Ok(total)
    }
}

/// Solvers allocate per report; a size far beyond any real scan is a caller's mistake.
fn check_cap(sizes: &[usize]) -> CoreResult<()> {
    match sizes.iter().position(|&n| n > MAX_REPORTS_PER_SENSOR) {
        Some(s) => Err(CoreError::CapExceeded {
            what: "sizes",
            count: sizes[s],
            cap: MAX_REPORTS_PER_SENSOR,
            hint: "one sensor's reports in one scan; check the sizes argument",
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_input_with_the_right_variant() {
        let e = SdProblem::new(vec![1], 1, vec![-1.0], vec![1]).unwrap_err();
        assert!(
            matches!(
                e,
                CoreError::OutOfRange {
                    arg: "n_sensors",
                    ..
                }
            ),
            "{e}"
        );
        let e = SdProblem::new(vec![1, 1], 2, vec![-1.0], vec![1]).unwrap_err();
        assert!(matches!(e, CoreError::Shape { arg: "sizes", .. }), "{e}");
        let e = SdProblem::new(vec![1, 1, 1], 2, vec![-1.0], vec![1, 1]).unwrap_err();
        assert!(matches!(e, CoreError::Shape { arg: "tuples", .. }), "{e}");
        let e = SdProblem::new(vec![1, 1, 0, 3], 2, vec![-1.0, -2.0], vec![1, 2]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "tuples: row 1 column 1 is 3 but sensor 1 has 2 reports"
        );
        let e = SdProblem::new(vec![1, 1], 2, vec![f64::NAN], vec![1, 1]).unwrap_err();
        assert_eq!(
            e,
            CoreError::NonFinite {
                arg: "costs",
                index: 0
            }
        );
    }

    #[test]
    fn ignores_dummy_and_non_negative_tuples() {
        let p = SdProblem::new(
            vec![0, 0, 1, 1, 1, 0, 0, 1],
            2,
            vec![-9.0, 0.0, -1.0, 2.0],
            vec![1, 1],
        )
        .unwrap();
        assert_eq!(p.active(), &[2]);
    }

    #[test]
    fn evaluate_reports_conflicts_and_bad_indices() {
        let p = SdProblem::new(vec![1, 1, 1, 0], 2, vec![-1.0, -2.0], vec![1, 1]).unwrap();
        assert!(matches!(
            p.evaluate(&[0, 1]),
            Err(CoreError::IllPosed { .. })
        ));
        assert!(matches!(
            p.evaluate(&[5]),
            Err(CoreError::OutOfRange { .. })
        ));
        assert_eq!(p.evaluate(&[1]), Ok(-2.0));
    }
}
