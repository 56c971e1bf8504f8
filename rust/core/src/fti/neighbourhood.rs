//! Regrouping's neighbourhood (a project extension, 3-D; docs/methods.md §1, *Regrouping*):
//! the rows of other sensors whose lines of sight meet a track's rows.
//!
//! For a row of sensor j at time t, the rows looked at are those of every other sensor's two
//! scans around t: with that sensor's scans in time order, the first at or after t and the
//! one before it (one at the ends). A row meets it when their lines of sight have a unique
//! closest pair, in front of both sensors, that passes the candidate formation's ray gate
//! (module `ray_pairs`: `ray_gate_sigmas` standard deviations of the crossing plus
//! `v_max`·|t_a − t_b|). The regrouping loop itself is the Python package's
//! (`passive_assoc.fti.regroup`); this is its inner test, the same one the formation runs.

use rayon::prelude::*;

use super::options::InitiationOptions;
use super::ray_pairs::{meet, ray_gate};
use super::scans::Scans;
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::geometry::model::{Observation, Space};

/// A table's rows as lines of sight, grouped by sensor and scan, with the ray gate's
/// settings: built once, asked for the neighbourhood of many row sets.
#[derive(Clone, Debug)]
pub struct Neighbourhood {
    observations: Vec<Observation>,
    sensor: Vec<usize>,
    /// The rows by sensor and scan, each sensor's scans in time order.
    scans: Scans,
    gate: Option<f64>,
    v_max: Option<f64>,
}

impl Neighbourhood {
    /// The rows of `measurements` with the ray gate of `options` (`ray_gate_sigmas`,
    /// `v_max`). Errors for a 2-D network, where every two bearing lines meet.
    pub fn new(
        sensors: &Sensors<'_>,
        measurements: &Measurements<'_>,
        options: &InitiationOptions,
    ) -> CoreResult<Self> {
        if sensors.space() != Space::Spatial {
            return Err(CoreError::ill_posed(
                "sensors",
                "the lines of sight of a 2-D network all meet: the neighbourhood needs 3-D",
            ));
        }
        let n = measurements.len();
        Ok(Self {
            observations: (0..n)
                .map(|m| measurements.observation(sensors, m))
                .collect(),
            sensor: (0..n).map(|m| measurements.sensor(m)).collect(),
            scans: Scans::new(measurements, sensors.len()),
            gate: options.ray_gate_sigmas(),
            v_max: options.v_max(),
        })
    }

    /// How many rows the table has.
    pub fn len(&self) -> usize {
        self.sensor.len()
    }

    /// Whether the table has no row.
    pub fn is_empty(&self) -> bool {
        self.sensor.is_empty()
    }

    /// The rows with `free` set (one flag per row) that meet any of `rows` (module doc),
    /// ascending. Runs on the current rayon pool; the answer does not depend on it. Asked to
    /// stop (Ctrl-C), it stops between rows with [`CoreError::Interrupted`].
    pub fn of(&self, rows: &[usize], free: &[bool]) -> CoreResult<Vec<usize>> {
        let n = self.len();
        if free.len() != n {
            return Err(CoreError::shape(
                "free",
                format!("has {} flags, the table {n} rows", free.len()),
            ));
        }
        if let Some(&bad) = rows.iter().find(|&&a| a >= n) {
            return Err(CoreError::out_of_range(
                "rows",
                format!("row {bad} is past the table's {n} rows"),
            ));
        }
        let met: Vec<Vec<usize>> = (rows.par_iter())
            .map(|&a| match crate::parallel::interrupted() {
                true => Vec::new(),
                false => self.meeting(a, free),
            })
            .collect();
        if crate::parallel::interrupted() {
            return Err(CoreError::Interrupted);
        }
        let mut out: Vec<usize> = met.into_iter().flatten().collect();
        out.sort_unstable();
        out.dedup();
        Ok(out)
    }

    /// The free rows meeting row `a`.
    fn meeting(&self, a: usize, free: &[bool]) -> Vec<usize> {
        let oa = &self.observations[a];
        let mut out = Vec::new();
        // A scan's time is its first row's (its rows share one).
        let time = |k: usize| self.observations[self.scans.scan(k)[0]].time;
        for (j, own) in self.scans.per_sensor.iter().enumerate() {
            if j == self.sensor[a] {
                continue;
            }
            let at = own.partition_point(|&k| time(k) < oa.time);
            let around = at.saturating_sub(1)..(at + 1).min(own.len());
            for &k in &own[around] {
                for &b in self.scans.scan(k).iter().filter(|&&b| free[b]) {
                    if self.meets(oa, &self.observations[b]) {
                        out.push(b);
                    }
                }
            }
        }
        out
    }

    /// Whether two lines of sight meet in front of both sensors within the ray gate.
    fn meets(&self, oa: &Observation, ob: &Observation) -> bool {
        let meeting = meet(Space::Spatial, oa, ob);
        meeting.is_some_and(|m| m.in_front())
            && ray_gate(
                Space::Spatial,
                self.gate,
                self.v_max,
                [oa, ob],
                meeting.as_ref(),
            )
    }
}

#[cfg(test)]
mod tests {
    use super::Neighbourhood;
    use crate::data::{Measurements, Sensors};
    use crate::fti::options::InitiationOptions;
    use crate::geometry::model::Space;

    /// Sensors 0 and 1 on the x axis and sensor 2 south of them see a target climbing at
    /// 400 m/s. Row 0 (sensor 0, t = 1.5 s): sensor 1's rays at 0 and 3 s pass 600 m from it,
    /// within `v_max`·1.5 s at 500 m/s, not at 100 m/s; sensor 2's ray at the same time meets
    /// it; a ray pointing away from the target meets it behind sensor 1; sensor 0's own other
    /// row is never looked at, nor sensor 2's scan at 6 s (outside the two around 1.5 s).
    #[test]
    fn the_rays_that_meet_a_row() {
        let positions = [-10e3, 0.0, 0.0, 10e3, 0.0, 0.0, 0.0, -10e3, 0.0];
        let sigma = [1e-3; 3];
        let sensors = Sensors::new(Space::Spatial, &positions, &sigma, &sigma).expect("sensors");
        let target = |t: f64| [2e3, 10e3, 1e3 + 400.0 * t];
        let look = |s: usize, t: f64| {
            let p = target(t);
            let d: [f64; 3] = std::array::from_fn(|k| p[k] - positions[3 * s + k]);
            (d[1].atan2(d[0]), d[2].atan2(d[0].hypot(d[1])))
        };
        let away = (look(1, 0.0).0 + std::f64::consts::PI, -look(1, 0.0).1);
        let rows = [
            (0, 1.5, look(0, 1.5)),
            (0, 1.5, look(0, 0.0)),
            (1, 0.0, look(1, 0.0)),
            (1, 0.0, away),
            (1, 3.0, look(1, 3.0)),
            (2, 0.0, look(2, 0.0)),
            (2, 1.5, look(2, 1.5)),
            (2, 6.0, look(2, 6.0)),
        ];
        let sensor: Vec<i64> = rows.iter().map(|r| r.0).collect();
        let time: Vec<f64> = rows.iter().map(|r| r.1).collect();
        let azimuth: Vec<f64> = rows.iter().map(|r| r.2 .0).collect();
        let elevation: Vec<f64> = rows.iter().map(|r| r.2 .1).collect();
        let table =
            Measurements::new(&sensors, &sensor, &time, &azimuth, &elevation).expect("rows");
        let near = |v_max: Option<f64>| {
            let options = InitiationOptions::default()
                .with_v_max(v_max)
                .expect("v_max");
            Neighbourhood::new(&sensors, &table, &options).expect("neighbourhood")
        };
        let free = vec![true; rows.len()];
        let of = |v_max: Option<f64>, free: &[bool]| near(v_max).of(&[0], free).expect("of");
        assert_eq!(of(Some(500.0), &free), vec![2, 4, 5, 6]);
        assert_eq!(of(Some(100.0), &free), vec![6]);
        // Unbounded motion: every ray at another time passes the gate, none behind.
        assert_eq!(of(None, &free), vec![2, 4, 5, 6]);
        let mut taken = free.clone();
        taken[2] = false;
        assert_eq!(of(Some(500.0), &taken), vec![4, 5, 6]);
        assert!(near(Some(500.0)).of(&[8], &free).is_err());
        assert!(near(Some(500.0)).of(&[0], &free[1..]).is_err());
    }
}
