//! The fuzzy closeness of two topology vectors (METHODS §4 eq. 3) and the closeness matrix
//! of one scan.
//!
//! `W(a, b) = Σ_p max(min(a_p, b_p), min(1 − a_p, 1 − b_p))`: M·N only for identical 0/1
//! vectors, unchanged when both vectors are complemented. The matrix is computed row by row
//! in parallel; each entry is the same sequential sum whatever the thread count.

use rayon::prelude::*;

/// W of two vectors of equal length.
#[inline]
pub fn closeness(a: &[f32], b: &[f32]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(&x, &y)| x.min(y).max((1.0 - x).min(1.0 - y)))
        .sum()
}

/// `W(local_i, system_j)` for every pair, `(n_local, n_system)` row-major, as `f64`.
pub fn closeness_matrix(local: &[f32], system: &[f32], cells: usize) -> Vec<f64> {
    if cells == 0 {
        return Vec::new();
    }
    let n_system = system.len() / cells;
    let mut out = vec![0.0; (local.len() / cells) * n_system];
    out.par_chunks_mut(n_system.max(1))
        .zip(local.par_chunks(cells))
        .for_each(|(row, a)| {
            for (w, b) in row.iter_mut().zip(system.chunks_exact(cells)) {
                *w = f64::from(closeness(a, b));
            }
        });
    out
}
