//! The quantiles the final track test reads its levels from: the standard normal's, by
//! Wichura's algorithm AS 241 (PPND16, relative error about 10⁻¹⁶), and χ²'s by the
//! Wilson–Hilferty approximation at a standard-normal level.

/// `Φ⁻¹(p)`, the standard normal quantile (AS 241 PPND16, Wichura 1988; accurate to about
/// 10⁻¹⁶ relative, and within a few units in the last place of SciPy's `ndtri`). `p` in
/// (0, 1); NaN outside, ±∞ at 0 and 1.
///
/// ```
/// use passive_assoc_core::fti::normal_quantile;
/// assert_eq!(normal_quantile(0.5), 0.0);
/// assert!((normal_quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-15);
/// assert!(normal_quantile(1e-6) < -4.75 && normal_quantile(0.0).is_infinite());
/// ```
#[allow(clippy::excessive_precision)] // AS 241's coefficients as published, rounded by the compiler
pub fn normal_quantile(p: f64) -> f64 {
    // Coefficients of AS 241 (Appl. Statist. 37(3), 477–484), in the published digits.
    const A: [f64; 8] = [
        3.387_132_872_796_366_608,
        1.331_416_678_917_843_774_5e2,
        1.971_590_950_306_551_442_7e3,
        1.373_169_376_550_946_112_5e4,
        4.592_195_393_154_987_145_7e4,
        6.726_577_092_700_870_085_3e4,
        3.343_057_558_358_812_810_5e4,
        2.509_080_928_730_122_672_7e3,
    ];
    const B: [f64; 8] = [
        1.0,
        4.231_333_070_160_091_125_2e1,
        6.871_870_074_920_579_083e2,
        5.394_196_021_424_751_107_7e3,
        2.121_379_430_158_659_586_7e4,
        3.930_789_580_009_271_061e4,
        2.872_908_573_572_194_267_4e4,
        5.226_495_278_852_854_561e3,
    ];
    const C: [f64; 8] = [
        1.423_437_110_749_683_577_34,
        4.630_337_846_156_545_295_9,
        5.769_497_221_460_691_405_5,
        3.647_848_324_763_204_605_04,
        1.270_458_252_452_368_382_58,
        2.417_807_251_774_506_117_7e-1,
        2.272_384_498_926_918_458_33e-2,
        7.745_450_142_783_414_076_4e-4,
    ];
    const D: [f64; 8] = [
        1.0,
        2.053_191_626_637_758_821_87,
        1.676_384_830_183_803_849_4,
        6.897_673_349_851_000_045_5e-1,
        1.481_039_764_274_800_745_9e-1,
        1.519_866_656_361_645_719_66e-2,
        5.475_938_084_995_344_946e-4,
        1.050_750_071_644_416_843_24e-9,
    ];
    const E: [f64; 8] = [
        6.657_904_643_501_103_777_2,
        5.463_784_911_164_114_369_9,
        1.784_826_539_917_291_335_8,
        2.965_605_718_285_048_912_3e-1,
        2.653_218_952_657_612_309_3e-2,
        1.242_660_947_388_078_438_6e-3,
        2.711_555_568_743_487_578_15e-5,
        2.010_334_399_292_288_132_65e-7,
    ];
    const F: [f64; 8] = [
        1.0,
        5.998_322_065_558_879_376_9e-1,
        1.369_298_809_227_358_053_1e-1,
        1.487_536_129_085_061_485_25e-2,
        7.868_691_311_456_132_591e-4,
        1.846_318_317_510_054_681_8e-5,
        1.421_511_758_316_445_888_7e-7,
        2.044_263_103_389_939_785_64e-15,
    ];
    // Horner's rule, highest degree first (plain multiply-add, as the published algorithm).
    let poly = |c: &[f64; 8], x: f64| c[..7].iter().rev().fold(c[7], |v, &k| v * x + k);
    if p.is_nan() || !(0.0..=1.0).contains(&p) {
        return f64::NAN;
    }
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180_625 - q * q;
        return q * poly(&A, r) / poly(&B, r);
    }
    let tail = if q < 0.0 { p } else { 1.0 - p };
    if tail == 0.0 {
        return if q < 0.0 {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        };
    }
    let r = (-tail.ln()).sqrt();
    let value = if r <= 5.0 {
        let r = r - 1.6;
        poly(&C, r) / poly(&D, r)
    } else {
        let r = r - 5.0;
        poly(&E, r) / poly(&F, r)
    };
    if q < 0.0 {
        -value
    } else {
        value
    }
}

/// The standard-normal level z of an upper tail probability `tail`: `P(Z > z) = tail`,
/// computed as `−Φ⁻¹(tail)` so that small tails keep their precision.
pub fn upper_normal_level(tail: f64) -> f64 {
    -normal_quantile(tail)
}

/// χ²(dof) quantile at standard-normal level `z` by Wilson–Hilferty (conservative, i.e.
/// slightly high, at few degrees of freedom; within 3 % from 10).
///
/// ```
/// use passive_assoc_core::fti::{chi2_quantile, normal_quantile};
/// let z = -normal_quantile(1e-6);
/// // SciPy's chi2.isf(1e-6, k) is 27.63, 46.86 and 182.13 at k = 2, 10, 100.
/// assert!((30.0..30.5).contains(&chi2_quantile(2.0, z)));
/// assert!((46.86..48.3).contains(&chi2_quantile(10.0, z)));
/// assert!((182.1..182.7).contains(&chi2_quantile(100.0, z)));
/// ```
pub fn chi2_quantile(dof: f64, z: f64) -> f64 {
    let h = 2.0 / (9.0 * dof);
    dof * (1.0 - h + z * h.sqrt()).powi(3)
}

#[cfg(test)]
mod tests {
    use super::{normal_quantile, upper_normal_level};

    /// Known quantiles (to 16–17 digits; the far tails as SciPy's `ndtri` gives them, which
    /// agrees with these to an ulp or two), each matched to 1e-15 relative, in both tails.
    #[test]
    fn the_normal_quantile_matches_known_values() {
        let known = [
            (0.5, 0.0),
            (0.975, 1.959_963_984_540_054),
            (0.95, 1.644_853_626_951_472_7),
            (0.9, 1.281_551_565_544_600_4),
            (0.7, 0.524_400_512_708_041),
            (0.51, 0.025_068_908_258_711_06),
        ];
        for (p, z) in known {
            for (p, z) in [(p, z), (1.0 - p, -z)] {
                let got = normal_quantile(p);
                assert!(
                    (got - z).abs() <= 1e-15 * z.abs().max(1e-300),
                    "{p}: {got} vs {z}"
                );
            }
        }
        let tails = [
            (1e-3, 3.090_232_306_167_813),
            (1e-4, 3.719_016_485_455_68),
            (1e-6, 4.753_424_308_822_899),
            (1e-10, 6.361_340_902_404_056),
            (1e-20, 9.262_340_089_798_408),
            (1e-300, 37.047_096_299_361_2),
        ];
        for (tail, z) in tails {
            let got = upper_normal_level(tail);
            assert!((got - z).abs() <= 1e-15 * z, "{tail}: {got} vs {z}");
        }
    }

    /// The default track test's level is SciPy's `-ndtri(1e-6)` to the bit, and the function
    /// is monotone and odd about ½ (up to the rounding of `1 − p`).
    #[test]
    fn the_default_level_is_scipys_to_the_bit() {
        assert_eq!(upper_normal_level(1e-6), 4.753_424_308_822_899);
        let mut last = f64::NEG_INFINITY;
        for k in 1..2000 {
            let p = k as f64 / 2000.0;
            let z = normal_quantile(p);
            assert!(z > last, "{p}");
            assert!((z + normal_quantile(1.0 - p)).abs() < 1e-12, "{p}");
            last = z;
        }
        assert!(normal_quantile(-0.1).is_nan() && normal_quantile(f64::NAN).is_nan());
        assert_eq!(normal_quantile(0.0), f64::NEG_INFINITY);
        assert_eq!(normal_quantile(1.0), f64::INFINITY);
    }
}
