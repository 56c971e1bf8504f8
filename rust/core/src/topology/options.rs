//! The topology associator's settings, built with validated `with_*` setters.

use crate::error::{parse_option, CoreError, CoreResult, UnknownOption};

/// Where sector 0 of a track's grid starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Reference {
    /// Sector 0 starts at north (+y) and sectors run clockwise (the paper's grid).
    #[default]
    North,
    /// Sector 0 starts at the track's own heading: a rotation of the whole picture then
    /// leaves every vector unchanged (METHODS §4 option).
    Heading,
}

impl std::str::FromStr for Reference {
    type Err = UnknownOption;

    /// `"north"` or `"heading"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [("north", Self::North), ("heading", Self::Heading)];
        parse_option(value, &choices, "'north' or 'heading'")
    }
}

/// How an occupied cell spreads into its neighbours (METHODS §4 "Diffusion").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Diffusion {
    /// Each occupied neighbour adds Δ (ring ± 1) or Δ′ (sector ± 1); the sum is clipped at 1.
    #[default]
    Additive,
    /// A neighbour of an occupied cell gets at least Δ (ring ± 1) or Δ′ (sector ± 1).
    AtLeast,
}

impl std::str::FromStr for Diffusion {
    type Err = UnknownOption;

    /// `"additive"` or `"at_least"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [("additive", Self::Additive), ("at_least", Self::AtLeast)];
        parse_option(value, &choices, "'additive' or 'at_least'")
    }
}

/// How one scan's pairs are chosen from the (window-averaged) scores.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Decision {
    /// Topology, then bias, then distance (the project's extension, METHODS §4 in
    /// docs/methods.md): the topology pairs register the local picture on the system's, and
    /// the pairs are decided on the registered positions' Mahalanobis distance and the
    /// closeness together (`fusion.rs`). Default.
    #[default]
    Fused,
    /// One-to-one pairs maximising the total closeness, each above the threshold.
    Assignment,
    /// The paper's rule: each system track takes its best local track if that beats the
    /// threshold; a local track claimed twice goes to the higher score.
    PerSystemTrack,
}

impl std::str::FromStr for Decision {
    type Err = UnknownOption;

    /// `"fused"`, `"assignment"` or `"per_system_track"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("fused", Self::Fused),
            ("assignment", Self::Assignment),
            ("per_system_track", Self::PerSystemTrack),
        ];
        parse_option(
            value,
            &choices,
            "'fused', 'assignment' or 'per_system_track'",
        )
    }
}

/// Which (local, system) pairs a scan scores at all.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Gate {
    /// Every pair (the paper's).
    Off,
    /// The pairs within this many metres (in 3-D where the scans carry heights).
    Distance(f64),
    /// The pairs the sensors' bias bound and the tracks' covariances allow: within
    /// `2·max_bias·max_range + 3·sqrt(tr P_i + tr P_j)` metres (planar; without covariances,
    /// the first term alone). Default.
    #[default]
    Auto,
}

/// The reference-topology grid and its diffusion (METHODS §4).
///
/// ```
/// use passive_assoc_core::topology::TopologyOptions;
/// let o = TopologyOptions::default().with_rings(4).unwrap().with_sectors(12).unwrap();
/// assert_eq!(o.cells(), 48);
/// assert!(TopologyOptions::default().with_delta(1.5).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopologyOptions {
    rings: usize,
    sectors: usize,
    radius: f64,
    delta: f64,
    delta_prime: f64,
    diffusion: Diffusion,
    reference: Reference,
}

impl Default for TopologyOptions {
    /// [`TopologyOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl TopologyOptions {
    /// The project's defaults, those of the Python package (`TopologyAssociator`): 4 rings ×
    /// 12 sectors (30°, wider than a 10° relative bias) of a 120 km disc, Δ = 0.5, Δ′ = 0.7,
    /// additive diffusion, north reference (`heading_reference=False`).
    pub fn recommended() -> Self {
        Self {
            rings: 4,
            sectors: 12,
            radius: 120e3,
            delta: 0.5,
            delta_prime: 0.7,
            diffusion: Diffusion::Additive,
            reference: Reference::North,
        }
    }

    /// The published grid (METHODS §4, paper 002): the same as
    /// [`recommended`](Self::recommended). The paper's diffusion adds Δ and its sectors start
    /// at north; it gives no M, N, R_ref, Δ or Δ′, so those are the recommended ones.
    pub fn paper() -> Self {
        Self::recommended()
    }
}

/// The largest grid accepted: a vector per track is allocated with this many cells.
pub const MAX_CELLS: usize = 1 << 16;

impl TopologyOptions {
    /// M, the rings of equal radial width, at least 1.
    pub fn with_rings(mut self, rings: usize) -> CoreResult<Self> {
        self.rings = check_count("rings", rings)?;
        check_cells(self.rings, self.sectors)?;
        Ok(self)
    }

    /// N, the sectors of equal angle, at least 1.
    pub fn with_sectors(mut self, sectors: usize) -> CoreResult<Self> {
        self.sectors = check_count("sectors", sectors)?;
        check_cells(self.rings, self.sectors)?;
        Ok(self)
    }

    /// R_ref, the disc's radius in metres: finite and > 0.
    pub fn with_radius(mut self, radius: f64) -> CoreResult<Self> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(CoreError::out_of_range(
                "radius",
                format!("{radius} must be finite and > 0"),
            ));
        }
        self.radius = radius;
        Ok(self)
    }

    /// Δ, the spread to ring ± 1, in [0, 1].
    pub fn with_delta(mut self, delta: f64) -> CoreResult<Self> {
        self.delta = check_unit("delta", delta)?;
        Ok(self)
    }

    /// Δ′, the spread to sector ± 1, in [0, 1] (the paper wants Δ′ ≥ Δ: sectors absorb the
    /// bias as well as the noise).
    pub fn with_delta_prime(mut self, delta_prime: f64) -> CoreResult<Self> {
        self.delta_prime = check_unit("delta_prime", delta_prime)?;
        Ok(self)
    }

    pub fn with_diffusion(mut self, diffusion: Diffusion) -> Self {
        self.diffusion = diffusion;
        self
    }

    pub fn with_reference(mut self, reference: Reference) -> Self {
        self.reference = reference;
        self
    }

    pub fn rings(&self) -> usize {
        self.rings
    }

    pub fn sectors(&self) -> usize {
        self.sectors
    }

    /// M·N, the length of a topology vector.
    pub fn cells(&self) -> usize {
        self.rings * self.sectors
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }

    pub fn delta(&self) -> f64 {
        self.delta
    }

    pub fn delta_prime(&self) -> f64 {
        self.delta_prime
    }

    pub fn diffusion(&self) -> Diffusion {
        self.diffusion
    }

    pub fn reference(&self) -> Reference {
        self.reference
    }
}

/// How pairs are decided from scores (closeness W, or minus a distance for the
/// nearest-neighbour baseline).
///
/// ```
/// use passive_assoc_core::topology::DecisionOptions;
/// use passive_assoc_core::topology::Gate;
/// let o = DecisionOptions::default().with_window(3).unwrap().with_gate(Gate::Distance(60e3)).unwrap();
/// assert_eq!(o.window(), 3);
/// assert!(DecisionOptions::default().with_window(0).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecisionOptions {
    threshold: f64,
    window: usize,
    gate: Gate,
    chi2_gate: Option<f64>,
    decision: Decision,
    max_bias_deg: f64,
    max_range: f64,
    gate_probability: f64,
    topology_weight: f64,
}

impl Default for DecisionOptions {
    /// [`DecisionOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

/// λ, the recommended decision threshold as a fraction of the grid's M·N cells (the Python
/// `TopologyAssociator`'s `threshold`).
pub const THRESHOLD_FRACTION: f64 = 0.7;

impl DecisionOptions {
    /// The project's defaults for the topology associator, the Python package's
    /// (`TopologyAssociator`): threshold λ·M·N with λ = [`THRESHOLD_FRACTION`] on the
    /// recommended 4 × 12 grid (33.6; with another grid, set λ·M·N), a window of 6 scans, the
    /// [`Gate::Auto`] gate from a bias bound of 5° per sensor and a 400 km range, the
    /// [`Decision::Fused`] decision with a 0.999 Mahalanobis gate and a topology weight of 10.
    /// The nearest-neighbour baseline scores minus distances: give it `threshold = −gate` and
    /// its own gate.
    pub fn recommended() -> Self {
        let grid = TopologyOptions::recommended();
        Self {
            threshold: THRESHOLD_FRACTION * grid.rings as f64 * grid.sectors as f64,
            window: 6,
            gate: Gate::Auto,
            chi2_gate: None,
            decision: Decision::Fused,
            max_bias_deg: 5.0,
            max_range: 400e3,
            gate_probability: 0.999,
            topology_weight: 10.0,
        }
    }

    /// The published decision (METHODS §4): the paper's per-system-track rule on the
    /// closeness alone, every pair scored (no gate). The paper gives no λ and keeps no window
    /// (its "association quality" has no rule; the window is the project's reading): those
    /// are the recommended ones, as are the fused decision's settings, which it does not
    /// read.
    pub fn paper() -> Self {
        Self {
            decision: Decision::PerSystemTrack,
            gate: Gate::Off,
            ..Self::recommended()
        }
    }

    /// A pair needs a window-averaged score strictly above this (finite), in score units:
    /// for topology scoring a closeness W out of M·N, so the Python `threshold` λ (a fraction
    /// of M·N) is `threshold / (M·N)`; for distance scoring minus metres.
    pub fn with_threshold(mut self, threshold: f64) -> CoreResult<Self> {
        if !threshold.is_finite() {
            return Err(CoreError::out_of_range(
                "threshold",
                format!("{threshold} must be finite"),
            ));
        }
        self.threshold = threshold;
        Ok(self)
    }

    /// Scans averaged, the current one included; at least 1 (1 = no memory).
    pub fn with_window(mut self, window: usize) -> CoreResult<Self> {
        self.window = check_count("window", window)?;
        Ok(self)
    }

    /// Which pairs are scored: every pair, those within a distance (metres, finite and > 0),
    /// or those the bias bound and covariances allow.
    pub fn with_gate(mut self, gate: Gate) -> CoreResult<Self> {
        if let Gate::Distance(g) = gate {
            if !(g.is_finite() && g > 0.0) {
                return Err(CoreError::out_of_range(
                    "gate",
                    format!("{g} must be finite and > 0 (or None)"),
                ));
            }
        }
        self.gate = gate;
        Ok(self)
    }

    /// Each sensor's largest azimuth bias, degrees, in [0, 45]: two sensors' pictures are
    /// turned by at most twice this relative to each other.
    pub fn with_max_bias_deg(mut self, max_bias_deg: f64) -> CoreResult<Self> {
        if !(0.0..=45.0).contains(&max_bias_deg) {
            return Err(CoreError::out_of_range(
                "max_bias_deg",
                format!("{max_bias_deg} must be in [0, 45]"),
            ));
        }
        self.max_bias_deg = max_bias_deg;
        Ok(self)
    }

    /// The sensors' range, metres (finite, > 0): the lever of the bias bound.
    pub fn with_max_range(mut self, max_range: f64) -> CoreResult<Self> {
        if !(max_range.is_finite() && max_range > 0.0) {
            return Err(CoreError::out_of_range(
                "max_range",
                format!("{max_range} must be finite and > 0"),
            ));
        }
        self.max_range = max_range;
        Ok(self)
    }

    /// The fused decision's Mahalanobis gate, as the probability (in (0, 1)) that a true
    /// pair's registered positions pass it.
    pub fn with_gate_probability(mut self, gate_probability: f64) -> CoreResult<Self> {
        if !(gate_probability > 0.0 && gate_probability < 1.0) {
            return Err(CoreError::out_of_range(
                "gate_probability",
                format!("{gate_probability} must be in (0, 1)"),
            ));
        }
        self.gate_probability = gate_probability;
        Ok(self)
    }

    /// κ, the weight of the closeness fraction W/(M·N) in the fused score `κ·W/(M·N) − m/2`
    /// (finite, ≥ 0; 0 decides on the registered distance alone).
    pub fn with_topology_weight(mut self, topology_weight: f64) -> CoreResult<Self> {
        if !(topology_weight.is_finite() && topology_weight >= 0.0) {
            return Err(CoreError::out_of_range(
                "topology_weight",
                format!("{topology_weight} must be finite and >= 0"),
            ));
        }
        self.topology_weight = topology_weight;
        Ok(self)
    }

    /// Pairs whose current positions give `dᵀ(P_i + P_j)⁻¹d` above this (> 0) are never
    /// made (the scans must carry position covariances); `None` = no χ² gate.
    pub fn with_chi2_gate(mut self, chi2_gate: Option<f64>) -> CoreResult<Self> {
        if let Some(g) = chi2_gate {
            if !(g.is_finite() && g > 0.0) {
                return Err(CoreError::out_of_range(
                    "chi2_gate",
                    format!("{g} must be finite and > 0 (or None)"),
                ));
            }
        }
        self.chi2_gate = chi2_gate;
        Ok(self)
    }

    pub fn with_decision(mut self, decision: Decision) -> Self {
        self.decision = decision;
        self
    }

    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    pub fn window(&self) -> usize {
        self.window
    }

    pub fn gate(&self) -> Gate {
        self.gate
    }

    /// Each sensor's bias bound, degrees.
    pub fn max_bias_deg(&self) -> f64 {
        self.max_bias_deg
    }

    /// The largest relative rotation of two pictures, radians: twice the bias bound.
    pub fn max_rotation(&self) -> f64 {
        2.0 * self.max_bias_deg.to_radians()
    }

    pub fn max_range(&self) -> f64 {
        self.max_range
    }

    /// The largest offset the two sensors' biases put between a track and its partner,
    /// metres: twice the chord `2·max_range·sin(max_bias/2)` by which a rotation of the bound
    /// moves a point at the sensors' range (≈ 70 km at 5° and 400 km).
    pub fn max_offset(&self) -> f64 {
        2.0 * 2.0 * (self.max_bias_deg.to_radians() / 2.0).sin() * self.max_range
    }

    pub fn gate_probability(&self) -> f64 {
        self.gate_probability
    }

    /// The Mahalanobis gate's χ² value for planar positions: `−2 ln(1 − p)`.
    pub fn fused_gate(&self) -> f64 {
        -2.0 * (1.0 - self.gate_probability).ln()
    }

    pub fn topology_weight(&self) -> f64 {
        self.topology_weight
    }

    pub fn chi2_gate(&self) -> Option<f64> {
        self.chi2_gate
    }

    pub fn decision(&self) -> Decision {
        self.decision
    }
}

fn check_count(arg: &'static str, value: usize) -> CoreResult<usize> {
    if value == 0 {
        return Err(CoreError::out_of_range(arg, "must be at least 1"));
    }
    Ok(value)
}

fn check_cells(rings: usize, sectors: usize) -> CoreResult<()> {
    match rings.checked_mul(sectors) {
        Some(cells) if cells <= MAX_CELLS => Ok(()),
        _ => Err(CoreError::CapExceeded {
            what: "rings × sectors",
            count: rings.saturating_mul(sectors),
            cap: MAX_CELLS,
            hint: "a grid this fine has no neighbour in most cells; use fewer rings or sectors",
        }),
    }
}

fn check_unit(arg: &'static str, value: f64) -> CoreResult<f64> {
    if !(0.0..=1.0).contains(&value) {
        return Err(CoreError::out_of_range(
            arg,
            format!("{value} must be in [0, 1]"),
        ));
    }
    Ok(value)
}
