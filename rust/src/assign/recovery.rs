//! Primal recovery for the Lagrangian solver: turn a relaxed (infeasible) solution into a
//! feasible one by successive 2-D assignments, then polish it with a swap local search.

use super::lagrangian::{keep_min, modified, EMPTY};
use super::lap::{sparse_core, SparseCosts};
use super::SdProblem;
use std::collections::HashMap;

/// Active tuples by ascending cost (ties by index): the local search's scan order.
pub(super) fn by_cost(problem: &SdProblem) -> Vec<usize> {
    let mut order = problem.active().to_vec();
    order.sort_by(|&a, &b| {
        problem.costs()[a]
            .total_cmp(&problem.costs()[b])
            .then(a.cmp(&b))
    });
    order
}

/// The best feasible solution derivable from the relaxed one, and its cost: the relaxed
/// solution itself if feasible, and the successive-assignment recovery, both polished.
pub(super) fn primal(
    problem: &SdProblem,
    by_cost: &[usize],
    mult: &[Vec<f64>],
    relaxed: &[usize],
) -> (Vec<usize>, f64) {
    let mut best = (Vec::new(), 0.0);
    let feasible = problem.evaluate(relaxed).is_ok().then(|| relaxed.to_vec());
    for chosen in [feasible, recover(problem, mult, relaxed)]
        .into_iter()
        .flatten()
    {
        let chosen = improve(problem, by_cost, chosen);
        let cost = chosen.iter().map(|&k| problem.costs()[k]).sum();
        if cost < best.1 {
            best = (chosen, cost);
        }
    }
    best
}

/// Swap local search: bring in any tuple that is cheaper than the chosen tuples it conflicts
/// with (none: a plain addition), until no such tuple is left. Each move strictly lowers the
/// cost, so it terminates; it catches what the stage-by-stage recovery cannot see.
fn improve(problem: &SdProblem, by_cost: &[usize], chosen: Vec<usize>) -> Vec<usize> {
    let mut owner: Vec<Vec<usize>> = problem.sizes().iter().map(|&n| vec![NONE; n + 1]).collect();
    let mut is_chosen = vec![false; problem.n_tuples()];
    let set = |owner: &mut Vec<Vec<usize>>, k: usize, value: usize| {
        for (s, &i) in problem.tuple(k).iter().enumerate().filter(|e| *e.1 > 0) {
            owner[s][i] = value;
        }
    };
    for &k in &chosen {
        set(&mut owner, k, k);
        is_chosen[k] = true;
    }
    let tol = 1e-12
        * chosen
            .iter()
            .map(|&k| problem.costs()[k])
            .sum::<f64>()
            .abs()
            .max(1.0);
    let mut conflicts = Vec::with_capacity(problem.n_sensors());
    let mut improved = true;
    while improved {
        improved = false;
        for &k in by_cost {
            if is_chosen[k] {
                continue;
            }
            conflicts.clear();
            for (s, &i) in problem.tuple(k).iter().enumerate().filter(|e| *e.1 > 0) {
                if owner[s][i] != NONE && !conflicts.contains(&owner[s][i]) {
                    conflicts.push(owner[s][i]);
                }
            }
            let freed: f64 = conflicts.iter().map(|&j| problem.costs()[j]).sum();
            if problem.costs()[k] < freed - tol {
                for &j in &conflicts {
                    set(&mut owner, j, NONE);
                    is_chosen[j] = false;
                }
                set(&mut owner, k, k);
                is_chosen[k] = true;
                improved = true;
            }
        }
    }
    (0..problem.n_tuples()).filter(|&k| is_chosen[k]).collect()
}

const NONE: usize = usize::MAX;

/// Marks a prefix that is all zeros so far (sensors 0..s all missed).
const ZERO: usize = usize::MAX;
/// Marks a tuple whose prefix was not kept: it can no longer be chosen.
const DEAD: usize = usize::MAX - 1;

/// Feasible recovery by successive 2-D assignments: keep the sensor-0/1 pairs of the relaxed
/// solution as prefixes, then for each later sensor s assign prefixes to its reports, costing
/// each by its best tuple with the multipliers of sensors after s still applied (so those
/// sensors are anticipated, not ignored). Every stage is feasible, so the result is.
fn recover(problem: &SdProblem, mult: &[Vec<f64>], relaxed: &[usize]) -> Option<Vec<usize>> {
    let mut ids = HashMap::new();
    for &k in relaxed {
        let t = problem.tuple(k);
        if (t[0], t[1]) != (0, 0) {
            let next = ids.len();
            ids.entry((t[0], t[1])).or_insert(next);
        }
    }
    let active = problem.active();
    let mut prefix: Vec<usize> = active
        .iter()
        .map(|&k| match problem.tuple(k) {
            [0, 0, ..] => ZERO,
            t => ids.get(&(t[0], t[1])).copied().unwrap_or(DEAD),
        })
        .collect();
    let mut n_rows = ids.len();
    for s in 2..problem.n_sensors() {
        let (next, best) = stage(problem, mult, s, &prefix, n_rows);
        if s + 1 == problem.n_sensors() {
            return Some(best);
        }
        for (pos, &k) in active.iter().enumerate() {
            let i = problem.tuple(k)[s];
            prefix[pos] = match prefix[pos] {
                DEAD => DEAD,
                ZERO if i == 0 => ZERO,
                old => next.get(&(old, i)).copied().unwrap_or(DEAD),
            };
        }
        n_rows = next.len();
    }
    None // S = 2: the relaxed solution is already the answer
}

/// Candidate costs of one stage: per (prefix, report) edge, per prefix "continue with 0",
/// per report "start a new all-zero prefix"; each keeps its cheapest tuple.
struct StageCosts {
    /// `(prefix row, report − 1, cost, tuple)`, sorted and unique by (row, report).
    edges: Vec<(usize, usize, f64, usize)>,
    rows: Vec<(f64, usize)>,
    cols: Vec<(f64, usize)>,
}

impl StageCosts {
    fn new(
        problem: &SdProblem,
        mult: &[Vec<f64>],
        s: usize,
        prefix: &[usize],
        n_rows: usize,
    ) -> Self {
        let n = problem.sizes()[s];
        let (mut rows, mut cols, mut edges) = (vec![EMPTY; n_rows], vec![EMPTY; n], Vec::new());
        for (pos, &k) in problem.active().iter().enumerate() {
            let (i, c) = (problem.tuple(k)[s], modified(problem, mult, k, s + 1));
            match prefix[pos] {
                DEAD => {}
                ZERO if i > 0 => keep_min(&mut cols[i - 1], (c, k)),
                ZERO => {}
                r if i == 0 => keep_min(&mut rows[r], (c, k)),
                r => edges.push((r, i - 1, c, k)),
            }
        }
        edges.sort_by(|x, y| {
            (x.0, x.1)
                .cmp(&(y.0, y.1))
                .then(x.2.total_cmp(&y.2))
                .then(x.3.cmp(&y.3))
        });
        edges.dedup_by(|later, first| (later.0, later.1) == (first.0, first.1));
        Self { edges, rows, cols }
    }

    fn matrix(&self) -> SparseCosts {
        let mut offs = vec![0; self.rows.len() + 1];
        for e in &self.edges {
            offs[e.0 + 1] += 1;
        }
        for r in 0..self.rows.len() {
            offs[r + 1] += offs[r];
        }
        let cols = self.edges.iter().map(|e| e.1).collect();
        let values = self.edges.iter().map(|e| e.2).collect();
        SparseCosts::from_csr_unchecked(self.rows.len(), self.cols.len(), offs, cols, values)
    }
}

/// One recovery stage: assigns the current prefixes to the reports of sensor `s`. Returns the
/// new prefixes keyed by `(old prefix, report or 0)` and the best tuple of each new prefix.
fn stage(
    problem: &SdProblem,
    mult: &[Vec<f64>],
    s: usize,
    prefix: &[usize],
    n_rows: usize,
) -> (HashMap<(usize, usize), usize>, Vec<usize>) {
    let st = StageCosts::new(problem, mult, s, prefix, n_rows);
    // Options costing >= 0 are never taken: dropping the prefix (or report) costs 0.
    let a: Vec<f64> = st.rows.iter().map(|r| r.0.min(0.0)).collect();
    let b: Vec<f64> = st.cols.iter().map(|c| c.0.min(0.0)).collect();
    let sol = sparse_core(&st.matrix(), &a, &b);
    let (mut next, mut best) = (HashMap::new(), Vec::new());
    let mut add = |key, k| {
        next.insert(key, best.len());
        best.push(k);
    };
    for (r, c) in sol.row_to_col.iter().enumerate() {
        match c {
            Some(c) => {
                // The solver only assigns stored pairs, so the search always succeeds.
                if let Ok(p) = st.edges.binary_search_by(|e| (e.0, e.1).cmp(&(r, *c))) {
                    add((r, c + 1), st.edges[p].3);
                }
            }
            None if a[r] < 0.0 => add((r, 0), st.rows[r].1),
            None => {}
        }
    }
    for c in (0..b.len()).filter(|&c| sol.col_to_row[c].is_none() && b[c] < 0.0) {
        add((ZERO, c + 1), st.cols[c].1);
    }
    (next, best)
}
