//! Combining a scan pair's first-scan ray pairs with its last-scan ray pairs under the
//! `v_max` rule and the motion-corrected ray gate, then fitting the survivors in chunks.
//!
//! Each first pair is tested against the last pairs in parallel, in blocks, and the survivors
//! are fitted in the order of a plain double loop, so the candidates do not depend on the
//! thread count. Two things keep the work bounded (a project extension):
//!
//! * **An index over the last meetings.** A last pair can pass `v_max` only if its meeting
//!   lies within `v_max · (t_last − t_first)` of the first's, so the last meetings go in a
//!   uniform grid (module `reach_grid`) and a first pair is tested only against those within
//!   that ball. Where the scene is smaller than a few such reaches the index cannot prune and
//!   every last pair is tested.
//! * **A cap on the tests, known before any is made.** More than `WORK_PER_CANDIDATE ·
//!   max_candidates` first × last tests for one scan pair is refused (`CapExceeded`) at once,
//!   instead of running for minutes before the survivors reach `max_candidates`.

use rayon::prelude::*;

use super::batch::{Batch, ScanPairRays};
use super::motion_gate::{self, Motion};
use super::options::InitiationOptions;
use super::pool::CandidateSet;
use super::problem::Problem;
use super::ray_pairs::RayPair;
use super::reach_grid::Grid;
use super::round_gate::RoundGate;
use crate::error::{CoreError, CoreResult};

/// First × last tests allowed per allowed candidate (`max_candidates`): a test costs a small
/// fraction of the fit a survivor costs, so this allows far more testing than fitting, and
/// still refuses in well under a minute (docs/methods.md §1).
const WORK_PER_CANDIDATE: usize = 200;

/// First pairs tested together in parallel: their survivors are held until fitted. A few
/// survive in a thousand tests, so a large block holds little, and at 64 the two threads
/// waited on each other at every block (5 × 100: the stage 1.36× faster on two threads than
/// on one, 1.5–1.7× at 512, with parallel ray pairs).
const BLOCK: usize = 512;

/// Survivors pushed to the fits between two polls of the stop flag within a block (about a
/// batch's worth of fits, tens of milliseconds).
const POLL_EVERY: usize = 16_384;

/// Survivors one slot may test ahead of its queueing ([`Combination::test_ahead`]): about a
/// megabyte. Past them the rest of the slot is tested and queued a block at a time, so a slot
/// with millions of survivors (weak gates) never holds them all. The unit tests hold 64, so
/// that their slots take both paths.
const HELD: usize = if cfg!(test) { 64 } else { 1 << 16 };

/// Combines a scan pair's first × last ray pairs (module doc) with the grid given (`None`:
/// test every last pair), and adds the survivors to `batch`, which fits them into `set` as it
/// fills (the caller flushes the rest).
#[cfg(test)]
pub(super) fn combine_with(
    problem: &Problem<'_>,
    rays: &ScanPairRays,
    grid: Option<Grid>,
    rounds: Option<RoundGate<'_>>,
    options: &InitiationOptions,
    batch: &mut Batch<'_>,
    set: &mut CandidateSet,
) -> CoreResult<()> {
    Combination::with_grid(rays.clone(), grid, rounds, options)?.queue(problem, options, batch, set)
}

/// One slot's first × last tests (module doc), in blocks of [`BLOCK`] first pairs: what the
/// tests read, and the survivors of the blocks tested ahead of their queueing. The tests read
/// nothing a fit writes, so several slots can test ahead at once and be queued one after
/// another with the candidates of one slot at a time.
pub(super) struct Combination<'r> {
    rays: ScanPairRays,
    grid: Option<Grid>,
    rounds: Option<RoundGate<'r>>,
    /// What the speed rule and the motion gate read of each pair, in small records (module
    /// `motion_gate`): a test reads two of them, not two ray pairs. The grid holds the last
    /// pairs' own; without it they are read in order.
    first_motion: Vec<Option<Motion>>,
    last_motion: Vec<Option<Motion>>,
    /// The survivors tested ahead, per first pair from the first on (each list ascending, as
    /// the plain double loop finds them), how many, and the first block not tested.
    held: Vec<Vec<usize>>,
    held_count: usize,
    next_block: usize,
}

impl<'r> Combination<'r> {
    /// The tests of `rays`, with the grid over the last meetings where it applies; refused
    /// (`CapExceeded`) before any test when they would be too many.
    pub(super) fn new(
        problem: &Problem<'_>,
        rays: ScanPairRays,
        rounds: Option<RoundGate<'r>>,
        options: &InitiationOptions,
    ) -> CoreResult<Self> {
        let (firsts, lasts) = (&rays.firsts[..], &rays.lasts[..]);
        let grid = Grid::new(problem.layout.space, firsts, lasts, options.v_max());
        Self::with_grid(rays, grid, rounds, options)
    }

    /// [`new`](Self::new) with the grid given (`None`: test every last pair).
    fn with_grid(
        rays: ScanPairRays,
        grid: Option<Grid>,
        rounds: Option<RoundGate<'r>>,
        options: &InitiationOptions,
    ) -> CoreResult<Self> {
        let (firsts, lasts) = (&rays.firsts[..], &rays.lasts[..]);
        let cap = WORK_PER_CANDIDATE.saturating_mul(options.max_candidates());
        // Every first × last pair bounds the grid's tests: counting them (a second query of
        // the grid per first pair) is needed only when that bound exceeds the cap.
        let every = firsts.len().saturating_mul(lasts.len());
        let work: usize = match &grid {
            Some(g) if every > cap => firsts.par_iter().map(|f| g.count_near(f)).sum(),
            _ => every,
        };
        if work > cap {
            return Err(CoreError::CapExceeded {
                what: "first × last ray-pair tests of one scan pair",
                count: work,
                cap,
                hint: "set or lower v_max, tighten ray_gate_sigmas, enable reject_behind, or \
                       raise max_candidates (the cap is 200 tests per allowed candidate)",
            });
        }
        let motion = |pairs: &[RayPair]| -> Vec<Option<Motion>> {
            pairs.par_iter().map(Motion::of).collect()
        };
        let first_motion = motion(firsts);
        let last_motion = if grid.is_none() {
            motion(lasts)
        } else {
            Vec::new()
        };
        Ok(Self {
            rays,
            grid,
            rounds,
            first_motion,
            last_motion,
            held: Vec::new(),
            held_count: 0,
            next_block: 0,
        })
    }

    fn blocks(&self) -> usize {
        self.rays.firsts.len().div_ceil(BLOCK)
    }

    /// The survivors of block `b`: for each of its first pairs, in order, the last pairs that
    /// pass, ascending (the block's first pairs tested in parallel).
    fn test_block(
        &self,
        problem: &Problem<'_>,
        options: &InitiationOptions,
        b: usize,
    ) -> Vec<Vec<usize>> {
        let (firsts, lasts) = (&self.rays.firsts[..], &self.rays.lasts[..]);
        let (space, v_max) = (problem.layout.space, options.v_max());
        let start = b * BLOCK;
        let block = (firsts.get(start..(start + BLOCK).min(firsts.len()))).unwrap_or_default();
        block
            .par_iter()
            .enumerate()
            .map(|(i, f)| {
                let fm = self.first_motion[start + i].as_ref();
                let passes = |l: usize, lm: Option<&Motion>| {
                    speed_passes(fm, lm, v_max)
                        && motion_gate::passes(space, fm, lm, options)
                        && (self.rounds.as_ref())
                            .is_none_or(|r| r.passes(start + i, l, f, &lasts[l]))
                };
                match (&self.grid, fm) {
                    (Some(g), Some(fm)) => {
                        let mut survivors = Vec::new();
                        g.for_each_near(&fm.point, |l, lm| {
                            if passes(l, Some(lm)) {
                                survivors.push(l);
                            }
                        });
                        survivors.sort_unstable(); // the plain double loop's order
                        survivors
                    }
                    // Without a meeting a first pair fails `v_max` with every last one.
                    (Some(_), None) => Vec::new(),
                    (None, _) => (0..lasts.len())
                        .filter(|&l| passes(l, self.last_motion[l].as_ref()))
                        .collect(),
                }
            })
            .collect()
    }

    /// The survivors of the next block (its progress reported first), or `None` past the
    /// last.
    fn test_next(
        &mut self,
        problem: &Problem<'_>,
        options: &InitiationOptions,
    ) -> Option<Vec<Vec<usize>>> {
        let blocks = self.blocks();
        if self.next_block >= blocks {
            return None;
        }
        (problem.progress).report("candidates", self.next_block as f64 / blocks as f64);
        let survivors = self.test_block(problem, options, self.next_block);
        self.next_block += 1;
        Some(survivors)
    }

    /// Tests blocks ahead of the queueing while their survivors stay within [`HELD`] (and
    /// the call is not stopped).
    pub(super) fn test_ahead(&mut self, problem: &Problem<'_>, options: &InitiationOptions) {
        while self.held_count <= HELD && !problem.stopped() {
            let Some(survivors) = self.test_next(problem, options) else {
                return;
            };
            self.held_count += survivors.iter().map(Vec::len).sum::<usize>();
            self.held.extend(survivors);
        }
    }

    /// Queues the survivors for their fits in `batch`, in the plain double loop's order,
    /// counting them against `max_candidates`: those tested ahead, then the rest of the slot
    /// tested a block at a time (one block's survivors held at once).
    pub(super) fn queue(
        mut self,
        problem: &Problem<'_>,
        options: &InitiationOptions,
        batch: &mut Batch<'_>,
        set: &mut CandidateSet,
    ) -> CoreResult<()> {
        let pair = batch.begin(self.rays.clone(), set)?;
        // The survivors of the first pairs from `first` on.
        let (mut first, mut survivors) = (0, std::mem::take(&mut self.held));
        loop {
            for (f, lasts) in (first..).zip(survivors) {
                for l in lasts {
                    set.counts.v_max += 1;
                    if set.counts.v_max > options.max_candidates() {
                        return Err(CoreError::CapExceeded {
                            what: "candidates reaching the fitting stage",
                            count: set.counts.v_max,
                            cap: options.max_candidates(),
                            hint: "tighten ray_gate_sigmas or v_max, enable reject_behind, use \
                                   fewer sensor pairs, or raise max_candidates",
                        });
                    }
                    batch.push([pair, f, l], set)?;
                    // A block's survivors can be millions without gates: poll between fits.
                    if set.counts.v_max % POLL_EVERY == 0 && problem.stopped() {
                        return Ok(());
                    }
                }
            }
            if problem.stopped() {
                return Ok(()); // the pipeline ends as interrupted; nothing partial escapes
            }
            first = self.next_block * BLOCK;
            match self.test_next(problem, options) {
                Some(next) => survivors = next,
                None => return Ok(()),
            }
        }
    }
}

/// The `v_max` rule on two pairs' records: their meetings no farther apart than `v_max` allows
/// in the time between them (always without `v_max`; never without a meeting).
pub(super) fn speed_passes(
    first: Option<&Motion>,
    last: Option<&Motion>,
    v_max: Option<f64>,
) -> bool {
    let Some(v_max) = v_max else { return true };
    let (Some(f), Some(l)) = (first, last) else {
        return false;
    };
    let distance = (0..3)
        .map(|k| (l.point[k] - f.point[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    distance <= v_max * (l.time - f.time)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fti::ray_pairs::ray_pairs;
    use crate::fti::scans::Scans;
    use crate::fti::tests::sim;
    use crate::geometry::model::{Motion, StateLayout};

    /// On cluttered 2-D and 3-D scenes with a `v_max` that reaches a few km, the grid prunes
    /// the tests and finds exactly the candidates, in the same order, of testing every pair;
    /// and a cap below the tests it needs refuses before testing anything.
    #[test]
    fn the_grid_finds_exactly_the_candidates_of_the_full_scan() {
        let mut capped = 0;
        for (seed, planar) in [(1, true), (2, true), (3, false), (4, false)] {
            let sc = if planar {
                sim::planar(seed, true, 20, 8)
            } else {
                sim::paper(seed, true, 16, 8)
            };
            let sensors = sc.sensors();
            let table = sc.measurements(&sensors);
            let problem = Problem {
                sensors,
                measurements: table,
                layout: StateLayout::new(sc.space, Motion::ConstantVelocity { t0: 0.0 }),
                t0: 0.0,
                progress: &crate::progress::Silent,
            };
            let scans = Scans::new(&table, sensors.len());
            let options = InitiationOptions::default()
                .with_v_max(Some(60.0))
                .expect("valid");
            let ((a1, a2), (b1, b2)) = (
                scans.first_last(0).expect("scans"),
                scans.first_last(1).expect("scans"),
            );
            let pairs = |a: usize, b: usize| {
                let rows = (scans.scan(a), scans.scan(b));
                ray_pairs(&problem, rows.0, rows.1, &options)
                    .expect("fits")
                    .0
            };
            let rays = ScanPairRays {
                firsts: pairs(a1, b1).into(),
                lasts: pairs(a2, b2).into(),
            };
            let (firsts, lasts) = (&rays.firsts[..], &rays.lasts[..]);
            let grid_of = || Grid::new(sc.space, firsts, lasts, options.v_max()).expect("applies");
            let grid = grid_of();
            let tests: usize = firsts.iter().map(|f| grid.count_near(f)).sum();
            assert!(
                tests < firsts.len() * lasts.len() / 2,
                "seed {seed}: {tests}"
            );
            let combined = |grid: Option<Grid>| {
                let mut batch = Batch::new(&problem, &options, None);
                let mut set = CandidateSet::default();
                combine_with(&problem, &rays, grid, None, &options, &mut batch, &mut set)
                    .expect("runs");
                batch.flush(&mut set).expect("fits");
                set
            };
            let (with, without) = (combined(Some(grid_of())), combined(None));
            assert!(with.counts.v_max > 0, "seed {seed}: nothing to compare");
            assert_eq!(with.counts.v_max, without.counts.v_max, "seed {seed}");
            assert_eq!(with.candidates, without.candidates, "seed {seed}");
            // The work is capped before any test: 200 tests per allowed candidate.
            if tests >= 400 {
                capped += 1;
                let few = options
                    .clone()
                    .with_max_candidates(tests / 400)
                    .expect("valid");
                let mut batch = Batch::new(&problem, &few, None);
                let mut none = CandidateSet::default();
                match combine_with(
                    &problem,
                    &rays,
                    Some(grid_of()),
                    None,
                    &few,
                    &mut batch,
                    &mut none,
                ) {
                    Err(CoreError::CapExceeded { count, .. }) => assert_eq!(count, tests),
                    other => panic!("seed {seed}: {other:?}"),
                }
                assert!(none.candidates.is_empty() && none.counts.v_max == 0);
            }
        }
        assert_eq!(capped, 2, "the cap was checked on the 2-D scenes");
    }
}
