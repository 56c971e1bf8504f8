//! The supported candidates of one pass, as stored until the search takes them.
//!
//! A fitted candidate is about 0.45 kB (its estimate, scales, covariance factor and scores).
//! Past the cap the support gate keeps millions of them (5 sensors × 100 targets: 23.9 M,
//! about 11 GB kept whole; docs/performance.md, *Initiation at scale*), while the search in
//! stages (module `stages`) descends only a few thousand. So past `search_stage` candidates,
//! with the support gate on (each then has the score the stages order by), the pool keeps only each
//! candidate's four rows and score, and the search refits the ones it takes. A refit is the
//! same computation on the same rows (`fit_candidate` from the same ray pairs), so it gives
//! the same candidate bit for bit (a test checks it), and nothing else about the search
//! changes. At or below `search_stage` candidates every candidate is searched and the pool
//! keeps them whole: refitting all of them would only cost time.

use std::borrow::Cow;

use rayon::prelude::*;

use super::candidate::{fit_candidate, Candidate};
use super::output::StageCounts;
use super::problem::Problem;
use super::ray_pairs::RayPair;
use crate::error::{reserve_one, CoreResult};

/// The candidates that survive every enabled rule, with stage counts and timings.
#[derive(Clone, Debug, Default)]
pub struct CandidateSet {
    pub candidates: Pool,
    pub counts: StageCounts,
    pub seconds_enumerate: f64,
    pub seconds_fit: f64,
    pub seconds_support: f64,
    /// The limit that ended the formation early, as the error it would have been
    /// (`stop_at_limit`); `None` when every slot was formed.
    pub limit: Option<String>,
    /// The slots formed in full: all of them unless the limit stopped the formation.
    pub slots_formed: usize,
}

/// A candidate as kept past the limit: what refits it, and its support-gate score.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Compact {
    rows: [usize; 4],
    support_score: Option<f64>,
}

/// The candidates of one pass, whole or compact (module doc).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pool {
    /// Past this many candidates the pool keeps them compact (`None`: never).
    limit: Option<usize>,
    whole: Vec<Candidate>,
    /// Every candidate once past the limit (`whole` is then empty).
    compact: Vec<Compact>,
}

impl Pool {
    pub fn new(limit: Option<usize>) -> Self {
        Self {
            limit,
            ..Self::default()
        }
    }

    pub fn len(&self) -> usize {
        self.whole.len() + self.compact.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Adds `candidate` (with its score when the gate is on), compacting the pool when it
    /// passes the limit.
    pub fn push(
        &mut self,
        candidate: Candidate,
        what: &'static str,
        hint: &'static str,
    ) -> CoreResult<()> {
        if self.compact.is_empty() && self.limit.is_some_and(|l| self.whole.len() >= l) {
            self.compact = self.whole.drain(..).map(|c| Compact::of(&c)).collect();
            self.whole = Vec::new(); // give the whole candidates' memory back
        }
        if self.compact.is_empty() {
            reserve_one(&mut self.whole, what, hint)?;
            self.whole.push(candidate);
        } else {
            reserve_one(&mut self.compact, what, hint)?;
            self.compact.push(Compact::of(&candidate));
        }
        Ok(())
    }

    /// Candidate `i`'s rows.
    pub fn rows(&self, i: usize) -> [usize; 4] {
        match self.compact.get(i) {
            Some(c) => c.rows,
            None => self.whole[i].rows,
        }
    }

    /// Candidate `i`'s support-gate score.
    pub fn score(&self, i: usize) -> Option<f64> {
        match self.compact.get(i) {
            Some(c) => c.support_score,
            None => self.whole[i].support_score,
        }
    }

    /// Candidate `i`, refitted when compact (`None` only if the refit failed, which the same
    /// computation cannot do where the first fit succeeded).
    pub fn get(&self, problem: &Problem<'_>, i: usize) -> Option<Cow<'_, Candidate>> {
        match self.compact.get(i) {
            Some(c) => c.refit(problem).map(Cow::Owned),
            None => self.whole.get(i).map(Cow::Borrowed),
        }
    }

    /// Candidates `indices`, refitted in parallel where compact, in order.
    pub fn get_all(&self, problem: &Problem<'_>, indices: &[usize]) -> Vec<Cow<'_, Candidate>> {
        (indices.par_iter())
            .filter_map(|&i| self.get(problem, i))
            .collect()
    }

    /// Every candidate, whole (for tests and diagnostics).
    pub fn into_whole(self, problem: &Problem<'_>) -> Vec<Candidate> {
        let compact = (self.compact.par_iter()).filter_map(|c| c.refit(problem));
        let mut whole = self.whole;
        whole.par_extend(compact);
        whole
    }
}

impl Compact {
    fn of(c: &Candidate) -> Self {
        Self {
            rows: c.rows,
            support_score: c.support_score,
        }
    }

    fn refit(&self, problem: &Problem<'_>) -> Option<Candidate> {
        let [a1, b1, a2, b2] = self.rows;
        let (first, last) = (RayPair::of(problem, a1, b1), RayPair::of(problem, a2, b2));
        let mut candidate = fit_candidate(problem, &first, &last)?;
        candidate.support_score = self.support_score;
        Some(candidate)
    }
}

#[cfg(test)]
mod tests {
    use super::Pool;
    use crate::fti::candidate::Candidate;
    use crate::fti::options::InitiationOptions;
    use crate::fti::tests::candidates_of;
    use crate::fti::tests::sim;

    /// A compact pool gives back every candidate exactly as it was fitted, score included,
    /// in 2-D and 3-D, and compacts only past its limit.
    #[test]
    fn refits_are_the_candidates_bit_for_bit() {
        for sc in [sim::paper(3, true, 16, 8), sim::planar(5, true, 12, 8)] {
            let sensors = sc.sensors();
            let table = sc.measurements(&sensors);
            let options = InitiationOptions::default();
            let (candidates, ..) = candidates_of(&sensors, &table, 0.0, &options).expect("runs");
            assert!(candidates.len() > 10, "{} candidates", candidates.len());
            let problem = sim::problem(sensors, table);
            let mut pool = Pool::new(Some(10));
            for (k, c) in candidates.iter().enumerate() {
                let mut scored = c.clone();
                scored.support_score = Some(k as f64 - 0.5);
                pool.push(scored, "test", "none").expect("fits in memory");
                assert_eq!(pool.compact.is_empty(), k < 10, "candidate {k}");
            }
            assert!(pool.whole.is_empty());
            for (k, c) in candidates.iter().enumerate() {
                let back = pool.get(&problem, k).expect("refits").into_owned();
                assert_eq!(back.support_score, Some(k as f64 - 0.5));
                assert_eq!(
                    Candidate {
                        support_score: None,
                        ..back
                    },
                    *c,
                    "candidate {k}"
                );
                assert_eq!(pool.rows(k), c.rows);
            }
            let whole = pool.into_whole(&problem);
            assert_eq!(whole.len(), candidates.len());
        }
    }
}
