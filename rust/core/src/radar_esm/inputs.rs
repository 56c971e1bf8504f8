//! Validated borrowed views of the coarse gate's input, row-major as NumPy holds them: the
//! approximation operator W, one sensor's tracks with per-scan position variances
//! ([`CoarseTracks`]), and one sensor's tracks with their coefficients' full covariance
//! ([`CoupledTracks`]).

use crate::error::{ensure_finite, CoreError, CoreResult};

/// The largest number of approximation coefficients per coordinate. Each track keeps a c × c
/// matrix per coordinate and each pair costs c³/6: the coarse gate is meant for the few
/// coefficients of a coarse level (6 for sym2, 3 levels, 30 scans).
pub const MAX_COEFFICIENTS: usize = 256;

/// W, `c × T`: column t is the approximation coefficients of the unit sequence at scan t, so
/// a track's coefficients are `a = W x` for its positions `x` over the T scans of the window.
///
/// ```
/// use passive_assoc_core::radar_esm::Operator;
/// let w = [0.5, 0.5, 0.0, 0.0, 0.5, 0.5];
/// let op = Operator::new(&w, 2, 3).unwrap();
/// assert_eq!((op.coefficients(), op.window()), (2, 3));
/// assert!(Operator::new(&w, 3, 2).is_err()); // more coefficients than scans
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Operator<'a> {
    values: &'a [f64],
    coefficients: usize,
    window: usize,
}

impl<'a> Operator<'a> {
    /// `values` row-major `(coefficients, window)`, finite; `1 ≤ coefficients ≤ window` (with
    /// more coefficients than scans `W Σ Wᵀ` would be singular).
    pub fn new(values: &'a [f64], coefficients: usize, window: usize) -> CoreResult<Self> {
        if coefficients == 0 || window == 0 {
            return Err(CoreError::shape(
                "operator",
                format!(
                    "needs at least one row and one column, got shape ({coefficients}, {window})"
                ),
            ));
        }
        if coefficients > window {
            return Err(CoreError::shape(
                "operator",
                format!(
                    "{coefficients} coefficients from {window} scans: W Σ Wᵀ would be singular \
                     (an approximation has at most as many coefficients as scans)"
                ),
            ));
        }
        if coefficients > MAX_COEFFICIENTS {
            return Err(CoreError::CapExceeded {
                what: "approximation coefficients per coordinate",
                count: coefficients,
                cap: MAX_COEFFICIENTS,
                hint: "decompose to a coarser level or shorten the window",
            });
        }
        if values.len() != coefficients * window {
            return Err(CoreError::shape(
                "operator",
                format!(
                    "{} values do not fill shape ({coefficients}, {window})",
                    values.len()
                ),
            ));
        }
        ensure_finite("operator", values)?;
        Ok(Self {
            values,
            coefficients,
            window,
        })
    }

    /// c, the approximation coefficients per coordinate.
    pub fn coefficients(&self) -> usize {
        self.coefficients
    }

    /// T, the scans of the window.
    pub fn window(&self) -> usize {
        self.window
    }

    /// Row `a` of W (length T).
    pub(super) fn row(&self, a: usize) -> &'a [f64] {
        &self.values[a * self.window..(a + 1) * self.window]
    }
}

/// Which sensor a [`CoarseTracks`] holds: names its arguments in errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Radar,
    Esm,
}

impl Side {
    fn coefficients_arg(self) -> &'static str {
        match self {
            Self::Radar => "radar_coefficients",
            Self::Esm => "esm_coefficients",
        }
    }

    fn variances_arg(self) -> &'static str {
        match self {
            Self::Radar => "radar_variances",
            Self::Esm => "esm_variances",
        }
    }
}

/// One sensor's tracks over the window: approximation coefficients `(n, ndim, c)` and the
/// filter's per-scan position variances `(n, ndim, T)` (Σ is diagonal in time; coordinates
/// are independent), both row-major.
#[derive(Debug, Clone, Copy)]
pub struct CoarseTracks<'a> {
    pub(super) coefficients: &'a [f64],
    pub(super) variances: &'a [f64],
    len: usize,
    ndim: usize,
    c: usize,
    window: usize,
}

impl<'a> CoarseTracks<'a> {
    /// Validates the lengths against `ndim` and `operator` (the track count follows from
    /// them), finite values and variances ≥ 0.
    pub fn new(
        side: Side,
        coefficients: &'a [f64],
        variances: &'a [f64],
        ndim: usize,
        operator: &Operator<'_>,
    ) -> CoreResult<Self> {
        let (c, window) = (operator.coefficients(), operator.window());
        if ndim == 0 {
            return Err(CoreError::shape(
                side.coefficients_arg(),
                "needs at least one coordinate (ndim ≥ 1)",
            ));
        }
        let per_track = ndim * c;
        if coefficients.len() % per_track != 0 {
            return Err(CoreError::shape(
                side.coefficients_arg(),
                format!(
                    "{} values are not whole tracks of ndim × c = {ndim} × {c}",
                    coefficients.len()
                ),
            ));
        }
        let len = coefficients.len() / per_track;
        if variances.len() != len * ndim * window {
            return Err(CoreError::shape(
                side.variances_arg(),
                format!(
                    "{} values, expected n × ndim × T = {len} × {ndim} × {window}",
                    variances.len()
                ),
            ));
        }
        ensure_finite(side.coefficients_arg(), coefficients)?;
        ensure_finite(side.variances_arg(), variances)?;
        if let Some(index) = variances.iter().position(|&v| v < 0.0) {
            return Err(CoreError::out_of_range(
                side.variances_arg(),
                format!("{} at index {index} is negative", variances[index]),
            ));
        }
        Ok(Self {
            coefficients,
            variances,
            len,
            ndim,
            c,
            window,
        })
    }

    /// n, the tracks.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The coordinates per track.
    pub fn ndim(&self) -> usize {
        self.ndim
    }

    /// Whether these tracks were validated against an operator of `operator`'s shape.
    pub(super) fn fits(&self, operator: &Operator<'_>) -> bool {
        (self.c, self.window) == (operator.coefficients(), operator.window())
    }
}

/// Relative asymmetry `|C_ab − C_ba| / sqrt(C_aa C_bb)` above which a covariance is refused:
/// a layout mistake (a transposed or mis-strided block) rather than rounding.
const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// One sensor's tracks: `m` coefficients per track (all coordinates, coordinate-major) and
/// their `m × m` covariance, row-major: `(n, m)` and `(n, m, m)`.
///
/// ```
/// use passive_assoc_core::radar_esm::{CoupledTracks, Side};
/// let tracks = CoupledTracks::new(Side::Radar, &[1.0, 2.0], &[2.0, 0.5, 0.5, 1.0], 2).unwrap();
/// assert_eq!((tracks.len(), tracks.width()), (1, 2));
/// assert!(CoupledTracks::new(Side::Esm, &[1.0, 2.0], &[2.0, 0.5, 0.4, 1.0], 2).is_err());
/// ```
#[derive(Debug, Clone, Copy)]
pub struct CoupledTracks<'a> {
    pub(super) coefficients: &'a [f64],
    pub(super) covariances: &'a [f64],
    len: usize,
    width: usize,
}

impl<'a> CoupledTracks<'a> {
    /// Validates the lengths against `width` (m ≥ 1, at most [`MAX_COEFFICIENTS`]), finite
    /// values, non-negative diagonals and symmetric covariances.
    pub fn new(
        side: Side,
        coefficients: &'a [f64],
        covariances: &'a [f64],
        width: usize,
    ) -> CoreResult<Self> {
        let (coefficients_arg, covariances_arg) = names(side);
        if width == 0 || width > MAX_COEFFICIENTS {
            return Err(CoreError::shape(
                coefficients_arg,
                format!("{width} coefficients per track; expected 1 to {MAX_COEFFICIENTS}"),
            ));
        }
        if coefficients.len() % width != 0 {
            return Err(CoreError::shape(
                coefficients_arg,
                format!(
                    "{} values are not whole tracks of {width}",
                    coefficients.len()
                ),
            ));
        }
        let len = coefficients.len() / width;
        if covariances.len() != len * width * width {
            return Err(CoreError::shape(
                covariances_arg,
                format!(
                    "{} values, expected n × m × m = {len} × {width} × {width}",
                    covariances.len()
                ),
            ));
        }
        ensure_finite(coefficients_arg, coefficients)?;
        ensure_finite(covariances_arg, covariances)?;
        for (track, c) in covariances.chunks_exact(width * width).enumerate() {
            check_covariance(covariances_arg, track, c, width)?;
        }
        Ok(Self {
            coefficients,
            covariances,
            len,
            width,
        })
    }

    /// n, the tracks.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// m, the coefficients per track.
    pub fn width(&self) -> usize {
        self.width
    }
}

fn names(side: Side) -> (&'static str, &'static str) {
    match side {
        Side::Radar => ("radar_coefficients", "radar_covariances"),
        Side::Esm => ("esm_coefficients", "esm_covariances"),
    }
}

fn check_covariance(name: &'static str, track: usize, c: &[f64], m: usize) -> CoreResult<()> {
    for a in 0..m {
        let caa = c[a * m + a];
        if caa < 0.0 {
            return Err(CoreError::out_of_range(
                name,
                format!("track {track}: diagonal entry {a} is {caa}, negative"),
            ));
        }
        for b in 0..a {
            let (x, y) = (c[a * m + b], c[b * m + a]);
            let scale = (caa * c[b * m + b]).sqrt();
            if (x - y).abs() > SYMMETRY_TOLERANCE * scale.max(f64::MIN_POSITIVE) {
                return Err(CoreError::ill_posed(
                    name,
                    format!(
                        "track {track}: not symmetric, entry ({a}, {b}) is {x}, ({b}, {a}) is {y}"
                    ),
                ));
            }
        }
    }
    Ok(())
}
