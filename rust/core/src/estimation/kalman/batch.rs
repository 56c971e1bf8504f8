//! Many independent tracks in one call, in parallel. Each track is filtered by the same
//! sequential code whatever thread runs it and writes only its own slice of a buffer laid out
//! like `indices` (track by track); the slices go back to the input's row order at the end
//! (a parallel gather, skipped when `indices` is already the row order). So the output is
//! bit-identical for any thread count.
//!
//! The buffers are never filled before use: the track buffers are zero-allocated (the
//! operating system's zero pages, touched first by the thread that filters the track) and
//! every track writes all its rows; the gather writes each output row once.

use rayon::prelude::*;

use super::input::{KalmanInput, Tracks, UNUSED};
use super::options::KalmanOptions;
use super::track::{filter_track, TrackOutput};
use crate::error::{CoreError, CoreResult};
use crate::parallel::interrupted;

/// The filtered tracks, aligned to the input rows: `states` is `n × state_dim`,
/// `covariances` `n × state_dim × state_dim` (row-major), `nis` `n` — the normalised
/// innovation squared of the row's update. Rows of no track, rows before their track's
/// initialisation is complete, and rows after a numerical failure are NaN; the row that
/// completes the initialisation has a state but NaN `nis`.
#[derive(Clone, Debug, PartialEq)]
pub struct KalmanOutcome {
    pub state_dim: usize,
    pub states: Vec<f64>,
    pub covariances: Vec<f64>,
    pub nis: Vec<f64>,
}

/// Filters every track of `tracks` over the rows of `input`; fails only on invalid input.
///
/// ```
/// use passive_assoc_core::estimation::kalman::{
///     kalman_filter, KalmanInput, KalmanOptions, MotionModel, Noise, Tracks,
/// };
/// // One 1-D track moving at 10 m/s, measured exactly at t = 0, 1, 2.
/// let input = KalmanInput {
///     times: &[0.0, 1.0, 2.0],
///     measurements: &[5.0, 15.0, 25.0],
///     columns: 1,
///     noise: Noise::Std(&[1.0, 1.0, 1.0]),
///     sensor_positions: None,
/// };
/// let tracks = Tracks { indices: &[0, 1, 2], offsets: &[0, 3] };
/// let options = KalmanOptions::new(MotionModel::ConstantVelocity, 0.0).unwrap();
/// let out = kalman_filter(&input, &tracks, &options).unwrap();
/// assert!(out.states[0].is_nan()); // differencing needs two rows
/// assert_eq!(&out.states[4..6], &[25.0, 10.0]);
/// ```
pub fn kalman_filter(
    input: &KalmanInput<'_>,
    tracks: &Tracks<'_>,
    options: &KalmanOptions,
) -> CoreResult<KalmanOutcome> {
    let dims = input.validate(options.measurement())?;
    let position = tracks.validate(input.times, options.init().points(options.motion()))?;
    match (options.motion().order(), dims) {
        (2, 1) => run::<1, 2>(input, tracks, options, &position),
        (3, 1) => run::<1, 3>(input, tracks, options, &position),
        (2, 2) => run::<2, 4>(input, tracks, options, &position),
        (3, 2) => run::<2, 6>(input, tracks, options, &position),
        (2, 3) => run::<3, 6>(input, tracks, options, &position),
        (3, 3) => run::<3, 9>(input, tracks, options, &position),
        (order, dims) => Err(CoreError::shape(
            "measurements",
            format!("no state layout for {dims} axes of order {order}"),
        )),
    }
}

/// Fewer tracks than this are filtered on the calling thread: a short track takes
/// microseconds, less than handing the batch to a thread pool and waking it
/// (`benches/bench_call_overhead.py`).
pub const PARALLEL_TRACKS: usize = 32;

/// Whether `tracks` tracks are filtered on the calling thread alone (so a caller can skip the
/// thread pool).
pub fn filters_sequentially(tracks: usize) -> bool {
    tracks < PARALLEL_TRACKS
}

fn run<const D: usize, const N: usize>(
    input: &KalmanInput<'_>,
    tracks: &Tracks<'_>,
    options: &KalmanOptions,
    position: &[usize],
) -> CoreResult<KalmanOutcome> {
    let used = tracks.indices.len();
    let mut states = vec![0.0; used * N];
    let mut covariances = vec![0.0; used * N * N];
    let mut nis = vec![0.0; used];
    let parts = split(&mut states, tracks.offsets, N)
        .into_iter()
        .zip(split(&mut covariances, tracks.offsets, N * N))
        .zip(split(&mut nis, tracks.offsets, 1))
        .map(|((states, covariances), nis)| TrackOutput {
            states,
            covariances,
            nis,
        })
        .collect::<Vec<_>>();
    let filter_one = |(p, out): (usize, TrackOutput<'_>)| {
        // Ctrl-C: skip the remaining tracks; the call returns Interrupted below.
        if !interrupted() {
            filter_track::<D, N>(input, options, tracks.rows(p), out);
        }
    };
    if filters_sequentially(parts.len()) {
        parts.into_iter().enumerate().for_each(filter_one);
    } else {
        parts.into_par_iter().enumerate().for_each(filter_one);
    }
    if interrupted() {
        return Err(CoreError::Interrupted);
    }
    let identity = used == position.len() && position.iter().enumerate().all(|(r, &k)| k == r);
    if identity {
        return Ok(KalmanOutcome {
            state_dim: N,
            states,
            covariances,
            nis,
        });
    }
    Ok(reorder::<N>(position, &states, &covariances, &nis))
}

/// The track-ordered buffers back in row order (NaN for rows of no track), each output row
/// written once.
fn reorder<const N: usize>(
    position: &[usize],
    states: &[f64],
    covariances: &[f64],
    nis: &[f64],
) -> KalmanOutcome {
    let row = |k: usize| -> [f64; N] {
        let mut out = [f64::NAN; N];
        if k != UNUSED {
            out.copy_from_slice(&states[k * N..(k + 1) * N]);
        }
        out
    };
    let matrix = |k: usize| -> [[f64; N]; N] {
        let mut out = [[f64::NAN; N]; N];
        if k != UNUSED {
            for (i, line) in out.iter_mut().enumerate() {
                line.copy_from_slice(&covariances[(k * N + i) * N..(k * N + i + 1) * N]);
            }
        }
        out
    };
    let states: Vec<[f64; N]> = position.par_iter().map(|&k| row(k)).collect();
    let covariances: Vec<[[f64; N]; N]> = position.par_iter().map(|&k| matrix(k)).collect();
    KalmanOutcome {
        state_dim: N,
        states: states.into_flattened(),
        covariances: covariances.into_flattened().into_flattened(),
        nis: position
            .par_iter()
            .map(|&k| if k == UNUSED { f64::NAN } else { nis[k] })
            .collect(),
    }
}

/// `buf` cut into one slice per track (`width` values per row), after the offsets'
/// validation.
fn split<'a>(mut buf: &'a mut [f64], offsets: &[i64], width: usize) -> Vec<&'a mut [f64]> {
    let mut parts = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (head, tail) = std::mem::take(&mut buf).split_at_mut((w[1] - w[0]) as usize * width);
        parts.push(head);
        buf = tail;
    }
    parts
}
