//! The witness gate (rounds and witnessed formations, a project extension): before its fit,
//! a candidate of a sensor pair must be seen by the network's other sensors in the scans
//! around its rounds.
//!
//! Two sensors' rays meet wherever they cross, target or not; a third sensor's ray passes a
//! true meeting and seldom a ghost (METHODS §2). The test uses the candidate's own trajectory,
//! so it needs no slack for the time between the sensors' scans: the two meetings give a
//! velocity `v`; moving each pair's second ray by `v·(t_a − t_b)` puts the target on both lines
//! at the first ray's instant, and their closest points' midpoint is where the target was then,
//! up to noise (as module `motion_gate` tests). The meetings' velocity is itself off by the
//! motion between each pair's rays, so the rays are moved once more by the velocity of those
//! two corrected points. Between and around those two instants the
//! candidate moves at constant velocity; in each *witness* scan (another sensor's scan within
//! half the slot's span of it, see [`crate::fti::Scans::round_slots`]) it predicts the
//! azimuth and elevation with the spread of the two meetings carried there (their covariances,
//! as module `round_gate` has them) added to the sensor's noise. A scan with a row inside the
//! 99 % ellipse of that prediction supports the candidate; at least half the witness scans
//! (rounded up) must, so a target missed once by another sensor still passes. The witnessed
//! formation's slots (the paper's first × last scans, every scan of the other sensors as
//! witnesses) need more than half; with two sensors its witnesses are the pair's own scans
//! outside the slot, of which it needs what detection will (module `formation_slots`).

use super::meeting::{Located3, Matrix};
use super::ray_pairs::RayPair;
use super::scans::WitnessNeed;
use super::support::{in_elevation, ScanAngles};
use crate::geometry::angles::wrap;
use crate::geometry::fastmath::{atan2, atan2_any};
use crate::geometry::los::closest_points;
use crate::geometry::model::Space;

/// χ²(2) at 99 %, `−2 ln 0.01`: the gate on a witness's two angles. A true target is missed
/// by one witness scan in a hundred. The wider 99.9 % gate fitted 1.8× the candidates of the
/// first slot at 5 sensors × 100 targets and found the same targets there, in 10 scenes of
/// 3 × 20 and in 5 of 4 × 50.
const CHI2_2DOF_99: f64 = 9.210_340_371_976_184;

/// The witness scans of one slot and how many must support a candidate.
pub(super) struct Witnesses<'t> {
    scans: Vec<&'t ScanAngles>,
    need: usize,
    gate: f64,
}

impl<'t> Witnesses<'t> {
    /// The scans of `table` numbered `witnesses`, as many of them needed as `need` says; none
    /// when `table` holds none of them (the support gate off: there is then nothing to ask).
    pub(super) fn new(table: &'t [ScanAngles], witnesses: &[usize], need: WitnessNeed) -> Self {
        let scans: Vec<&ScanAngles> = witnesses.iter().filter_map(|&k| table.get(k)).collect();
        Self {
            need: need.of(scans.len()),
            scans,
            gate: CHI2_2DOF_99,
        }
    }

    /// Whether there is a witness scan to ask.
    pub(super) fn asks(&self) -> bool {
        self.need > 0
    }

    /// Whether enough witness scans see the candidate of `first` and `last` (meetings
    /// `located`: points and covariances). Passes when there is no witness to ask or the
    /// candidate has no trajectory to predict with (the fit decides those).
    pub(super) fn passes(
        &self,
        space: Space,
        [first, last]: [&RayPair; 2],
        [f, l]: [&Located3; 2],
    ) -> bool {
        if self.need == 0 {
            return true;
        }
        let Some([(pf, tf), (pl, tl)]) = trajectory(first, last, f, l) else {
            return true;
        };
        let span = tl - tf;
        let mut found = 0;
        for (k, scan) in self.scans.iter().enumerate() {
            if found + (self.scans.len() - k) < self.need {
                return false; // the scans left cannot make up the count
            }
            let w = (scan.probe.time - tf) / span;
            let point: [f64; 3] = std::array::from_fn(|i| pf[i] + w * (pl[i] - pf[i]));
            let mut covariance = [[0.0; 3]; 3];
            for (i, row) in covariance.iter_mut().enumerate() {
                for (j, value) in row.iter_mut().enumerate() {
                    *value = (1.0 - w).powi(2) * f.covariance[i][j] + w * w * l.covariance[i][j];
                }
            }
            if sees(space, scan, &point, &covariance, self.gate) {
                found += 1;
                if found >= self.need {
                    return true;
                }
            }
        }
        false
    }
}

/// Where the target was at each pair's first-ray instant: the midpoint of the closest points
/// once the second ray is moved by the velocity of the two meetings (module doc).
fn trajectory(
    first: &RayPair,
    last: &RayPair,
    f: &Located3,
    l: &Located3,
) -> Option<[([f64; 3], f64); 2]> {
    let span = l.time - f.time;
    if !(span.is_finite() && span > 0.0) {
        return None;
    }
    let mut v: [f64; 3] = std::array::from_fn(|k| (l.point[k] - f.point[k]) / span);
    let at = |pair: &RayPair, v: &[f64; 3]| -> Option<([f64; 3], f64)> {
        let [oa, ob] = &pair.observations;
        let dt = oa.time - ob.time;
        let shifted: [f64; 3] = std::array::from_fn(|k| ob.sensor[k] + v[k] * dt);
        let m = closest_points(
            &oa.sensor,
            &oa.line_of_sight(),
            &shifted,
            &ob.line_of_sight(),
        )?;
        Some((m.midpoint(), oa.time))
    };
    let (a, b) = (at(first, &v)?, at(last, &v)?);
    // Once more with the velocity of the corrected points: the meetings' own velocity is
    // biased by the time between each pair's rays, which in the paper's slots of sensors
    // that scan unequally is tens of seconds (CHANGELOG.md has the figures).
    let span = b.1 - a.1;
    if !(span.is_finite() && span > 0.0) {
        return None;
    }
    v = std::array::from_fn(|k| (b.0[k] - a.0[k]) / span);
    let (a, b) = (at(first, &v)?, at(last, &v)?);
    (b.1 - a.1 > 0.0).then_some([a, b])
}

/// Whether `scan` holds a row whose angles lie within the χ² gate `gate` of those it sees
/// `point` at: the residual's covariance is the sensor's noise plus `covariance` carried
/// through the angles' gradient (in 2-D, the azimuth alone).
fn sees(space: Space, scan: &ScanAngles, point: &[f64; 3], covariance: &Matrix, gate: f64) -> bool {
    let sensor = &scan.probe.sensor;
    let d: [f64; 3] = std::array::from_fn(|k| point[k] - sensor[k]);
    let rho2 = d[0] * d[0] + d[1] * d[1];
    let r2 = rho2 + d[2] * d[2];
    if !(rho2 > 0.0 && rho2.is_finite()) {
        return true; // overhead the azimuth is undefined: do not judge
    }
    // The azimuth `predict` gives, by the residual kernel's arctangent (a few ulp from the
    // standard library's, at a fraction of its cost: this runs per witness scan per candidate).
    let azimuth = atan2_any(d[1], d[0]);
    // The angles' gradients (the azimuth's has no z term) carried through the covariance:
    // `s = σ² + g C gᵀ`, symmetric, so three entries.
    let c = covariance;
    let inv_rho2 = 1.0 / rho2;
    let g0 = [-d[1] * inv_rho2, d[0] * inv_rho2];
    let s00 = scan.sigma[0].powi(2)
        + g0[0] * (c[0][0] * g0[0] + c[0][1] * g0[1])
        + g0[1] * (c[1][0] * g0[0] + c[1][1] * g0[1]);
    let mut window = scan.angles.window(azimuth, (gate * s00).sqrt());
    if space == Space::Planar {
        return window.next().is_some();
    }
    let rho = rho2.sqrt();
    let k = 1.0 / (r2 * rho);
    let g1 = [-d[0] * d[2] * k, -d[1] * d[2] * k, rho2 * k];
    let cg1: [f64; 3] =
        std::array::from_fn(|i| c[i][0] * g1[0] + c[i][1] * g1[1] + c[i][2] * g1[2]);
    let s01 = g0[0] * cg1[0] + g0[1] * cg1[1];
    let s11 = scan.sigma[1].powi(2) + g1[0] * cg1[0] + g1[1] * cg1[1] + g1[2] * cg1[2];
    let det = s00 * s11 - s01 * s01;
    if !(det.is_finite() && det > 0.0) {
        return true;
    }
    // A scan without a row in the azimuth window cannot see the candidate: the elevation's
    // arctangent is then not taken.
    let Some(first) = window.next() else {
        return false;
    };
    let elevation = atan2(d[2], rho);
    let half = (gate * s11).sqrt();
    std::iter::once(first)
        .chain(window)
        .filter(|angles| in_elevation(angles, elevation, half))
        .any(|angles| {
            let e = [wrap(angles[0] - azimuth), angles[1] - elevation];
            let q = (s11 * e[0] * e[0] - 2.0 * s01 * e[0] * e[1] + s00 * e[1] * e[1]) / det;
            q <= gate
        })
}
