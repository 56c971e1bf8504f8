//! Steps 2–3 of the intensity search within one level: exclusive rays, the set H of start
//! points, and the probability-intensity chains (see [`super::intensity`] for the rules).

use rayon::prelude::*;

use super::intensity::IntensityInput;
use super::measurement_ids::MeasurementIds;

/// The working set of one level, with its measurement ↔ candidate incidence.
///
/// Candidates are numbered in member order (the caller's) outside and in rank order — by
/// (cost, member index), the chain's tie-break — inside the chain, so that "best rank" is
/// "lowest index" and a bitset scan finds it.
pub(super) struct Level {
    stride: usize,
    /// Candidate c's measurement ids at `ids[c*stride..]` (member order).
    ids: Vec<u32>,
    pub costs: Vec<f64>,
    /// Exclusive rays of each member at the start of the level.
    initial_m: Vec<u32>,
    /// Rank of each member, and the member of each rank.
    rank: Vec<u32>,
    by_rank: Vec<u32>,
    /// The chain's view, all in rank order.
    chain: ChainData,
}

/// What every chain starts from, indexed by rank.
struct ChainData {
    /// Rank r's measurement ids at `ids[r*stride..]`.
    ids: Vec<u32>,
    /// CSR: the ranks using measurement id.
    user_offsets: Vec<usize>,
    users: Vec<u32>,
    /// Per measurement: how many candidates use it, and the XOR of their ranks — when one
    /// user is left, the XOR *is* that user, so nobody scans a user list to find it.
    uses: Vec<u32>,
    xor: Vec<u32>,
    /// Exclusive rays per rank.
    m: Vec<u32>,
    /// For each m = 0..=stride, a bitset over ranks of the candidates starting at that m.
    start_sets: Vec<u64>,
    /// Levels of m, 0..=stride.
    levels: usize,
    words: usize,
    /// Per measurement, its users as a bitset over ranks — kept only in dense levels, where a
    /// user list is longer than a bitset has words; a chain then finds the alive users of a
    /// measurement with one AND per word instead of one test per user.
    user_sets: Option<Vec<u64>>,
}

impl Level {
    pub fn new(
        input: &IntensityInput<'_>,
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
        let costs: Vec<f64> = members.iter().map(|&c| input.costs[c]).collect();
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
        let chain = ChainData::new(&ids, stride, &by_rank, &initial_m, uses);
        Level {
            stride,
            ids,
            costs,
            initial_m,
            rank,
            by_rank,
            chain,
        }
    }

    pub fn len(&self) -> usize {
        self.costs.len()
    }

    pub fn ids(&self, c: usize) -> &[u32] {
        &self.ids[c * self.stride..(c + 1) * self.stride]
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
                .map_init(
                    || Scratch::new(&self.chain, self.stride),
                    |scratch, &h| self.chain(scratch, h),
                )
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

    /// One chain from member `start`; returns the accepted members in acceptance order.
    ///
    /// The next candidate is the alive one of largest current m, then best rank: each level m
    /// keeps a bitset of its alive candidates, whose lowest bit is the best rank, and a word
    /// cursor that only moves back when a promotion lands below it. `scratch` is reset here,
    /// so one can serve many chains without reallocating.
    fn chain(&self, scratch: &mut Scratch, start: usize) -> Vec<u32> {
        let data = &self.chain;
        scratch.reset(data);
        let mut accepted = Vec::new();
        let mut next = Some(self.rank[start] as usize);
        while let Some(c) = next {
            accepted.push(self.by_rank[c]);
            for &id in data.ids(c, self.stride) {
                match &data.user_sets {
                    Some(sets) => {
                        let row = &sets[id as usize * data.words..(id as usize + 1) * data.words];
                        for (w, &users) in row.iter().enumerate() {
                            let mut hit = scratch.alive[w] & users;
                            while hit != 0 {
                                scratch.kill(
                                    data,
                                    self.stride,
                                    w * 64 + hit.trailing_zeros() as usize,
                                );
                                hit &= hit - 1;
                            }
                        }
                    }
                    None => {
                        for &u in data.users(id) {
                            if scratch.is_alive(u as usize) {
                                scratch.kill(data, self.stride, u as usize);
                            }
                        }
                    }
                }
            }
            next = (0..=self.stride)
                .rev()
                .find_map(|level| scratch.best_at(data, level));
        }
        accepted
    }
}

/// Chains run per batch when the vote may stop early: small enough to stop soon after the
/// outcome is decided, large enough to keep both cores of a small machine busy.
pub const VOTE_BATCH: usize = 16;

impl ChainData {
    fn new(
        member_ids: &[u32],
        stride: usize,
        by_rank: &[u32],
        member_m: &[u32],
        uses: Vec<u32>,
    ) -> ChainData {
        let n = by_rank.len();
        let n_meas = uses.len();
        let mut ids = Vec::with_capacity(member_ids.len());
        for &c in by_rank {
            let c = c as usize;
            ids.extend_from_slice(&member_ids[c * stride..(c + 1) * stride]);
        }
        let mut user_offsets = vec![0usize; n_meas + 1];
        for m in 0..n_meas {
            user_offsets[m + 1] = user_offsets[m] + uses[m] as usize;
        }
        let mut fill = user_offsets.clone();
        let mut users = vec![0u32; ids.len()];
        let mut xor = vec![0u32; n_meas];
        for (r, chunk) in ids.chunks(stride.max(1)).enumerate() {
            for &m in chunk {
                users[fill[m as usize]] = r as u32;
                fill[m as usize] += 1;
                xor[m as usize] ^= r as u32;
            }
        }
        let m: Vec<u32> = by_rank.iter().map(|&c| member_m[c as usize]).collect();
        let words = n.div_ceil(64);
        let mut start_sets = vec![0u64; (stride + 1) * words];
        for (r, &mr) in m.iter().enumerate() {
            start_sets[mr as usize * words + r / 64] |= 1 << (r % 64);
        }
        let dense = n_meas > 0 && words * n_meas < ids.len();
        let user_sets = dense.then(|| {
            let mut sets = vec![0u64; n_meas * words];
            for (r, chunk) in ids.chunks(stride.max(1)).enumerate() {
                for &m in chunk {
                    sets[m as usize * words + r / 64] |= 1 << (r % 64);
                }
            }
            sets
        });
        ChainData {
            ids,
            user_offsets,
            users,
            uses,
            xor,
            m,
            start_sets,
            levels: stride + 1,
            words,
            user_sets,
        }
    }

    fn ids(&self, r: usize, stride: usize) -> &[u32] {
        &self.ids[r * stride..(r + 1) * stride]
    }

    fn users(&self, id: u32) -> &[u32] {
        &self.users[self.user_offsets[id as usize]..self.user_offsets[id as usize + 1]]
    }
}

/// The per-chain working state (rank-indexed), reused across the chains one thread runs.
struct Scratch {
    alive: Vec<u64>,
    /// Per level m, a bitset of the alive candidates whose current m is that level.
    at: Vec<u64>,
    /// Per level, a word index below which `at` is all zero.
    cursor: Vec<usize>,
    uses: Vec<u32>,
    xor: Vec<u32>,
    m: Vec<u32>,
}

impl Scratch {
    fn new(data: &ChainData, stride: usize) -> Scratch {
        Scratch {
            alive: Vec::with_capacity(data.words),
            at: Vec::with_capacity(data.start_sets.len()),
            cursor: Vec::with_capacity(stride + 1),
            uses: Vec::with_capacity(data.uses.len()),
            xor: Vec::with_capacity(data.xor.len()),
            m: Vec::with_capacity(data.m.len()),
        }
    }

    fn reset(&mut self, data: &ChainData) {
        let n = data.m.len();
        self.alive.clear();
        self.alive.resize(data.words, !0);
        if n % 64 != 0 {
            if let Some(last) = self.alive.last_mut() {
                *last = (1u64 << (n % 64)) - 1;
            }
        }
        self.at.clear();
        self.at.extend_from_slice(&data.start_sets);
        self.cursor.clear();
        self.cursor
            .resize(data.start_sets.len() / data.words.max(1), 0);
        self.uses.clear();
        self.uses.extend_from_slice(&data.uses);
        self.xor.clear();
        self.xor.extend_from_slice(&data.xor);
        self.m.clear();
        self.m.extend_from_slice(&data.m);
    }

    fn is_alive(&self, r: usize) -> bool {
        self.alive[r / 64] >> (r % 64) & 1 == 1
    }

    /// Deletes rank `u`; every measurement left with one alive user gives that user an
    /// exclusive ray.
    #[inline]
    fn kill(&mut self, data: &ChainData, stride: usize, u: usize) {
        let words = data.words;
        let (word, bit) = (u / 64, 1u64 << (u % 64));
        self.alive[word] &= !bit;
        self.at[self.m[u] as usize * words + word] &= !bit;
        for &id in data.ids(u, stride) {
            let id = id as usize;
            self.uses[id] -= 1;
            self.xor[id] ^= u as u32;
            if self.uses[id] == 1 {
                // Exactly one alive user is left, and the XOR of the alive users is it.
                let v = self.xor[id] as usize;
                let (word, bit) = (v / 64, 1u64 << (v % 64));
                self.at[self.m[v] as usize * words + word] &= !bit;
                self.m[v] += 1;
                let level = self.m[v] as usize;
                self.at[level * words + word] |= bit;
                self.cursor[level] = self.cursor[level].min(word);
            }
        }
    }

    /// The best (lowest) alive rank whose current m is `level`, if any.
    fn best_at(&mut self, data: &ChainData, level: usize) -> Option<usize> {
        let set = &self.at[level * data.words..(level + 1) * data.words];
        let cursor = &mut self.cursor[level];
        while *cursor < set.len() && set[*cursor] == 0 {
            *cursor += 1;
        }
        set.get(*cursor)
            .map(|&w| *cursor * 64 + w.trailing_zeros() as usize)
    }
}
