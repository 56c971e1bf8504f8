//! Fixed-size matrix products as plain loops over compile-time bounds. nalgebra's generic
//! `Mul` is not inlined into the filter's loop (its calls would take a fifth of the bench);
//! these unroll into straight multiply-adds, column by column (contiguous in nalgebra's
//! column-major storage).

use nalgebra::SMatrix;

/// `a · b`.
#[inline(always)]
pub(crate) fn mul<const R: usize, const K: usize, const C: usize>(
    a: &SMatrix<f64, R, K>,
    b: &SMatrix<f64, K, C>,
) -> SMatrix<f64, R, C> {
    let mut out = SMatrix::<f64, R, C>::zeros();
    for j in 0..C {
        for k in 0..K {
            let scale = b[(k, j)];
            for i in 0..R {
                out[(i, j)] += a[(i, k)] * scale;
            }
        }
    }
    out
}

/// `a · bᵀ`.
#[inline(always)]
pub(crate) fn mul_t<const R: usize, const K: usize, const C: usize>(
    a: &SMatrix<f64, R, K>,
    b: &SMatrix<f64, C, K>,
) -> SMatrix<f64, R, C> {
    let mut out = SMatrix::<f64, R, C>::zeros();
    for j in 0..C {
        for k in 0..K {
            let scale = b[(j, k)];
            for i in 0..R {
                out[(i, j)] += a[(i, k)] * scale;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_match_nalgebra() {
        let a = SMatrix::<f64, 3, 4>::from_fn(|i, j| (i * 4 + j) as f64 - 5.5);
        let b = SMatrix::<f64, 4, 2>::from_fn(|i, j| (i as f64 + 1.0) / (j as f64 + 2.0));
        assert_eq!(mul(&a, &b), a * b);
        let c = SMatrix::<f64, 2, 4>::from_fn(|i, j| (i + j) as f64 * 0.25);
        assert_eq!(mul_t(&a, &c), a * c.transpose());
    }
}
