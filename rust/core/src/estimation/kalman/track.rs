//! One track's filter: initialise, then predict and update row by row. Sequential and
//! deterministic; the batch driver runs many of these in parallel.

use nalgebra::{SMatrix, SVector};

use super::init::{differencing, single_point, Init};
use super::input::KalmanInput;
use super::measurement::{update_polar, update_position, MeasurementModel, Point};
use super::motion::predict;
use super::options::KalmanOptions;

/// A track's output rows, in the track's own (time) order: `states` is `len × N`,
/// `covariances` `len × N × N`, `nis` `len`. The filter writes every row (NaN where it has
/// no state), so the caller need not fill the buffers first.
pub(crate) struct TrackOutput<'a> {
    pub states: &'a mut [f64],
    pub covariances: &'a mut [f64],
    pub nis: &'a mut [f64],
}

impl TrackOutput<'_> {
    fn write<const N: usize>(
        &mut self,
        k: usize,
        x: &SVector<f64, N>,
        p: &SMatrix<f64, N, N>,
        nis: f64,
    ) {
        self.states[k * N..(k + 1) * N].copy_from_slice(x.as_slice());
        // nalgebra stores column-major: the transpose's storage is P row-major.
        self.covariances[k * N * N..(k + 1) * N * N].copy_from_slice(p.transpose().as_slice());
        self.nis[k] = nis;
    }
}

impl TrackOutput<'_> {
    /// NaN in `rows` (no state there).
    fn blank<const N: usize>(&mut self, rows: std::ops::Range<usize>) {
        self.states[rows.start * N..rows.end * N].fill(f64::NAN);
        self.covariances[rows.start * N * N..rows.end * N * N].fill(f64::NAN);
        self.nis[rows].fill(f64::NAN);
    }
}

/// Whether a state can be reported: finite, with no negative variance. A negative variance is
/// rounding that kept no digits (a time step of 10¹² s in a constant-acceleration filter
/// scales the prediction by 10⁶⁰), not a covariance.
fn sound<const N: usize>(x: &SVector<f64, N>, p: &SMatrix<f64, N, N>) -> bool {
    x.iter().chain(p.iter()).all(|v| v.is_finite()) && p.diagonal().iter().all(|&v| v >= 0.0)
}

/// Filters the rows `rows` (validated, time-ordered) of `input` into `out`. `D` is the
/// position dimension, `N = order · D` the state's.
///
/// Rows before the start get NaN (every row of a track too short to start). If an update
/// fails numerically — the prediction on a polar sensor, or arithmetic overflowing or losing
/// every digit (a negative variance) on absurd but finite inputs — that row and the rest of
/// the track get NaN.
pub(crate) fn filter_track<const D: usize, const N: usize>(
    input: &KalmanInput<'_>,
    options: &KalmanOptions,
    rows: &[i64],
    mut out: TrackOutput<'_>,
) {
    let (motion, model, q) = (
        options.motion(),
        options.measurement(),
        options.process_noise(),
    );
    let start = options.init().points(motion);
    if rows.len() < start {
        out.blank::<N>(0..rows.len());
        return;
    }
    let (mut x, mut p) = match options.init() {
        Init::Differencing => {
            let mut times = [0.0; 3];
            let mut points = [Point::<D> {
                z: SVector::zeros(),
                r: SMatrix::zeros(),
            }; 3];
            for (k, &row) in rows[..start].iter().enumerate() {
                times[k] = input.times[row as usize];
                points[k] = input.point::<D>(model, row as usize);
            }
            differencing::<D, N>(motion, q, &times[..start], &points[..start])
        }
        Init::SinglePoint => single_point::<D, N>(
            &input.point::<D>(model, rows[0] as usize),
            options.init_velocity_std(),
            options.init_acceleration_std(),
        ),
    };
    if !sound(&x, &p) {
        out.blank::<N>(0..rows.len());
        return;
    }
    out.blank::<N>(0..start - 1);
    out.write(start - 1, &x, &p, f64::NAN);
    let mut time = input.times[rows[start - 1] as usize];
    for (k, &row) in rows.iter().enumerate().skip(start) {
        let row = row as usize;
        predict::<D, N>(motion, input.times[row] - time, q, &mut x, &mut p);
        time = input.times[row];
        let nis = match model {
            MeasurementModel::Position | MeasurementModel::PolarConverted => {
                update_position(&mut x, &mut p, &input.point::<D>(model, row))
            }
            MeasurementModel::Polar => {
                let values = input.values(row);
                update_polar(
                    &mut x,
                    &mut p,
                    input.sensor(row),
                    [values[0], values[1]],
                    &input.noise_matrix::<2>(row),
                )
            }
        };
        match nis {
            Some(nis) if sound(&x, &p) => out.write(k, &x, &p, nis),
            _ => {
                out.blank::<N>(k..rows.len());
                return;
            }
        }
    }
}
