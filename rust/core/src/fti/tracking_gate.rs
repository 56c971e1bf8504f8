//! The tracking gate (a project extension, part of the support gate): a candidate that passed
//! the fixed support gate must also find a row in more than Nd scans when it is *updated* on
//! the rows it finds, as a tracker would.
//!
//! Why: the fixed gate widens each scan's window by the candidate's own uncertainty, and a
//! candidate fitted on four rows is unsure of its range (of everything, in 2-D, where four
//! bearings fix the four unknowns exactly). Other sensors' scans then pass it almost always,
//! and on cluttered scenes the descents of candidates detection later rejects would be most
//! of the run (docs/methods.md §1, *Tracking gate*).
//!
//! How: the scans other than the candidate's own four are visited from the one it predicts
//! best (smallest spread `∇h·P·∇hᵀ`) to the worst. A scan supports the candidate when a row
//! lies within `gate` standard deviations of the prediction in each angle (the standard
//! deviation being `√(σ² + ∇h·P·∇hᵀ)`, as in the fixed gate); the nearest such row then
//! updates the state and covariance (an extended Kalman update, one angle at a time), so
//! later windows narrow. At the first scan whose window is wider than the noise would make
//! it (spread above σ², usually the first scan of a third sensor) and holds several rows, the
//! nearest is not trusted: each of the rows (up to [`MAX_BRANCHES`], nearest first) is tried
//! as its own continuation, and the candidate survives when one of them does. Own scans count
//! as support; their rows are already in the fit, so they update nothing. The descent still
//! starts from the candidate's own fit: the gate only decides whether it runs.
//!
//! **Score.** Where clutter is dense a count is weak evidence: in the cluttered 2-D scenes of
//! `benches/bench_initiation_2d.py` most gates hold a row by chance, and most candidates that
//! reach more than Nd scans are clutter.
//! So the walk also sums, over the rows it takes, the log-likelihood ratio of each
//! row under the candidate (the predictive Gaussian: innovation variance `σ² + ∇h·P·∇hᵀ`
//! per angle) against clutter at the scan's local density (rows per radian, per rad² in 3-D,
//! in a box of ±[`DENSITY_WIDTH`] predicted standard deviations, the scored row left out and
//! at least one counted), and the candidate must not end with a negative sum: the rows it
//! found are at least as likely from a target as from clutter (a candidate with no scan
//! beyond its own four has no score, and the count alone decides). Misses are not priced by
//! default: the detection probability is unknown (METHODS §1); with `gate_pd` = p each scan
//! without a row in the gate adds `ln(1 − p)` ([`Gate::miss_score`]). The own four scans
//! add nothing (their rows are in the fit). On the paper's scene it removes 3 of the 24
//! candidates a run that the count passes and no figure `reproduce fti` prints at Pd = 1
//! changes; on the bench's 8-target 2-D scene it keeps about a tenth of the candidates the
//! count passes (CHANGELOG.md, *Dense clutter*).
//!
//! **Pruning.** No row can add more than `ln(2·DENSITY_WIDTH) − ½·ln 2π` per angle to the
//! score (`most_per_scan`), and a miss adds nothing or less. So a branch whose score, with
//! that much for every scan left, stays below 0 is ended where it stands: it would end
//! rejected. Before the branching the walk goes on regardless, since a crowded scan there
//! keeps the candidate whatever its score.

use std::f64::consts::PI;

use super::candidate::Candidate;
use super::problem::Problem;
use super::support::{in_box, Gate, ScanAngles};
use crate::geometry::angles::wrap;
use crate::geometry::model::{gradient_rows, predict, Space, MAX_DIM};

/// Rows tried at the one ambiguous wide scan. The true row lies within the gate; past this
/// many nearer rows the window is so crowded that the candidate is kept untested instead.
pub const MAX_BRANCHES: usize = 32;

/// Half-width, in predicted standard deviations, of the box in which a scan's clutter density
/// is counted: four times the 5σ gate, so the rows of the gate itself are a small part of it.
const DENSITY_WIDTH: f64 = 20.0;

type Matrix = [[f64; MAX_DIM]; MAX_DIM];

/// A candidate's state and covariance as the gate updates them.
#[derive(Clone)]
struct Belief {
    x: [f64; MAX_DIM],
    p: Matrix,
    dim: usize,
}

/// One scan as the belief sees it: the predicted angles, their gradients and the variances
/// of the innovation, per angle (one in 2-D, two in 3-D).
struct Prediction {
    angles: [f64; 2],
    gradient: [[f64; MAX_DIM]; 2],
    variance: [f64; 2],
    spread: [f64; 2],
    count: usize,
}

impl Belief {
    fn of(c: &Candidate, dim: usize) -> Self {
        let mut p = [[0.0; MAX_DIM]; MAX_DIM];
        for (i, row) in p.iter_mut().enumerate().take(dim) {
            for (j, value) in row.iter_mut().enumerate().take(dim) {
                *value = (0..dim).map(|k| c.factor[i][k] * c.factor[j][k]).sum();
            }
        }
        Self {
            x: c.estimate,
            p,
            dim,
        }
    }

    /// `P·g` for a gradient row `g`.
    fn p_times(&self, g: &[f64; MAX_DIM]) -> [f64; MAX_DIM] {
        std::array::from_fn(|i| (0..self.dim).map(|j| self.p[i][j] * g[j]).sum())
    }

    /// The summed spread `∇h·P·∇hᵀ` of `scan`'s angles (infinite on the sensor's axis):
    /// [`predict`](Self::predict)'s without the angles, to order the scans.
    fn spread(&self, problem: &Problem<'_>, scan: &ScanAngles) -> f64 {
        let x = &self.x[..self.dim];
        let Some((count, gradient)) = gradient_rows(&problem.layout, x, &scan.probe) else {
            return f64::INFINITY;
        };
        gradient[..count].iter().map(|g| self.spread_of(g)).sum()
    }

    /// `g·P·gᵀ` for a gradient row `g`.
    fn spread_of(&self, g: &[f64; MAX_DIM]) -> f64 {
        let pg = self.p_times(g);
        (0..self.dim).map(|i| g[i] * pg[i]).sum()
    }

    /// The prediction of `scan`, or `None` on the sensor's axis (angles undefined).
    fn predict(&self, problem: &Problem<'_>, scan: &ScanAngles) -> Option<Prediction> {
        let layout = &problem.layout;
        let x = &self.x[..self.dim];
        let target = layout.position(x, scan.probe.time);
        let (count, gradient) = gradient_rows(layout, x, &scan.probe)?;
        let spread: [f64; 2] = gradient.each_ref().map(|g| self.spread_of(g));
        Some(Prediction {
            angles: predict(layout.space, &scan.probe.sensor, &target),
            gradient,
            variance: std::array::from_fn(|a| scan.sigma[a] * scan.sigma[a] + spread[a]),
            spread,
            count,
        })
    }

    /// The extended Kalman update on a row's angles, one angle at a time.
    fn update(&mut self, pred: &Prediction, angles: &[f64; 2], sigma: &[f64; 2]) {
        for a in 0..pred.count {
            let g = &pred.gradient[a];
            let pg = self.p_times(g);
            let s = sigma[a] * sigma[a] + (0..self.dim).map(|i| g[i] * pg[i]).sum::<f64>();
            if !(s > 0.0 && s.is_finite()) {
                return;
            }
            let innovation = wrap(angles[a] - pred.angles[a]);
            for i in 0..self.dim {
                self.x[i] += pg[i] * innovation / s;
                for j in 0..self.dim {
                    self.p[i][j] -= pg[i] * pg[j] / s;
                }
            }
        }
    }
}

impl Prediction {
    /// The rows of `scan` within `gate` σ in each angle, nearest (normalised) first.
    fn hits(&self, scan: &ScanAngles, space: Space, gate: f64) -> Vec<(f64, [f64; 2])> {
        let mut hits: Vec<(f64, [f64; 2])> = self.gated(scan, space, gate).collect();
        hits.sort_by(|p, q| p.0.total_cmp(&q.0));
        hits
    }

    /// [`hits`](Self::hits)' first entry and length, without collecting them: nearly every
    /// step of the walk needs only these (the sort is stable, so the first of equally near
    /// rows in window order is the nearest in both).
    fn nearest(
        &self,
        scan: &ScanAngles,
        space: Space,
        gate: f64,
    ) -> Option<((f64, [f64; 2]), usize)> {
        let mut best: Option<(f64, [f64; 2])> = None;
        let mut count = 0;
        for hit in self.gated(scan, space, gate) {
            count += 1;
            if best.is_none_or(|b| hit.0.total_cmp(&b.0).is_lt()) {
                best = Some(hit);
            }
        }
        best.map(|b| (b, count))
    }

    /// The rows of `scan` within `gate` σ in each angle with their normalised squared
    /// distances, in window order.
    fn gated<'a>(
        &'a self,
        scan: &'a ScanAngles,
        space: Space,
        gate: f64,
    ) -> impl Iterator<Item = (f64, [f64; 2])> + 'a {
        let width = move |a: usize| gate * self.variance[a].sqrt();
        (scan.angles.window(self.angles[0], width(0))).filter_map(move |angles| {
            let mut d2 = 0.0;
            let pairs = angles.iter().zip(&self.angles).take(self.count);
            for (a, (&z, &h)) in pairs.enumerate() {
                let y = wrap(z - h);
                if a == 1 && space == Space::Spatial && y.abs() > width(1) {
                    return None;
                }
                d2 += y * y / self.variance[a];
            }
            Some((d2, *angles))
        })
    }

    /// Log-likelihood ratio of a row at normalised squared distance `d2`: the target's
    /// predictive Gaussian (the innovation variances) against clutter spread at the scan's
    /// local density (module doc, *Score*).
    fn log_ratio(&self, d2: f64, scan: &ScanAngles, space: Space) -> f64 {
        let log_norm: f64 = (0..self.count)
            .map(|a| (2.0 * PI * self.variance[a]).ln())
            .sum();
        -0.5 * d2 - 0.5 * log_norm - self.clutter_density(scan, space).ln()
    }

    /// Rows per radian (per rad² in 3-D) in a box of ±[`DENSITY_WIDTH`] predicted standard
    /// deviations around the prediction, the row being scored left out, and at least one.
    fn clutter_density(&self, scan: &ScanAngles, space: Space) -> f64 {
        let half: [f64; 2] = std::array::from_fn(|a| DENSITY_WIDTH * self.variance[a].sqrt());
        let rows = in_box(scan, self.angles, half, space).count();
        let mut area = (2.0 * half[0]).min(2.0 * PI);
        if space == Space::Spatial {
            area *= (2.0 * half[1]).min(PI);
        }
        rows.saturating_sub(1).max(1) as f64 / area
    }

    /// Wider than the noise alone would make the window: the nearest row is not trusted.
    fn wide(&self, sigma: &[f64; 2]) -> bool {
        (0..self.count).any(|a| self.spread[a] > sigma[a] * sigma[a])
    }
}

impl Gate<'_> {
    /// The support gate's verdict: the fixed gate (module `support`), then this walk on its
    /// survivors. The walk's score when the candidate passes both, `None` when not.
    pub fn keeps(&self, problem: &Problem<'_>, c: &Candidate) -> Option<f64> {
        let (table, scans, gate, n_detect) = (self.table, self.scans, self.gate, self.n_detect);
        if !table.supports(problem, scans, c, gate, n_detect) {
            return None;
        }
        score(problem, self, c)
    }
}

/// Whether `c` finds a row in more than `n_detect` scans, updated as it goes, and the rows
/// it finds are likelier from it than from clutter (module doc).
#[cfg(test)]
pub fn confirms(problem: &Problem<'_>, gating: &Gate<'_>, c: &Candidate) -> bool {
    score(problem, gating, c).is_some()
}

/// The walk's score (the summed log-likelihood ratios of the rows taken, misses priced when
/// asked) when `c` passes the gate, `None` when it does not. Where the one ambiguous scan
/// branches, the score is that of the first branch (nearest row first) that passes; a
/// candidate kept untested in a crowd scores what it had before the crowd.
pub fn score(problem: &Problem<'_>, gating: &Gate<'_>, c: &Candidate) -> Option<f64> {
    let (table, scans) = (gating.table, gating.scans);
    let dim = problem.layout.dim();
    let belief = Belief::of(c, dim);
    let mut own: Vec<usize> = c.rows.iter().map(|&r| scans.scan_of[r]).collect();
    own.sort_unstable();
    own.dedup();
    let mut order: Vec<(f64, usize)> = (0..table.scans.len())
        .filter(|k| own.binary_search(k).is_err())
        .map(|k| (belief.spread(problem, &table.scans[k]), k))
        .collect();
    order.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
    let walk = Walk {
        problem,
        gating,
        order: &order,
        most_per_scan: most_per_scan(problem.layout.space),
    };
    walk.from(0, belief, own.len(), 0.0, false)
}

/// The most one scan's row can add to a walk's score, with a hair of slack for rounding: the
/// row's log-likelihood ratio ([`Prediction::log_ratio`]) is at most its value at `d2 = 0`
/// against a density of one row in the counting box, and with the box's half-widths
/// `DENSITY_WIDTH·√v` per angle that is `ln(2·DENSITY_WIDTH) − ½·ln(2π)` per angle, whatever
/// the variance `v` (the box's clamps to 2π and π only lower it). A miss adds at most 0.
fn most_per_scan(space: Space) -> f64 {
    let angles = match space {
        Space::Spatial => 2.0,
        Space::Planar => 1.0,
    };
    angles * ((2.0 * DENSITY_WIDTH).ln() - 0.5 * (2.0 * PI).ln()) + 1e-6
}

/// The fixed inputs of one candidate's walk over its ordered scans.
struct Walk<'a> {
    problem: &'a Problem<'a>,
    gating: &'a Gate<'a>,
    order: &'a [(f64, usize)],
    /// The most one scan can add to the score ([`most_per_scan`]).
    most_per_scan: f64,
}

impl Walk<'_> {
    /// Continues at position `start` of the order with `supported` scans and `score` so far;
    /// `branched` once the ambiguous wide scan has been split. The final score when the
    /// candidate passes.
    fn from(
        &self,
        start: usize,
        mut belief: Belief,
        mut supported: usize,
        mut score: f64,
        branched: bool,
    ) -> Option<f64> {
        let space = self.problem.layout.space;
        for (at, &(_, k)) in self.order.iter().enumerate().skip(start) {
            let left = self.order.len() - at;
            if supported + left <= self.gating.n_detect {
                return None; // even every remaining scan would not be enough
            }
            // Nor can any score climb back: past the branching no scan keeps a candidate
            // untested, so a branch whose score even the best rows could not raise to 0
            // ends as it would have.
            if branched && score + left as f64 * self.most_per_scan < 0.0 {
                return None;
            }
            let scan = &self.gating.table.scans[k];
            let Some(pred) = belief.predict(self.problem, scan) else {
                supported += 1; // on the sensor's axis: do not prune, as the fixed gate
                continue;
            };
            let Some(((d2, nearest), count)) = pred.nearest(scan, space, self.gating.gate) else {
                // A miss: priced only at an assumed detection probability (`gate_pd`).
                score += self.gating.miss_score;
                continue;
            };
            supported += 1;
            if count == 1 || branched || !pred.wide(&scan.sigma) {
                score += pred.log_ratio(d2, scan, space);
                belief.update(&pred, &nearest, &scan.sigma);
                continue;
            }
            let hits = pred.hits(scan, space, self.gating.gate);
            if hits.len() > MAX_BRANCHES {
                return Some(score); // too crowded to test: keep the candidate
            }
            return hits.iter().find_map(|&(d2, angles)| {
                let mut branch = belief.clone();
                branch.update(&pred, &angles, &scan.sigma);
                let score = score + pred.log_ratio(d2, scan, space);
                self.from(at + 1, branch, supported, score, true)
            });
        }
        // A candidate with no scan beyond its own four has no score (0): the count decides.
        (supported > self.gating.n_detect && score >= 0.0).then_some(score)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fti::options::InitiationOptions;
    use crate::fti::support::SupportTable;
    use crate::fti::tests::candidates_of;
    use crate::fti::tests::sim;

    /// In 2-D with clutter (where the χ² gate has no information): every candidate made of
    /// one target's four rows passes, and the gate removes candidates the fixed gate keeps;
    /// pricing misses at an assumed Pd of 0.9 keeps every true candidate too, and only
    /// removes more (a priced walk's score is never higher).
    #[test]
    fn keeps_every_true_candidate_and_removes_some_the_fixed_gate_keeps() {
        let (mut fixed, mut tracked, mut priced, mut true_ones) = (0, 0, 0, 0);
        for seed in 0..4 {
            let sc = sim::planar(seed, true, 12, 8);
            let sensors = sc.sensors();
            let table = sc.measurements(&sensors);
            let options = InitiationOptions::default();
            let (candidates, _, scans, _) =
                candidates_of(&sensors, &table, 0.0, &options).expect("runs");
            let problem = sim::problem(sensors, table);
            let support = SupportTable::new(&problem, &scans);
            let n_detect = options.n_detect_for(scans.len());
            for c in &candidates {
                let owner = sc.truth[c.rows[0]];
                let is_true = owner >= 0 && c.rows.iter().all(|&m| sc.truth[m] == owner);
                if !support.supports(&problem, &scans, c, options.gate_sigmas(), n_detect) {
                    assert!(!is_true, "the fixed gate lost a true candidate");
                    continue;
                }
                fixed += 1;
                let gating = |miss_score| Gate {
                    table: &support,
                    scans: &scans,
                    gate: options.gate_sigmas(),
                    n_detect,
                    miss_score,
                };
                let kept = confirms(&problem, &gating(0.0), c);
                let kept_priced = confirms(&problem, &gating(0.1f64.ln()), c);
                assert!(kept || !kept_priced, "pricing misses kept a candidate");
                tracked += usize::from(kept);
                priced += usize::from(kept_priced);
                if is_true {
                    true_ones += 1;
                    assert!(
                        kept && kept_priced,
                        "seed {seed}: target {owner}'s own candidate was removed"
                    );
                }
            }
        }
        assert!(true_ones >= 8, "{true_ones} true candidates");
        assert!(tracked < fixed, "kept {tracked} of {fixed}");
        assert!(priced < tracked, "priced kept {priced} of {tracked}");
    }

    /// No row's log-likelihood ratio exceeds [`most_per_scan`], the bound the walk prunes
    /// with: predictions at variances from 10⁻¹⁴ to 10 rad² (boxes clamped to the whole sky
    /// at the top), rows exactly on the prediction, on scans of one to 300 rows, in 2-D and
    /// 3-D; and the bound is nearly reached (one row, on the prediction, an unclamped box).
    #[test]
    fn no_row_adds_more_than_the_walks_bound() {
        use crate::fti::angle_index::Azimuths;
        use crate::fti::support::ScanAngles;
        use crate::geometry::model::Observation;
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut nearest: f64 = f64::NEG_INFINITY;
        for case in 0..3_000 {
            let space = if case % 2 == 0 {
                Space::Spatial
            } else {
                Space::Planar
            };
            let n = 1 + case % 300;
            let rows: Vec<[f64; 2]> = (0..n)
                .map(|_| [rng.random_range(-PI..=PI), rng.random_range(-0.5..0.5)])
                .collect();
            let scan = ScanAngles {
                probe: Observation::new([0.0; 3], 0.0, [0.0; 2], [1.0; 2]),
                sigma: [1e-3; 2],
                angles: Azimuths::new(rows.clone()),
            };
            let variance: [f64; 2] =
                std::array::from_fn(|_| 10f64.powf(rng.random_range(-14.0..1.0)));
            let row = rows[case % n];
            let pred = Prediction {
                angles: row,
                gradient: [[0.0; MAX_DIM]; 2],
                variance,
                spread: variance,
                count: space.position_dim() - 1,
            };
            let most = most_per_scan(space);
            for d2 in [0.0, 1e-9, 0.5, 3.0] {
                let ratio = pred.log_ratio(d2, &scan, space);
                assert!(ratio <= most, "case {case}: {ratio} > {most}");
            }
            nearest = nearest.max(pred.log_ratio(0.0, &scan, space) - most);
        }
        assert!(nearest > -1e-3, "the bound is {nearest} from the best row");
    }
}
