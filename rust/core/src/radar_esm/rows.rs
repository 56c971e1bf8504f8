//! The coarse gate's pair loop: both sides prepared once (per track and coordinate,
//! `C = W diag(v) Wᵀ` or the mean variance), then one radar track's row of statistics
//! against every ESM track.
//!
//! Whitened rows take the ESM tracks four at a time through the lane kernel of `cholesky`
//! (the last `n_esm mod 4` one at a time); every pair's arithmetic is the same either way.

use rayon::prelude::*;

use super::cholesky::quadratic_forms;
use super::inputs::{CoarseTracks, CoupledTracks, Operator};

/// ESM tracks per call of the lane kernel.
const LANES: usize = 4;

/// Where a row failed: (ESM track, coordinate) of the first pair, in (track, coordinate)
/// order, whose summed covariance is not positive definite.
pub(super) type Failure = (usize, usize);

/// Fills one radar track's row of statistics against every ESM track.
pub(super) type RowKernel = fn(&Sides<'_>, usize, &mut [f64]) -> Result<(), Failure>;

/// Both sides prepared for the pair loop: the coefficients, and per track and coordinate
/// either `C = W diag(v) Wᵀ` (c × c, full) or the mean variance. Whitened, the ESM side is
/// also laid out lane-innermost for the lane kernel: groups of [`LANES`] tracks, then the
/// rest one by one.
pub(super) struct Sides<'a> {
    radar: &'a [f64],
    esm: &'a [f64],
    radar_spread: Vec<f64>,
    esm_spread: Vec<f64>,
    groups: Lanes<LANES>,
    rest: Lanes<1>,
    ndim: usize,
    c: usize,
    whitened: bool,
}

/// ESM tracks lane-innermost: per group of L tracks and coordinate, the c × c entries of C
/// and the c coefficients, each a vector over the L tracks.
struct Lanes<const L: usize> {
    covariances: Vec<[f64; L]>,
    coefficients: Vec<[f64; L]>,
}

impl<const L: usize> Lanes<L> {
    /// The tracks `first .. first + groups · L` of `covariances` (per track `per_track.0`
    /// values) and `coefficients` (`per_track.1`), regrouped.
    fn new(
        covariances: &[f64],
        coefficients: &[f64],
        (first, groups): (usize, usize),
        per_track: (usize, usize),
    ) -> Self {
        let regroup = |values: &[f64], size: usize| -> Vec<[f64; L]> {
            (0..groups)
                .flat_map(|g| {
                    let start = first + g * L;
                    (0..size).map(move |e| std::array::from_fn(|x| values[(start + x) * size + e]))
                })
                .collect()
        };
        Self {
            covariances: regroup(covariances, per_track.0),
            coefficients: regroup(coefficients, per_track.1),
        }
    }

    fn empty() -> Self {
        Self {
            covariances: Vec::new(),
            coefficients: Vec::new(),
        }
    }
}

impl<'a> Sides<'a> {
    /// Prepares both sides, in parallel over tracks if `parallel`.
    pub(super) fn new(
        operator: &Operator<'_>,
        (radar, esm): (&CoarseTracks<'a>, &CoarseTracks<'a>),
        whitened: bool,
        parallel: bool,
    ) -> Self {
        let spread = |variances| spreads(operator, variances, whitened, parallel);
        let (ndim, c) = (radar.ndim(), operator.coefficients());
        let (radar_side, esm_side) = (
            (radar.coefficients, spread(radar.variances)),
            (esm.coefficients, spread(esm.variances)),
        );
        if whitened {
            Self::whitened(radar_side, esm_side, ndim, c)
        } else {
            Self {
                radar: radar_side.0,
                esm: esm_side.0,
                radar_spread: radar_side.1,
                esm_spread: esm_side.1,
                groups: Lanes::empty(),
                rest: Lanes::empty(),
                ndim,
                c,
                whitened,
            }
        }
    }

    /// Sides whose tracks carry their coefficients' full covariance already (coordinates
    /// coupled): one block of `m` coefficients and an `m × m` C per track.
    pub(super) fn coupled(radar: &CoupledTracks<'a>, esm: &CoupledTracks<'a>) -> Self {
        Self::whitened(
            (radar.coefficients, radar.covariances.to_vec()),
            (esm.coefficients, esm.covariances.to_vec()),
            1,
            radar.width(),
        )
    }

    /// Whitened sides from each side's coefficients and per (track, coordinate) c × c C; the
    /// ESM side laid out lane-innermost for the lane kernel.
    fn whitened(
        (radar, radar_spread): (&'a [f64], Vec<f64>),
        (esm, esm_spread): (&'a [f64], Vec<f64>),
        ndim: usize,
        c: usize,
    ) -> Self {
        let per_track = (ndim * c * c, ndim * c);
        let n_esm = esm.len() / per_track.1;
        let first_rest = n_esm / LANES * LANES;
        Self {
            radar,
            esm,
            radar_spread,
            // The kernels read the ESM side from `groups` and `rest` only.
            esm_spread: Vec::new(),
            groups: Lanes::new(&esm_spread, esm, (0, first_rest / LANES), per_track),
            rest: Lanes::new(
                &esm_spread,
                esm,
                (first_rest, n_esm - first_rest),
                per_track,
            ),
            ndim,
            c,
            whitened: true,
        }
    }

    /// The row kernel for this c: a compile-time size for the common small c (the loops
    /// unroll and the scratch lives on the stack), a heap-scratch one above.
    pub(super) fn row_kernel(&self) -> RowKernel {
        if !self.whitened {
            return scalar_row;
        }
        match self.c {
            1 => whitened_row_fixed::<1>,
            2 => whitened_row_fixed::<2>,
            3 => whitened_row_fixed::<3>,
            4 => whitened_row_fixed::<4>,
            5 => whitened_row_fixed::<5>,
            6 => whitened_row_fixed::<6>,
            7 => whitened_row_fixed::<7>,
            8 => whitened_row_fixed::<8>,
            // Coupled 2-D tracks: two coordinates of 5 or 6 coefficients.
            10 => whitened_row_fixed::<10>,
            12 => whitened_row_fixed::<12>,
            _ => whitened_row_any,
        }
    }
}

/// Per track and coordinate (blocks of T variances): `W diag(v) Wᵀ` (c² values, full) if
/// whitened, else the mean of v (one value).
fn spreads(operator: &Operator<'_>, variances: &[f64], whitened: bool, parallel: bool) -> Vec<f64> {
    let (c, window) = (operator.coefficients(), operator.window());
    let mean = |v: &[f64]| v.iter().sum::<f64>() / window as f64;
    if !whitened {
        return if parallel {
            variances.par_chunks_exact(window).map(mean).collect()
        } else {
            variances.chunks_exact(window).map(mean).collect()
        };
    }
    let covariance = |(cov, v): (&mut [f64], &[f64])| {
        for a in 0..c {
            let wa = operator.row(a);
            for b in 0..=a {
                let wb = operator.row(b);
                let value: f64 = (0..window).map(|t| wa[t] * v[t] * wb[t]).sum();
                cov[a * c + b] = value;
                cov[b * c + a] = value;
            }
        }
    };
    let mut out = vec![0.0; variances.len() / window * c * c];
    if parallel {
        out.par_chunks_exact_mut(c * c)
            .zip(variances.par_chunks_exact(window))
            .for_each(covariance);
    } else {
        out.chunks_exact_mut(c * c)
            .zip(variances.chunks_exact(window))
            .for_each(covariance);
    }
    out
}

fn whitened_row_fixed<const C: usize>(
    sides: &Sides<'_>,
    i: usize,
    out: &mut [f64],
) -> Result<(), Failure> {
    let mut lanes = ([[[0.0; LANES]; C]; C], [[0.0; LANES]; C]);
    let mut single = ([[[0.0; 1]; C]; C], [[0.0; 1]; C]);
    whitened_row(
        sides,
        i,
        out,
        (lanes.0.as_flattened_mut(), &mut lanes.1),
        (single.0.as_flattened_mut(), &mut single.1),
    )
}

fn whitened_row_any(sides: &Sides<'_>, i: usize, out: &mut [f64]) -> Result<(), Failure> {
    let c = sides.c;
    let mut lanes = (vec![[0.0; LANES]; c * c], vec![[0.0; LANES]; c]);
    let mut single = (vec![[0.0; 1]; c * c], vec![[0.0; 1]; c]);
    whitened_row(
        sides,
        i,
        out,
        (&mut lanes.0, &mut lanes.1),
        (&mut single.0, &mut single.1),
    )
}

/// Scratch of the lane kernel: S (c × c lane vectors) and d (c lane vectors).
type Scratch<'s, const L: usize> = (&'s mut [[f64; L]], &'s mut [[f64; L]]);

/// `out[j] = Σ_k dᵀ (C_ik + C_jk)⁻¹ d`, d = a_ik − a_jk: groups of [`LANES`] ESM tracks,
/// then the rest one by one.
#[inline(always)]
fn whitened_row(
    sides: &Sides<'_>,
    i: usize,
    out: &mut [f64],
    lanes: Scratch<'_, LANES>,
    single: Scratch<'_, 1>,
) -> Result<(), Failure> {
    let first_rest = out.len() / LANES * LANES;
    let (head, tail) = out.split_at_mut(first_rest);
    for (g, chunk) in head.chunks_exact_mut(LANES).enumerate() {
        pair_group(
            sides,
            i,
            (&sides.groups, g),
            (&mut *lanes.0, &mut *lanes.1),
            chunk,
        )
        .map_err(|(x, k)| (g * LANES + x, k))?;
    }
    for (t, slot) in tail.chunks_exact_mut(1).enumerate() {
        pair_group(
            sides,
            i,
            (&sides.rest, t),
            (&mut *single.0, &mut *single.1),
            slot,
        )
        .map_err(|(_, k)| (first_rest + t, k))?;
    }
    Ok(())
}

/// The statistics of radar track `i` against group `g` of `lanes` into `out`; on failure
/// (lane, coordinate) of the first pair in (track, coordinate) order.
// The lane loops index several lane vectors in lockstep, which is clearer than nested zips.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn pair_group<const L: usize>(
    sides: &Sides<'_>,
    i: usize,
    (lanes, g): (&Lanes<L>, usize),
    (s, d): Scratch<'_, L>,
    out: &mut [f64],
) -> Result<(), Failure> {
    let (c, ndim) = (d.len(), sides.ndim);
    let cc = c * c;
    let mut total = [0.0; L];
    let mut failed: [Option<usize>; L] = [None; L];
    for k in 0..ndim {
        let (block, group) = (i * ndim + k, g * ndim + k);
        let ci = &sides.radar_spread[block * cc..(block + 1) * cc];
        let ai = &sides.radar[block * c..(block + 1) * c];
        let cj = &lanes.covariances[group * cc..(group + 1) * cc];
        let aj = &lanes.coefficients[group * c..(group + 1) * c];
        for r in 0..c {
            for q in 0..=r {
                let e = r * c + q;
                for x in 0..L {
                    s[e][x] = ci[e] + cj[e][x];
                }
            }
            for x in 0..L {
                d[r][x] = ai[r] - aj[r][x];
            }
        }
        let (forms, positive) = quadratic_forms(s, d);
        for x in 0..L {
            total[x] += forms[x];
            if !positive[x] && failed[x].is_none() {
                failed[x] = Some(k);
            }
        }
    }
    if let Some(first) = (0..L).find_map(|x| failed[x].map(|k| (x, k))) {
        return Err(first);
    }
    out.copy_from_slice(&total);
    Ok(())
}

/// `out[j] = Σ_k |a_ik − a_jk|² / (σ_ik² + σ_jk²)`.
fn scalar_row(sides: &Sides<'_>, i: usize, out: &mut [f64]) -> Result<(), Failure> {
    let (c, ndim) = (sides.c, sides.ndim);
    let radar_var = &sides.radar_spread[i * ndim..(i + 1) * ndim];
    let radar = &sides.radar[i * ndim * c..(i + 1) * ndim * c];
    let pairs = sides
        .esm_spread
        .chunks_exact(ndim)
        .zip(sides.esm.chunks_exact(ndim * c));
    for (j, (slot, (esm_var, esm))) in out.iter_mut().zip(pairs).enumerate() {
        let mut total = 0.0;
        for k in 0..ndim {
            let variance = radar_var[k] + esm_var[k];
            if !(variance > 0.0 && variance.is_finite()) {
                return Err((j, k));
            }
            let (ai, aj) = (&radar[k * c..][..c], &esm[k * c..][..c]);
            let squared: f64 = ai.iter().zip(aj).map(|(x, y)| (x - y) * (x - y)).sum();
            total += squared / variance;
        }
        *slot = total;
    }
    Ok(())
}
