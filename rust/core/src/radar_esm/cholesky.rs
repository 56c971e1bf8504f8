//! The pair kernel's linear algebra: `dᵀ S⁻¹ d` for small symmetric positive-definite S by
//! a Cholesky factorisation and one forward substitution, hand-rolled on flat slices, for L
//! independent (S, d) at once.
//!
//! Why not nalgebra: the coarse gate factors one c × c matrix (c ≈ 6) per pair and
//! coordinate, 250 000 of them for 500 × 500 tracks. At that size the work is ~60 flops and
//! nalgebra's per-call cost (a `DMatrix` allocation per sum, the `Cholesky` wrapper, a
//! separate solve and a dot product) dominates it. Here the factorisation and the solve run
//! in one pass over S in place, on stack buffers whose size the caller fixes at compile time
//! for the common c, so the loops unroll. One factorisation is a chain of c square roots and
//! divisions, each row waiting for the last; running L pairs side by side ("lanes", the
//! innermost index) overlaps those chains and lets the compiler use SIMD. Each lane's
//! arithmetic is the same sequence of operations whatever L, so a pair's result does not
//! depend on which lane or group computed it.

/// A pivot at most this fraction of its diagonal entry means S is singular to working
/// precision (a condition number beyond ~10¹²): the quadratic form would be rounding noise.
pub(super) const PIVOT_TOLERANCE: f64 = 1e-12;

/// `dᵀ S⁻¹ d` of L lanes: S (`c × c` lane vectors, row-major, only the lower triangle read)
/// and d (c lane vectors).
///
/// Row by row, S = L Lᵀ and L y = d; then `dᵀ S⁻¹ d = |y|²`. Overwrites S's strict lower
/// triangle with L, its diagonal with `1 / L_ii`, and d with y. Returns the forms and, per
/// lane, whether S was positive definite (every pivot > [`PIVOT_TOLERANCE`] × its diagonal
/// and finite); a lane that was not holds no meaningful form.
// The lane loops index several lane vectors in lockstep, which is clearer than nested zips.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
pub(super) fn quadratic_forms<const L: usize>(
    s: &mut [[f64; L]],
    d: &mut [[f64; L]],
) -> ([f64; L], [bool; L]) {
    let c = d.len();
    debug_assert_eq!(s.len(), c * c);
    let mut total = [0.0; L];
    let mut positive = [true; L];
    for i in 0..c {
        let (done, rest) = s.split_at_mut(i * c);
        let row = &mut rest[..c];
        // L_ij = (S_ij − Σ_{k<j} L_ik L_jk) / L_jj, for j < i.
        for j in 0..i {
            let lj = &done[j * c..j * c + j + 1];
            let mut v = row[j];
            for (r, l) in row[..j].iter().zip(&lj[..j]) {
                for x in 0..L {
                    v[x] -= r[x] * l[x];
                }
            }
            for x in 0..L {
                v[x] *= lj[j][x];
            }
            row[j] = v;
        }
        // L_ii² = S_ii − Σ_{k<i} L_ik².
        let diagonal = row[i];
        let mut pivot = diagonal;
        for r in &row[..i] {
            for x in 0..L {
                pivot[x] -= r[x] * r[x];
            }
        }
        let mut inverse = [0.0; L];
        for x in 0..L {
            positive[x] &= pivot[x] > PIVOT_TOLERANCE * diagonal[x] && pivot[x].is_finite();
            inverse[x] = 1.0 / pivot[x].sqrt();
        }
        row[i] = inverse;
        // y_i = (d_i − Σ_{k<i} L_ik y_k) / L_ii.
        let mut y = d[i];
        for (r, yk) in row[..i].iter().zip(&d[..i]) {
            for x in 0..L {
                y[x] -= r[x] * yk[x];
            }
        }
        for x in 0..L {
            y[x] *= inverse[x];
            total[x] += y[x] * y[x];
        }
        d[i] = y;
    }
    (total, positive)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One lane: the form, or None if S is not positive definite.
    fn form(s: &[f64], d: &[f64]) -> Option<f64> {
        let mut s: Vec<[f64; 1]> = s.iter().map(|&v| [v]).collect();
        let mut d: Vec<[f64; 1]> = d.iter().map(|&v| [v]).collect();
        let (q, ok) = quadratic_forms(&mut s, &mut d);
        ok[0].then_some(q[0])
    }

    #[test]
    fn two_by_two_by_hand() {
        // S = [[2, 1], [1, 1]], S⁻¹ = [[1, −1], [−1, 2]].
        for (d, expected) in [([1.0, 0.0], 1.0), ([0.0, 1.0], 2.0), ([1.0, 1.0], 1.0)] {
            let q = form(&[2.0, 1.0, 1.0, 1.0], &d).unwrap();
            assert!((q - expected).abs() < 1e-14, "{q} vs {expected}");
        }
    }

    #[test]
    fn reads_only_the_lower_triangle() {
        // S = [[4, 2], [2, 5]], det 16, S⁻¹ = [[5, −2], [−2, 4]] / 16: (20 − 8 + 4) / 16 = 1.
        let q = form(&[4.0, f64::NAN, 2.0, 5.0], &[2.0, 1.0]).unwrap();
        assert!((q - 1.0).abs() < 1e-14);
    }

    #[test]
    fn singular_and_indefinite_are_refused() {
        assert!(form(&[1.0, 1.0, 1.0, 1.0], &[1.0, 0.0]).is_none());
        assert!(form(&[1.0, 2.0, 2.0, 1.0], &[1.0, 0.0]).is_none());
        assert!(form(&[0.0], &[1.0]).is_none());
        assert!(form(&[f64::INFINITY], &[1.0]).is_none());
    }

    #[test]
    fn lanes_are_independent_and_equal_to_one_lane() {
        let matrices = [
            [2.0, 0.0, 1.0, 1.0],
            [1.0, 0.0, 2.0, 1.0], // indefinite
            [4.0, 0.0, 2.0, 5.0],
            [3.0, 0.0, 0.5, 0.25],
        ];
        let vectors = [[1.0, -2.0], [1.0, 0.0], [2.0, 1.0], [0.3, 0.7]];
        let mut s = [[0.0; 4]; 4];
        let mut d = [[0.0; 4]; 2];
        for lane in 0..4 {
            for e in 0..4 {
                s[e][lane] = matrices[lane][e];
            }
            for r in 0..2 {
                d[r][lane] = vectors[lane][r];
            }
        }
        let (q, ok) = quadratic_forms(&mut s, &mut d);
        for lane in 0..4 {
            let alone = form(&matrices[lane], &vectors[lane]);
            assert_eq!(ok[lane], alone.is_some(), "lane {lane}");
            if let Some(expected) = alone {
                assert_eq!(q[lane].to_bits(), expected.to_bits(), "lane {lane}");
            }
        }
    }
}
