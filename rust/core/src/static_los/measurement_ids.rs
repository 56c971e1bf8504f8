//! Dense ids for the reports the intensity search uses, so that its per-level incidence
//! arrays are sized by the candidates, never by the caller's report counts.

use super::intensity_input::IntensityInput;
use crate::error::{CoreError, CoreResult};

/// Dense measurement ids `0..n_meas` of the searched candidates, one row of `S` per candidate
/// (`NONE` where a sensor missed it or the candidate is not searched), computed once. Ids
/// cover only the reports in use, so memory follows the candidates, not the caller-given
/// report counts. A report is (sensor, index).
pub(super) struct MeasurementIds {
    n_sensors: usize,
    ids: Vec<u32>,
}

impl MeasurementIds {
    const NONE: u32 = u32::MAX;

    pub(super) fn new(input: &IntensityInput, searched: &[bool]) -> CoreResult<(Self, usize)> {
        let s_count = input.n_sensors();
        // Every (slot, sensor, report) of the searched candidates; ids go to the distinct
        // (sensor, report) pairs in ascending order.
        let slots = (0..searched.len())
            .filter(|&c| searched[c])
            .flat_map(|c| (0..s_count).map(move |s| (c, s)))
            .filter_map(|(c, s)| {
                let t = input.tuple(c)[s];
                (t > 0).then_some((c * s_count + s, s, t))
            });
        let mut ids = vec![Self::NONE; searched.len() * s_count];
        let n_meas = if input.sizes_total() <= 4 * ids.len() + 1024 {
            Self::by_table(input, slots, &mut ids)
        } else {
            // Report counts far beyond the candidates: a table would cost more than a sort.
            let mut by_report: Vec<(usize, usize, usize)> = slots.collect();
            by_report.sort_unstable_by_key(|&(slot, s, t)| (s, t, slot));
            let mut n_meas = 0;
            for (i, &(slot, s, t)) in by_report.iter().enumerate() {
                if i > 0 && (by_report[i - 1].1, by_report[i - 1].2) != (s, t) {
                    n_meas += 1;
                }
                ids[slot] = n_meas as u32;
            }
            n_meas + usize::from(!by_report.is_empty())
        };
        // NONE marks a miss, so every id must stay below it.
        if n_meas >= Self::NONE as usize {
            return Err(CoreError::out_of_range(
                "tuples",
                "more than 2^32 - 1 distinct reports in use",
            ));
        }
        Ok((
            Self {
                n_sensors: s_count,
                ids,
            },
            n_meas,
        ))
    }

    /// Ids through one lookup table over every sensor's reports: no sort, no search.
    fn by_table(
        input: &IntensityInput,
        slots: impl Iterator<Item = (usize, usize, usize)> + Clone,
        ids: &mut [u32],
    ) -> usize {
        let mut offset = vec![0usize; input.n_sensors() + 1];
        for s in 0..input.n_sensors() {
            offset[s + 1] = offset[s] + input.size(s) + 1;
        }
        let mut table = vec![Self::NONE; offset[input.n_sensors()]];
        const IN_USE: u32 = 0;
        for (_, s, t) in slots.clone() {
            table[offset[s] + t] = IN_USE;
        }
        let mut n_meas = 0u32;
        for entry in table.iter_mut().filter(|e| **e == IN_USE) {
            *entry = n_meas;
            n_meas += 1;
        }
        for (slot, s, t) in slots {
            ids[slot] = table[offset[s] + t];
        }
        n_meas as usize
    }

    /// Candidate c's measurement ids, in sensor order.
    pub(super) fn of(&self, c: usize) -> impl Iterator<Item = u32> + '_ {
        self.ids[c * self.n_sensors..(c + 1) * self.n_sensors]
            .iter()
            .copied()
            .filter(|&m| m != Self::NONE)
    }
}
