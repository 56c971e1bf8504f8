//! Baseline B of METHODS.md §2: exact S-D assignment by depth-first branch and bound.
//!
//! The root is solved by [`lagrangian`], which gives a good incumbent and
//! often proves optimality outright. Otherwise the search branches on reports: at each node it
//! takes the first undecided report (static order, fewest candidate tuples first, which keeps
//! the tree narrow) that still has a compatible tuple, and tries each such tuple (cheapest
//! first, so good incumbents come early) and finally "this report stays a false alarm".
//!
//! Bound: split each tuple's cost evenly over its `m` real reports. Any feasible completion
//! uses every report at most once, so its cost is at least the sum, over undecided reports, of
//! `min(0, cheapest share of a still-compatible tuple)`. It is cheap (no LP) and tight enough
//! for the sizes this baseline is meant for (S = 3–4, ≤ 8 reports per sensor).

use super::lagrangian::{self, LagrangianOptions};
use super::{relative_gap, Limit, SdProblem, SdSolution, Termination};
use crate::error::{CoreError, CoreResult};
use std::time::{Duration, Instant};

/// Options of [`solve`], built with validated `with_*` setters.
///
/// ```
/// use passive_assoc_core::assign::branch_bound::BranchBoundOptions;
/// use std::time::Duration;
/// let o = BranchBoundOptions::default().with_max_nodes(1000).unwrap()
///     .with_time_limit(Duration::from_millis(50)).unwrap();
/// assert_eq!(o.max_nodes(), 1000);
/// assert!(BranchBoundOptions::default().with_max_nodes(0).is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BranchBoundOptions {
    max_nodes: usize,
    time_limit: Option<Duration>,
    root: LagrangianOptions,
}

impl Default for BranchBoundOptions {
    /// [`BranchBoundOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl BranchBoundOptions {
    /// The project's defaults, those of the Python package (`assign_sd(method="exact")`):
    /// 10 million nodes, 10 s, and the recommended Lagrangian options at the root.
    pub fn recommended() -> Self {
        Self {
            max_nodes: 10_000_000,
            time_limit: Some(Duration::from_secs(10)),
            root: LagrangianOptions::recommended(),
        }
    }

    /// Baseline B of METHODS §2: differs from [`recommended`](Self::recommended) only in the
    /// root Lagrangian, [`LagrangianOptions::paper`] (the root only bounds and seeds the
    /// search: the answer is the optimum either way). The node and time caps are not the
    /// method's: they are the recommended ones.
    pub fn paper() -> Self {
        Self {
            root: LagrangianOptions::paper(),
            ..Self::recommended()
        }
    }

    /// Node cap (at least 1); reaching it returns `NotProven(Limit::Nodes)`.
    pub fn with_max_nodes(mut self, max_nodes: usize) -> CoreResult<Self> {
        if max_nodes == 0 {
            return Err(CoreError::out_of_range(
                "max_nodes",
                "must be at least 1, got 0",
            ));
        }
        self.max_nodes = max_nodes;
        Ok(self)
    }

    /// Wall-clock cap (non-zero); reaching it returns `NotProven(Limit::Time)`. The result is
    /// then no longer deterministic.
    pub fn with_time_limit(mut self, time_limit: Duration) -> CoreResult<Self> {
        if time_limit.is_zero() {
            return Err(CoreError::out_of_range(
                "time_limit",
                "must be positive, got 0",
            ));
        }
        self.time_limit = Some(time_limit);
        Ok(self)
    }

    /// No wall-clock cap (only the node cap stops the search).
    pub fn without_time_limit(mut self) -> Self {
        self.time_limit = None;
        self
    }

    /// Options of the Lagrangian run at the root.
    pub fn with_root(mut self, root: LagrangianOptions) -> Self {
        self.root = root;
        self
    }

    pub fn max_nodes(&self) -> usize {
        self.max_nodes
    }

    pub fn time_limit(&self) -> Option<Duration> {
        self.time_limit
    }

    pub fn root(&self) -> &LagrangianOptions {
        &self.root
    }
}

/// Solves the S-D problem exactly, or returns the best incumbent with
/// `Termination::NotProven` when a limit is hit. `iterations` counts search nodes (0 when the
/// root Lagrangian already proved optimality).
///
/// ```
/// use passive_assoc_core::assign::{branch_bound, SdProblem};
/// let p = SdProblem::new(vec![1, 1, 1, 1, 1, 0, 0, 0, 1], 3, vec![-5.0, -3.0, -1.0], vec![1, 1, 1]).unwrap();
/// let s = branch_bound::solve(&p, &Default::default());
/// assert_eq!((s.chosen, s.primal_cost), (vec![0], -5.0));
/// assert!(s.termination.is_optimal());
/// ```
pub fn solve(problem: &SdProblem, options: &BranchBoundOptions) -> SdSolution {
    let root = lagrangian::solve(problem, &options.root);
    if root.termination.is_optimal() {
        return SdSolution {
            iterations: 0,
            ..root
        };
    }
    let mut search = Search::new(problem, root.chosen, root.primal_cost, options);
    let root_bound = root.dual_bound.max(search.bound(0, 0.0).0);
    let outcome = search.run();
    let mut chosen = search.best_chosen;
    chosen.sort_unstable();
    let primal_cost = chosen.iter().map(|&k| problem.costs()[k]).sum();
    let (dual_bound, termination) = match outcome {
        None => (primal_cost, Termination::Optimal),
        Some(limit) => (root_bound.min(primal_cost), Termination::NotProven(limit)),
    };
    let gap = relative_gap(primal_cost, dual_bound);
    SdSolution {
        chosen,
        primal_cost,
        dual_bound,
        gap,
        iterations: search.nodes,
        termination,
    }
}

/// What a search frame applied to reach its current child, to be undone on backtrack.
#[derive(Clone, Copy)]
enum Applied {
    Nothing,
    Tuple(usize),
    Uncovered,
}

/// A node on the explicit DFS stack (no recursion: depth can reach the number of reports).
struct Frame {
    /// Position in `order` of the report branched on.
    pos: usize,
    /// Next index into that report's `by_cost` list.
    next: usize,
    cost: f64,
    applied: Applied,
    uncovered_tried: bool,
}

struct Search<'a> {
    problem: &'a SdProblem,
    /// Reports of each active tuple (CSR over tuple position), as global report ids.
    t_offs: Vec<usize>,
    t_reports: Vec<usize>,
    share: Vec<f64>,
    /// Per global report: tuple positions by ascending cost, and by ascending share.
    by_cost: Vec<Vec<usize>>,
    by_share: Vec<Vec<usize>>,
    /// Global reports that appear in some tuple, fewest tuples first.
    order: Vec<usize>,
    blocked: Vec<bool>,
    chosen: Vec<usize>,
    best_chosen: Vec<usize>,
    best: f64,
    nodes: usize,
    max_nodes: usize,
    deadline: Option<Instant>,
}

impl<'a> Search<'a> {
    fn new(
        problem: &'a SdProblem,
        incumbent: Vec<usize>,
        best: f64,
        options: &BranchBoundOptions,
    ) -> Self {
        let mut base = vec![0];
        for &n in problem.sizes() {
            base.push(base[base.len() - 1] + n);
        }
        let n_reports = base[problem.n_sensors()];
        let (mut t_offs, mut t_reports, mut share) = (vec![0], Vec::new(), Vec::new());
        let (mut by_cost, mut by_share) =
            (vec![Vec::new(); n_reports], vec![Vec::new(); n_reports]);
        for (pos, &k) in problem.active().iter().enumerate() {
            for (s, &i) in problem.tuple(k).iter().enumerate().filter(|e| *e.1 > 0) {
                t_reports.push(base[s] + i - 1);
                by_cost[base[s] + i - 1].push(pos);
            }
            t_offs.push(t_reports.len());
            share.push(problem.costs()[k] / (t_offs[pos + 1] - t_offs[pos]) as f64);
        }
        let cost = |p: &usize| problem.costs()[problem.active()[*p]];
        for r in 0..n_reports {
            by_cost[r].sort_by(|a, b| cost(a).total_cmp(&cost(b)).then(a.cmp(b)));
            by_share[r] = by_cost[r].clone();
            by_share[r].sort_by(|a, b| share[*a].total_cmp(&share[*b]).then(a.cmp(b)));
        }
        let mut order: Vec<usize> = (0..n_reports).filter(|&r| !by_cost[r].is_empty()).collect();
        order.sort_by_key(|&r| (by_cost[r].len(), r));
        Self {
            problem,
            t_offs,
            t_reports,
            share,
            by_cost,
            by_share,
            order,
            blocked: vec![false; n_reports],
            chosen: Vec::new(),
            best_chosen: incumbent,
            best,
            nodes: 0,
            max_nodes: options.max_nodes,
            deadline: crate::assign::deadline(options.time_limit),
        }
    }

    fn reports(&self, pos: usize) -> &[usize] {
        &self.t_reports[self.t_offs[pos]..self.t_offs[pos + 1]]
    }

    fn compatible(&self, pos: usize) -> bool {
        self.reports(pos).iter().all(|&r| !self.blocked[r])
    }

    fn set_blocked(&mut self, pos: usize, value: bool) {
        for at in self.t_offs[pos]..self.t_offs[pos + 1] {
            self.blocked[self.t_reports[at]] = value;
        }
    }

    /// Lower bound of the node at `cost` whose undecided reports are in `order[from..]`, and the
    /// position of the first report that still has a compatible tuple (the one to branch on).
    fn bound(&self, from: usize, cost: f64) -> (f64, Option<usize>) {
        let (mut bound, mut branch) = (cost, None);
        for (p, &r) in self.order.iter().enumerate().skip(from) {
            if self.blocked[r] {
                continue;
            }
            if let Some(&t) = self.by_share[r].iter().find(|&&t| self.compatible(t)) {
                bound += self.share[t].min(0.0);
                branch = branch.or(Some(p));
            }
        }
        (bound, branch)
    }

    /// Counts a node, records the incumbent, and pushes a frame unless pruned or a leaf.
    fn enter(&mut self, stack: &mut Vec<Frame>, from: usize, cost: f64) -> Option<Limit> {
        if self.nodes == self.max_nodes {
            return Some(Limit::Nodes);
        }
        self.nodes += 1;
        if self.nodes & 255 == 0
            && (self.deadline.is_some_and(|d| Instant::now() >= d)
                || crate::parallel::interrupted())
        {
            return Some(Limit::Time); // an interrupt ends it like the clock; the binding raises
        }
        // Every node's partial selection is feasible, so it can be the incumbent.
        if cost < self.best {
            self.best = cost;
            self.best_chosen = self
                .chosen
                .iter()
                .map(|&p| self.problem.active()[p])
                .collect();
        }
        let (bound, branch) = self.bound(from, cost);
        // Prune ties too: a completion equal to the incumbent is not worth finding.
        let tol = 1e-12 * self.best.abs().max(1.0);
        if let Some(pos) = branch.filter(|_| bound < self.best - tol) {
            stack.push(Frame {
                pos,
                next: 0,
                cost,
                applied: Applied::Nothing,
                uncovered_tried: false,
            });
        }
        None
    }

    /// Runs the DFS to exhaustion (`None`) or to a limit.
    fn run(&mut self) -> Option<Limit> {
        let mut stack = Vec::new();
        if let Some(limit) = self.enter(&mut stack, 0, 0.0) {
            return Some(limit);
        }
        while let Some(top) = stack.len().checked_sub(1) {
            let Frame {
                pos,
                next,
                cost,
                applied,
                uncovered_tried,
            } = stack[top];
            let r = self.order[pos];
            match applied {
                Applied::Tuple(t) => {
                    self.set_blocked(t, false);
                    self.chosen.pop();
                }
                Applied::Uncovered => self.blocked[r] = false,
                Applied::Nothing => {}
            }
            let found =
                (next..self.by_cost[r].len()).find(|&n| self.compatible(self.by_cost[r][n]));
            let child_cost = if let Some(n) = found {
                let t = self.by_cost[r][n];
                self.set_blocked(t, true);
                self.chosen.push(t);
                (stack[top].next, stack[top].applied) = (n + 1, Applied::Tuple(t));
                cost + self.problem.costs()[self.problem.active()[t]]
            } else if !uncovered_tried {
                self.blocked[r] = true;
                (stack[top].applied, stack[top].uncovered_tried) = (Applied::Uncovered, true);
                cost
            } else {
                stack.pop();
                continue;
            };
            if let Some(limit) = self.enter(&mut stack, pos + 1, child_cost) {
                return Some(limit);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests;
