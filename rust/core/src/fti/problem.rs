//! The data of one initiation call, as every stage reads it.

use crate::data::{Measurements, Sensors};
use crate::geometry::model::{Observation, StateLayout};
use crate::progress::Progress;

/// The data of one initiation call: the validated views, the constant-velocity layout and
/// its epoch t0.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a> {
    pub sensors: Sensors<'a>,
    pub measurements: Measurements<'a>,
    pub layout: StateLayout,
    pub t0: f64,
    /// Where the stages report how far they are ([`crate::progress`]).
    pub progress: &'a dyn Progress,
}

impl Problem<'_> {
    /// Whether the call should end now: Ctrl-C, or the progress watcher asked.
    pub fn stopped(&self) -> bool {
        crate::parallel::interrupted() || self.progress.cancelled()
    }

    /// Row `m` as the model sees it.
    #[inline]
    pub fn observation(&self, m: usize) -> Observation {
        self.measurements.observation(&self.sensors, m)
    }

    /// The largest noise stds `[σβ, σε]` of `rows` (one scan): the scan-level gates' width
    /// when the reports carry their own noise; the sensor's otherwise.
    pub fn scan_sigma(&self, rows: &[usize]) -> [f64; 2] {
        rows.iter()
            .map(|&m| self.measurements.sigma(&self.sensors, m))
            .fold([0.0; 2], |a, s| [a[0].max(s[0]), a[1].max(s[1])])
    }
}
