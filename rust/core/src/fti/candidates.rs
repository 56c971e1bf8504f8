//! Candidate targets (METHODS §1 eq. 20–22): one measurement from each of a-first, b-first,
//! a-last, b-last of a sensor pair (a, b), fitted by Gauss-Newton ML.
//!
//! The product of the four scans is never materialised. The first-scan rays of a and b are
//! paired and the pair-level rules applied; likewise the last-scan rays; then surviving
//! first-pairs × last-pairs are combined under the v_max rule (module `combine`: a grid over
//! the meetings, parallel tests, a cap on the work) and fitted in large batches (module `batch`: in parallel,
//! collected in order). The pruning rules, each optional:
//!
//! * **ray gate** (3-D only; `ray_gate` in σ): the two rays' closest-point distance must be
//!   ≤ `ray_gate·√((σ_a·r_a)² + (σ_b·r_b)²) + v_max·|t_a − t_b|`. The first term is the
//!   lateral spread of each ray at its range r from angle noise, with σ_j = max(σβ_j, σε_j)
//!   (conservative: never rejects more than the larger angle's noise allows). The second is
//!   how far the target moves between asynchronous samples: without it the gate would reject
//!   the true rays of any moving target seen at different times. When the two times differ
//!   and `v_max` is off the motion is unbounded and the gate passes the pair (the rule is
//!   vacuous there). In 2-D two bearing lines always meet, so the rule does not exist.
//! * **behind-sensor**: the meeting point must be in front of both sensors (positive ranges).
//! * **v_max**: the speed implied by the first and last meeting midpoints (each at the mean
//!   time of its two rays) must be ≤ `v_max`. Give a margin: midpoints carry noise. The
//!   `v_max` count also applies the motion-corrected ray gate (module `motion_gate`).
//! * **χ² gate** (3-D only): after the fit, λ ≤ `chi2_gate` (default χ²(2) 99.9 % = 13.8155:
//!   8 equations, 6 unknowns). In 2-D the 4 bearings give 4 equations for 4 unknowns: the fit
//!   is exact (λ = 0 up to rounding) and the gate has no information, so it is skipped.
//!
//! A ray pair without a unique meeting (parallel rays) fails every enabled geometric rule;
//! with the rules off its candidate starts from the pseudo-linear solution instead.

use std::time::Instant;

use super::batch::{Batch, ScanPairRays};
use super::combine;
use super::pool::Pool;
use super::scans::Scans;
use super::support::Gate;
use super::{InitiationOptions, Problem, StageCounts};
use crate::error::{reserve_one, CoreError, CoreResult};
use crate::estimation::fit::gauss_newton::{fit_into, FitSlots};
use crate::estimation::fit::{FitOptions, Termination};
use crate::geometry::los::{closest_points, direction, intersect_bearings, pseudo_linear_state};
use crate::geometry::model::{Observation, Space, MAX_DIM};
use crate::progress::{Progress, Tally};

/// Candidate fits stop once the Gauss-Newton step is shorter than this many standard
/// deviations (Mahalanobis). The remaining χ² decrease is then of order its square (0.01),
/// nothing next to the χ² gate, and the descent refines the estimate anyway; stopping there
/// instead of at 1e-6 σ halves the fitting time (clutter 4-tuples have large residuals and
/// Gauss-Newton converges only linearly on them).
const CANDIDATE_STEP_SIGMAS: f64 = 0.1;

/// A fitted candidate: its rows (a-first, b-first, a-last, b-last), X0, the fit's standard
/// deviations and the lower Cholesky factor of its covariance (the descent's scalings).
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub rows: [usize; 4],
    pub estimate: [f64; MAX_DIM],
    pub scale: [f64; MAX_DIM],
    /// Row-major `L` with `L·Lᵀ` = covariance (zero past `dim`).
    pub factor: [[f64; MAX_DIM]; MAX_DIM],
    pub chi2: f64,
    /// The tracking gate's score (module `tracking_gate`); `None` when the support gate is
    /// off.
    pub support_score: Option<f64>,
}

/// Where two rays (lines in 2-D) meet: midpoint of the closest points, the mean time of the
/// two samples, ranges along each ray and the closest-point distance (0 in 2-D).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Meeting {
    pub(super) point: [f64; 3],
    pub(super) time: f64,
    pub(super) range_a: f64,
    pub(super) range_b: f64,
    distance: f64,
}

/// Two rows of one scan pair, as the model sees them, and their meeting (`None` for
/// parallel rays). The observations are built once here: each costs a sine and a cosine per
/// angle, and every candidate and motion-gate test of the pair reads them.
#[derive(Clone, Copy, Debug)]
pub(super) struct RayPair {
    pub(super) rows: [usize; 2],
    pub(super) observations: [Observation; 2],
    pub(super) meeting: Option<Meeting>,
}

impl RayPair {
    pub(super) fn of(problem: &Problem<'_>, ra: usize, rb: usize) -> Self {
        let observations = [problem.observation(ra), problem.observation(rb)];
        Self {
            rows: [ra, rb],
            meeting: meet(problem.layout.space, &observations),
            observations,
        }
    }
}

/// The candidates that survive every enabled rule, with stage counts and timings.
#[derive(Clone, Debug, Default)]
pub struct CandidateSet {
    pub candidates: Pool,
    pub counts: StageCounts,
    pub seconds_enumerate: f64,
    pub seconds_fit: f64,
    pub seconds_support: f64,
}

/// Generates, prunes and fits the candidates of every scan quadruple `[a-first, b-first,
/// a-last, b-last]` of `slots` (see [`Scans::scan_slots`]), in order, from the rows that are
/// `available` (every row when `None`), keeping those the support `gate` keeps (all when
/// `None`).
pub fn generate(
    problem: &Problem<'_>,
    scans: &Scans,
    slots: &[[usize; 4]],
    available: Option<&[bool]>,
    options: &InitiationOptions,
    gate: Option<&Gate<'_>>,
) -> CoreResult<CandidateSet> {
    // One batch across the slots (module `batch`).
    let batch = Batch::new(problem, options, gate);
    generate_in(problem, scans, slots, available, options, batch)
}

/// [`generate`], fitting in `batch` (whose limits the tests shrink).
pub(super) fn generate_in(
    problem: &Problem<'_>,
    scans: &Scans,
    slots: &[[usize; 4]],
    available: Option<&[bool]>,
    options: &InitiationOptions,
    mut batch: Batch<'_>,
) -> CoreResult<CandidateSet> {
    let start = Instant::now();
    let mut set = CandidateSet {
        // Compact past one stage when the gate scores them (module `pool`).
        candidates: Pool::new(options.search_stage().filter(|_| batch.gated())),
        ..CandidateSet::default()
    };
    let rows_of = |k: usize| -> Vec<usize> {
        let rows = scans.scan(k).iter().copied();
        rows.filter(|&m| available.is_none_or(|a| a[m])).collect()
    };
    let tally = Tally::new(problem.progress, "candidates", slots.len() as u64);
    for (index, &slot) in slots.iter().enumerate() {
        let [sa1, sb1, sa2, sb2] = slot.map(rows_of);
        let raw = [sa1.len(), sb1.len(), sa2.len(), sb2.len()]
            .iter()
            .fold(1usize, |p, &n| p.saturating_mul(n));
        set.counts.raw = set.counts.raw.saturating_add(raw);
        let (firsts, f_ray) = ray_pairs(problem, &sa1, &sb1, options)?;
        let (lasts, l_ray) = ray_pairs(problem, &sa2, &sb2, options)?;
        set.counts.ray_gate = set
            .counts
            .ray_gate
            .saturating_add(f_ray.saturating_mul(l_ray));
        set.counts.behind = set
            .counts
            .behind
            .saturating_add(firsts.len().saturating_mul(lasts.len()));
        // The combination reports how far through this slot it is; the tally makes that a
        // fraction of the whole stage.
        let within = tally.unit(index as u64);
        let slot_problem = Problem {
            progress: &within,
            ..*problem
        };
        let rays = ScanPairRays {
            firsts: firsts.into(),
            lasts: lasts.into(),
        };
        combine::combine(&slot_problem, &rays, options, &mut batch, &mut set)?;
        within.report("candidates", 1.0);
    }
    if !problem.stopped() {
        batch.flush(&mut set)?;
    }
    set.seconds_enumerate = start.elapsed().as_secs_f64() - set.seconds_fit - set.seconds_support;
    Ok(set)
}

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
    for &ra in rows_a {
        for &rb in rows_b {
            let pair = RayPair::of(problem, ra, rb);
            if !ray_gate_passes(problem, &pair, options) {
                continue;
            }
            passed_ray += 1;
            if options.reject_behind()
                && !pair
                    .meeting
                    .is_some_and(|m| m.range_a > 0.0 && m.range_b > 0.0)
            {
                continue;
            }
            if out.len() == options.max_candidates() {
                return Err(CoreError::CapExceeded {
                    what: "ray pairs of one scan pair",
                    count: out.len() + 1,
                    cap: options.max_candidates(),
                    hint: "tighten ray_gate, enable reject_behind, or raise max_candidates",
                });
            }
            reserve_one(&mut out, "ray pairs of one scan pair", OOM_HINT)?;
            out.push(pair);
        }
    }
    Ok((out, passed_ray))
}

/// Meeting of the lines of sight of two observations (of different sensors).
fn meet(space: Space, [oa, ob]: &[Observation; 2]) -> Option<Meeting> {
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
            let ua = direction(oa.angles[0], oa.angles[1]);
            let ub = direction(ob.angles[0], ob.angles[1]);
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

fn ray_gate_passes(problem: &Problem<'_>, pair: &RayPair, options: &InitiationOptions) -> bool {
    let Some(gate) = options.ray_gate() else {
        return true;
    };
    if problem.layout.space == Space::Planar {
        return true; // lines in the plane always meet: the rule is vacuous
    }
    let [oa, ob] = &pair.observations;
    let motion = match options.v_max() {
        Some(v) => v * (oa.time - ob.time).abs(),
        None if oa.time != ob.time => return true, // unbounded motion between the samples
        None => 0.0,
    };
    let Some(m) = pair.meeting else {
        return false;
    };
    let (sa, sb) = (oa.sigma[0].max(oa.sigma[1]), ob.sigma[0].max(ob.sigma[1]));
    let noise = ((sa * m.range_a).powi(2) + (sb * m.range_b).powi(2)).sqrt();
    m.distance <= gate * noise + motion
}

/// What to do when the candidates outgrow memory (max_candidates bounds them only by count).
pub(super) const OOM_HINT: &str =
    "lower max_candidates, set v_max, tighten ray_gate_sigmas or enable reject_behind";

/// Gauss-Newton fit of the 4 measurements from the triangulated start; `None` when the fit
/// is singular or non-finite.
pub(super) fn fit_candidate(
    problem: &Problem<'_>,
    first: &RayPair,
    last: &RayPair,
) -> Option<Candidate> {
    let rows = [first.rows[0], first.rows[1], last.rows[0], last.rows[1]];
    let [f, l] = [&first.observations, &last.observations];
    let obs: [Observation; 4] = [f[0], f[1], l[0], l[1]];
    let initial = match (first.meeting, last.meeting) {
        (Some(f), Some(l)) => start_from_meetings(problem, &f, &l),
        _ => pseudo_linear_state(&problem.layout, &obs)?,
    };
    let d = problem.layout.dim();
    let options = FitOptions::default()
        .with_step_sigmas(CANDIDATE_STEP_SIGMAS)
        .unwrap_or_default();
    // Stack slots: no allocation per fit.
    let (mut estimate, mut covariance) = ([0.0; MAX_DIM], [0.0; MAX_DIM * MAX_DIM]);
    let slots = FitSlots {
        estimate: &mut estimate[..d],
        covariance: &mut covariance[..d * d],
    };
    let summary = fit_into(&problem.layout, &obs, &initial[..d], &options, slots);
    if matches!(
        summary.termination,
        Termination::Singular | Termination::NonFinite
    ) || estimate[..d].iter().any(|v| !v.is_finite())
    {
        return None;
    }
    Some(Candidate {
        rows,
        estimate,
        scale: std::array::from_fn(|k| {
            if k < d {
                covariance[k * d + k].sqrt()
            } else {
                0.0
            }
        }),
        factor: cholesky(&covariance[..d * d], d)?,
        chi2: summary.chi2,
        support_score: None,
    })
}

/// Lower Cholesky factor of the row-major `d × d` matrix `a`, or `None` unless it is finite
/// and positive definite.
fn cholesky(a: &[f64], d: usize) -> Option<[[f64; MAX_DIM]; MAX_DIM]> {
    if a.len() < d * d {
        return None;
    }
    let mut l = [[0.0; MAX_DIM]; MAX_DIM];
    for i in 0..d {
        for j in 0..=i {
            let s = a[i * d + j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    l.iter().flatten().all(|v| v.is_finite()).then_some(l)
}

/// X0 at t0 from the first and last meeting points: velocity = difference / time.
pub(super) fn start_from_meetings(
    problem: &Problem<'_>,
    first: &Meeting,
    last: &Meeting,
) -> [f64; MAX_DIM] {
    let p = problem.layout.space.position_dim();
    let t0 = problem.t0;
    let mut x = [0.0; MAX_DIM];
    for k in 0..p {
        let v = (last.point[k] - first.point[k]) / (last.time - first.time);
        x[k] = first.point[k] + (t0 - first.time) * v;
        x[p + k] = v;
    }
    x
}
