//! Steps 2–3 of the intensity search within one level: exclusive rays, the set H of start
//! points, and the probability-intensity chains (see [`super::intensity`] for the rules).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::intensity::IntensityInput;

/// The working set of one level, with its measurement ↔ candidate incidence.
pub(super) struct Level {
    stride: usize,
    /// Candidate c's measurement ids at `ids[c*stride..]`.
    ids: Vec<u32>,
    pub costs: Vec<f64>,
    /// Position of each candidate in the order (cost, index): the chain's tie-break.
    rank: Vec<u32>,
    /// Candidates by rank (the inverse of `rank`).
    by_rank: Vec<u32>,
    /// CSR: the candidates using measurement id.
    user_offsets: Vec<usize>,
    users: Vec<u32>,
    initial_uses: Vec<u32>,
    initial_m: Vec<u32>,
    /// For each m = 0..=stride, the candidates with that initial m in rank order.
    initial_by_m: Vec<Vec<u32>>,
}

impl Level {
    pub fn new(
        input: &IntensityInput<'_>,
        members: &[usize],
        stride: usize,
        n_meas: usize,
        ids_of: &dyn Fn(usize) -> Vec<u32>,
    ) -> Level {
        let mut ids = Vec::with_capacity(members.len() * stride);
        for &c in members {
            ids.extend(ids_of(c));
        }
        let mut initial_uses = vec![0u32; n_meas];
        for &m in &ids {
            initial_uses[m as usize] += 1;
        }
        let mut user_offsets = vec![0usize; n_meas + 1];
        for m in 0..n_meas {
            user_offsets[m + 1] = user_offsets[m] + initial_uses[m] as usize;
        }
        let mut fill = user_offsets.clone();
        let mut users = vec![0u32; ids.len()];
        for (c, chunk) in ids.chunks(stride.max(1)).enumerate() {
            for &m in chunk {
                users[fill[m as usize]] = c as u32;
                fill[m as usize] += 1;
            }
        }
        let initial_m: Vec<u32> = ids
            .chunks(stride.max(1))
            .map(|chunk| {
                chunk
                    .iter()
                    .filter(|&&m| initial_uses[m as usize] == 1)
                    .count() as u32
            })
            .collect();
        let costs: Vec<f64> = members.iter().map(|&c| input.costs[c]).collect();
        let mut order: Vec<usize> = (0..members.len()).collect();
        order.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]).then(a.cmp(&b)));
        let mut rank = vec![0u32; members.len()];
        for (r, &c) in order.iter().enumerate() {
            rank[c] = r as u32;
        }
        let mut initial_by_m = vec![Vec::new(); stride + 1];
        for &c in &order {
            initial_by_m[initial_m[c] as usize].push(c as u32);
        }
        let by_rank = order.iter().map(|&c| c as u32).collect();
        Level {
            stride,
            ids,
            costs,
            rank,
            by_rank,
            user_offsets,
            users,
            initial_uses,
            initial_m,
            initial_by_m,
        }
    }

    pub fn len(&self) -> usize {
        self.costs.len()
    }

    pub fn ids(&self, c: usize) -> &[u32] {
        &self.ids[c * self.stride..(c + 1) * self.stride]
    }

    fn users(&self, m: u32) -> &[u32] {
        &self.users[self.user_offsets[m as usize]..self.user_offsets[m as usize + 1]]
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
    /// With `early_exit`, chains run in fixed batches of [`VOTE_BATCH`] (in parallel within a
    /// batch) and stop once every candidate is decided against the threshold `threshold` over
    /// all `starts.len()` chains: confirmed (`votes > threshold`) or out of reach
    /// (`votes + chains left <= threshold`). The confirmed set is then the full vote's, but
    /// the counts are partial, so callers use it only when the confirmed set's order does not
    /// depend on them (τ >= 0.5). The batches are fixed, so the chains run do not depend on
    /// the thread count.
    pub fn vote(&self, starts: &[usize], threshold: f64, early_exit: bool) -> (Vec<usize>, usize) {
        let mut votes = vec![0usize; self.len()];
        let batch = if early_exit {
            VOTE_BATCH
        } else {
            starts.len().max(1)
        };
        let mut run = 0;
        for chunk in starts.chunks(batch) {
            let accepted: Vec<Vec<u32>> = chunk
                .par_iter()
                .map_init(|| Scratch::new(self), |scratch, &h| self.chain(scratch, h))
                .collect();
            for chain in &accepted {
                for &c in chain {
                    votes[c as usize] += 1;
                }
            }
            run += chunk.len();
            let left = (starts.len() - run) as f64;
            if early_exit
                && votes
                    .iter()
                    .all(|&v| v as f64 > threshold || v as f64 + left <= threshold)
            {
                break;
            }
        }
        (votes, run)
    }

    /// One chain from `start`; returns the accepted candidates in acceptance order.
    ///
    /// The next candidate is the alive one of largest current m, then best rank. Since m only
    /// grows, each level m keeps a cursor into the candidates that started at m (rank order;
    /// dead or promoted ones are skipped for good) and a small heap of those promoted to m.
    /// `scratch` is reset here, so one can serve many chains without reallocating.
    fn chain(&self, scratch: &mut Scratch, start: usize) -> Vec<u32> {
        scratch.reset(self);
        let Scratch {
            alive,
            uses,
            m,
            cursor,
            promoted,
        } = scratch;
        let mut accepted = Vec::new();
        let mut next = Some(start);
        while let Some(c) = next {
            accepted.push(c as u32);
            for &id in self.ids(c) {
                for &u in self.users(id) {
                    let u = u as usize;
                    if !alive[u] {
                        continue;
                    }
                    alive[u] = false;
                    for &other in self.ids(u) {
                        let left = &mut uses[other as usize];
                        *left -= 1;
                        if *left == 1 {
                            if let Some(&v) = self.users(other).iter().find(|&&v| alive[v as usize])
                            {
                                let v = v as usize;
                                m[v] += 1;
                                promoted[m[v] as usize].push(Reverse(self.rank[v]));
                            }
                        }
                    }
                }
            }
            next = None;
            for level in (0..=self.stride).rev() {
                let current = |c: usize| alive[c] && m[c] as usize == level;
                let list = &self.initial_by_m[level];
                while cursor[level] < list.len() && !current(list[cursor[level]] as usize) {
                    cursor[level] += 1;
                }
                let heap = &mut promoted[level];
                while let Some(&Reverse(r)) = heap.peek() {
                    if current(self.by_rank[r as usize] as usize) {
                        break;
                    }
                    heap.pop();
                }
                let from_list = list.get(cursor[level]).map(|&c| self.rank[c as usize]);
                let from_heap = heap.peek().map(|&Reverse(r)| r);
                let best = match (from_list, from_heap) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                };
                if let Some(r) = best {
                    next = Some(self.by_rank[r as usize] as usize);
                    break;
                }
            }
        }
        accepted
    }
}

/// Chains run per batch when the vote may stop early: small enough to stop soon after the
/// outcome is decided, large enough to keep both cores of a small machine busy.
pub const VOTE_BATCH: usize = 16;

/// The per-chain working state, reused across the chains one thread runs.
struct Scratch {
    alive: Vec<bool>,
    uses: Vec<u32>,
    m: Vec<u32>,
    cursor: Vec<usize>,
    promoted: Vec<BinaryHeap<Reverse<u32>>>,
}

impl Scratch {
    fn new(level: &Level) -> Scratch {
        Scratch {
            alive: Vec::with_capacity(level.len()),
            uses: Vec::with_capacity(level.initial_uses.len()),
            m: Vec::with_capacity(level.len()),
            cursor: Vec::with_capacity(level.stride + 1),
            promoted: vec![BinaryHeap::new(); level.stride + 1],
        }
    }

    fn reset(&mut self, level: &Level) {
        self.alive.clear();
        self.alive.resize(level.len(), true);
        self.uses.clear();
        self.uses.extend_from_slice(&level.initial_uses);
        self.m.clear();
        self.m.extend_from_slice(&level.initial_m);
        self.cursor.clear();
        self.cursor.resize(level.stride + 1, 0);
        for heap in &mut self.promoted {
            heap.clear();
        }
    }
}
