//! Emitter-attribute evidence between two reports (METHODS §3 "Support" and "Evidence
//! combination"): the per-attribute support of eq. 3 and its Dempster combination into the
//! mass on "the two reports are the same emitter". Used by the formation method's baseline
//! intersections and by the static association's attribute gate, so it sits below both.

use crate::error::{ensure_finite, parse_option, CoreError, CoreResult, UnknownOption};

/// How the K per-attribute supports combine into `m(assoc)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Combination {
    /// Each attribute is a simple support function (`s_k` on {assoc}, `1 − s_k` on Θ), so
    /// Dempster's rule gives `1 − Π(1 − s_k)`. The reading that reproduces the paper's
    /// Table 3 (METHODS §3); the default.
    SimpleSupport,
    /// Each attribute splits its mass between {assoc} (`s_k`) and {not} (`1 − s_k`), so
    /// `m = Π s_k / (Π s_k + Π(1 − s_k))`. Stricter: it prunes pairs the paper keeps.
    TwoOutcome,
}

impl std::str::FromStr for Combination {
    type Err = UnknownOption;

    /// `"simple"` or `"two_outcome"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("simple", Self::SimpleSupport),
            ("two_outcome", Self::TwoOutcome),
        ];
        parse_option(value, &choices, "'simple' or 'two_outcome'")
    }
}

/// Eq. 3: the support one attribute gives two reports, `exp(−Δ² / (2(σ_a² + σ_b²)))`.
#[inline]
pub fn support(value_a: f64, std_a: f64, value_b: f64, std_b: f64) -> f64 {
    let diff = value_a - value_b;
    (-diff * diff / (2.0 * (std_a * std_a + std_b * std_b))).exp()
}

/// The attribute columns of a measurement table, attribute-major (`K × N`: column `i` is
/// `values[i N .. (i + 1) N]`, as NumPy stacks a table's columns without a transpose), with
/// stds either per value (`K × N`) or per attribute (`K`). Borrowed, validated once.
#[derive(Clone, Copy, Debug)]
pub struct AttributeTable<'a> {
    values: &'a [f64],
    stds: &'a [f64],
    n_rows: usize,
    n_attributes: usize,
    /// 1 when `stds` has one value per row, 0 when one per attribute.
    std_row_step: usize,
}

impl<'a> AttributeTable<'a> {
    /// Checks `values` is `n_attributes × n_rows` and finite, and `stds` is the same shape or
    /// one per attribute, finite and `> 0` (a zero std would make eq. 3 a 0/0 for two equal
    /// values).
    ///
    /// ```
    /// use passive_assoc_core::evidence::AttributeTable;
    /// let t = AttributeTable::new(&[1.0, 2.0], &[0.5, 0.5], 2, 1).unwrap();
    /// assert_eq!(t.n_attributes(), 1);
    /// assert!(AttributeTable::new(&[1.0, 2.0], &[0.5], 2, 1).is_ok()); // one std per attribute
    /// assert!(AttributeTable::new(&[1.0, 2.0], &[0.5, 0.0], 2, 1).is_err());
    /// ```
    pub fn new(
        values: &'a [f64],
        stds: &'a [f64],
        n_rows: usize,
        n_attributes: usize,
    ) -> CoreResult<Self> {
        let per_value = n_rows.checked_mul(n_attributes);
        if per_value != Some(values.len()) {
            return Err(CoreError::shape(
                "attributes",
                format!(
                    "expected {n_attributes} attributes × {n_rows} rows, got {} values",
                    values.len()
                ),
            ));
        }
        let std_row_step = match stds.len() {
            len if Some(len) == per_value => 1,
            len if len == n_attributes => 0,
            len => {
                return Err(CoreError::shape(
                    "attribute_std",
                    format!(
                        "expected {n_attributes} × {n_rows} values or {n_attributes}, got {len}"
                    ),
                ))
            }
        };
        ensure_finite("attributes", values)?;
        if let Some(index) = stds.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
            let row_count = if std_row_step == 1 { n_rows.max(1) } else { 1 };
            return Err(CoreError::out_of_range(
                "attribute_std",
                format!(
                    "attribute {} (row {}) has std {}, must be finite and > 0",
                    index / row_count,
                    index % row_count,
                    stds[index]
                ),
            ));
        }
        Ok(Self {
            values,
            stds,
            n_rows,
            n_attributes,
            std_row_step,
        })
    }

    /// Rows of the table, which must be those of the measurement table it describes.
    pub fn n_rows(&self) -> usize {
        self.n_rows
    }

    pub fn n_attributes(&self) -> usize {
        self.n_attributes
    }

    /// `m(assoc)` of rows `a` and `b` under `combination` (callers guarantee both rows exist).
    /// With no attributes there is no evidence either way: 1, so no gate ever drops a pair.
    pub fn association_mass(&self, a: usize, b: usize, combination: Combination) -> f64 {
        let k = self.n_attributes;
        if k == 0 {
            return 1.0; // both empty products would otherwise give 0 (simple) or ½ (two-outcome)
        }
        let exponent = |i: usize| self.exponent(a, b, i);
        match combination {
            Combination::SimpleSupport => {
                // exp(−x) < 2⁻⁵⁷ for x > 40, so 1 − s rounds to exactly 1: skipping the exp
                // changes no bit, and it is most pairs (emitters that differ in an attribute).
                let miss: f64 = (0..k)
                    .map(|i| match exponent(i) {
                        x if x > NEGLIGIBLE_EXPONENT => 1.0,
                        x => 1.0 - (-x).exp(),
                    })
                    .product();
                1.0 - miss
            }
            Combination::TwoOutcome => two_outcome((0..k).map(|i| (-exponent(i)).exp())),
        }
    }
}

impl AttributeTable<'_> {
    /// Eq. 3's exponent `Δ² / (2(σ_a² + σ_b²))` of attribute `i` for rows `a` and `b`.
    #[inline]
    fn exponent(&self, a: usize, b: usize, i: usize) -> f64 {
        let (diff, variance) = self.difference(a, b, i);
        diff * diff / (2.0 * variance)
    }

    /// `(f_a − f_b, σ_a² + σ_b²)` of attribute `i`.
    #[inline]
    fn difference(&self, a: usize, b: usize, i: usize) -> (f64, f64) {
        let column = i * self.n_rows;
        let std_column = i * (self.n_rows * self.std_row_step).max(1);
        let sa = self.stds[std_column + a * self.std_row_step];
        let sb = self.stds[std_column + b * self.std_row_step];
        (
            self.values[column + a] - self.values[column + b],
            sa * sa + sb * sb,
        )
    }

    /// Whether attribute `i`'s exponent exceeds `threshold`, without the division.
    #[inline]
    fn exponent_above(&self, a: usize, b: usize, i: usize, threshold: f64) -> bool {
        let (diff, variance) = self.difference(a, b, i);
        diff * diff > threshold * (2.0 * variance)
    }
}

/// Above this exponent eq. 3's support is below half an ulp of 1 (see `association_mass`).
const NEGLIGIBLE_EXPONENT: f64 = 40.0;

/// `Π s / (Π s + Π(1 − s))`. When both products vanish (one attribute says certainly the
/// same emitter, another certainly not) the sources are in total conflict and Dempster's rule
/// is undefined; the gate reads that as no support (0), so the pair is dropped.
fn two_outcome(supports: impl Iterator<Item = f64>) -> f64 {
    let (agree, disagree) = supports.fold((1.0, 1.0), |(a, d), s| (a * s, d * (1.0 - s)));
    let total = agree + disagree;
    if total > 0.0 {
        agree / total
    } else {
        0.0
    }
}

/// The attribute test of a gate: rows whose `m(assoc)` is below `eta` are not the same emitter.
#[derive(Clone, Copy, Debug)]
pub struct AttributeGate<'a> {
    pub table: AttributeTable<'a>,
    pub combination: Combination,
    eta: f64,
    /// A pair whose every exponent exceeds this cannot reach η (see [`Self::admitted_mass`]).
    reject_above: f64,
}

impl<'a> AttributeGate<'a> {
    /// `eta` must lie in (0, 1): 0 would keep everything, 1 would need certainty.
    pub fn new(table: AttributeTable<'a>, combination: Combination, eta: f64) -> CoreResult<Self> {
        if !(eta > 0.0 && eta < 1.0) {
            return Err(CoreError::out_of_range(
                "eta",
                format!("{eta} must lie in (0, 1)"),
            ));
        }
        let k = table.n_attributes() as f64;
        let reject_above = match combination {
            Combination::SimpleSupport if k > 0.0 => {
                // Every factor 1 − s_k above (1 − η)^{1/K} makes Π(1 − s_k) > 1 − η. The
                // margin keeps the decision far from rounding (it moves the product by
                // ≳ 1e-12 relative, the float error by ~1e-16).
                let per_factor = (1.0 - eta).powf(1.0 / k);
                let exponent = -(-per_factor).ln_1p();
                exponent + 1e-6 * exponent.max(1.0)
            }
            _ => f64::INFINITY,
        };
        Ok(Self {
            table,
            combination,
            eta,
            reject_above,
        })
    }

    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// `m(assoc)` of rows `a` and `b`.
    #[inline]
    pub fn mass(&self, a: usize, b: usize) -> f64 {
        self.table.association_mass(a, b, self.combination)
    }

    /// `m(assoc)` of rows `a` and `b` when it reaches η, else `None`. Under the simple
    /// reading a pair that differs clearly in every attribute is refused without one `exp`
    /// (most pairs of a real scene); the decision is the same as `mass(a, b) >= eta`'s.
    #[inline]
    pub fn admitted_mass(&self, a: usize, b: usize) -> Option<f64> {
        let k = self.table.n_attributes();
        if (0..k).all(|i| self.table.exponent_above(a, b, i, self.reject_above)) {
            return None;
        }
        let mass = self.mass(a, b);
        (mass >= self.eta).then_some(mass)
    }

    /// Whether rows `a` and `b` may be the same emitter.
    #[inline]
    pub fn admits(&self, a: usize, b: usize) -> bool {
        self.admitted_mass(a, b).is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_support_matches_the_closed_form_and_the_paper_pair() {
        // Targets 1 and 4 of the paper (RF, PRF, PW, ASP) with σ = (10, 5, 0.2, 0.2).
        // Attribute-major: (RF of both rows), (PRF of both), ...; one std per attribute.
        let values = [4008.0, 3987.0, 1005.0, 994.0, 4.9, 5.1, 2.2, 1.8];
        let stds = [10.0, 5.0, 0.2, 0.2];
        let table = AttributeTable::new(&values, &stds, 2, 4).expect("valid");
        let per_value = [10.0, 10.0, 5.0, 5.0, 0.2, 0.2, 0.2, 0.2];
        let expanded = AttributeTable::new(&values, &per_value, 2, 4).expect("valid");
        let s: Vec<f64> = (0..4)
            .map(|k| support(values[2 * k], stds[k], values[2 * k + 1], stds[k]))
            .collect();
        let simple = 1.0 - s.iter().map(|v| 1.0 - v).product::<f64>();
        let mass = table.association_mass(0, 1, Combination::SimpleSupport);
        assert!((mass - simple).abs() < 1e-15);
        assert_eq!(
            mass,
            expanded.association_mass(0, 1, Combination::SimpleSupport)
        );
        assert!(mass > 0.6, "the paper keeps T1–T4: {mass}");
        let strict = table.association_mass(0, 1, Combination::TwoOutcome);
        assert!(strict < 0.6, "the two-outcome reading prunes it: {strict}");
        assert_eq!(
            table.association_mass(0, 0, Combination::SimpleSupport),
            1.0
        );
    }

    #[test]
    fn the_quick_refusal_decides_as_the_full_mass_does() {
        // Pairs straddling the threshold: attribute differences on a fine grid around the
        // exponent where a pair of equal exponents sits exactly at η.
        let mut values = vec![0.0; 6];
        let stds = [1.0; 3];
        let mut rows = Vec::new();
        for step in 0..4000 {
            let d = 0.5 + step as f64 * 1e-3;
            values.clear();
            values.extend([0.0, d, 0.0, d, 0.0, d * 0.999]); // attribute-major, 2 rows
            rows.push(values.clone());
        }
        for eta in [0.05, 0.6, 0.95] {
            for row in &rows {
                let table = AttributeTable::new(row, &stds, 2, 3).expect("valid");
                let gate =
                    AttributeGate::new(table, Combination::SimpleSupport, eta).expect("gate");
                assert_eq!(
                    gate.admits(0, 1),
                    gate.mass(0, 1) >= eta,
                    "{row:?} at {eta}"
                );
            }
        }
    }

    #[test]
    fn total_conflict_is_no_support_and_eta_is_checked() {
        assert_eq!(two_outcome([1.0, 0.0].into_iter()), 0.0);
        assert!((two_outcome([0.5, 0.5].into_iter()) - 0.5).abs() < 1e-15);
        let table = AttributeTable::new(&[], &[], 3, 0).expect("no attributes");
        assert_eq!(table.association_mass(0, 2, Combination::TwoOutcome), 1.0);
        for eta in [0.0, 1.0, f64::NAN, -0.1] {
            assert!(AttributeGate::new(table, Combination::SimpleSupport, eta).is_err());
        }
        assert!("dempster".parse::<Combination>().is_err());
    }
}
