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
}
