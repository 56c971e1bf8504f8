//! Merging the optima of the search that are the same optimum (METHODS §1, after eq. 19).
//!
//! Two optima are the same when their scaled distance
//! `√Σ_k (x_ik − x_jk)² / ((s_ik² + s_jk²)/2)` (s = the two candidates' standard deviations)
//! is ≤ `merge_tol`. Optima are visited by decreasing R (ties: lower candidate index) and
//! each is kept unless it merges with an already kept one: deterministic, and of merging
//! optima the one with the larger R survives.
//!
//! **An index over the first coordinate, exact.** Compared with every kept optimum, the merge
//! was quadratic, and where tens of thousands of optima are kept it took a quarter of the
//! initiation (docs/performance.md, *Initiation at scale*). Two optima can merge only if their first coordinates differ by at most
//! `merge_tol·√((s_i0² + s_j0²)/2) ≤ merge_tol·max(s_i0, s_j0)`: either the kept one's
//! interval `x_j0 ± merge_tol·s_j0` holds `x_i0`, or the new one's interval holds `x_j0`. So
//! each kept optimum is filed twice in cells of the first coordinate, under its point and
//! under every cell its interval covers, and a new one is compared only with the kept optima
//! filed under its point's cell (intervals) and under its interval's cells (points). The
//! comparison itself is unchanged, so the kept set is the same, in the same order, as the
//! plain double loop's; optima whose intervals cover too many cells, or are not finite, are
//! compared always.

use std::collections::HashMap;

use super::descent::Optimum;

/// Cells an interval may cover before its optimum is compared with every new one instead.
const MAX_CELLS: i64 = 64;

/// Indices of the optima that survive merging, by decreasing R (ties: lower index). Optima
/// with a non-finite R are dropped.
pub fn merge(optima: &[Optimum], dim: usize, merge_tol: f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..optima.len())
        .filter(|&i| optima[i].closeness.is_finite())
        .collect();
    order.sort_by(|&i, &j| {
        optima[j]
            .closeness
            .total_cmp(&optima[i].closeness)
            .then(i.cmp(&j))
    });
    let tol2 = merge_tol * merge_tol;
    let mut index = Index::new(optima, &order, merge_tol);
    let mut kept: Vec<usize> = Vec::new();
    for i in order {
        let same = index
            .near(&optima[i])
            .any(|k| scaled_distance2(&optima[i], &optima[k], dim) <= tol2);
        if !same {
            index.file(i, &optima[i]);
            kept.push(i);
        }
    }
    kept
}

pub(super) fn scaled_distance2(a: &Optimum, b: &Optimum, dim: usize) -> f64 {
    (0..dim)
        .map(|k| {
            let diff = a.x[k] - b.x[k];
            diff * diff / (0.5 * (a.scale[k] * a.scale[k] + b.scale[k] * b.scale[k]))
        })
        .sum()
}

/// The kept optima filed by cells of the first coordinate (module doc).
struct Index {
    /// Cell width; `None` when no optimum has a usable interval (then all go to `always`).
    width: Option<f64>,
    tol: f64,
    points: HashMap<i64, Vec<usize>>,
    intervals: HashMap<i64, Vec<usize>>,
    always: Vec<usize>,
}

impl Index {
    /// Cells as wide as the median interval half-width of the optima to merge: most
    /// intervals then cover a few cells.
    fn new(optima: &[Optimum], order: &[usize], tol: f64) -> Self {
        let mut halves: Vec<f64> = order
            .iter()
            .map(|&i| tol * optima[i].scale[0])
            .filter(|h| h.is_finite() && *h > 0.0)
            .collect();
        halves.sort_by(f64::total_cmp);
        Self {
            width: halves.get(halves.len() / 2).copied(),
            tol,
            points: HashMap::new(),
            intervals: HashMap::new(),
            always: Vec::new(),
        }
    }

    /// The cells of `[lo, hi]`, or `None` when they are not finite or too many.
    fn cells(&self, lo: f64, hi: f64) -> Option<(i64, i64)> {
        let width = self.width?;
        let (a, b) = ((lo / width).floor(), (hi / width).floor());
        let finite = a.is_finite() && b.is_finite() && a.abs() < 1e15 && b.abs() < 1e15;
        // In range: the casts are exact (|a|, |b| < 2⁵³).
        (finite && b - a < MAX_CELLS as f64).then_some((a as i64, b as i64))
    }

    fn interval(&self, o: &Optimum) -> Option<(i64, i64)> {
        // The margin covers the rounding of the bounds and of the distance itself.
        let half = self.tol * o.scale[0] * (1.0 + 1e-9);
        self.cells(o.x[0] - half, o.x[0] + half)
    }

    fn file(&mut self, i: usize, o: &Optimum) {
        match (self.cells(o.x[0], o.x[0]), self.interval(o)) {
            (Some((cell, _)), Some((lo, hi))) => {
                self.points.entry(cell).or_default().push(i);
                for c in lo..=hi {
                    self.intervals.entry(c).or_default().push(i);
                }
            }
            _ => self.always.push(i),
        }
    }

    /// Every kept optimum that may merge with `o` (some more than once).
    fn near<'s>(&'s self, o: &Optimum) -> Box<dyn Iterator<Item = usize> + 's> {
        let (Some((cell, _)), Some((lo, hi))) = (self.cells(o.x[0], o.x[0]), self.interval(o))
        else {
            // Compared with all: every kept optimum is filed under its point or in `always`.
            let filed = self.points.values().flatten().copied();
            return Box::new(filed.chain(self.always.iter().copied()));
        };
        let theirs = self.intervals.get(&cell).into_iter().flatten();
        let mine = (lo..=hi).flat_map(|c| self.points.get(&c).into_iter().flatten());
        Box::new(theirs.chain(mine).chain(&self.always).copied())
    }
}

#[cfg(test)]
mod tests {
    use super::{merge, scaled_distance2, Optimum};
    use crate::fti::sim::Rng;
    use crate::geometry::model::MAX_DIM;

    /// The plain double loop the index replaces.
    fn merge_plain(optima: &[Optimum], dim: usize, tol: f64) -> Vec<usize> {
        let mut order: Vec<usize> = (0..optima.len())
            .filter(|&i| optima[i].closeness.is_finite())
            .collect();
        order.sort_by(|&i, &j| {
            (optima[j].closeness)
                .total_cmp(&optima[i].closeness)
                .then(i.cmp(&j))
        });
        let mut kept: Vec<usize> = Vec::new();
        for i in order {
            if !kept
                .iter()
                .any(|&k| scaled_distance2(&optima[i], &optima[k], dim) <= tol * tol)
            {
                kept.push(i);
            }
        }
        kept
    }

    /// An optimum near one of 20 centres spread over `[0, spread]` in each coordinate.
    fn optimum(rng: &mut Rng, spread: f64, scale: f64) -> Optimum {
        let centre = (20.0 * rng.uniform()).floor();
        Optimum {
            x: std::array::from_fn(|k| {
                let at = (centre * 7.3 + k as f64 * 3.1) % 20.0 / 20.0;
                spread * at + scale * rng.normal()
            }),
            closeness: (10.0 * rng.uniform()).round(), // ties in R
            iterations: 0,
            evaluations: 0,
            scale: std::array::from_fn(|_| scale * (0.05 + 3.0 * rng.uniform())),
        }
    }

    /// Clusters, scales from 0.05 to 3 times a base (so intervals from a fraction of a cell
    /// to past `MAX_CELLS`), tied R, and non-finite coordinates, R and scales: the index
    /// keeps exactly what the double loop keeps, in its order, and merges a fair share.
    #[test]
    fn the_index_keeps_what_the_double_loop_keeps() {
        let mut rng = Rng::new(11);
        for (n, spread, scale) in [(400, 100.0, 1.0), (400, 1000.0, 1.0), (300, 10.0, 30.0)] {
            let mut optima: Vec<Optimum> =
                (0..n).map(|_| optimum(&mut rng, spread, scale)).collect();
            optima[3].x[0] = f64::NAN;
            optima[5].scale[0] = f64::INFINITY;
            optima[7].closeness = f64::NAN;
            optima[9].x[0] = 1e300;
            optima[11].scale[0] = 1e-300;
            for dim in [4, MAX_DIM] {
                let plain = merge_plain(&optima, dim, 1.0);
                assert_eq!(merge(&optima, dim, 1.0), plain, "n {n} spread {spread}");
                assert!(plain.len() < n - 20 && plain.len() > 10, "{}", plain.len());
            }
        }
    }
}
