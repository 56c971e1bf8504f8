//! The support gate (a project extension, not in the paper): before its descent, a fitted
//! candidate must be *seen* in more than Nd scans, or it cannot become a target.
//!
//! Detection (eq. 23) accepts an optimum only when more than Nd rows are related to it, at
//! most one per scan. A candidate whose neighbourhood holds fewer supporting scans than that
//! climbs to an optimum detection rejects, and its descent (the dominant cost: tens of
//! closeness evaluations over every row) is wasted. In 3-D the χ² gate already removes most
//! such candidates; in 2-D four bearings fix the four unknowns exactly, the χ² gate has no
//! information, and every 4-tuple of clutter bearings that survives `v_max` would be
//! descended (32 000 descents for 5 targets and 3 sensors).
//!
//! A scan *supports* the candidate X̂ (covariance `P = L·Lᵀ` from its fit) when one of its rows
//! lies within `g` standard deviations of the predicted angles in each angle, where the
//! standard deviation includes the candidate's own uncertainty: `σ²_pred = σ² + |∇h·L|²` —
//! so the gate is wider than detection's and widest where the candidate is least sure, which
//! is where the descent may still move it. The candidate survives when more than Nd scans
//! support it. Each scan's rows are kept sorted by azimuth and indexed (module `angle_index`).

use super::angle_index::Azimuths;
use super::candidate::Candidate;
use super::problem::Problem;
use super::scans::Scans;
use crate::geometry::angles::wrap;
use crate::geometry::model::{gradient_rows, predict, Observation, Space};

/// One scan as the gate reads it: where and when, the angle stds, and the rows' angles
/// `[azimuth, elevation]` (wrapped) sorted by azimuth.
pub(super) struct ScanAngles {
    pub(super) probe: Observation,
    pub(super) sigma: [f64; 2],
    pub(super) angles: Azimuths,
}

/// Every scan of a table, prepared once per initiation.
pub struct SupportTable {
    pub(super) scans: Vec<ScanAngles>,
}

impl SupportTable {
    pub fn new(problem: &Problem<'_>, scans: &Scans) -> Self {
        Self::of_rows(problem, scans, None)
    }

    /// The table of the rows that are `available` (every row when `None`): pass 2's gates
    /// count only the rows its detection may still take.
    pub fn of_rows(problem: &Problem<'_>, scans: &Scans, available: Option<&[bool]>) -> Self {
        let scans = (0..scans.len())
            .map(|k| {
                let rows = scans.scan(k);
                let first = problem.observation(rows[0]);
                let angles: Vec<[f64; 2]> = (rows.iter())
                    .filter(|&&m| available.is_none_or(|a| a[m]))
                    .map(|&m| problem.observation(m).angles.map(wrap))
                    .collect();
                ScanAngles {
                    // Unit stds: `residual_rows` then returns the plain gradient ∇h.
                    probe: Observation::new(first.sensor, first.time, [0.0; 2], [1.0; 2]),
                    sigma: problem.scan_sigma(rows),
                    angles: Azimuths::new(angles),
                }
            })
            .collect();
        Self { scans }
    }

    /// Whether more than `n_detect` scans support `candidate` at gate `gate` (σ units).
    ///
    /// The candidate's own four scans are visited last: the count and so the answer do not
    /// depend on the order, and its own rows nearly always support it, so a candidate that
    /// fails is usually rejected before reaching them.
    pub fn supports(
        &self,
        problem: &Problem<'_>,
        scans: &Scans,
        candidate: &Candidate,
        gate: f64,
        n_detect: usize,
    ) -> bool {
        let own = candidate.rows.map(|r| scans.scan_of[r]);
        let n = self.scans.len();
        let order = (0..n)
            .filter(|k| !own.contains(k))
            .chain((0..n).filter(|k| own.contains(k)));
        let mut supported = 0usize;
        for (at, k) in order.enumerate() {
            if supported + (n - at) <= n_detect {
                return false; // even every remaining scan would not be enough
            }
            if scan_supports(problem, &self.scans[k], candidate, gate) {
                supported += 1;
                if supported > n_detect {
                    return true;
                }
            }
        }
        false
    }
}

/// Whether a row of `scan` lies within the candidate's inflated gate.
fn scan_supports(problem: &Problem<'_>, scan: &ScanAngles, c: &Candidate, gate: f64) -> bool {
    let layout = &problem.layout;
    let d = layout.dim();
    let x = &c.estimate[..d];
    let target = layout.position(x, scan.probe.time);
    let predicted = predict(layout.space, &scan.probe.sensor, &target);
    let neighbours = Neighbours::around(&scan.angles, predicted[0]);
    let any_within = |widths: [f64; 2]| match layout.space {
        Space::Planar => neighbours.any_within(widths[0]),
        Space::Spatial => in_box(scan, predicted, widths, layout.space)
            .next()
            .is_some(),
    };
    // The window only widens with the candidate's spread, so a row within `gate·σ` supports
    // the scan whatever the spread: most supported scans end here, before the gradient.
    if any_within(scan.sigma.map(|s| gate * s)) {
        return true;
    }
    let Some((count, gradient)) = gradient_rows(layout, x, &scan.probe) else {
        return true; // on the sensor's axis: the angles are undefined, do not prune
    };
    any_within(std::array::from_fn(|a| {
        if a >= count {
            return f64::INFINITY;
        }
        let spread: f64 = (0..d)
            .map(|j| {
                let gl: f64 = (0..d).map(|i| gradient[a][i] * c.factor[i][j]).sum();
                gl * gl
            })
            .sum();
        gate * (scan.sigma[a] * scan.sigma[a] + spread).sqrt()
    }))
}

/// Where `centre` falls among a scan's rows sorted by azimuth. In 2-D a window holds a row
/// exactly when the nearest row on either side (modulo 2π) is in it, so the fixed gate's two
/// windows need one search instead of two each (this test is most of the gate's work on
/// dense 2-D scenes).
struct Neighbours<'s> {
    sorted: &'s [[f64; 2]],
    centre: f64,
    /// The first row at or above `centre`.
    above: usize,
}

impl<'s> Neighbours<'s> {
    fn around(azimuths: &'s Azimuths, centre: f64) -> Self {
        Self {
            sorted: azimuths.rows(),
            centre,
            above: azimuths.first_not_below(centre),
        }
    }

    /// Whether [`Azimuths::window`] of `width` around the centre holds a row; the same
    /// comparisons on the only rows that can decide it, so the same answer.
    fn any_within(&self, width: f64) -> bool {
        use std::f64::consts::PI;
        let sorted = self.sorted;
        let (Some(first), Some(last)) = (sorted.first(), sorted.last()) else {
            return false;
        };
        if width >= PI || width.is_nan() {
            return true;
        }
        let (lo, hi) = (self.centre - width, self.centre + width);
        let below = self.above.checked_sub(1).map(|i| &sorted[i]);
        sorted.get(self.above).is_some_and(|a| a[0] <= hi)
            || below.is_some_and(|a| a[0] >= lo)
            || (lo < -PI && last[0] >= lo + 2.0 * PI)
            || (hi > PI && first[0] <= hi - 2.0 * PI)
    }
}

/// The rows of `scan` within `half` of `centre` in each angle (azimuth modulo 2π; elevation
/// only in 3-D).
pub(super) fn in_box(
    scan: &ScanAngles,
    centre: [f64; 2],
    half: [f64; 2],
    space: Space,
) -> impl Iterator<Item = &[f64; 2]> {
    scan.angles
        .window(centre[0], half[0])
        .filter(move |angles| space == Space::Planar || in_elevation(angles, centre[1], half[1]))
}

/// Whether a row's elevation lies within `half` of `centre` (the box test's second angle).
pub(super) fn in_elevation(angles: &[f64; 2], centre: f64, half: f64) -> bool {
    wrap(angles[1] - centre).abs() <= half
}

/// The support gate's tables and settings, as the fitting stage applies it to each fitted
/// candidate: the fixed gate above, then the tracking gate (module `tracking_gate`, which
/// holds [`Gate::keeps`]) on the survivors.
pub struct Gate<'a> {
    pub table: &'a SupportTable,
    pub scans: &'a Scans,
    /// Half-width in standard deviations.
    pub gate: f64,
    pub n_detect: usize,
    /// What the tracking gate adds to the score per scan without a row: `ln(1 − gate_pd)`,
    /// or 0 when misses are not priced.
    pub miss_score: f64,
}

#[cfg(test)]
mod tests {
    use super::{Azimuths, Neighbours};
    use crate::fti::options::InitiationOptions;
    use crate::fti::tests::run;
    use crate::fti::tests::sim;
    use crate::fti::Formation;
    use std::f64::consts::PI;

    /// The one-search test agrees with the window it replaces, around and across ±π, on
    /// both edges of each window (rows exactly at `centre ± width`).
    #[test]
    fn neighbours_agree_with_the_azimuth_window() {
        let sorted = [[-3.1, 0.0], [-1.0, 0.0], [0.0, 0.0], [0.5, 0.0], [3.1, 0.0]];
        let azimuths = Azimuths::new(sorted.to_vec());
        for centre in [-PI, -3.12, -2.0, -0.5, 0.0, 0.25, 1.0, 3.0, 3.13, PI] {
            let neighbours = Neighbours::around(&azimuths, centre);
            let edges = sorted.iter().map(|a| (a[0] - centre).abs());
            for width in [0.0, 0.01, 0.1, 0.3, 1.0, 3.0, 3.2, f64::NAN]
                .into_iter()
                .chain(edges)
            {
                let expected = azimuths.window(centre, width).next().is_some();
                assert_eq!(neighbours.any_within(width), expected, "{centre} ± {width}");
            }
        }
        assert!(!Neighbours::around(&Azimuths::new(Vec::new()), 0.0).any_within(1.0));
    }

    /// On the paper's formation, whose candidates are not tested before their fit (the default
    /// at two sensors asks the pair's own scans first, which leaves the gate little to do).
    #[test]
    fn the_gate_removes_descents_but_not_targets() {
        for (seed, clutter) in [(2024, 8), (7, 16)] {
            let sc = sim::paper(seed, true, clutter, 8);
            let on = InitiationOptions::default().with_candidates(Formation::Paper);
            let off = on.clone().with_support_gate(false);
            let (with, without) = (run(&sc, &on).expect("runs"), run(&sc, &off).expect("runs"));
            let c = with.stage_counts;
            assert!(c.supported < c.chi2_gate / 2, "{c:?}");
            assert_eq!(
                without.stage_counts.supported,
                without.stage_counts.chi2_gate
            );
            assert_eq!(with.labels, without.labels, "seed {seed}");
            assert_eq!(with.tracks.len(), 4);
        }
    }
}
