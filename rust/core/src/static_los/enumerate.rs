//! Pruned enumeration of the candidate tuples (METHODS §2 "Candidates"; the gate is defined in
//! the module docs of [`super`]).
//!
//! A depth-first search over sensors 0..S: at sensor s a partial tuple branches into "missed"
//! (first) and each report of s (ascending), so leaves come out in lexicographic tuple order.
//! The top two levels — every `(i_1, i_2)` choice of sensors 0 and 1, "missed" included — are
//! independent tasks, run in parallel with rayon in fixed-size chunks of consecutive tasks and
//! concatenated in task order, so the output
//! (and every counter) is identical for any thread count without a final sort. A shared atomic
//! counter enforces `max_candidates`; the error is raised iff the total exceeds the cap.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;

use super::cost::DetectionModel;
use super::prepared::{Estimate, Prepared};
use super::window::{select, Window};
use super::{Candidates, EnumerateOptions, StageCounts};
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::evidence::AttributeGate;
use crate::geometry::model::Observation;

/// A partial tuple during the search.
#[derive(Clone, Copy, Debug)]
struct Node {
    rays: usize,
    estimate: Option<Estimate>,
    window: Option<Window>,
}

const ROOT: Node = Node {
    rays: 0,
    estimate: None,
    window: None,
};

/// Per-task scratch and output.
struct Ctx {
    tuple: Vec<u32>,
    rows: Vec<i64>,
    obs: Vec<Observation>,
    hits: Vec<u32>,
    out: Output,
}

#[derive(Default)]
struct Output {
    tuples: Vec<i64>,
    rows: Vec<i64>,
    positions: Vec<f64>,
    covariances: Vec<f64>,
    costs: Vec<f64>,
    intensity: Vec<i64>,
    chi2: Vec<f64>,
    stages: StageCounts,
}

struct Shared {
    count: AtomicUsize,
    abort: AtomicBool,
}

impl Prepared<'_> {
    /// The child of `node` when sensor s takes report `i` (`None` = missed), or `None` when
    /// the child fails the gate. Pushes the report onto `ctx.obs` on success.
    fn branch(&self, s: usize, i: Option<usize>, node: &Node, ctx: &mut Ctx) -> Option<Node> {
        let Some(i) = i else {
            ctx.tuple[s] = 0;
            ctx.rows[s] = -1;
            return Some(*node);
        };
        let ray = &self.rays[s][i];
        if let Some(gate) = &self.attributes {
            let chosen = &ctx.rows[..s];
            if chosen
                .iter()
                .any(|&r| r >= 0 && !gate.admits(r as usize, ray.row))
            {
                ctx.out.stages.attribute_pruned += 1;
                return None;
            }
        }
        ctx.tuple[s] = (i + 1) as u32;
        ctx.rows[s] = ray.row as i64;
        let child = match node.rays {
            0 => Node {
                rays: 1,
                estimate: None,
                window: None,
            },
            1 => {
                ctx.out.stages.tested[2] += 1;
                let first = ctx.tuple[..s]
                    .iter()
                    .position(|&t| t > 0)
                    .and_then(|f| self.rays[f].get(ctx.tuple[f] as usize - 1));
                let estimate = first
                    .and_then(|first| self.estimate_pair(first, ray).map(|e| (e, first.wedge)));
                match estimate {
                    Some((e, first_wedge)) => {
                        // Only prefixes that can still grow need the window.
                        let grows = s + 1 < self.n_sensors;
                        let window = if self.options.use_window() && grows {
                            Window::new(first_wedge, ray.wedge)
                        } else {
                            None
                        };
                        Node {
                            rays: 2,
                            estimate: Some(e),
                            window,
                        }
                    }
                    None => {
                        ctx.out.stages.pruned[2] += 1;
                        return None;
                    }
                }
            }
            k => {
                ctx.out.stages.tested[k + 1] += 1;
                ctx.obs.push(ray.obs);
                let estimate = node
                    .estimate
                    .and_then(|parent| self.estimate_extension(&parent, &ctx.obs));
                return match estimate {
                    Some(e) => Some(Node {
                        rays: k + 1,
                        estimate: Some(e),
                        window: node.window,
                    }),
                    None => {
                        ctx.obs.pop();
                        ctx.out.stages.pruned[k + 1] += 1;
                        None
                    }
                };
            }
        };
        ctx.obs.push(ray.obs);
        Some(child)
    }

    fn descend(&self, s: usize, node: &Node, ctx: &mut Ctx, shared: &Shared) {
        if shared.abort.load(Ordering::Relaxed) || crate::parallel::interrupted() {
            return;
        }
        if s == self.n_sensors {
            if node.rays >= self.options.min_intensity() {
                self.emit(node, ctx, shared);
            }
            return;
        }
        if node.rays + (self.n_sensors - s) < self.options.min_intensity() {
            return;
        }
        if let Some(child) = self.branch(s, None, node, ctx) {
            self.descend(s + 1, &child, ctx, shared);
        }
        let n = self.rays[s].len();
        let interval = match (node.rays >= 2, node.window) {
            (true, Some(w)) => {
                self.apex[s].and_then(|apex| w.azimuth_interval(&apex, self.half_width[s]))
            }
            _ => None,
        };
        let start = ctx.hits.len();
        match interval {
            Some((lo, hi)) => select(&self.by_azimuth[s], lo, hi, &mut ctx.hits),
            None => ctx.hits.extend(0..n as u32),
        }
        ctx.out.stages.windowed_out += (n - (ctx.hits.len() - start)) as u64;
        for h in start..ctx.hits.len() {
            let i = ctx.hits[h] as usize;
            if let Some(child) = self.branch(s, Some(i), node, ctx) {
                self.descend(s + 1, &child, ctx, shared);
                ctx.obs.pop();
            }
        }
        ctx.hits.truncate(start);
        ctx.tuple[s] = 0;
        ctx.rows[s] = -1;
    }

    fn emit(&self, node: &Node, ctx: &mut Ctx, shared: &Shared) {
        let Some(estimate) = node.estimate else {
            return;
        };
        let seen = shared.count.fetch_add(1, Ordering::Relaxed) + 1;
        if seen > self.options.max_candidates() {
            shared.abort.store(true, Ordering::Relaxed);
            return;
        }
        let dim = self.dim();
        let covariance = estimate
            .covariance
            .unwrap_or_else(|| self.covariance_at(&estimate.point, &ctx.obs));
        let out = &mut ctx.out;
        out.tuples.extend(ctx.tuple.iter().map(|&t| t as i64));
        out.rows.extend_from_slice(&ctx.rows);
        out.positions.extend_from_slice(&estimate.point[..dim]);
        out.covariances.extend_from_slice(&covariance[..dim * dim]);
        let excess: f64 = (ctx.tuple.iter().enumerate())
            .filter(|&(_, &t)| t > 0)
            .map(|(s, &t)| self.rays[s][t as usize - 1].cost_excess)
            .sum();
        out.costs.push(
            self.detection
                .cost(ctx.tuple.iter().map(|&t| t > 0), estimate.chi2)
                + excess,
        );
        out.intensity.push(node.rays as i64);
        out.chi2.push(estimate.chi2);
        out.stages.candidates += 1;
    }

    /// The subtrees of tasks `tasks` in order, into one output. Task `t` is sensor 0 taking
    /// choice `t / second` and sensor 1 choice `t % second` (0 = missed, else 1-based): decoded,
    /// never listed, since the list of all pairs is as large as the two sensors' product.
    fn run_tasks(&self, tasks: Range<usize>, second: usize, shared: &Shared) -> Output {
        let s_count = self.n_sensors;
        let mut ctx = Ctx {
            tuple: vec![0; s_count],
            rows: vec![-1; s_count],
            obs: Vec::with_capacity(s_count),
            hits: Vec::new(),
            out: Output {
                stages: StageCounts::new(s_count),
                ..Output::default()
            },
        };
        let choice = |i: usize| i.checked_sub(1);
        for t in tasks {
            if shared.abort.load(Ordering::Relaxed) || crate::parallel::interrupted() {
                break; // over the cap, or asked to stop: the caller discards everything
            }
            let (i0, i1) = (t / second, t % second);
            ctx.obs.clear();
            if let Some(first) = self.branch(0, choice(i0), &ROOT, &mut ctx) {
                if let Some(second) = self.branch(1, choice(i1), &first, &mut ctx) {
                    self.descend(2, &second, &mut ctx, shared);
                }
            }
        }
        ctx.out
    }
}

/// Fewest tasks per parallel chunk. The chunk size is a function of the problem only, never
/// of the thread count, so the concatenated output is the same for any pool.
const TASKS_PER_CHUNK: usize = 16;

/// Most chunks: a chunk's output has a fixed overhead, so a huge pair count gets bigger chunks
/// rather than millions of outputs.
const MAX_CHUNKS: usize = 1 << 14;

/// Enumerates the candidate tuples of one scan (times are ignored) with their ML positions,
/// covariances and eq. 2 costs. Runs on the current rayon pool (wrap in
/// [`crate::parallel::with_threads`] to choose the thread count); the result does not depend
/// on it.
///
/// Errors: invalid options or detection model, fewer than 2 sensors, or
/// [`CoreError::CapExceeded`] when more than `max_candidates` tuples survive.
pub fn enumerate(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    detection: &DetectionModel,
    options: &EnumerateOptions,
) -> CoreResult<Candidates> {
    enumerate_with_attributes(sensors, measurements, detection, options, None)
}

/// [`enumerate`] with an attribute gate: a tuple holding two reports whose `m(assoc)` is
/// below η is never formed (the prefix is cut as soon as the second report joins it).
pub fn enumerate_with_attributes(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    detection: &DetectionModel,
    options: &EnumerateOptions,
    attributes: Option<AttributeGate<'_>>,
) -> CoreResult<Candidates> {
    let prepared = Prepared::new(sensors, measurements, detection, options)?
        .with_attributes(attributes, measurements.len())?;
    enumerate_prepared(&prepared)
}

/// Whether the enumeration of a scan whose sensors have `reports` reports each runs on the
/// calling thread alone: it does when its task pairs (reports of the first two sensors, each
/// plus "missed") fit in one chunk, whichever two sensors go first.
pub fn enumerates_sequentially(reports: &[usize]) -> bool {
    let most = reports.iter().copied().max().unwrap_or(0);
    (most + 1).saturating_mul(most + 1) <= TASKS_PER_CHUNK
}

pub(crate) fn enumerate_prepared(p: &Prepared<'_>) -> CoreResult<Candidates> {
    let s_count = p.n_sensors;
    let sizes: Vec<usize> = p.rays.iter().map(Vec::len).collect();
    let second = sizes[1] + 1;
    let n_tasks = (sizes[0] + 1).saturating_mul(second);
    let chunk = TASKS_PER_CHUNK.max(n_tasks.div_ceil(MAX_CHUNKS));
    let shared = Shared {
        count: AtomicUsize::new(0),
        abort: AtomicBool::new(false),
    };
    let run_chunk =
        |c: usize| p.run_tasks(c * chunk..((c + 1) * chunk).min(n_tasks), second, &shared);
    let n_chunks = n_tasks.div_ceil(chunk);
    // One chunk (a small scan) runs here: from outside a pool a parallel iterator would hand
    // it to rayon's pool and wait, which costs more than the chunk.
    let parts: Vec<Output> = if n_chunks <= 1 {
        (0..n_chunks).map(run_chunk).collect()
    } else {
        (0..n_chunks).into_par_iter().map(run_chunk).collect()
    };
    if crate::parallel::interrupted() {
        return Err(CoreError::Interrupted); // before concatenating what was found so far
    }
    if shared.abort.load(Ordering::Relaxed) {
        return Err(CoreError::CapExceeded {
            what: "candidate tuples",
            count: p.options.max_candidates() + 1,
            cap: p.options.max_candidates(),
            hint: "the enumeration stopped at the first tuple over the cap; raise max_candidates, lower the gate or raise min_intensity",
        });
    }
    let total: usize = parts.iter().map(|o| o.costs.len()).sum();
    let dim = p.dim();
    let mut c = Candidates {
        n_sensors: s_count,
        dim,
        tuples: Vec::with_capacity(total * s_count),
        rows: Vec::with_capacity(total * s_count),
        positions: Vec::with_capacity(total * dim),
        covariances: Vec::with_capacity(total * dim * dim),
        costs: Vec::with_capacity(total),
        intensity: Vec::with_capacity(total),
        chi2: Vec::with_capacity(total),
        sizes,
        stages: StageCounts::new(s_count),
    };
    for o in parts {
        c.tuples.extend(o.tuples);
        c.rows.extend(o.rows);
        c.positions.extend(o.positions);
        c.covariances.extend(o.covariances);
        c.costs.extend(o.costs);
        c.intensity.extend(o.intensity);
        c.chi2.extend(o.chi2);
        c.stages.add(&o.stages);
    }
    Ok(c)
}
