//! Jonker & Volgenant's initialisation of a square dense problem (column reduction, reduction
//! transfer, two passes of augmenting row reduction), the start that makes LAPJV fast: on
//! typical matrices it assigns most rows with cheap row scans, and the shortest-augmenting-path
//! phase then runs only for the rows left free.
//!
//! It leaves column duals `v` and a partial matching in which every assigned row `i → j` has
//! `c_ij − v_j = min_k (c_ik − v_k)`: the duals are feasible on the assigned rows, which is
//! the invariant the shortest-augmenting-path phase keeps (with `u_i = c_ij − v_j`). Duals only
//! decrease after the column reduction, so no assigned row loses that property when another
//! row's column is repriced. Square only: for a rectangular problem the free columns' duals
//! must stay 0, which the column reduction would break. `+inf` entries (forbidden pairs) are
//! allowed when every row and every column has a finite one ([`startable`]): the prices are
//! then finite, a forbidden pair's reduced cost is `+inf` and is never the cheapest, and a
//! row with one finite entry has no second price to lower to.

use super::{refill, Entry, NONE};

/// Duals and a partial matching from [`jv_init`]; `free` lists the unassigned rows.
/// `cheapest` and `unique` are the column reduction's scratch. Every vector is refilled by
/// [`jv_init`], so one `Init` serves many solves without allocating again.
#[derive(Default)]
pub(super) struct Init {
    pub v: Vec<f64>,
    pub col4row: Vec<usize>,
    pub row4col: Vec<usize>,
    pub free: Vec<usize>,
    cheapest: Vec<usize>,
    unique: Vec<bool>,
}

/// Repricing steps per free row allowed in one pass of augmenting row reduction. LAPJV's own
/// bound (current · n) lets the first pass run until no row is free, which at 1000² and 3000²
/// is most of the solve. Past a few steps per row the shortest augmenting paths finish the
/// remaining rows for less. A sweep of 1 to 64 (uniform costs, 100² to 3000², three seeds)
/// puts the best between 8 and 16; 8 is the better of the two below 1000². The resulting
/// times are in docs/performance.md (`benches/bench_lap.py`).
const ARR_STEPS_PER_ROW: usize = 8;

/// Whether the `n × n` row-major `cost` has a finite entry in every row and every column, as
/// [`jv_init`] needs. One read of the matrix, done only when some entry is `+inf`.
pub(super) fn startable<C: Entry>(n: usize, cost: &[C]) -> bool {
    let mut column_ok = vec![false; n];
    for row in cost.chunks_exact(n) {
        let mut row_ok = false;
        for (ok, c) in column_ok.iter_mut().zip(row) {
            let finite = c.get() < f64::INFINITY;
            *ok |= finite;
            row_ok |= finite;
        }
        if !row_ok {
            return false;
        }
    }
    column_ok.iter().all(|&ok| ok)
}

/// The initialisation of an `n × n` row-major matrix with a finite entry in every row and
/// column ([`startable`]), into `init`.
pub(super) fn jv_init<C: Entry>(n: usize, cost: &[C], init: &mut Init) {
    column_reduction(n, cost, init);
    for _ in 0..2 {
        if init.free.is_empty() {
            break;
        }
        augmenting_row_reduction(n, cost, init);
    }
}

/// Each column priced at its cheapest row and given to it if that row has no column yet
/// (columns in reverse order, as LAPJV); then each row that won exactly one column transfers
/// its slack to that column's price.
fn column_reduction<C: Entry>(n: usize, cost: &[C], init: &mut Init) {
    refill(&mut init.v, n, f64::INFINITY);
    refill(&mut init.cheapest, n, NONE);
    let (v, cheapest) = (&mut init.v, &mut init.cheapest);
    for (i, row) in cost.chunks_exact(n).enumerate() {
        // Selects, not branches, so that the loop vectorises; strict `<` keeps the first row
        // of a tie, as the branching form did.
        for ((vj, cj), &c) in v.iter_mut().zip(cheapest.iter_mut()).zip(row) {
            let c = c.get();
            let less = c < *vj;
            *vj = if less { c } else { *vj };
            *cj = if less { i } else { *cj };
        }
    }
    refill(&mut init.col4row, n, NONE);
    refill(&mut init.row4col, n, NONE);
    refill(&mut init.unique, n, true);
    let (col4row, row4col, unique) = (&mut init.col4row, &mut init.row4col, &mut init.unique);
    for j in (0..n).rev() {
        let i = init.cheapest[j];
        if col4row[i] == NONE {
            col4row[i] = j;
            row4col[j] = i;
        } else {
            unique[i] = false;
        }
    }
    init.free.clear();
    let v = &mut init.v;
    for i in 0..n {
        let j = col4row[i];
        if j == NONE {
            init.free.push(i);
        } else if unique[i] {
            let row = &cost[i * n..(i + 1) * n];
            let slack =
                min_reduced(&row[..j], &v[..j]).min(min_reduced(&row[j + 1..], &v[j + 1..]));
            if slack.is_finite() {
                v[j] -= slack;
            }
        }
    }
}

/// `min_k (row_k − v_k)` (∞ when empty). Four running minima so that the comparisons do not
/// wait on each other; min is exact, so the order does not change the result.
fn min_reduced<C: Entry>(row: &[C], v: &[f64]) -> f64 {
    let mut lanes = [f64::INFINITY; 4];
    let (rows, vs) = (row.chunks_exact(4), v.chunks_exact(4));
    let tail = rows.remainder().iter().zip(vs.remainder());
    for (r, w) in rows.zip(vs) {
        for k in 0..4 {
            let h = r[k].get() - w[k];
            lanes[k] = if h < lanes[k] { h } else { lanes[k] };
        }
    }
    let tail_min = tail.map(|(r, w)| r.get() - w).fold(f64::INFINITY, f64::min);
    lanes.into_iter().fold(tail_min, f64::min)
}

/// One pass over the free rows: each takes its cheapest column, repriced down to its second
/// cheapest so that the two tie, and the row it displaces is processed next (while that keeps
/// lowering a price) or left for the next pass. Leaves `init.free` the rows still free.
fn augmenting_row_reduction<C: Entry>(n: usize, cost: &[C], init: &mut Init) {
    let mut free = std::mem::take(&mut init.free);
    let n_free = free.len();
    let (mut current, mut next_free, mut steps) = (0, 0, 0usize);
    while current < n_free {
        steps += 1;
        let i = free[current];
        current += 1;
        let row = &cost[i * n..(i + 1) * n];
        let (mut j1, u1, u2) = two_cheapest(row, &init.v);
        let mut i0 = init.row4col[j1];
        let lowered = init.v[j1] - (u2 - u1);
        // A one-column row has no second price (u2 = ∞): nothing to lower.
        let lowers = u2.is_finite() && lowered < init.v[j1];
        // LAPJV bounds the repricing steps of a pass by current · n; we also stop at
        // ARR_STEPS_PER_ROW per row that entered the pass, past which rows are only moved on.
        if steps
            < current
                .saturating_mul(n)
                .min(ARR_STEPS_PER_ROW.saturating_mul(n_free))
        {
            if lowers {
                init.v[j1] = lowered;
            } else if i0 != NONE && u2.is_finite() {
                let j2 = second_column(row, &init.v, j1, u2);
                j1 = j2;
                i0 = init.row4col[j2];
            }
            if i0 != NONE {
                if lowers {
                    current -= 1;
                    free[current] = i0;
                } else {
                    free[next_free] = i0;
                    next_free += 1;
                }
            }
        } else if i0 != NONE {
            free[next_free] = i0;
            next_free += 1;
        }
        init.col4row[i] = j1;
        init.row4col[j1] = i;
        if i0 != NONE && init.col4row[i0] == j1 {
            init.col4row[i0] = NONE;
        }
    }
    free.truncate(next_free);
    init.free = free;
}

/// The cheapest and second-cheapest reduced costs `c_j − v_j` of a row, with the first column
/// of the cheapest (a duplicated minimum is also the second value; a one-column row has
/// `u2 = ∞`). This scan is most of the augmenting row reduction, which is most of a 100²
/// solve (perf), so it keeps four lanes (columns `j ≡ k mod 4`) with branch-free updates
/// that compile to packed min/max, and merges them at the end.
fn two_cheapest<C: Entry>(row: &[C], v: &[f64]) -> (usize, f64, f64) {
    let (mut u1, mut u2, mut j1) = ([f64::INFINITY; 4], [f64::INFINITY; 4], [NONE; 4]);
    let (rows, vs) = (row.chunks_exact(4), v.chunks_exact(4));
    let tail = rows.remainder().iter().zip(vs.remainder()).enumerate();
    let tail_start = row.len() - row.len() % 4;
    for (chunk, (r, w)) in rows.zip(vs).enumerate() {
        for k in 0..4 {
            let h = r[k].get() - w[k];
            // `if a < b { a } else { b }` is one minsd/maxsd (no NaN here: costs are checked).
            let high = if u1[k] < h { h } else { u1[k] };
            u2[k] = if high < u2[k] { high } else { u2[k] };
            j1[k] = if h < u1[k] { 4 * chunk + k } else { j1[k] };
            u1[k] = if h < u1[k] { h } else { u1[k] };
        }
    }
    let (mut best, mut second, mut col) = (f64::INFINITY, f64::INFINITY, NONE);
    let lanes = (0..4).map(|k| (u1[k], u2[k], j1[k]));
    let tail = tail.map(|(t, (r, w))| (r.get() - w, f64::INFINITY, tail_start + t));
    for (h1, h2, j) in lanes.chain(tail) {
        // Merging (h1 ≤ h2) into (best ≤ second); ties on the minimum go to the lower column.
        if h1 < best || (h1 == best && j < col) {
            second = best.min(h2);
            (best, col) = (h1, j);
        } else {
            second = second.min(h1);
        }
    }
    (col, best, second)
}

/// A column other than `j1` whose reduced cost is `u2` (the one [`two_cheapest`] saw last on
/// a tie is not tracked; this scan runs only when the row moves instead of repricing).
fn second_column<C: Entry>(row: &[C], v: &[f64], j1: usize, u2: f64) -> usize {
    (0..row.len())
        .filter(|&j| j != j1)
        .min_by(|&a, &b| {
            (row[a].get() - v[a] - u2)
                .abs()
                .total_cmp(&(row[b].get() - v[b] - u2).abs())
        })
        .unwrap_or(NONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The plain sequential scan the lanes replace.
    fn two_cheapest_reference(row: &[f64], v: &[f64]) -> (usize, f64, f64) {
        let (mut j1, mut u1, mut u2) = (NONE, f64::INFINITY, f64::INFINITY);
        for (j, (&c, &vj)) in row.iter().zip(v).enumerate() {
            let h = c - vj;
            if h < u2 {
                if h >= u1 {
                    u2 = h;
                } else {
                    (u2, u1, j1) = (u1, h, j);
                }
            }
        }
        (j1, u1, u2)
    }

    #[test]
    fn lane_scans_match_the_sequential_ones_ties_included() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for case in 0..2000 {
            let n = 1 + case % 13;
            // Small integers: many ties, on the minimum too.
            let row: Vec<f64> = (0..n)
                .map(|_| f64::from(rng.random_range(0..4u8)))
                .collect();
            let v: Vec<f64> = (0..n)
                .map(|_| f64::from(rng.random_range(0..2u8)))
                .collect();
            assert_eq!(
                two_cheapest(&row, &v),
                two_cheapest_reference(&row, &v),
                "{row:?} {v:?}"
            );
            let plain = (0..n).map(|k| row[k] - v[k]).fold(f64::INFINITY, f64::min);
            assert_eq!(min_reduced(&row, &v), plain);
        }
    }
}
