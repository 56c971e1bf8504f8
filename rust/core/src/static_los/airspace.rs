//! Step 1 of the intensity search, the valid airspace (eq. 12–13), with exact nearest- and
//! farthest-point queries that avoid the all-pairs loop over candidates × intensity-S points.
//!
//! "Is another intensity-S point within d?" is asked of every candidate. A sweep along x
//! answers it fast when the answer is yes, but a ghost with no point within d scans every
//! point of the x-window, and d (about the scene's size) makes that window nearly all of them
//! — quadratic in large scans (at M = 500 it would be most of the search). So the sweep looks at a
//! bounded number of points, and a candidate it does not settle goes to an R*-tree (the
//! `rstar` crate, a well-kept spatial index), built on first use: in small scans the sweep
//! settles everything and the tree, whose building costs more than their sweeps, is never
//! built.

use std::cell::OnceCell;

use rstar::primitives::GeomWithData;
use rstar::RTree;

use super::intensity_input::IntensityInput;

/// An intensity-S point in 3-D (planar points get z = 0, which leaves distances unchanged),
/// with its candidate index.
type Located = GeomWithData<[f64; 3], usize>;

/// Points of at most 3 coordinates, padded to 3.
fn padded(point: &[f64]) -> [f64; 3] {
    let mut out = [0.0; 3];
    out[..point.len()].copy_from_slice(point);
    out
}

/// The intensity-S points, sorted by their first coordinate (nearest-neighbour sweeps) and by
/// distance from their centroid (farthest-point search). Exact; no approximation.
pub(super) struct PointIndex<'a> {
    input: &'a IntensityInput,
    /// `(x, candidate)` ascending.
    by_x: Vec<(f64, usize)>,
    centroid: Vec<f64>,
    /// `(distance from the centroid, candidate)` descending.
    by_spread: Vec<(f64, usize)>,
    /// Bounding box of the points.
    lower: Vec<f64>,
    upper: Vec<f64>,
    tree: OnceCell<RTree<Located>>,
}

/// Points the sweep looks at on each side before asking the tree.
const SWEEP_LIMIT: usize = 256;

impl<'a> PointIndex<'a> {
    pub fn new(input: &'a IntensityInput, full: &[usize]) -> Self {
        let mut by_x: Vec<(f64, usize)> = full.iter().map(|&c| (input.point(c)[0], c)).collect();
        by_x.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut centroid = vec![0.0; input.dim()];
        for &c in full {
            for (acc, v) in centroid.iter_mut().zip(input.point(c)) {
                *acc += v / full.len() as f64;
            }
        }
        let spread = |c: usize| {
            input
                .point(c)
                .iter()
                .zip(&centroid)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt()
        };
        let mut by_spread: Vec<(f64, usize)> = full.iter().map(|&c| (spread(c), c)).collect();
        by_spread.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let (mut lower, mut upper) = (
            vec![f64::INFINITY; input.dim()],
            vec![f64::NEG_INFINITY; input.dim()],
        );
        for &c in full {
            for (k, v) in input.point(c).iter().enumerate() {
                lower[k] = lower[k].min(*v);
                upper[k] = upper[k].max(*v);
            }
        }
        Self {
            input,
            by_x,
            centroid,
            by_spread,
            lower,
            upper,
            tree: OnceCell::new(),
        }
    }

    /// Distance from candidate `c` to the nearest intensity-S point other than itself, searching
    /// no farther than `limit` (returns ∞ if none is within it).
    fn nearest(&self, c: usize, limit: f64) -> f64 {
        let x = self.input.point(c)[0];
        let mut best = limit;
        let mut found = f64::INFINITY;
        let start = self.by_x.partition_point(|e| e.0 < x);
        // Walk right, then left, while the x gap alone can still beat the best.
        for e in &self.by_x[start..] {
            if e.0 - x > best {
                break;
            }
            if e.1 != c {
                let d = self.input.distance(c, e.1);
                if d <= best {
                    best = d;
                    found = d;
                }
            }
        }
        for e in self.by_x[..start].iter().rev() {
            if x - e.0 > best {
                break;
            }
            if e.1 != c {
                let d = self.input.distance(c, e.1);
                if d <= best {
                    best = d;
                    found = d;
                }
            }
        }
        found
    }

    /// Distance from candidate `c` to the farthest other intensity-S point. Points are visited
    /// by decreasing distance r_b from the centroid; `|P_b − P_c| ≤ r_b + r_c` ends the search.
    fn farthest(&self, c: usize) -> f64 {
        let r_c = self
            .input
            .point(c)
            .iter()
            .zip(&self.centroid)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        let mut best = 0.0f64;
        for &(r_b, b) in &self.by_spread {
            if r_b + r_c < best {
                break;
            }
            if b != c {
                best = best.max(self.input.distance(c, b));
            }
        }
        best
    }

    /// `d` of eq. 13 (at least two points).
    pub fn radius(&self) -> f64 {
        let total: f64 = self
            .by_x
            .iter()
            .map(|&(_, j)| 0.5 * (self.nearest(j, f64::INFINITY) + self.farthest(j)))
            .sum();
        total / self.by_x.len() as f64
    }

    /// Whether some intensity-S point other than `c` lies within `d` of candidate `c`.
    pub fn has_neighbour_within(&self, c: usize, d: f64) -> bool {
        let p = self.input.point(c);
        // Farther than d from the points' bounding box: no need to look at any point.
        let outside: f64 = p
            .iter()
            .zip(self.lower.iter().zip(&self.upper))
            .map(|(v, (lo, hi))| (lo - v).max(v - hi).max(0.0).powi(2))
            .sum();
        if outside > d * d {
            return false;
        }
        let start = self.by_x.partition_point(|e| e.0 < p[0]);
        let within = |e: &(f64, usize)| e.1 != c && self.input.distance_squared(c, e.1) <= d * d;
        let right = &self.by_x[start..];
        let right = &right[..right.partition_point(|e| e.0 - p[0] <= d)];
        let left = &self.by_x[..start];
        let left = &left[left.partition_point(|e| p[0] - e.0 > d)..];
        let (near_right, near_left) = (
            &right[..right.len().min(SWEEP_LIMIT)],
            &left[left.len().saturating_sub(SWEEP_LIMIT)..],
        );
        if near_right.iter().any(within) || near_left.iter().any(within) {
            return true;
        }
        if near_right.len() == right.len() && near_left.len() == left.len() {
            return false; // the whole window was looked at
        }
        let tree = self.tree.get_or_init(|| {
            let located = self
                .by_x
                .iter()
                .map(|&(_, b)| Located::new(padded(self.input.point(b)), b));
            RTree::bulk_load(located.collect())
        });
        tree.locate_within_distance(padded(p), d * d)
            .any(|e| e.data != c)
    }
}
