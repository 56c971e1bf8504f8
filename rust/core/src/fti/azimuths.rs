//! A scan's rows sorted by azimuth, with a bucket index that finds where an azimuth falls
//! among them in a step or two instead of a binary search.
//!
//! The witness gate, the support gate and the tracking gate each ask, per candidate and scan,
//! which rows lie within a window of azimuths: at 5 sensors × 100 targets that is millions of
//! windows a run, and the two binary searches of each (their branches unpredictable) were a
//! tenth of the initiation's time. The index cuts [−π, π] into as many equal buckets as the
//! scan has rows (a power of two) and keeps, per bucket, the first row at or above it; a
//! search looks in its bucket's rows only. The bucket of an azimuth is a monotone function of
//! it, so the rows of earlier buckets all lie below it and those of later buckets above:
//! the answer is always within its bucket's rows, and is exactly
//! [`slice::partition_point`]'s (checked at the bucket's ends all the same, so no input,
//! NaN or infinite, can make it differ).

use std::f64::consts::PI;

/// The rows `[azimuth, elevation]` (wrapped) of one scan, sorted by azimuth, and their index.
pub(super) struct Azimuths {
    rows: Vec<[f64; 2]>,
    /// `starts[b]`: the rows of bucket `b` are `rows[starts[b]..starts[b + 1]]`.
    starts: Vec<usize>,
    /// Buckets per radian.
    scale: f64,
}

impl Azimuths {
    /// Sorts `rows` by azimuth (`total_cmp`) and indexes them.
    pub(super) fn new(mut rows: Vec<[f64; 2]>) -> Self {
        rows.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let buckets = rows.len().next_power_of_two();
        let scale = buckets as f64 / (2.0 * PI);
        let mut starts = vec![0usize; buckets + 1];
        for row in &rows {
            starts[bucket(row[0], scale, buckets) + 1] += 1;
        }
        for b in 1..starts.len() {
            starts[b] += starts[b - 1];
        }
        Self {
            rows,
            starts,
            scale,
        }
    }

    pub(super) fn rows(&self) -> &[[f64; 2]] {
        &self.rows
    }

    /// The first row whose azimuth is not below `x`: `rows.partition_point(|a| a[0] < x)`.
    pub(super) fn first_not_below(&self, x: f64) -> usize {
        self.point(x, |a| a < x)
    }

    /// The first row whose azimuth is above `x`: `rows.partition_point(|a| a[0] <= x)`.
    pub(super) fn first_above(&self, x: f64) -> usize {
        self.point(x, |a| a <= x)
    }

    /// The rows within `width` of `centre`, modulo 2π (every row when `width` reaches π or
    /// is NaN): those from `centre − width` up, then those past ±π.
    pub(super) fn window(&self, centre: f64, width: f64) -> impl Iterator<Item = &[f64; 2]> {
        let range = |lo: f64, hi: f64| {
            let start = self.first_not_below(lo);
            &self.rows[start..self.first_above(hi).max(start)]
        };
        let (lo, hi) = (centre - width, centre + width);
        let (main, wrapped): (&[[f64; 2]], &[[f64; 2]]) = if width >= PI || width.is_nan() {
            (&self.rows, &[])
        } else if lo < -PI {
            (range(-PI, hi), range(lo + 2.0 * PI, PI))
        } else if hi > PI {
            (range(lo, PI), range(-PI, hi - 2.0 * PI))
        } else {
            (range(lo, hi), &[])
        };
        main.iter().chain(wrapped)
    }

    /// `rows.partition_point(|a| below(a[0]))` for a `below` that holds up to some azimuth
    /// near `x` and not past it, searched within `x`'s bucket.
    fn point(&self, x: f64, below: impl Fn(f64) -> bool) -> usize {
        let n = self.rows.len();
        let b = bucket(x, self.scale, self.starts.len() - 1);
        let (mut lo, mut hi) = (self.starts[b], self.starts[b + 1]);
        // Never taken for sorted rows (the buckets are monotone in the azimuth); a guard, so
        // that the answer is partition_point's whatever the input.
        if lo > 0 && !below(self.rows[lo - 1][0]) {
            lo = 0;
        }
        if hi < n && below(self.rows[hi][0]) {
            hi = n;
        }
        lo + self.rows[lo..hi].partition_point(|a| below(a[0]))
    }
}

/// The bucket of azimuth `x` among `buckets` over [−π, π]: monotone in `x`; below −π and NaN
/// go to the first, from π on to the last.
fn bucket(x: f64, scale: f64, buckets: usize) -> usize {
    let at = (x + PI) * scale;
    if at >= 0.0 {
        (at as usize).min(buckets - 1)
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The index's searches equal `partition_point` on scans of 0 to 300 rows, clustered and
    /// spread, with repeated azimuths, at the rows' own azimuths, between them, at ±π, past
    /// it, at infinities and NaN.
    #[test]
    fn the_searches_are_partition_points() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut checked = 0;
        for case in 0..200 {
            let n = case * 3 / 2;
            let clustered = case % 3 == 0;
            let rows: Vec<[f64; 2]> = (0..n)
                .map(|_| {
                    let a = match clustered {
                        true => 0.3 + rng.random_range(-0.01..0.01),
                        false => rng.random_range(-PI..=PI),
                    };
                    // Some repeated azimuths.
                    let a = if rng.random_bool(0.1) {
                        (a * 8.0).round() / 8.0
                    } else {
                        a
                    };
                    [a.clamp(-PI, PI), 0.0]
                })
                .collect();
            let index = Azimuths::new(rows);
            let rows = index.rows();
            let mut probes = vec![-PI, PI, -4.0, 4.0, 0.0, -0.0, f64::INFINITY];
            probes.extend([f64::NEG_INFINITY, f64::NAN]);
            probes.extend(rows.iter().map(|a| a[0]));
            probes.extend((0..50).map(|_| rng.random_range(-3.5..3.5)));
            probes.extend(rows.iter().map(|a| a[0].next_up()));
            for x in probes {
                assert_eq!(
                    index.first_not_below(x),
                    rows.partition_point(|a| a[0] < x),
                    "{x}"
                );
                assert_eq!(
                    index.first_above(x),
                    rows.partition_point(|a| a[0] <= x),
                    "{x}"
                );
                checked += 1;
            }
        }
        assert!(checked > 20_000, "{checked}");
    }

    #[test]
    fn the_window_wraps_around_pi() {
        let index = Azimuths::new(vec![[3.1, 0.0], [-1.0, 0.0], [0.0, 0.0], [-3.1, 0.0]]);
        let found = |c: f64, w: f64| index.window(c, w).map(|a| a[0]).collect::<Vec<_>>();
        assert_eq!(found(PI, 0.1), vec![3.1, -3.1]);
        assert_eq!(found(-PI + 0.01, 0.1), vec![-3.1, 3.1]);
        assert_eq!(found(0.0, 0.5), vec![0.0]);
        assert_eq!(found(0.0, 4.0).len(), 4);
        assert_eq!(found(0.0, f64::NAN).len(), 4);
    }
}
