//! The probability-intensity chains of one level, run 64 at a time: bit j of every word
//! belongs to chain j, so one AND, OR or popcount advances 64 chains at once.
//!
//! A chain alone costs O(incidence) per chain however it is stored: every candidate dies once
//! and every death updates its measurements. The vote runs hundreds of chains over the same
//! level, all from the same initial state, so the block runs them in lock-step rounds, each
//! chain accepting one candidate per round, and recomputes everything from a per-measurement
//! "taken" mask:
//!
//! 1. `alive[u]` = chains in which none of u's measurements is taken by an accepted candidate;
//! 2. per measurement, the chains in which it has ≥ 1 (`ones`) and ≥ 2 (`twos`) alive users;
//! 3. per candidate, `ge[k]` = chains in which at least k of its measurements have it as their
//!    only alive user (m ≥ k, its exclusive rays);
//! 4. each chain accepts the best-ranked alive candidate at its own largest m: one pass over
//!    the candidates in rank order, stopping once every chain has its pick.
//!
//! Candidates dead in all 64 chains leave the pass for good, so a round costs O(live
//! incidence). The result is each chain's accepted set exactly as the one-at-a-time rule of
//! [`super::intensity`] defines it (tested against the obvious implementation).

/// The level's incidence in rank order (rank = position in the order (cost, index), the
/// chain's tie-break): what every block starts from.
pub(super) struct ChainData {
    stride: usize,
    /// Rank r's measurement ids at `ids[r*stride..]`.
    ids: Vec<u32>,
    n_meas: usize,
}

/// Chains per block: the bits of a word.
pub(super) const LANES: usize = 64;

impl ChainData {
    /// `ids` holds each candidate's `stride` measurement ids (all `< n_meas`), in rank order.
    pub fn new(ids: Vec<u32>, stride: usize, n_meas: usize) -> ChainData {
        ChainData {
            stride,
            ids,
            n_meas,
        }
    }

    fn len(&self) -> usize {
        self.ids.len() / self.stride.max(1)
    }

    /// Rank `r`'s measurement ids.
    pub fn ids(&self, r: usize) -> &[u32] {
        &self.ids[r * self.stride..(r + 1) * self.stride]
    }

    /// Runs the chains from the ranks `starts` (at most [`LANES`]) and returns, per rank, how
    /// many of them accepted it.
    pub fn run_block(&self, starts: &[u32]) -> Vec<u32> {
        debug_assert!(starts.len() <= LANES);
        let n = self.len();
        let levels = self.stride + 1;
        let lanes: u64 = if starts.len() >= LANES {
            !0
        } else {
            (1u64 << starts.len()) - 1
        };
        let mut votes = vec![0u32; n];
        let mut taken = vec![0u64; self.n_meas];
        for (j, &s) in starts.iter().enumerate() {
            self.accept(s as usize, 1 << j, &mut votes, &mut taken);
        }
        let mut live: Vec<u32> = (0..n as u32).collect();
        let mut alive = vec![0u64; n];
        let (mut ones, mut twos) = (vec![0u64; self.n_meas], vec![0u64; self.n_meas]);
        let mut ge = vec![0u64; n * levels];
        let mut has = vec![0u64; levels];
        let mut want = vec![0u64; levels];
        loop {
            if crate::parallel::interrupted() {
                break votes; // the vote is discarded and the binding raises KeyboardInterrupt
            }
            // 1. Alive: none of the candidate's measurements taken; the dead-everywhere leave.
            let mut active = 0u64;
            live.retain(|&u| {
                let dead = self
                    .ids(u as usize)
                    .iter()
                    .fold(0, |acc, &r| acc | taken[r as usize]);
                let a = !dead & lanes;
                alive[u as usize] = a;
                active |= a;
                a != 0
            });
            if active == 0 {
                return votes;
            }
            // 2. Alive users per measurement: at least one, at least two.
            ones.fill(0);
            twos.fill(0);
            for &u in &live {
                let a = alive[u as usize];
                for &r in self.ids(u as usize) {
                    twos[r as usize] |= ones[r as usize] & a;
                    ones[r as usize] |= a;
                }
            }
            // 3. m ≥ k per candidate, and per k the chains where some candidate reaches it.
            has.fill(0);
            for &u in &live {
                let u = u as usize;
                let g = &mut ge[u * levels..(u + 1) * levels];
                g.fill(0);
                g[0] = alive[u];
                for (i, &r) in self.ids(u).iter().enumerate() {
                    let only_user = ones[r as usize] & !twos[r as usize] & alive[u];
                    for k in (1..=i + 1).rev() {
                        g[k] |= g[k - 1] & only_user;
                    }
                }
                for (h, &gk) in has.iter_mut().zip(g.iter()) {
                    *h |= gk;
                }
            }
            // Each chain's own largest m.
            for k in 0..levels {
                want[k] = has[k] & !has.get(k + 1).copied().unwrap_or(0);
            }
            // 4. Each chain accepts the best-ranked candidate at its largest m.
            let mut unresolved = active;
            for &u in &live {
                let u = u as usize;
                let g = &ge[u * levels..(u + 1) * levels];
                let picks = want.iter().zip(g).fold(0, |acc, (w, gk)| acc | (w & gk)) & unresolved;
                if picks != 0 {
                    self.accept(u, picks, &mut votes, &mut taken);
                    unresolved &= !picks;
                    if unresolved == 0 {
                        break;
                    }
                }
            }
        }
    }

    /// Rank `r` accepted by the chains `lanes`: its measurements are taken there.
    fn accept(&self, r: usize, lanes: u64, votes: &mut [u32], taken: &mut [u64]) {
        votes[r] += lanes.count_ones();
        for &m in self.ids(r) {
            taken[m as usize] |= lanes;
        }
    }
}
