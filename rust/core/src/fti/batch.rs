//! Fitting and gating the candidates that survive combination, in large parallel batches.
//!
//! Each batch is two parallel regions (fits, then gates) with serial steps between them. Each
//! region ends when its slowest thread does, so many small regions lose most where a thread
//! is now and then descheduled (a loaded machine), and small batches gain nothing on a quiet
//! one (the measurements are in CHANGELOG.md, *Progress and batches*). So a batch is large and
//! gathers the 4-tuples of several scan pairs instead of ending with each: pass 2 combines
//! fifteen slots per sensor pair, most with far fewer survivors than a batch. It holds each
//! 4-tuple as indices into its scan pair's ray pairs, which it shares (`Arc`) until fitted:
//! rebuilding the two ray pairs from the rows would repeat their sines, cosines and meetings
//! for every 4-tuple, and copying them would move 0.6 kB a 4-tuple on the serial path.

use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use super::candidate::{fit_candidate, Candidate};
use super::options::InitiationOptions;
use super::options::OOM_HINT;
use super::pool::CandidateSet;
use super::problem::Problem;
use super::ray_pairs::RayPair;
use super::support::Gate;
use crate::error::CoreResult;
use crate::geometry::model::Space;

/// 4-tuples fitted per parallel batch. The fitted batch is held until gated:
/// 16 384 × ≈ 0.45 kB ≈ 7 MB.
pub(super) const BATCH: usize = 16_384;

/// Past this many ray pairs held for unfitted 4-tuples (0.3 kB each) the batch is fitted
/// early, so that many sparse scan pairs cannot pile up their ray pairs.
const MAX_HELD_PAIRS: usize = 1 << 18;

/// One scan pair's first-scan and last-scan ray pairs, shared by its combination and the
/// batch that fits its 4-tuples. The vectors are shared as built: an `Arc<[RayPair]>` would
/// copy them, serially, and a pair is a few hundred bytes, thousands of them a scan pair at
/// 5 × 100.
#[derive(Clone)]
pub(super) struct ScanPairRays {
    pub(super) firsts: Arc<Vec<RayPair>>,
    pub(super) lasts: Arc<Vec<RayPair>>,
}

/// The 4-tuples waiting to be fitted, in the order the combination found them (the order of
/// the candidates, whatever the thread count).
pub(super) struct Batch<'a> {
    problem: &'a Problem<'a>,
    options: &'a InitiationOptions,
    /// The support gate (none when off).
    gate: Option<&'a Gate<'a>>,
    /// The ray pairs of each scan pair begun, until no waiting 4-tuple needs them.
    held: Vec<Option<ScanPairRays>>,
    held_pairs: usize,
    /// 4-tuples per batch ([`BATCH`]; the tests shrink it).
    size: usize,
    /// Ray pairs held before an early fit ([`MAX_HELD_PAIRS`]; the tests shrink it).
    max_held_pairs: usize,
    /// `[scan pair, first, last]`: indices into `held` and its two lists.
    tuples: Vec<[usize; 3]>,
}

impl<'a> Batch<'a> {
    pub(super) fn new(
        problem: &'a Problem<'a>,
        options: &'a InitiationOptions,
        gate: Option<&'a Gate<'a>>,
    ) -> Self {
        Self {
            problem,
            options,
            gate,
            held: Vec::new(),
            held_pairs: 0,
            size: BATCH,
            max_held_pairs: MAX_HELD_PAIRS,
            tuples: Vec::with_capacity(BATCH),
        }
    }

    /// The batch with `size` 4-tuples per fit and an early fit past `max_held_pairs` held ray
    /// pairs: the tests shrink both.
    #[cfg(test)]
    pub(super) fn with_limits(self, size: usize, max_held_pairs: usize) -> Self {
        Self {
            size,
            max_held_pairs,
            ..self
        }
    }

    /// Whether the support gate is on.
    pub(super) fn gated(&self) -> bool {
        self.gate.is_some()
    }

    /// The support gate (none when off).
    pub(super) fn support(&self) -> Option<&'a Gate<'a>> {
        self.gate
    }

    /// Starts a scan pair whose 4-tuples will follow; its handle for [`push`](Self::push).
    pub(super) fn begin(
        &mut self,
        rays: ScanPairRays,
        set: &mut CandidateSet,
    ) -> CoreResult<usize> {
        if self.held_pairs > self.max_held_pairs {
            self.flush(set)?;
        }
        self.held_pairs += rays.firsts.len() + rays.lasts.len();
        self.held.push(Some(rays));
        Ok(self.held.len() - 1)
    }

    /// Adds the 4-tuple of `first` and `last` of scan pair `pair`, fitting the batch once it
    /// is full.
    pub(super) fn push(
        &mut self,
        [pair, first, last]: [usize; 3],
        set: &mut CandidateSet,
    ) -> CoreResult<()> {
        self.tuples.push([pair, first, last]);
        if self.tuples.len() < self.size {
            return Ok(());
        }
        self.flush(set)
    }

    /// Fits and gates the waiting 4-tuples, keeping the survivors, and lets go of the ray
    /// pairs no later 4-tuple can need (all but the latest scan pair's).
    pub(super) fn flush(&mut self, set: &mut CandidateSet) -> CoreResult<()> {
        let outcome = self.fit_and_gate(set);
        self.tuples.clear();
        let latest = self.held.len().saturating_sub(1);
        self.held[..latest].iter_mut().for_each(|h| *h = None);
        self.held_pairs = (self.held.last().and_then(Option::as_ref))
            .map_or(0, |r| r.firsts.len() + r.lasts.len());
        outcome
    }

    /// Fits the 4-tuples in parallel (collected in order), applies the χ² gate and then the
    /// support `gate` (when on), and keeps the survivors. Gating each batch as it is fitted,
    /// instead of every candidate after all are fitted, keeps only the survivors in memory
    /// (6 145 of the 465 152 fitted on the 8-target 2-D scene of
    /// `benches/bench_initiation_2d.py` with the paper's formation, each ≈ 0.45 kB).
    fn fit_and_gate(&self, set: &mut CandidateSet) -> CoreResult<()> {
        let (problem, options, gate) = (self.problem, self.options, self.gate);
        let start = Instant::now();
        let held = &self.held;
        let fitted: Vec<Option<Candidate>> = (self.tuples.par_iter())
            .map(|&[pair, first, last]| {
                // Every waiting 4-tuple's scan pair is held (`flush`).
                let rays = held.get(pair)?.as_ref()?;
                fit_candidate(problem, rays.firsts.get(first)?, rays.lasts.get(last)?)
            })
            .collect();
        set.seconds_fit += start.elapsed().as_secs_f64();
        let start = Instant::now();
        let verdicts = judge(problem, &fitted, options, gate);
        for (fit, verdict) in fitted.into_iter().zip(verdicts) {
            let Some(candidate) = fit else {
                continue;
            };
            set.counts.fitted += 1;
            if verdict == Verdict::Chi2 {
                continue;
            }
            set.counts.chi2_gate += 1;
            let Verdict::Kept(score) = verdict else {
                continue;
            };
            set.counts.supported += 1;
            let kept = Candidate {
                support_score: score,
                ..candidate
            };
            (set.candidates).push(kept, "fitted candidates", OOM_HINT)?;
        }
        set.seconds_support += start.elapsed().as_secs_f64();
        Ok(())
    }
}

/// The gates' verdict on each fit, in parallel, read where the fits lie: copying every fit
/// out first (0.44 kB each) would be serial work, and only the survivors are moved.
fn judge(
    problem: &Problem<'_>,
    fitted: &[Option<Candidate>],
    options: &InitiationOptions,
    gate: Option<&Gate<'_>>,
) -> Vec<Verdict> {
    let chi2_gate = match problem.layout.space {
        Space::Spatial => options.chi2_gate(),
        Space::Planar => None, // 0 degrees of freedom: see module `candidates`
    };
    fitted
        .par_iter()
        .map(|fit| match fit {
            None => Verdict::Unfit,
            Some(c) if chi2_gate.is_some_and(|g| c.chi2.is_nan() || c.chi2 > g) => Verdict::Chi2,
            Some(c) => match gate {
                Some(g) => g
                    .keeps(problem, c)
                    .map_or(Verdict::Unsupported, |s| Verdict::Kept(Some(s))),
                None => Verdict::Kept(None),
            },
        })
        .collect()
}

/// What the gates made of one 4-tuple.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    Unfit,
    Chi2,
    Unsupported,
    /// With the support gate's score when the gate is on.
    Kept(Option<f64>),
}
