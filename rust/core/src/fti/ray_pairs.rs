//! Ray pairs (METHODS §1 eq. 20–22): one row of each of two scans of a sensor pair, where
//! their lines of sight meet, and the pair-level pruning rules, the ray gate and the
//! behind-sensor rule (module `candidates` describes every rule). A candidate is a first-scan
//! and a last-scan ray pair (module `candidate`).

use rayon::prelude::*;

use super::options::{InitiationOptions, OOM_HINT};
use super::problem::Problem;
use crate::error::{reserve, CoreError, CoreResult};
use crate::geometry::los::{closest_points, intersect_bearings};
use crate::geometry::model::{Observation, Space};

/// Where two rays (lines in 2-D) meet: midpoint of the closest points, the mean time of the
/// two samples, ranges along each ray and the closest-point distance (0 in 2-D).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Meeting {
    pub(super) point: [f64; 3],
    pub(super) time: f64,
    pub(super) range_a: f64,
    pub(super) range_b: f64,
    pub(super) distance: f64,
}

impl Meeting {
    /// Whether the meeting lies in front of both sensors (the behind-sensor rule's test).
    pub(super) fn in_front(&self) -> bool {
        self.range_a > 0.0 && self.range_b > 0.0
    }
}

/// Two rows of one scan pair, as the model sees them, and their meeting (`None` for
/// parallel rays). The observations are built once here: each costs a sine and a cosine per
/// angle, and every candidate and motion-gate test of the pair reads them.
#[derive(Clone, Copy, Debug)]
pub(super) struct RayPair {
    pub(super) rows: [usize; 2],
    pub(super) observations: [Observation; 2],
    pub(super) meeting: Option<Meeting>,
    /// In 3-D, the unit normal `n = (u_a × u_b)/|u_a × u_b|` of the two lines of sight and
    /// `(s_a − s_b)·n`: the distance between the lines once sensor b moves by `δ` is
    /// `|(s_a − s_b)·n − δ·n|` (module `motion_gate`). `None` in 2-D and for parallel rays.
    pub(super) normal: Option<([f64; 3], f64)>,
}

impl RayPair {
    pub(super) fn of(problem: &Problem<'_>, ra: usize, rb: usize) -> Self {
        let observations = [problem.observation(ra), problem.observation(rb)];
        Self::from_observations(problem.layout.space, [ra, rb], observations)
    }

    /// The pair of rows `rows` whose observations are already built.
    fn from_observations(space: Space, rows: [usize; 2], observations: [Observation; 2]) -> Self {
        let meeting = meet(space, &observations[0], &observations[1]);
        Self::with_meeting(space, rows, observations, meeting)
    }

    /// [`Self::from_observations`] with the meeting already found.
    fn with_meeting(
        space: Space,
        rows: [usize; 2],
        observations: [Observation; 2],
        meeting: Option<Meeting>,
    ) -> Self {
        Self {
            rows,
            meeting,
            normal: normal(space, &observations),
            observations,
        }
    }
}

/// [`RayPair::normal`]: `None` in 2-D and where the lines are parallel by
/// [`closest_points`]' test (`1 − (u_a·u_b)² ≤ 1e-14`).
fn normal(space: Space, [oa, ob]: &[Observation; 2]) -> Option<([f64; 3], f64)> {
    if space == Space::Planar {
        return None;
    }
    let (ua, ub) = (oa.line_of_sight(), ob.line_of_sight());
    let b = ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2];
    let denom = 1.0 - b * b;
    if denom <= 1e-14 {
        return None;
    }
    let scale = 1.0 / denom.sqrt();
    let n = [
        (ua[1] * ub[2] - ua[2] * ub[1]) * scale,
        (ua[2] * ub[0] - ua[0] * ub[2]) * scale,
        (ua[0] * ub[1] - ua[1] * ub[0]) * scale,
    ];
    let offset = (0..3).map(|k| (oa.sensor[k] - ob.sensor[k]) * n[k]).sum();
    Some((n, offset))
}

/// Meeting of the lines of sight of two observations (of different sensors).
pub(super) fn meet(space: Space, oa: &Observation, ob: &Observation) -> Option<Meeting> {
    let time = 0.5 * (oa.time + ob.time);
    match space {
        Space::Planar => {
            let (sa, sb) = ([oa.sensor[0], oa.sensor[1]], [ob.sensor[0], ob.sensor[1]]);
            let (p, range_a, range_b) = intersect_bearings(&sa, oa.angles[0], &sb, ob.angles[0])?;
            Some(Meeting {
                point: [p[0], p[1], 0.0],
                time,
                range_a,
                range_b,
                distance: 0.0,
            })
        }
        Space::Spatial => {
            let (ua, ub) = (oa.line_of_sight(), ob.line_of_sight());
            let m = closest_points(&oa.sensor, &ua, &ob.sensor, &ub)?;
            Some(Meeting {
                point: m.midpoint(),
                time,
                range_a: m.range_a,
                range_b: m.range_b,
                distance: m.distance,
            })
        }
    }
}

/// Rows of the first scan paired in one parallel step: enough work to share between threads,
/// few enough pairs (× the other scan's rows) held before the cap is checked.
const ROWS_PER_CHUNK: usize = 256;

/// Pairs every row of `rows_a` with every row of `rows_b` under the ray gate and the
/// behind-sensor rule; returns the survivors and how many passed the ray gate.
pub(super) fn ray_pairs(
    problem: &Problem<'_>,
    rows_a: &[usize],
    rows_b: &[usize],
    options: &InitiationOptions,
) -> CoreResult<(Vec<RayPair>, usize)> {
    let mut out = Vec::new();
    let mut passed_ray = 0usize;
    let space = problem.layout.space;
    // Each row's observation once (its sines and cosines), not once per pair.
    let observed = |rows: &[usize]| -> Vec<Observation> {
        rows.iter().map(|&m| problem.observation(m)).collect()
    };
    let (obs_a, obs_b) = (observed(rows_a), observed(rows_b));
    // The rows of a in parallel chunks, each chunk's pairs appended in order: the pairs and
    // their order are those of the double loop, and at most one chunk's pairs are held past
    // the cap before it is checked.
    let a: Vec<(usize, Observation)> = rows_a.iter().copied().zip(obs_a).collect();
    for chunk in a.chunks(ROWS_PER_CHUNK) {
        let found: Vec<(Vec<RayPair>, usize)> = chunk
            .par_iter()
            .map(|&(ra, oa)| {
                let (mut kept, mut passed) = (Vec::new(), 0usize);
                for (&rb, ob) in rows_b.iter().zip(&obs_b) {
                    // The rules read only the meeting: the pair itself (its observations
                    // copied, its normal) is built for the few that pass.
                    let meeting = meet(space, &oa, ob);
                    if !ray_gate_passes(problem, [&oa, ob], meeting.as_ref(), options) {
                        continue;
                    }
                    passed += 1;
                    let behind = options.reject_behind() && !meeting.is_some_and(|m| m.in_front());
                    if !behind {
                        kept.push(RayPair::with_meeting(space, [ra, rb], [oa, *ob], meeting));
                    }
                }
                (kept, passed)
            })
            .collect();
        // Room for the chunk's pairs at once (up to the cap, which the rows below check), so
        // that `out` grows, and moves the pairs it holds, at most once a chunk.
        let chunk_pairs: usize = found.iter().map(|(kept, _)| kept.len()).sum();
        let room = chunk_pairs.min(options.max_candidates().saturating_sub(out.len()));
        reserve(&mut out, room, "ray pairs of one scan pair", OOM_HINT)?;
        for (kept, passed) in found {
            passed_ray += passed;
            if out.len() + kept.len() > options.max_candidates() {
                return Err(CoreError::CapExceeded {
                    what: "ray pairs of one scan pair",
                    count: out.len() + kept.len(),
                    cap: options.max_candidates(),
                    hint: "tighten ray_gate_sigmas, enable reject_behind, or raise max_candidates",
                });
            }
            out.extend(kept);
        }
    }
    Ok((out, passed_ray))
}

fn ray_gate_passes(
    problem: &Problem<'_>,
    observations: [&Observation; 2],
    meeting: Option<&Meeting>,
    options: &InitiationOptions,
) -> bool {
    let (gate, v_max) = (options.ray_gate_sigmas(), options.v_max());
    ray_gate(problem.layout.space, gate, v_max, observations, meeting)
}

/// The ray gate (module `candidates`) of two observations and their `meeting`, with
/// `ray_gate_sigmas` = `gate` and `v_max`: the closest-point distance within `gate` standard
/// deviations of the crossing plus how far `v_max` moves the target between the samples.
/// Vacuous in 2-D, with no `gate`, and between samples at different times with no `v_max`;
/// parallel rays (no meeting) fail it otherwise.
pub(super) fn ray_gate(
    space: Space,
    gate: Option<f64>,
    v_max: Option<f64>,
    [oa, ob]: [&Observation; 2],
    meeting: Option<&Meeting>,
) -> bool {
    let Some(gate) = gate else {
        return true;
    };
    if space == Space::Planar {
        return true; // lines in the plane always meet: the rule is vacuous
    }
    let motion = match v_max {
        Some(v) => v * (oa.time - ob.time).abs(),
        None if oa.time != ob.time => return true, // unbounded motion between the samples
        None => 0.0,
    };
    let Some(m) = meeting else {
        return false;
    };
    let (sa, sb) = (oa.sigma[0].max(oa.sigma[1]), ob.sigma[0].max(ob.sigma[1]));
    let noise = ((sa * m.range_a).powi(2) + (sb * m.range_b).powi(2)).sqrt();
    m.distance <= gate * noise + motion
}
