//! The order in which detection (eq. 23) visits the merged optima: the paper's, by decreasing
//! closeness R, or the project's (a project extension), by the membership of the rows each
//! optimum would take.
//!
//! **Why not R.** R is a mean over *every* row, so an optimum that sits between several
//! targets collects membership from all of their rows, more than a true target's optimum whose
//! neighbourhood holds only its own. Detection then takes such a ghost first; it takes one row
//! per scan from two or three targets, and they fall below `Nd`. On the scale bench's 2 × 32
//! scene, in R's order 1 of the first 8 tracks accepted holds a target, and 9 of 32 targets
//! are found (docs/methods.md §1, *Detection order*).
//!
//! **Membership order.** An optimum's score is `Σ exp(−d²_m / 4)` over the rows it would take
//! now (its related rows among those not yet removed, the nearest of each scan with
//! `one_per_scan`): the paper's membership at its spread `s = 2σ`, taken over both angles at
//! once (in 2-D exactly the paper's μ). The optimum with the largest current score goes first
//! (ties: the R order). Removing rows only lowers a score (a scan's nearest remaining row is
//! no nearer), so each optimum keeps its last score as an upper bound in a heap and is
//! rescored when it reaches the top: the first whose score is still current is the largest.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::descent::Optimum;
use super::detection::{detect_by_closeness, related_rows_with};
use super::options::{DetectionOrder, InitiationOptions};
use super::problem::Problem;
use super::row_window::RowWindows;
use super::scans::Scans;

/// Eq. 23 detection over the merged optima `order` (by decreasing R), visited in the
/// options' [`DetectionOrder`], among the rows still `available` (one flag per row; an
/// accepted target's related rows are cleared, so a later pass continues where this one
/// stopped); returns the accepted optima in acceptance order.
pub fn detect(
    problem: &Problem<'_>,
    scans: &Scans,
    optima: &[Optimum],
    order: &[usize],
    options: &InitiationOptions,
    available: &mut [bool],
) -> Vec<usize> {
    match options.detection_order() {
        DetectionOrder::Closeness => {
            detect_by_closeness(problem, scans, optima, order, options, available)
        }
        DetectionOrder::Membership => {
            detect_by_membership(problem, scans, optima, order, options, available)
        }
    }
}

/// A heap entry: an optimum's position in the R order and its last score.
struct Ranked {
    score: f64,
    position: usize,
}

impl Ord for Ranked {
    /// Larger score first; on equal scores the earlier position (higher R).
    fn cmp(&self, other: &Self) -> Ordering {
        (self.score.total_cmp(&other.score)).then(other.position.cmp(&self.position))
    }
}

impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Ranked {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Ranked {}

/// [`detect`] in membership order.
fn detect_by_membership(
    problem: &Problem<'_>,
    scans: &Scans,
    optima: &[Optimum],
    order: &[usize],
    options: &InitiationOptions,
    available: &mut [bool],
) -> Vec<usize> {
    let gate2 = options.gate_sigmas() * options.gate_sigmas();
    let n_detect = options.n_detect_for(scans.len());
    let one = options.one_per_scan();
    let windows = RowWindows::new(problem, scans);
    let taken = |i: usize, available: &[bool]| {
        let mut score = 0.0;
        let x = &optima[i].x;
        let rows = related_rows_with(problem, &windows, x, gate2, one, available, |d2| {
            score += (-d2 / 4.0).exp();
        });
        (rows, score)
    };
    // An optimum's related rows only shrink as rows are taken, so one with `Nd` or fewer now
    // can never be accepted: most optima leave here, after one scoring. The first scorings
    // read the same rows, so they run in parallel; the heap orders by (score, position), a
    // total order, so it pops the same whatever the order they arrive in.
    let first: &[bool] = available;
    let ranked: Vec<Ranked> = (order.par_iter().enumerate())
        .filter_map(|(position, &i)| {
            let (rows, score) = taken(i, first);
            (rows.len() > n_detect).then_some(Ranked { score, position })
        })
        .collect();
    let mut heap = BinaryHeap::from(ranked);
    let mut accepted = Vec::new();
    while let Some(top) = heap.pop() {
        let i = order[top.position];
        let (rows, score) = taken(i, available);
        if rows.len() <= n_detect {
            continue;
        }
        if score < top.score {
            // Rows were taken since it was scored: back in line with its current score.
            heap.push(Ranked { score, ..top });
            continue;
        }
        for &m in &rows {
            available[m] = false;
        }
        accepted.push(i);
    }
    accepted
}

#[cfg(test)]
mod tests {
    use super::detect;
    use crate::data::{Measurements, Sensors};
    use crate::fti::descent::Optimum;
    use crate::fti::options::{DetectionOrder, InitiationOptions};
    use crate::fti::scans::Scans;
    use crate::fti::tests::sim;
    use crate::geometry::model::{predict, Motion, Space, StateLayout, MAX_DIM};

    fn optimum(x: [f64; 4]) -> Optimum {
        let mut state = [0.0; MAX_DIM];
        state[..4].copy_from_slice(&x);
        Optimum {
            x: state,
            closeness: 0.0,
            iterations: 0,
            evaluations: 0,
            scale: [1.0; MAX_DIM],
        }
    }

    /// The two-sensor ghost, built exactly: sensor 0 sees target A on the line of sight of the
    /// ghost G at every scan, sensor 1 sees target B on it, so G relates 16 rows (all of A's
    /// from sensor 0 and B's from sensor 1) and each target 24. Given G first (as R would
    /// rank it), the paper's order accepts it and then both targets on their 16 remaining
    /// rows: three tracks for two targets. The membership order takes A and B, and G has no
    /// rows left.
    #[test]
    fn membership_order_takes_the_targets_before_their_ghost() {
        let sensor_xy = [[0.0, 0.0], [20e3, 0.0], [45e3, 0.0]];
        let ghost = [8e3, 20e3, 120.0, -40.0];
        // A = 1.25 · G seen from sensor 0 (at the origin); B likewise from sensor 1: both CV.
        let a = ghost.map(|v| 1.25 * v);
        let b = [
            20e3 + 1.25 * (ghost[0] - 20e3),
            1.25 * ghost[1],
            1.25 * ghost[2],
            1.25 * ghost[3],
        ];
        let layout = StateLayout::new(Space::Planar, Motion::ConstantVelocity { t0: 0.0 });
        let (mut sensor, mut time, mut azimuth) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..8 {
            for (j, xy) in sensor_xy.iter().enumerate() {
                for target in [a, b] {
                    let t = 10.0 * k as f64;
                    let p = [xy[0], xy[1], 0.0];
                    sensor.push(j as i64);
                    time.push(t);
                    azimuth.push(predict(Space::Planar, &p, &layout.position(&target, t))[0]);
                }
            }
        }
        let elevation = vec![f64::NAN; sensor.len()];
        let positions: Vec<f64> = sensor_xy.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
        let sigma = [2e-3; 3];
        let sensors = Sensors::new(Space::Planar, &positions, &sigma, &sigma).expect("sensors");
        let table =
            Measurements::new(&sensors, &sensor, &time, &azimuth, &elevation).expect("rows");
        let problem = sim::problem(sensors, table);
        let scans = Scans::new(&table, 3);
        let optima = [optimum(ghost), optimum(a), optimum(b)];
        let accepted = |order: DetectionOrder| {
            let options = InitiationOptions::default().with_detection_order(order);
            let mut available = vec![true; table.len()];
            let got = detect(
                &problem,
                &scans,
                &optima,
                &[0, 1, 2],
                &options,
                &mut available,
            );
            (got, available.iter().filter(|&&free| free).count())
        };
        assert_eq!(accepted(DetectionOrder::Closeness), (vec![0, 1, 2], 0));
        assert_eq!(accepted(DetectionOrder::Membership), (vec![1, 2], 0));
    }

    #[test]
    fn the_order_parses_by_name() {
        assert_eq!("membership".parse(), Ok(DetectionOrder::Membership));
        assert_eq!("closeness".parse(), Ok(DetectionOrder::Closeness));
        assert!("R".parse::<DetectionOrder>().is_err());
    }
}
