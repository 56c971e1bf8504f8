//! The fuzzy closeness of two topology vectors (METHODS §4 eq. 3), for the candidate pairs
//! of one scan.
//!
//! `W(a, b) = Σ_p max(min(a_p, b_p), min(1 − a_p, 1 − b_p))`: M·N only for identical 0/1
//! vectors, unchanged when both vectors are complemented. The kernel sums in eight lanes so
//! the compiler can vectorise it (a single running `f32` sum is a serial dependency it may
//! not reorder); every pair is summed the same way whatever the thread count.

use rayon::prelude::*;

use super::candidates::Candidates;

/// Pairs below this many cell evaluations are scored on the calling thread: handing work to
/// the pool costs more than the work (a 20 × 20 scan is 19 200 evaluations).
const PARALLEL_MIN_CELLS: usize = 1 << 18;

/// W of two vectors of equal length.
#[inline]
pub fn closeness(a: &[f32], b: &[f32]) -> f32 {
    const LANES: usize = 8;
    let mut acc = [0.0f32; LANES];
    let (a_chunks, b_chunks) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let (a_rest, b_rest) = (a_chunks.remainder(), b_chunks.remainder());
    for (x, y) in a_chunks.zip(b_chunks) {
        for k in 0..LANES {
            acc[k] += cell(x[k], y[k]);
        }
    }
    let tail: f32 = a_rest.iter().zip(b_rest).map(|(&x, &y)| cell(x, y)).sum();
    acc.iter().sum::<f32>() + tail
}

/// One cell's term: with `lo ≤ hi` the two values, `max(lo, 1 − hi)` (the same as
/// `max(min(a, b), min(1 − a, 1 − b))`). Plain comparisons, since the values are never NaN:
/// `f32::min`'s NaN handling would cost extra instructions in the vector loop.
#[inline(always)]
fn cell(x: f32, y: f32) -> f32 {
    let (lo, hi) = if x < y { (x, y) } else { (y, x) };
    let other = 1.0 - hi;
    if lo > other {
        lo
    } else {
        other
    }
}

/// W of each candidate pair, as `f64`, in candidate order. On a stop request the rows (or
/// blocks of pairs) not yet begun are left at 0: a caller that polls the request afterwards
/// (`parallel::interrupted`) must not use the scores.
pub fn pair_closeness(local: &[f32], system: &[f32], cells: usize, pairs: &Candidates) -> Vec<f64> {
    let row = |i: usize| &local[i * cells..(i + 1) * cells];
    let col = |j: usize| &system[j * cells..(j + 1) * cells];
    let parallel = pairs.len() * cells >= PARALLEL_MIN_CELLS;
    match pairs {
        Candidates::All { n_system, .. } => {
            let mut out = vec![0.0; pairs.len()];
            let fill = |(i, out_row): (usize, &mut [f64])| {
                if crate::parallel::interrupted() {
                    return;
                }
                for (j, w) in out_row.iter_mut().enumerate() {
                    *w = f64::from(closeness(row(i), col(j)));
                }
            };
            let width = (*n_system).max(1);
            if parallel {
                out.par_chunks_mut(width).enumerate().for_each(fill);
            } else {
                out.chunks_mut(width).enumerate().for_each(fill);
            }
            out
        }
        Candidates::Listed(list) => {
            let mut out = vec![0.0; list.len()];
            let fill = |(block, scores): (&[(u32, u32)], &mut [f64])| {
                if crate::parallel::interrupted() {
                    return;
                }
                for (&(i, j), w) in block.iter().zip(scores) {
                    *w = f64::from(closeness(row(i as usize), col(j as usize)));
                }
            };
            // Blocks of pairs: the unit of work, and of the stop request's polling.
            const BLOCK: usize = 1024;
            if parallel {
                (list.par_chunks(BLOCK).zip(out.par_chunks_mut(BLOCK))).for_each(fill);
            } else {
                list.chunks(BLOCK).zip(out.chunks_mut(BLOCK)).for_each(fill);
            }
            out
        }
    }
}
