//! Settings of the modified baseline least-distance method, built with validated `with_*`
//! setters. Checks that need the network (the baseline and reference sensors exist) run in
//! [`locate`](super::locate).

use crate::error::{parse_option, CoreError, CoreResult, UnknownOption};
use crate::estimation::fit::FitOptions;

/// Which other sensor's intersection subset supplies the reference points (step 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    /// The smallest subset, ties by the lowest sensor index: the fewest candidates to score.
    Smallest,
    /// Always this sensor (never the baseline).
    Sensor(usize),
}

/// How a candidate's clustering is measured (step 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClusterRadius {
    /// Over all `M(M−1)/2` pairwise intersections of the chosen lines, in the plane (eq. 6):
    /// the paper's modification, the default.
    Planar,
    /// Over the `M − 1` intersections on the baseline line only, i.e. along one coordinate:
    /// the unmodified method of the paper's ref. \[3\].
    AlongBaseline,
}

impl std::str::FromStr for ClusterRadius {
    type Err = UnknownOption;

    /// `"2d"` or `"1d"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [("2d", Self::Planar), ("1d", Self::AlongBaseline)];
        parse_option(value, &choices, "'2d' or '1d'")
    }
}

/// The surveillance region `[x_min, x_max] × [y_min, y_max]` (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub x: [f64; 2],
    pub y: [f64; 2],
}

impl Region {
    #[inline]
    pub fn contains(&self, point: &[f64; 2]) -> bool {
        (self.x[0]..=self.x[1]).contains(&point[0]) && (self.y[0]..=self.y[1]).contains(&point[1])
    }
}

/// Settings of [`locate`](super::locate).
///
/// ```
/// use passive_assoc_core::formation::{FormationOptions, Reference};
/// let o = FormationOptions::default()
///     .with_reference(Reference::Sensor(2)).with_r_max(150e3).unwrap();
/// assert_eq!((o.reference(), o.r_max()), (Reference::Sensor(2), 150e3));
/// assert!(FormationOptions::default().with_r_max(0.0).is_err());
/// assert!(FormationOptions::default().with_region([0.0, -1.0, 0.0, 1.0]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FormationOptions {
    baseline_sensor: usize,
    reference: Reference,
    cluster_radius: ClusterRadius,
    one_to_one: bool,
    r_max: f64,
    region: Option<Region>,
    in_front: bool,
    fit: FitOptions,
    max_pairs: usize,
}

/// The default cap on the (baseline report, other report) pairs a location examines,
/// [`FormationOptions::max_pairs`]: about 10 s of one core, and at most 800 MB of kept
/// meetings in the one-to-one mode. The paper's scene has 6 × 12 pairs, the 5 × 200 bench
/// scene 160 000; 3 sensors × 16 000 reports would be 5.1 × 10⁸ (90 CPU-s).
pub const DEFAULT_MAX_PAIRS: usize = 50_000_000;

impl Default for FormationOptions {
    /// [`FormationOptions::recommended`].
    fn default() -> Self {
        Self::recommended()
    }
}

impl FormationOptions {
    /// The project's defaults, those of the Python package (`FormationLocator`), which are
    /// the paper's settings (η and the Dempster reading belong to the attribute gate,
    /// [`crate::evidence::AttributeGate`]): baseline sensor 0, the smallest reference subset,
    /// the planar cluster radius, independent baselines, R_max = 200 km, no region, full lines
    /// (not only in front of the sensors), [`triangulation_fit_options`].
    pub fn recommended() -> Self {
        Self {
            baseline_sensor: 0,
            reference: Reference::Smallest,
            cluster_radius: ClusterRadius::Planar,
            one_to_one: false,
            r_max: 200e3,
            region: None,
            in_front: false,
            fit: triangulation_fit_options(),
            max_pairs: DEFAULT_MAX_PAIRS,
        }
    }

    /// The published method (METHODS §3, paper 004): the same as
    /// [`recommended`](Self::recommended), whose values are the paper's (R_max = 200 km, the
    /// planar "2d" radius of its modification, full lines, each baseline report decided on
    /// its own); where it is silent (the baseline sensor, "any" reference subset, the ML
    /// triangulation's tolerance) they are the recommended ones.
    pub fn paper() -> Self {
        Self::recommended()
    }
}

/// The Gauss-Newton settings of the triangulation: the library defaults, except that a step
/// shorter than 10⁻³ standard deviations ends the fit (as the static enumeration's): the start,
/// the mean of the chosen lines' intersections, is already close, and the position is then
/// within ~10⁻³σ of the ML point — far inside its own covariance — in 1–2 fewer iterations.
pub fn triangulation_fit_options() -> FitOptions {
    let defaults = FitOptions::default();
    defaults.with_step_sigmas(1e-3).unwrap_or(defaults)
}

impl FormationOptions {
    pub fn with_baseline_sensor(mut self, baseline_sensor: usize) -> Self {
        self.baseline_sensor = baseline_sensor;
        self
    }

    pub fn with_reference(mut self, reference: Reference) -> Self {
        self.reference = reference;
        self
    }

    pub fn with_cluster_radius(mut self, cluster_radius: ClusterRadius) -> Self {
        self.cluster_radius = cluster_radius;
        self
    }

    pub fn with_one_to_one(mut self, one_to_one: bool) -> Self {
        self.one_to_one = one_to_one;
        self
    }

    /// Largest detection range in metres (finite, `> 0`).
    pub fn with_r_max(mut self, r_max: f64) -> CoreResult<Self> {
        if !(r_max.is_finite() && r_max > 0.0) {
            return Err(CoreError::out_of_range(
                "r_max",
                format!("{r_max} must be finite and > 0 (metres)"),
            ));
        }
        self.r_max = r_max;
        Ok(self)
    }

    /// `[x_min, x_max, y_min, y_max]`, finite, each minimum ≤ its maximum.
    pub fn with_region(mut self, bounds: [f64; 4]) -> CoreResult<Self> {
        let finite = bounds.iter().all(|b| b.is_finite());
        if !finite || bounds[0] > bounds[1] || bounds[2] > bounds[3] {
            return Err(CoreError::out_of_range(
                "region",
                format!("{bounds:?} must be finite [x_min, x_max, y_min, y_max] with min ≤ max"),
            ));
        }
        self.region = Some(Region {
            x: [bounds[0], bounds[1]],
            y: [bounds[2], bounds[3]],
        });
        Ok(self)
    }

    pub fn with_in_front(mut self, in_front: bool) -> Self {
        self.in_front = in_front;
        self
    }

    pub fn with_fit(mut self, fit: FitOptions) -> Self {
        self.fit = fit;
        self
    }

    /// Most (baseline report, other sensor's report) pairs a location may examine (`≥ 1`):
    /// the work and the one-to-one mode's memory grow with them, so a larger snapshot is
    /// refused before any work ([`DEFAULT_MAX_PAIRS`]).
    pub fn with_max_pairs(mut self, max_pairs: usize) -> CoreResult<Self> {
        if max_pairs == 0 {
            return Err(CoreError::out_of_range("max_pairs", "must be at least 1"));
        }
        self.max_pairs = max_pairs;
        Ok(self)
    }

    pub fn baseline_sensor(&self) -> usize {
        self.baseline_sensor
    }
    pub fn reference(&self) -> Reference {
        self.reference
    }
    pub fn cluster_radius(&self) -> ClusterRadius {
        self.cluster_radius
    }
    pub fn one_to_one(&self) -> bool {
        self.one_to_one
    }
    pub fn r_max(&self) -> f64 {
        self.r_max
    }
    pub fn region(&self) -> Option<Region> {
        self.region
    }
    pub fn in_front(&self) -> bool {
        self.in_front
    }
    pub fn fit(&self) -> &FitOptions {
        &self.fit
    }
    pub fn max_pairs(&self) -> usize {
        self.max_pairs
    }
}
