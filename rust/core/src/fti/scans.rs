//! Scans: the rows of one sensor that share one time value. Times are compared exactly (a
//! scan is what the sensor reported in one sampling instant, so its rows carry the identical
//! time stamp); rows with times that differ in the last bit are different scans.

use crate::data::Measurements;
use crate::error::{CoreError, CoreResult};

/// The scan structure of a measurement table, CSR-style.
#[derive(Clone, Debug, PartialEq)]
pub struct Scans {
    /// Scan (group) index of every row.
    pub scan_of: Vec<usize>,
    /// Rows of scan `k` are `rows[offsets[k]..offsets[k + 1]]`, ascending.
    pub offsets: Vec<usize>,
    pub rows: Vec<usize>,
    /// Scans of each sensor in increasing time.
    pub per_sensor: Vec<Vec<usize>>,
}

impl Scans {
    /// Groups the rows of `measurements` (already validated against `n_sensors`).
    pub fn new(measurements: &Measurements<'_>, n_sensors: usize) -> Self {
        let mut order: Vec<usize> = (0..measurements.len()).collect();
        // Sort by (sensor, time, row): rows of one scan become contiguous and ascending.
        order.sort_by(|&p, &q| {
            measurements
                .sensor(p)
                .cmp(&measurements.sensor(q))
                .then(measurements.time(p).total_cmp(&measurements.time(q)))
                .then(p.cmp(&q))
        });
        let mut scans = Scans {
            scan_of: vec![0; measurements.len()],
            offsets: vec![0],
            rows: Vec::with_capacity(order.len()),
            per_sensor: vec![Vec::new(); n_sensors],
        };
        // Times are compared by their bits, as the sort above orders them: −0.0 and +0.0
        // are two time stamps, so two scans.
        let mut previous: Option<(usize, u64)> = None;
        for &row in &order {
            let key = (measurements.sensor(row), measurements.time(row).to_bits());
            if previous != Some(key) {
                if previous.is_some() {
                    scans.offsets.push(scans.rows.len());
                }
                scans.per_sensor[key.0].push(scans.offsets.len() - 1);
                previous = Some(key);
            }
            scans.scan_of[row] = scans.offsets.len() - 1;
            scans.rows.push(row);
        }
        if previous.is_some() {
            scans.offsets.push(scans.rows.len());
        }
        scans
    }

    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Rows of scan `k`.
    pub fn scan(&self, k: usize) -> &[usize] {
        &self.rows[self.offsets[k]..self.offsets[k + 1]]
    }

    /// First and last scan of sensor `j`, or an error naming it when it has fewer than two.
    pub fn first_last(&self, j: usize) -> CoreResult<(usize, usize)> {
        match self.per_sensor[j].as_slice() {
            [first, .., last] => Ok((*first, *last)),
            other => Err(CoreError::ill_posed(
                "pairs",
                format!(
                    "sensor {j} has {} scan{}; need first and last",
                    other.len(),
                    if other.len() == 1 { "" } else { "s" }
                ),
            )),
        }
    }

    /// The scans `[a-first, b-first, a-last, b-last]` of pair (a, b) that candidates combine, for
    /// every slot `(i, j)` with `i, j < depth`: each sensor's `i`-th scan from the start and `j`-th
    /// from the end (slot (0, 0) is the paper's first and last scan; with `inner_only` it is left
    /// out). A slot is used only when both sensors' first scan precedes their last. The two
    /// sensors move together (a diagonal, not every mix): `depth²` slots instead of `depth⁴`, and a
    /// target missed in one outer scan is still covered by the next slot (docs/methods.md §1).
    pub fn scan_slots(
        &self,
        [a, b]: [usize; 2],
        depth: usize,
        inner_only: bool,
    ) -> Vec<[usize; 4]> {
        let (sa, sb) = (&self.per_sensor[a], &self.per_sensor[b]);
        let mut out = Vec::new();
        for i in 0..depth {
            for j in 0..depth {
                if inner_only && (i, j) == (0, 0) {
                    continue;
                }
                let last_a = sa.len().checked_sub(1 + j);
                let last_b = sb.len().checked_sub(1 + j);
                if let (Some(la), Some(lb)) = (last_a, last_b) {
                    if i < la && i < lb {
                        out.push([sa[i], sb[i], sa[la], sb[lb]]);
                    }
                }
            }
        }
        out
    }
}

/// One slot: the scans `[a-first, b-first, a-last, b-last]` of a sensor pair; the pair's
/// other rounds (`[a, b]` scans) its candidates are tested against before their fit, and how
/// many of those must support a candidate (module `round_gate`); and the other sensors' scans
/// that must witness it (module `witness_gate`), and how many of those must
/// (`WitnessNeed`).
#[derive(Clone, Debug, PartialEq)]
pub struct Slot {
    pub scans: [usize; 4],
    pub tested: Vec<[usize; 2]>,
    pub need: usize,
    pub witnesses: Vec<usize>,
    pub witness_need: WitnessNeed,
}

/// How many of a slot's witness scans must see a candidate before its fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WitnessNeed {
    /// At least half of them (rounded up).
    Half,
    /// More than half.
    Majority,
    /// At least this many (all of them if there are fewer).
    AtLeast(usize),
}

impl WitnessNeed {
    /// The count of `n` witness scans this rule needs: 0 when there are none.
    pub fn of(self, n: usize) -> usize {
        match self {
            _ if n == 0 => 0,
            Self::Half => n.div_ceil(2),
            Self::Majority => n / 2 + 1,
            Self::AtLeast(k) => k.clamp(1, n),
        }
    }
}

impl Slot {
    /// The slot of `scans` with nothing to test before the fit (as the paper forms its
    /// candidates).
    pub fn untested(scans: [usize; 4]) -> Self {
        Self {
            scans,
            tested: Vec::new(),
            need: 0,
            witnesses: Vec::new(),
            witness_need: WitnessNeed::Half,
        }
    }

    /// Whether a candidate of this slot is tested before its fit.
    pub fn is_tested(&self) -> bool {
        self.need > 0 || !self.witnesses.is_empty()
    }
}

impl Scans {
    /// The rounds of pair (a, b): for each of sensor a's scans k with a next one, the scans
    /// k and k + 1 with sensor b's scans nearest in time to each (`times[s]` is scan s's time),
    /// and the rounds k − 1 and k + 2 likewise. A round whose two b scans coincide is left out.
    /// The witnesses are the other sensors' scans within half the slot's span of it.
    pub fn round_slots(&self, [a, b]: [usize; 2], times: &[f64]) -> Vec<Slot> {
        let (sa, sb) = (&self.per_sensor[a], &self.per_sensor[b]);
        let nearest = |t: f64| -> Option<usize> {
            sb.iter()
                .copied()
                .min_by(|&p, &q| (times[p] - t).abs().total_cmp(&(times[q] - t).abs()))
        };
        let round = |k: usize| -> Option<[usize; 2]> {
            let a_scan = *sa.get(k)?;
            Some([a_scan, nearest(times[a_scan])?])
        };
        let mut out = Vec::new();
        for k in 0..sa.len().saturating_sub(1) {
            if let (Some([a0, b0]), Some([a1, b1])) = (round(k), round(k + 1)) {
                if b0 != b1 {
                    let before = k.checked_sub(1).and_then(round);
                    let scans = [a0, b0, a1, b1];
                    out.push(Slot {
                        scans,
                        tested: before.into_iter().chain(round(k + 2)).collect(),
                        need: 1,
                        witnesses: self.witnesses([a, b], scans, times),
                        witness_need: WitnessNeed::Half,
                    });
                }
            }
        }
        out
    }

    /// The scans of every sensor but `pair` within half the span of `scans` of it.
    fn witnesses(&self, pair: [usize; 2], scans: [usize; 4], times: &[f64]) -> Vec<usize> {
        let at = scans.map(|s| times[s]);
        let lo = at.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = at.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let margin = (hi - lo) / 2.0;
        (self.per_sensor.iter().enumerate())
            .filter(|(c, _)| !pair.contains(c))
            .flat_map(|(_, list)| list.iter().copied())
            .filter(|&s| times[s] >= lo - margin && times[s] <= hi + margin)
            .collect()
    }
}

/// The sensor pairs to use: `requested`, checked, or every pair a < b. Both sensors of each
/// pair need a first and a last scan; pairs may not repeat (in either order).
pub fn resolve_pairs(
    requested: Option<&[[usize; 2]]>,
    scans: &Scans,
) -> CoreResult<Vec<[usize; 2]>> {
    let n_sensors = scans.per_sensor.len();
    let pairs: Vec<[usize; 2]> = match requested {
        Some(p) if !p.is_empty() => p.to_vec(),
        _ => (0..n_sensors)
            .flat_map(|a| (a + 1..n_sensors).map(move |b| [a, b]))
            .collect(),
    };
    if pairs.is_empty() {
        return Err(CoreError::ill_posed(
            "pairs",
            "need at least two sensors to form a pair",
        ));
    }
    for (k, &[a, b]) in pairs.iter().enumerate() {
        if a >= n_sensors || b >= n_sensors {
            return Err(CoreError::out_of_range(
                "pairs",
                format!("pair {k} is ({a}, {b}) but the network has {n_sensors} sensors"),
            ));
        }
        if a == b {
            return Err(CoreError::out_of_range(
                "pairs",
                format!("pair {k} uses sensor {a} twice"),
            ));
        }
        if pairs[..k]
            .iter()
            .any(|&[c, d]| (c, d) == (a, b) || (c, d) == (b, a))
        {
            return Err(CoreError::out_of_range(
                "pairs",
                format!("pair {k} ({a}, {b}) repeats an earlier pair"),
            ));
        }
        scans.first_last(a)?;
        scans.first_last(b)?;
    }
    Ok(pairs)
}

#[cfg(test)]
mod tests {
    use super::Scans;
    use crate::data::{Measurements, Sensors};
    use crate::geometry::model::Space;

    /// A scan is one exact time stamp, compared as the sort compares it: −0.0 and +0.0 are
    /// two scans (equality would join them while the sort keeps them apart), 1.0 one.
    #[test]
    fn scans_split_on_the_bits_of_the_time() {
        let positions = [0.0, 0.0, 0.0, 1e4, 0.0, 0.0];
        let sensors = Sensors::new(Space::Planar, &positions, &[1e-3; 2], &[]).expect("valid");
        let (sensor, time) = ([0, 0, 0, 0, 1], [0.0, -0.0, 1.0, 0.0, -0.0]);
        let table =
            Measurements::new(&sensors, &sensor, &time, &[0.1; 5], &[f64::NAN; 5]).expect("valid");
        let scans = Scans::new(&table, 2);
        assert_eq!(scans.len(), 4);
        assert_eq!(scans.scan(scans.scan_of[0]), &[0, 3]);
        assert_eq!(scans.scan(scans.scan_of[1]), &[1]);
        assert_eq!(scans.per_sensor, vec![vec![0, 1, 2], vec![3]]);
    }
}
