//! Merging the optima of the search that are the same optimum (METHODS §1, after eq. 19).
//!
//! Two optima are the same when their scaled distance
//! `√Σ_k (x_ik − x_jk)² / ((s_ik² + s_jk²)/2)` (s = the two candidates' standard deviations)
//! is ≤ `merge_tol`. Optima are visited by decreasing R (ties: lower candidate index) and
//! each is kept unless it merges with an already kept one: deterministic, and of merging
//! optima the one with the larger R survives.
//!
//! **An index over the first coordinate, exact.** Comparing each optimum with every kept one
//! is quadratic, and where tens of thousands of optima are kept that would be a large share
//! of the initiation (CHANGELOG.md, *Many candidates*). Two optima can merge only if
//! their first coordinates differ by at most
//! `merge_tol·√((s_i0² + s_j0²)/2) ≤ merge_tol·max(s_i0, s_j0)`. So the optima are sorted by
//! their first coordinate once, in classes of similar `s_0` (one per power of two, each with
//! its largest `s_0`), and a new optimum is compared only with the kept ones that lie within
//! `merge_tol·max(s_i0, largest s_0 of the class)` of it in some class: two binary searches
//! per class. The comparison itself is unchanged, so the kept set is the same, in the same
//! order, as the plain double loop's. The bound holds for the computed distance, not only
//! the exact one, as long as no square overflows or underflows: so optima whose first
//! coordinate or `s_0` lies outside `[2⁻⁴⁰⁰, 2⁴⁰⁰]` in magnitude (or is not finite) are
//! compared always and with all, and a `merge_tol` outside `[2⁻¹⁰⁰, 2¹⁰⁰]` turns the index
//! off (the double loop itself).

use std::collections::BTreeMap;

use super::descent::Optimum;

/// 2⁴⁰⁰ and 2⁻⁴⁰⁰: the magnitudes of a first coordinate or `s_0` within which the index's
/// bound holds for the computed distance (module doc).
const LARGE: f64 = 2.582_249_878_086_908_6e120;
const SMALL: f64 = 3.872_591_914_849_318_3e-121;
/// 2¹⁰⁰ and 2⁻¹⁰⁰: the `merge_tol` within which the index is used.
const TOL_LARGE: f64 = 1.267_650_600_228_229_4e30;
const TOL_SMALL: f64 = 7.888_609_052_210_118e-31;

/// Whether an optimum with first coordinate `x` and `s_0` = `s` can be classed.
fn classable(x: f64, s: f64) -> bool {
    x.abs() <= LARGE && (SMALL..=LARGE).contains(&s)
}

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
            .near(optima, i)
            .any(|k| scaled_distance2(&optima[i], &optima[k], dim) <= tol2);
        if !same {
            index.keep(i);
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

/// The optima to merge sorted by first coordinate in classes of `s_0` (module doc), and
/// which of them are kept so far.
struct Index {
    tol: f64,
    /// Per class: its largest `s_0`, and its optima's `(x_0, index)` sorted.
    classes: Vec<(f64, Vec<(f64, usize)>)>,
    /// Optima outside every class (module doc).
    unclassed: Vec<usize>,
    kept: Vec<bool>,
    kept_list: Vec<usize>,
}

impl Index {
    fn new(optima: &[Optimum], order: &[usize], tol: f64) -> Self {
        let mut classes: BTreeMap<i32, (f64, Vec<(f64, usize)>)> = BTreeMap::new();
        let mut unclassed = Vec::new();
        let usable = (TOL_SMALL..=TOL_LARGE).contains(&tol);
        for &i in order {
            let (x, s) = (optima[i].x[0], optima[i].scale[0]);
            if !(usable && classable(x, s)) {
                unclassed.push(i);
                continue;
            }
            // The class is only a grouping: its bound is the largest s_0 it really holds.
            let class = classes.entry(s.log2().floor() as i32).or_default();
            class.0 = class.0.max(s);
            class.1.push((x, i));
        }
        let mut classes: Vec<_> = classes.into_values().collect();
        for (_, members) in &mut classes {
            members.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        }
        Self {
            tol,
            classes,
            unclassed,
            kept: vec![false; optima.len()],
            kept_list: Vec::new(),
        }
    }

    fn keep(&mut self, i: usize) {
        self.kept[i] = true;
        self.kept_list.push(i);
    }

    /// Every kept optimum that may merge with optimum `i`.
    fn near<'s>(&'s self, optima: &[Optimum], i: usize) -> Box<dyn Iterator<Item = usize> + 's> {
        let (x, s) = (optima[i].x[0], optima[i].scale[0]);
        if self.classes.is_empty() || !classable(x, s) {
            return Box::new(self.kept_list.iter().copied());
        }
        let tol = self.tol;
        let in_classes = self.classes.iter().flat_map(move |(largest, members)| {
            // The margins cover the rounding of the bounds and of the distance itself.
            let reach = tol * s.max(*largest) * (1.0 + 1e-9) + 4.0 * f64::EPSILON * x.abs() + SMALL;
            let start = members.partition_point(|m| m.0 < x - reach);
            let end = members.partition_point(|m| m.0 <= x + reach);
            members[start..end.max(start)].iter().map(|m| m.1)
        });
        let unclassed = self.unclassed.iter().copied();
        Box::new(in_classes.chain(unclassed).filter(|&k| self.kept[k]))
    }
}

#[cfg(test)]
mod tests {
    use super::{merge, scaled_distance2, Optimum};
    use crate::fti::tests::sim::Rng;
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

    /// Clusters, scales from 0.05 to 3 times a base (several classes), tied R, and
    /// non-finite coordinates, R and scales: the index keeps exactly what the double loop
    /// keeps, in its order, and merges a fair share.
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

    /// Two optima equal but in the first coordinate, at distances around the bound, and at
    /// the extremes of the float range (squares that overflow or underflow, a huge or tiny
    /// `merge_tol`): the index merges exactly the pairs the double loop merges.
    #[test]
    fn the_index_agrees_at_the_bound_and_at_the_extremes() {
        let pair = |s: f64, dx: f64| -> Vec<Optimum> {
            let at = |x0: f64, closeness: f64| Optimum {
                x: std::array::from_fn(|k| if k == 0 { x0 } else { 1.0 }),
                closeness,
                iterations: 0,
                evaluations: 0,
                scale: [s; MAX_DIM],
            };
            vec![at(5.0, 2.0), at(5.0 + dx, 1.0)]
        };
        let mut cases = Vec::new();
        for factor in [0.8, 0.99, 1.0 - 1e-15, 1.0, 1.0 + 1e-15, 1.01] {
            cases.push((pair(2.0, 2.0 * factor), 1.0));
            cases.push((pair(3e-3, 3e-3 * factor), 1.0));
        }
        cases.push((pair(1e154, 1.3e154), 1.0)); // s² overflows: the term is 0
        cases.push((pair(1.6e-162, 2.1e-162), 1.0)); // subnormal squares
        cases.push((pair(1.0, 1e150), 1e200)); // tol² overflows: everything merges
        cases.push((pair(1e-200, 1e-170), 0.0)); // Δ² underflows to 0
        let mut merged = 0;
        for (optima, tol) in &cases {
            let plain = merge_plain(optima, MAX_DIM, *tol);
            assert_eq!(merge(optima, MAX_DIM, *tol), plain, "{optima:?} tol {tol}");
            merged += usize::from(plain.len() == 1);
        }
        assert!(merged >= 8 && merged < cases.len(), "{merged}");
    }
}
