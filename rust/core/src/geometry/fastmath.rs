//! A hand-rolled arctangent for the residual kernels. Every Gauss-Newton and closeness
//! evaluation takes two arctangents per measurement; glibc's `atan2` costs ~170 instructions
//! a call (measured with callgrind: a third of a 6-D fit), while the residual arctangent is
//! almost always of a small angle with a positive cosine, where one rational approximation
//! suffices. Accuracy is that of Cephes' `atan` (≈ 1 ulp), checked against `f64::atan2`.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

const P: [f64; 5] = [
    -8.750_608_600_031_904e-1,
    -1.615_753_718_733_365_1e1,
    -7.500_855_792_314_705e1,
    -1.228_866_684_490_136_2e2,
    -6.485_021_904_942_025e1,
];
const Q: [f64; 5] = [
    2.485_846_490_142_306_4e1,
    1.650_270_098_316_988_6e2,
    4.328_810_604_912_903e2,
    4.853_903_996_359_137e2,
    1.945_506_571_482_614e2,
];
/// tan(3π/8).
const T3P8: f64 = 2.414_213_562_373_095;
/// The low-order bits of π/4 lost in its f64 rounding (Cephes' MOREBITS).
const MOREBITS: f64 = 6.123_233_995_736_766e-17;

/// arctan(t) for finite `t` (Cephes range reduction and rational approximation).
#[inline(always)]
pub fn atan(t: f64) -> f64 {
    let x = t.abs();
    let (base, reduced, extra) = if x > T3P8 {
        (FRAC_PI_2, -1.0 / x, MOREBITS)
    } else if x > 0.66 {
        (FRAC_PI_4, (x - 1.0) / (x + 1.0), 0.5 * MOREBITS)
    } else {
        (0.0, x, 0.0)
    };
    let z = reduced * reduced;
    let p = (((P[0] * z + P[1]) * z + P[2]) * z + P[3]) * z + P[4];
    let q = ((((z + Q[0]) * z + Q[1]) * z + Q[2]) * z + Q[3]) * z + Q[4];
    let y = base + (reduced * (z * p / q) + reduced + extra);
    y.copysign(t)
}

/// atan2(y, x) in (−π, π]: the fast path for x > 0 (|angle| < π/2, the residual case),
/// the standard library otherwise.
#[inline(always)]
pub fn atan2(y: f64, x: f64) -> f64 {
    let t = y / x;
    if x > 0.0 && t.is_finite() {
        atan(t)
    } else {
        y.atan2(x)
    }
}

/// atan2(y, x) in (−π, π] for every quadrant: [`atan`] of `y/x`, moved by π when x < 0; the
/// standard library where `y/x` is not finite or x is 0. For a window test that predicts an
/// azimuth in any direction (module `fti::witness_gate`); within a few ulp of `f64::atan2`.
#[inline(always)]
pub fn atan2_any(y: f64, x: f64) -> f64 {
    let t = y / x;
    if !t.is_finite() || x == 0.0 {
        return y.atan2(x);
    }
    match x > 0.0 {
        true => atan(t),
        false => atan(t) + std::f64::consts::PI.copysign(y),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (f64::EPSILON * b.abs().max(f64::MIN_POSITIVE))
    }

    #[test]
    fn atan_matches_the_standard_library_to_two_ulp() {
        let mut worst: f64 = 0.0;
        for k in -200_000..=200_000 {
            // Dense near 0, then out to ±1e6.
            let t = (k as f64 * 1e-4).sinh();
            let err = ulps(atan(t), t.atan());
            worst = worst.max(err);
        }
        assert!(worst <= 2.0, "worst error {worst} ulp");
    }

    #[test]
    fn atan2_matches_everywhere_including_the_fallback() {
        for ours in [atan2 as fn(f64, f64) -> f64, atan2_any] {
            for i in -60..=60 {
                for j in -60..=60 {
                    let (y, x) = (i as f64 * 0.37, j as f64 * 0.53);
                    let (ours, std) = (ours(y, x), y.atan2(x));
                    assert!(
                        (ours - std).abs() <= 4.0 * f64::EPSILON * std.abs().max(1e-300),
                        "{y} {x}: {ours} vs {std}"
                    );
                }
            }
        }
        for (y, x) in [
            (0.0, -1.0),
            (-0.0, -1.0),
            (1e-300, -1.0),
            (-1e-300, -1.0),
            (2.0, -1e-300),
        ] {
            assert_eq!(atan2_any(y, x), f64::atan2(y, x), "{y} {x}");
        }
        assert_eq!(atan2(0.0, 1.0), 0.0);
        assert_eq!(atan2(1.0, 0.0), FRAC_PI_2);
        assert!(atan2(f64::NAN, 1.0).is_nan());
    }
}
