//! The round gate (a project extension): before its fit, a candidate must find its sensor
//! pair's rays meeting where it predicts them in the pair's other rounds.
//!
//! A candidate joins the pair's meeting in one round with its meeting in a later one, so the
//! two meetings give a position and a velocity. Carried at constant velocity to another round
//! of the pair (a round is a scan of the pair's first sensor with the second sensor's scan
//! nearest in time), the target's meeting there is predicted with the covariance of the two
//! meetings, scaled by how far it is carried; a meeting of the pair's rays in that round
//! within the 99.9 % ellipsoid of the prediction (the predicted meeting's own covariance
//! added) supports the candidate. The candidate passes when `need` of the rounds tested
//! support it: for the rounds formation the round before and the round after its two (one
//! of them will do), for the paper's first and last scans the rounds between them (two of
//! them). A target missed in a round by either sensor has no meeting to find there, which is
//! why not every round is required.
//!
//! The test reads only the pair's own rays, so the time offset between the pair's sensors
//! plays no part: it biases every round's meeting alike, and the bias cancels in the
//! prediction. Each meeting's covariance is that of the two lines of sight crossing, from the
//! angle noise at the meeting's ranges: information `(I − u·uᵀ)/(σ·r)²` per ray in 3-D, the
//! bearing line's normal in 2-D, so a meeting of nearly parallel rays is loose along them.
//! A candidate without a meeting in either round, or with a round missing, passes.
//!
//! The bias cancels only as far as the geometry stays the same from round to round, and near
//! a sensor it does not, so the round gate loses true targets that the witness gate alone
//! keeps (docs/methods.md §1, *Round gate*). So a slot with witness scans (module `witness_gate`) is judged by them alone, and the round
//! gate judges only slots without any: a sensor pair with no third sensor scanning near its
//! rounds.

use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};

use super::meeting::{Located3, Matrix};
use super::ray_pairs::RayPair;
use super::witness_gate::Witnesses;
use crate::geometry::model::Space;

/// A meeting looser than this (metres, the root of its covariance's trace) says too little
/// about where the target is to test a prediction with: such meetings (nearly parallel
/// lines of sight) are left out of a round, and a candidate made of one is not tested.
const LOOSEST: f64 = 2_000.0;

/// How much wider than the noise alone the gate is, in squared distance (distances doubled).
/// The rays of a round are not simultaneous when the sensors are not, so a target's meeting
/// is off its position by a motion bias; the bias cancels in the prediction only as far as it
/// is the same in every round, and it changes with the geometry. Without this margin 1 in 20
/// targets of 3 asynchronous sensors × 20 targets was lost (5 scenes); with it none, for
/// 2.4× the fits.
const MARGIN: f64 = 4.0;

/// χ²(3) at 99.9 % (3-D) with the margin: the Mahalanobis gate on a predicted meeting.
const GATE_3D: f64 = 16.266_236_196_238_13 * MARGIN;
/// χ²(2) at 99.9 % with the margin (2-D).
const GATE_2D: f64 = 13.815_510_557_964_274 * MARGIN;

type Located = GeomWithData<Rectangle<[f64; 3]>, usize>;

/// The meetings of one round of a sensor pair, each indexed by the box its gate may reach
/// (its own spread at the gate).
pub(super) struct RoundMeetings {
    meetings: Vec<Located3>,
    tree: RTree<Located>,
    gate: f64,
}

impl RoundMeetings {
    /// The meetings of `pairs` (those without one, or too loose, are left out).
    pub(super) fn new(space: Space, pairs: &[RayPair]) -> Self {
        let gate = gate_of(space);
        let meetings: Vec<Located3> = (pairs.iter())
            .filter_map(|p| located(space, p))
            .filter(|m| trace(&m.covariance) <= LOOSEST * LOOSEST)
            .collect();
        let tree = RTree::bulk_load(
            (meetings.iter().enumerate())
                .map(|(k, m)| Located::new(reach(&m.point, &m.covariance, gate), k))
                .collect(),
        );
        Self {
            meetings,
            tree,
            gate,
        }
    }
}

/// The box of half-widths `√(gate·C_kk)` around `point`.
fn reach(point: &[f64; 3], c: &Matrix, gate: f64) -> Rectangle<[f64; 3]> {
    let half: [f64; 3] = std::array::from_fn(|k| (gate * c[k][k]).sqrt());
    let lo = std::array::from_fn(|k| point[k] - half[k]);
    let hi = std::array::from_fn(|k| point[k] + half[k]);
    Rectangle::from_corners(lo, hi)
}

fn gate_of(space: Space) -> f64 {
    match space {
        Space::Spatial => GATE_3D,
        Space::Planar => GATE_2D,
    }
}

/// The rounds a slot's candidates are tested against, how many must support each, and the
/// meetings of the slot's own first and last ray pairs, located once; and the other sensors'
/// scans that must witness a candidate (module `witness_gate`).
pub(super) struct RoundGate<'t> {
    pub(super) space: Space,
    pub(super) rounds: Vec<RoundMeetings>,
    pub(super) need: usize,
    pub(super) firsts: Vec<Option<Located3>>,
    pub(super) lasts: Vec<Option<Located3>>,
    pub(super) witnesses: Witnesses<'t>,
}

impl<'t> RoundGate<'t> {
    /// The gate of `rounds` (those with a meeting) needing `need` of them, and of
    /// `witnesses`, for the slot of `firsts` × `lasts`.
    pub(super) fn new(
        space: Space,
        rounds: Vec<RoundMeetings>,
        need: usize,
        witnesses: Witnesses<'t>,
        [firsts, lasts]: [&[RayPair]; 2],
    ) -> Self {
        let locate = |pairs: &[RayPair]| pairs.iter().map(|p| located(space, p)).collect();
        Self {
            space,
            rounds: rounds
                .into_iter()
                .filter(|r| !r.meetings.is_empty())
                .collect(),
            need,
            firsts: locate(firsts),
            lasts: locate(lasts),
            witnesses,
        }
    }

    /// Whether the candidate of first pair `i` (`first`) and last pair `j` (`last`) is seen
    /// by its witnesses, or, without witnesses, finds the pair's rays meeting where it
    /// predicts them in `need` of the rounds (module doc). The round test passes every candidate when fewer than `need`
    /// rounds are there to test (or none is needed); a candidate whose meetings are too loose
    /// to predict with, or missing, fails: its fit would be as loose.
    pub(super) fn passes(&self, i: usize, j: usize, first: &RayPair, last: &RayPair) -> bool {
        let (Some(Some(f)), Some(Some(l))) = (self.firsts.get(i), self.lasts.get(j)) else {
            return false;
        };
        // Witnesses, where there are any, decide alone: the pair's own rounds add little
        // against ghosts once a third sensor has looked, and they lose true targets whose
        // meetings move with the sensors' time offsets (module doc).
        if self.witnesses.asks() {
            self.witnesses.passes(self.space, [first, last], [f, l])
        } else {
            self.rounds_pass(f, l)
        }
    }

    fn rounds_pass(&self, f: &Located3, l: &Located3) -> bool {
        if self.need == 0 || self.rounds.len() < self.need {
            return true;
        }
        if trace(&f.covariance).max(trace(&l.covariance)) > LOOSEST * LOOSEST {
            return false;
        }
        let span = l.time - f.time;
        if !(span.is_finite() && span > 0.0) {
            return true;
        }
        let mut found = 0;
        for (k, round) in self.rounds.iter().enumerate() {
            if found + (self.rounds.len() - k) < self.need {
                return false; // the rounds left cannot make up the count
            }
            if finds(self.space, round, f, l, span) {
                found += 1;
                if found >= self.need {
                    return true;
                }
            }
        }
        false
    }
}

/// Whether `round` holds a meeting within the gate of the candidate's prediction there.
fn finds(space: Space, round: &RoundMeetings, f: &Located3, l: &Located3, span: f64) -> bool {
    let Some(time) = round.meetings.first().map(|m| m.time) else {
        return false;
    };
    // Carried from the first meeting: w = how many spans beyond it (within [0, 1] between).
    let w = (time - f.time) / span;
    let predicted: [f64; 3] = std::array::from_fn(|k| f.point[k] + w * (l.point[k] - f.point[k]));
    let mut covariance = [[0.0; 3]; 3];
    for (i, row) in covariance.iter_mut().enumerate() {
        for (j, value) in row.iter_mut().enumerate() {
            *value = (1.0 - w).powi(2) * f.covariance[i][j] + w * w * l.covariance[i][j];
        }
    }
    let gate = round.gate;
    // Boxes overlap where the two ellipsoids may: the prediction's, and each meeting's own.
    let searched = reach(&predicted, &covariance, gate);
    let envelope = AABB::from_corners(searched.lower(), searched.upper());
    round
        .tree
        .locate_in_envelope_intersecting(envelope)
        .any(|hit| {
            let m = &round.meetings[hit.data];
            let mut total = covariance;
            for (i, row) in total.iter_mut().enumerate() {
                for (j, value) in row.iter_mut().enumerate() {
                    *value += m.covariance[i][j];
                }
            }
            let d: [f64; 3] = std::array::from_fn(|k| m.point[k] - predicted[k]);
            // dᵀC⁻¹d ≥ |d|²/trace C: a meeting farther than that bound fails without the
            // inverse (most of those the boxes let through).
            let d2: f64 = d.iter().map(|v| v * v).sum();
            d2 <= gate * trace(&total) && mahalanobis(&total, &d, space).is_some_and(|q| q <= gate)
        })
}

fn trace(c: &Matrix) -> f64 {
    c[0][0] + c[1][1] + c[2][2]
}

/// The meeting of a ray pair with its covariance (module doc), or `None` without one.
fn located(space: Space, pair: &RayPair) -> Option<Located3> {
    let m = pair.meeting?;
    let mut information = [[0.0; 3]; 3];
    for (o, range) in pair.observations.iter().zip([m.range_a, m.range_b]) {
        // In 2-D only the bearing is measured (the elevation's σ is a placeholder).
        let angle_sigma = match space {
            Space::Spatial => o.sigma[0].max(o.sigma[1]),
            Space::Planar => o.sigma[0],
        };
        let sigma = angle_sigma * range.abs().max(1.0);
        let scale = 1.0 / (sigma * sigma);
        match space {
            Space::Spatial => {
                let u = o.line_of_sight();
                for i in 0..3 {
                    for j in 0..3 {
                        let identity = if i == j { 1.0 } else { 0.0 };
                        information[i][j] += scale * (identity - u[i] * u[j]);
                    }
                }
            }
            Space::Planar => {
                let [c, s] = o.cos_sin()[0];
                let n = [-s, c];
                for i in 0..2 {
                    for j in 0..2 {
                        information[i][j] += scale * n[i] * n[j];
                    }
                }
            }
        }
    }
    let covariance = match space {
        Space::Spatial => inverse3(&information)?,
        Space::Planar => inverse2(&information)?,
    };
    Some(Located3 {
        point: m.point,
        covariance,
        time: m.time,
    })
}

/// `dᵀ C⁻¹ d` (the first two coordinates in 2-D), `None` when `C` is singular.
fn mahalanobis(c: &Matrix, d: &[f64; 3], space: Space) -> Option<f64> {
    let inverse = match space {
        Space::Spatial => inverse3(c)?,
        Space::Planar => inverse2(c)?,
    };
    let n = space.position_dim();
    let q = (0..n)
        .map(|i| (0..n).map(|j| d[i] * inverse[i][j] * d[j]).sum::<f64>())
        .sum::<f64>();
    q.is_finite().then_some(q)
}

fn inverse3(a: &Matrix) -> Option<Matrix> {
    let cof = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]
    };
    let det = a[0][0] * cof(0, 0) + a[0][1] * cof(0, 1) + a[0][2] * cof(0, 2);
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(det.is_finite() && det.abs() > 1e-12 * scale.powi(3)) {
        return None;
    }
    Some(std::array::from_fn(|i| {
        std::array::from_fn(|j| cof(j, i) / det)
    }))
}

fn inverse2(a: &Matrix) -> Option<Matrix> {
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let scale = a[0][0].abs().max(a[1][1].abs());
    if !(det.is_finite() && det.abs() > 1e-12 * scale * scale) {
        return None;
    }
    let mut out = [[0.0; 3]; 3];
    out[0][0] = a[1][1] / det;
    out[1][1] = a[0][0] / det;
    out[0][1] = -a[0][1] / det;
    out[1][0] = -a[1][0] / det;
    Some(out)
}
