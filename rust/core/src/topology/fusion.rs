//! The fused decision (the project's extension of METHODS §4; docs/methods.md §4): topology,
//! then bias, then distance.
//!
//! 1. *Registration.* Each two topology pairs of the scan (those with the highest closeness
//!    first, at most [`MAX_HYPOTHESIS_PAIRS`] of them) whose separations agree within their
//!    noise (a rigid move keeps distances) propose a rigid transform of the system picture
//!    onto the local one; the previous scans' estimate, when reliable, is one more proposal,
//!    and so is no bias at all (the identity).
//!    Proposals turning the pictures by more than twice the bias bound, or moving them apart
//!    by more than the bias can, are dropped. A proposal's *consensus* is
//!    the best one-to-one pairing of the scan's gated candidates under it, a pair worth
//!    `½(g − m) + κ(w − λ)` (at least 0), `m` the registered Mahalanobis distance, `g` its
//!    gate, `w` the window-averaged closeness as a fraction of M·N, `λ` the topology
//!    threshold. The [`TOP_PROPOSALS`] best of this scan, and the previous estimate, are then
//!    judged over time: their consensus on each of the last
//!    [`RECENT_SCANS`](super::memory::RECENT_SCANS) − 1 pictures is
//!    added (distance alone, `½(g − m)`, one-to-one per scan). A coincidence of one scan (a
//!    formation matched one slot off, tracks of targets only one radar sees lining up) does
//!    not last, and an early wrong registration yields as soon as the pictures share more.
//!    With no proposal (fewer than two topology pairs that agree) and no estimate yet, no pair
//!    is confirmed and none is made: pictures sharing no target are left unpaired.
//! 2. *Decision.* Under the best proposal, a pair needs `m ≤ g`, `m = dᵀS⁻¹d`,
//!    `d = p_i − T(q_j)`, `S = P_i + R P_j Rᵀ + S_T(q_j)`, `S_T` the estimate's own
//!    uncertainty at `q_j` (rotation std times the lever from its centroid, plus the
//!    centroid's); among the gated pairs the one-to-one pairing with the most pairs, then the
//!    largest `Σ (κ·w − m/2)`.
//! 3. *Refit and repeat.* The decided pairs, with every earlier scan of the pairs still
//!    believed (`memory.rs`), give a new trimmed estimate; with it the decision is made
//!    again, until the pairs stop changing (at most [`MAX_ROUNDS`] rounds).
//!
//! Without covariances on both sides, `P_i + R P_j Rᵀ` is the latest estimate's residual
//! variance (the pictures' relative noise once registered, trimmed of wrong pairs), so the
//! fused decision starts from the second scan, once the topology pairs have given one.

use super::bias::BiasEstimate;
use super::candidates::Candidates;
use super::decision::decide;
use super::memory::{Entry, PairMemory, Picture};
use super::options::{Decision, DecisionOptions};
use super::scan::ScanTracks;
use crate::error::CoreResult;

/// Topology pairs at most that propose transforms: the best `K` by closeness give
/// `K(K − 1)/2` proposals.
pub const MAX_HYPOTHESIS_PAIRS: usize = 32;

/// Proposals of the scan judged over the recent pictures too (besides the prior).
pub const TOP_PROPOSALS: usize = 4;

/// Pairs a proposal needs in this scan's consensus (its own two count) to be used without a
/// reliable prior.
pub const MIN_SUPPORT: usize = 2;

/// Decision rounds at most in one scan.
pub const MAX_ROUNDS: usize = 5;

/// An estimate is reliable when its rotation's (honest) standard deviation is at most this
/// (radians: 1°), it rests on at least [`MIN_CLUSTERS`](super::bias::MIN_CLUSTERS) track pairs and it is within the
/// bias bound (3 standard deviations allowed).
pub const RELIABLE_ROTATION_STD: f64 = std::f64::consts::PI / 180.0;

/// A rigid transform of system positions onto local ones, `T(q) = R(θ)(q − q̄) + p̄`, with the
/// standard deviations of θ and of `p̄` (per axis). A proposal of two pairs is judged as
/// exact (its consensus, and the first decision under it): its uncertainty would widen its
/// own gates and let it collect pairs by chance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    rotation: f64,
    centre: [f64; 2],
    image: [f64; 2],
    rotation_std: f64,
    centre_std: f64,
    /// Fitted to the believed pairs (its uncertainty widens the decision's gate), or proposed
    /// by two pairs.
    estimated: bool,
}

impl Transform {
    pub fn from_estimate(e: &BiasEstimate) -> Self {
        Self {
            rotation: e.rotation,
            centre: e.centre,
            image: e.apply(e.centre),
            rotation_std: e.rotation_std,
            centre_std: e.centre_std,
            estimated: true,
        }
    }

    /// No rotation, no offset.
    fn identity() -> Self {
        Self {
            rotation: 0.0,
            centre: [0.0, 0.0],
            image: [0.0, 0.0],
            rotation_std: 0.0,
            centre_std: 0.0,
            estimated: false,
        }
    }

    /// The rotation taking `q2 − q1` to `p2 − p1`, about the pairs' midpoints.
    fn from_pairs(p1: [f64; 2], q1: [f64; 2], p2: [f64; 2], q2: [f64; 2]) -> Option<Self> {
        let dq = [q2[0] - q1[0], q2[1] - q1[1]];
        let dp = [p2[0] - p1[0], p2[1] - p1[1]];
        let length2 = dq[0] * dq[0] + dq[1] * dq[1];
        if length2.is_nan() || length2 <= 0.0 {
            return None;
        }
        Some(Self {
            rotation: (dq[0] * dp[1] - dq[1] * dp[0]).atan2(dq[0] * dp[0] + dq[1] * dp[1]),
            centre: [(q1[0] + q2[0]) / 2.0, (q1[1] + q2[1]) / 2.0],
            image: [(p1[0] + p2[0]) / 2.0, (p1[1] + p2[1]) / 2.0],
            rotation_std: 0.0,
            centre_std: 0.0,
            estimated: false,
        })
    }

    fn turned(&self, q: [f64; 2]) -> [f64; 2] {
        let (c, s) = (self.rotation.cos(), self.rotation.sin());
        let (x, y) = (q[0] - self.centre[0], q[1] - self.centre[1]);
        [c * x - s * y, s * x + c * y]
    }

    pub fn apply(&self, q: [f64; 2]) -> [f64; 2] {
        let t = self.turned(q);
        [t[0] + self.image[0], t[1] + self.image[1]]
    }

    /// `T⁻¹(p)`: distances are kept, so a query about `T⁻¹(p)` among system positions is one
    /// about `p` among their images.
    fn invert(&self, p: [f64; 2]) -> [f64; 2] {
        let (c, s) = (self.rotation.cos(), self.rotation.sin());
        let (x, y) = (p[0] - self.image[0], p[1] - self.image[1]);
        [
            c * x + s * y + self.centre[0],
            -s * x + c * y + self.centre[1],
        ]
    }

    /// The covariance `[xx, xy, yy]` of `apply(q)` from the transform's own uncertainty (none
    /// for a proposal).
    fn spread(&self, q: [f64; 2]) -> [f64; 3] {
        if !self.estimated {
            return [0.0; 3];
        }
        let t = self.turned(q);
        let v = [-t[1], t[0]];
        let (a, c) = (self.rotation_std.powi(2), self.centre_std.powi(2));
        [a * v[0] * v[0] + c, a * v[0] * v[1], a * v[1] * v[1] + c]
    }

    /// Whether the transform is within what the bias bound allows: the rotation within
    /// `max_rotation`, the image of its centroid within `max_offset` of it (each with
    /// `sigmas` of its standard deviations).
    fn within(&self, options: &DecisionOptions, sigmas: f64) -> bool {
        let offset = (self.image[0] - self.centre[0]).hypot(self.image[1] - self.centre[1]);
        self.rotation.abs() <= options.max_rotation() + sigmas * self.rotation_std
            && offset <= options.max_offset() + sigmas * self.centre_std
    }
}

/// Whether an estimate can be used (and is reported reliable): enough track pairs, a small
/// honest spread, within the bias bound.
pub fn reliable(e: &BiasEstimate, options: &DecisionOptions) -> bool {
    e.reliable
        && e.rotation_std <= RELIABLE_ROTATION_STD
        && Transform::from_estimate(e).within(options, 3.0)
}

/// The relative noise `P_i + R P_j Rᵀ` of a pair `[xx, xy, yy]`, from the two tracks'
/// covariances, or `isotropic` (a variance per axis) where either has none.
fn pair_noise(a: &Entry, b: &Entry, rotation: f64, isotropic: Option<f64>) -> Option<[f64; 3]> {
    match (a.covariance, b.covariance) {
        (Some(a), Some(b)) => {
            let (c, s) = (rotation.cos(), rotation.sin());
            // R B Rᵀ for B = [[b0, b1], [b1, b2]].
            let rb = [
                c * c * b[0] - 2.0 * c * s * b[1] + s * s * b[2],
                c * s * (b[0] - b[2]) + (c * c - s * s) * b[1],
                s * s * b[0] + 2.0 * c * s * b[1] + c * c * b[2],
            ];
            Some([a[0] + rb[0], a[1] + rb[1], a[2] + rb[2]])
        }
        _ => isotropic.map(|v| [v, 0.0, v]),
    }
}

/// `dᵀ S⁻¹ d` of a 2 × 2 `S = [xx, xy, yy]`; ∞ unless S is positive definite.
fn mahalanobis(d: [f64; 2], s: [f64; 3]) -> f64 {
    let det = s[0] * s[2] - s[1] * s[1];
    if !(det > 0.0 && s[0] > 0.0) {
        return f64::INFINITY;
    }
    (s[2] * d[0] * d[0] - 2.0 * s[1] * d[0] * d[1] + s[0] * d[1] * d[1]) / det
}

/// `mahalanobis` of `p` against `T(q)`, S the pair's noise plus the transform's spread.
fn registered(t: &Transform, a: &Entry, b: &Entry, isotropic: Option<f64>) -> f64 {
    let Some(base) = pair_noise(a, b, t.rotation, isotropic) else {
        return f64::INFINITY;
    };
    let image = t.apply(b.position);
    let extra = t.spread(b.position);
    mahalanobis(
        [a.position[0] - image[0], a.position[1] - image[1]],
        [base[0] + extra[0], base[1] + extra[1], base[2] + extra[2]],
    )
}

/// What the fused decision reads of one scan besides the options.
pub struct Scan<'a> {
    pub local: &'a ScanTracks<'a>,
    pub system: &'a ScanTracks<'a>,
    /// The candidate pairs (the position gate's).
    pub pairs: &'a Candidates,
    /// Each candidate's window-averaged closeness as a fraction of M·N.
    pub closeness: &'a [f64],
    /// The topology decision (rows), and λ as a fraction of M·N.
    pub topology: &'a [(usize, usize)],
    pub lambda: f64,
}

/// The scan as entries, with the noise model.
struct Prepared<'a> {
    scan: &'a Scan<'a>,
    local: Vec<Entry>,
    system: Vec<Entry>,
    /// The variance per axis standing in for missing covariances.
    isotropic: Option<f64>,
}

impl Prepared<'_> {
    /// Whether pair noise is known: covariances on both sides, or an isotropic stand-in.
    fn has_noise(&self) -> bool {
        let covariances = self
            .local
            .iter()
            .chain(&self.system)
            .all(|e| e.covariance.is_some());
        covariances || self.isotropic.is_some()
    }

    fn distances(&self, t: &Transform) -> Vec<f64> {
        (0..self.scan.pairs.len())
            .map(|k| {
                let (i, j) = self.scan.pairs.pair(k);
                registered(t, &self.local[i], &self.system[j], self.isotropic)
            })
            .collect()
    }
}

/// The fused decision of one scan (module docs): pairs as (local row, system row), ascending.
/// `latest` is the previous scans' estimate: a proposal when reliable, and, without
/// covariances, the noise scale (its residuals') even when not.
pub fn fused_pairs(
    scan: &Scan<'_>,
    memory: &PairMemory,
    latest: Option<&BiasEstimate>,
    options: &DecisionOptions,
) -> CoreResult<Vec<(usize, usize)>> {
    let (local, system) = (scan.local, scan.system);
    if local.is_empty() || system.is_empty() {
        return Ok(Vec::new());
    }
    let isotropic = |e: Option<&BiasEstimate>| {
        e.map(|e| e.residual_std.powi(2))
            .filter(|v| *v > 0.0 && v.is_finite())
    };
    let mut prepared = Prepared {
        scan,
        local: Entry::all(local),
        system: Entry::all(system),
        isotropic: isotropic(latest),
    };
    if !prepared.has_noise() {
        return Ok(scan.topology.to_vec());
    }
    let prior = latest
        .filter(|e| reliable(e, options))
        .map(Transform::from_estimate);
    // No registration (fewer than two topology pairs that agree, and no estimate yet): no
    // pair is confirmed, so none is made.
    let Some(mut transform) = register(&prepared, memory, prior, options)? else {
        return Ok(Vec::new());
    };
    let mut chosen: Vec<(usize, usize)> = Vec::new();
    for round in 0..MAX_ROUNDS {
        let next = decide_under(&prepared, &transform, options)?;
        if round > 0 && next == chosen {
            break;
        }
        chosen = next;
        let believed = memory.believed_with(local, system, &chosen);
        match memory.fit(&believed, None) {
            Some(e) if reliable(&e, options) => {
                transform = Transform::from_estimate(&e);
                prepared.isotropic = isotropic(Some(&e)).or(prepared.isotropic);
            }
            _ => break,
        }
    }
    Ok(chosen)
}

/// The best proposal (module docs, step 1), or None when there is no prior and no proposal
/// has the support of at least [`MIN_SUPPORT`] pairs in this scan.
fn register(
    prepared: &Prepared<'_>,
    memory: &PairMemory,
    prior: Option<Transform>,
    options: &DecisionOptions,
) -> CoreResult<Option<Transform>> {
    let scan = prepared.scan;
    let (gate, kappa) = (options.fused_gate(), options.topology_weight());
    // The topology pairs with the highest closeness propose (ties: in row order).
    let mut proposers: Vec<(usize, usize, f64)> = scan
        .topology
        .iter()
        .map(|&(i, j)| (i, j, scan.closeness[scan.pairs.index_of(i, j)]))
        .collect();
    proposers.sort_by(|a, b| b.2.total_cmp(&a.2));
    proposers.truncate(MAX_HYPOTHESIS_PAIRS);
    // No bias at all is a proposal too: with few shared targets, where topology pairs are
    // scarce, it lets pictures of well-aligned sensors register from the first scan.
    let mut proposals: Vec<Transform> = vec![Transform::identity()];
    for (u, &(i1, j1, _)) in proposers.iter().enumerate() {
        for &(i2, j2, _) in &proposers[u + 1..] {
            let (a1, b1) = (&prepared.local[i1], &prepared.system[j1]);
            let (a2, b2) = (&prepared.local[i2], &prepared.system[j2]);
            // A rigid move keeps distances: two pairs whose separations differ by more than
            // their noise allows cannot both be right.
            let spread = [(a1, b1), (a2, b2)]
                .iter()
                .filter_map(|(a, b)| pair_noise(a, b, 0.0, prepared.isotropic))
                .map(|s| (s[0] + s[2]) / 2.0)
                .sum::<f64>();
            let length = |x: [f64; 2], y: [f64; 2]| (x[0] - y[0]).hypot(x[1] - y[1]);
            let mismatch = length(a1.position, a2.position) - length(b1.position, b2.position);
            if mismatch.abs() > 3.0 * spread.sqrt() {
                continue;
            }
            let t = Transform::from_pairs(a1.position, b1.position, a2.position, b2.position);
            if let Some(t) = t.filter(|t| t.within(options, 0.0)) {
                proposals.push(t);
            }
        }
    }
    // This scan's consensus of every proposal, then the best few over time.
    let mut judged: Vec<(f64, usize, Transform)> = Vec::with_capacity(proposals.len());
    for t in proposals {
        let (value, support) = consensus_now(prepared, &t, gate, kappa)?;
        judged.push((value, support, t));
    }
    judged.sort_by(|a, b| b.0.total_cmp(&a.0));
    judged.truncate(TOP_PROPOSALS);
    if let Some(p) = prior {
        let (value, support) = consensus_now(prepared, &p, gate, kappa)?;
        judged.push((value, support, p));
    }
    let mut best: Option<(f64, usize, Transform)> = None;
    for (now, support, t) in judged {
        if prior != Some(t) && support < MIN_SUPPORT {
            continue;
        }
        let mut value = now;
        for picture in memory.earlier() {
            value += consensus_then(picture, &t, gate, prepared.isotropic)?;
        }
        if best.as_ref().is_none_or(|(v, _, _)| value > *v) {
            best = Some((value, support, t));
        }
    }
    Ok(best.map(|(_, _, t)| t))
}

/// A proposal's consensus on this scan, and how many pairs make it.
fn consensus_now(
    prepared: &Prepared<'_>,
    t: &Transform,
    gate: f64,
    kappa: f64,
) -> CoreResult<(f64, usize)> {
    let scan = prepared.scan;
    let worth: Vec<f64> = prepared
        .distances(t)
        .iter()
        .zip(scan.closeness)
        .map(|(&m, &w)| {
            if m <= gate {
                (0.5 * (gate - m) + kappa * (w - scan.lambda)).max(0.0)
            } else {
                0.0
            }
        })
        .collect();
    let dims = (scan.local.len(), scan.system.len());
    let matched = decide(scan.pairs, &worth, dims, 0.0, Decision::Assignment)?;
    let value = matched
        .iter()
        .map(|&(i, j)| worth[scan.pairs.index_of(i, j)])
        .sum();
    Ok((value, matched.len()))
}

/// A proposal's consensus on an earlier picture: the best one-to-one pairing, each gated pair
/// worth `½(g − m)`.
fn consensus_then(
    picture: &Picture,
    t: &Transform,
    gate: f64,
    isotropic: Option<f64>,
) -> CoreResult<f64> {
    let widest = |entries: &[Entry]| {
        entries
            .iter()
            .map(|e| {
                e.covariance
                    .map_or(isotropic.unwrap_or(0.0), |c| c[0] + c[2])
            })
            .fold(0.0_f64, f64::max)
    };
    let reach = (gate * (widest(&picture.local) + widest(&picture.system))).sqrt();
    let mut listed = Vec::new();
    let mut worth = Vec::new();
    let mut near = Vec::new();
    for (i, a) in picture.local.iter().enumerate() {
        near.clear();
        near.extend(
            picture
                .tree
                .locate_within_distance(t.invert(a.position), reach * reach)
                .map(|q| q.data),
        );
        near.sort_unstable();
        for &j in &near {
            let m = registered(t, a, &picture.system[j as usize], isotropic);
            if m <= gate {
                listed.push((i as u32, j));
                worth.push(0.5 * (gate - m));
            }
        }
    }
    if listed.is_empty() {
        return Ok(0.0);
    }
    let pairs = Candidates::Listed(listed);
    let dims = (picture.local.len(), picture.system.len());
    let matched = decide(&pairs, &worth, dims, 0.0, Decision::Assignment)?;
    Ok(matched
        .iter()
        .map(|&(i, j)| worth[pairs.index_of(i, j)])
        .sum())
}

/// The decision under one transform (module docs, step 2), ascending by local row.
fn decide_under(
    prepared: &Prepared<'_>,
    t: &Transform,
    options: &DecisionOptions,
) -> CoreResult<Vec<(usize, usize)>> {
    let scan = prepared.scan;
    let (gate, kappa) = (options.fused_gate(), options.topology_weight());
    let score: Vec<f64> = prepared
        .distances(t)
        .iter()
        .zip(scan.closeness)
        .map(|(&m, &w)| {
            if m <= gate {
                kappa * w - 0.5 * m
            } else {
                f64::NEG_INFINITY
            }
        })
        .collect();
    // Every gated pair is worth more than any sum of scores: the most pairs, then the best.
    let lift = 1.0
        + 2.0
            * score
                .iter()
                .filter(|s| s.is_finite())
                .map(|s| s.abs())
                .sum::<f64>();
    let lifted: Vec<f64> = score.iter().map(|&s| s + lift).collect();
    let dims = (scan.local.len(), scan.system.len());
    decide(scan.pairs, &lifted, dims, 0.0, Decision::Assignment)
}
