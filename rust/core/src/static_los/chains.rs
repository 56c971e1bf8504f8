//! Steps 2–3 of the intensity search within one level: exclusive rays, the set H of start
//! points, and the probability-intensity chains (see [`super::intensity`] for the rules).

use rayon::prelude::*;

use super::chain_block::{ChainData, LANES};
use super::intensity_input::IntensityInput;
use super::measurement_ids::MeasurementIds;

/// The working set of one level, with its measurement ↔ candidate incidence.
///
/// Candidates are numbered in member order (the caller's) outside and in rank order — by
/// (cost, member index), the chain's tie-break — inside the chains, so that "best rank" is
/// "first in a pass".
pub(super) struct Level {
    pub costs: Vec<f64>,
    /// Exclusive rays of each member at the start of the level.
    initial_m: Vec<u32>,
    /// Rank of each member.
    rank: Vec<u32>,
    /// The chains' view, in rank order (the only copy of the incidence).
    chain: ChainData,
}

impl Level {
    pub fn new(
        input: &IntensityInput,
        members: &[usize],
        stride: usize,
        n_meas: usize,
        meas: &MeasurementIds,
    ) -> Level {
        let mut ids = Vec::with_capacity(members.len() * stride);
        for &c in members {
            ids.extend(meas.of(c));
        }
        let mut uses = vec![0u32; n_meas];
        for &m in &ids {
            uses[m as usize] += 1;
        }
        let initial_m: Vec<u32> = ids
            .chunks(stride.max(1))
            .map(|chunk| chunk.iter().filter(|&&m| uses[m as usize] == 1).count() as u32)
            .collect();
        let costs: Vec<f64> = members.iter().map(|&c| input.costs()[c]).collect();
        let mut by_rank: Vec<u32> = (0..members.len() as u32).collect();
        by_rank.sort_by(|&a, &b| {
            costs[a as usize]
                .total_cmp(&costs[b as usize])
                .then(a.cmp(&b))
        });
        let mut rank = vec![0u32; members.len()];
        for (r, &c) in by_rank.iter().enumerate() {
            rank[c as usize] = r as u32;
        }
        let mut rank_ids = Vec::with_capacity(ids.len());
        for &c in &by_rank {
            let c = c as usize;
            rank_ids.extend_from_slice(&ids[c * stride..(c + 1) * stride]);
        }
        let chain = ChainData::new(rank_ids, stride, n_meas);
        Level {
            costs,
            initial_m,
            rank,
            chain,
        }
    }

    pub fn len(&self) -> usize {
        self.costs.len()
    }

    /// Member `c`'s measurement ids.
    pub fn ids(&self, c: usize) -> &[u32] {
        self.chain.ids(self.rank[c] as usize)
    }

    /// H: the candidates of maximal m, ascending; if there are more than `max_chains`, the
    /// `max_chains` best of them by (cost, index).
    pub fn start_points(&self, max_chains: Option<usize>) -> Vec<usize> {
        let best = self.initial_m.iter().copied().max().unwrap_or(0);
        let mut h: Vec<usize> = (0..self.len())
            .filter(|&c| self.initial_m[c] == best)
            .collect();
        if let Some(cap) = max_chains {
            if h.len() > cap {
                h.sort_by_key(|&c| self.rank[c]);
                h.truncate(cap);
                h.sort_unstable();
            }
        }
        h
    }

    /// Votes of the chains from `starts`: per candidate, the number of chains that accepted
    /// it, and the number of chains run.
    ///
    /// Chains run in blocks of [`LANES`] (see [`super::chain_block`]). With `early_exit`,
    /// they run in fixed batches of [`VOTE_BATCH`] (blocks in parallel within a batch) and
    /// stop once every candidate is decided against the threshold `threshold` over all
    /// `starts.len()` chains: confirmed (`votes > threshold`) or out of reach (`votes + chains
    /// left <= threshold`). The confirmed set is then the full vote's, but the counts are
    /// partial, so callers use it only when the confirmed set's order does not depend on them
    /// (τ >= 0.5). The batches are fixed, so the chains run do not depend on the thread count.
    pub fn vote(&self, starts: &[usize], threshold: f64, early_exit: bool) -> (Vec<usize>, usize) {
        let ranks: Vec<u32> = starts.iter().map(|&c| self.rank[c]).collect();
        let mut by_rank = vec![0usize; self.len()];
        let batch = if early_exit {
            VOTE_BATCH
        } else {
            ranks.len().max(1)
        };
        let mut run = 0;
        for chunk in ranks.chunks(batch) {
            if crate::parallel::interrupted() {
                break; // the binding raises KeyboardInterrupt; the partial vote is discarded
            }
            // One block (a small scan's vote) runs here: from outside a pool a parallel
            // iterator would hand it to rayon's pool and wait, which costs more than the block.
            let counts: Vec<usize> = if chunk.len() <= LANES {
                let votes = self.chain.run_block(chunk);
                votes.into_iter().map(|v| v as usize).collect()
            } else {
                self.vote_blocks(chunk)
            };
            add(&mut by_rank, &counts);
            run += chunk.len();
            let left = (starts.len() - run) as f64;
            if early_exit
                && by_rank
                    .iter()
                    .all(|&v| v as f64 > threshold || v as f64 + left <= threshold)
            {
                break;
            }
        }
        let votes = self.rank.iter().map(|&r| by_rank[r as usize]).collect();
        (votes, run)
    }

    /// The votes of `chunk`'s chains, its blocks of [`LANES`] in parallel. Summed as the
    /// blocks finish, not collected: a full vote may run thousands of blocks, each with a
    /// count per candidate. Integer sums do not depend on the order.
    fn vote_blocks(&self, chunk: &[u32]) -> Vec<usize> {
        chunk
            .par_chunks(LANES)
            .fold(
                || vec![0usize; self.len()],
                |mut sum, block| {
                    let votes = self.chain.run_block(block);
                    sum.iter_mut()
                        .zip(votes)
                        .for_each(|(t, v)| *t += v as usize);
                    sum
                },
            )
            .reduce(
                || vec![0usize; self.len()],
                |mut a, b| {
                    add(&mut a, &b);
                    a
                },
            )
    }
}

/// `total[k] += part[k]` for every candidate.
fn add(total: &mut [usize], part: &[usize]) {
    for (t, &v) in total.iter_mut().zip(part) {
        *t += v;
    }
}

/// Chains per batch when the vote may stop early: two blocks, to keep both cores of a small
/// machine busy; more would run further past the point where the outcome is decided.
pub const VOTE_BATCH: usize = 2 * LANES;
