//! A scan's rows sorted by azimuth, with a bucket index that finds where an azimuth falls
//! among them in a step or two instead of a binary search.
//!
//! The witness, support and tracking gates ask, per candidate and scan, which rows lie within a
//! window of azimuths: at 5 sensors × 100 targets that is millions of windows a run, and the
//! two binary searches of each (their branches unpredictable) were a tenth of the
//! initiation's samples. [`BucketIndex`] cuts the range of a scan's sorted angles into as many
//! equal buckets as there are angles (a power of two) and keeps, per bucket, its first angle;
//! a search looks in its bucket only. The bucket of an angle is a monotone function of it, so
//! the angles of earlier buckets all lie below it and those of later buckets above: the answer
//! is always within its bucket, and is exactly [`slice::partition_point`]'s (checked at the
//! bucket's ends all the same, so no input, NaN or infinite, can make it differ). The
//! closeness's windows (module `closeness`) keep their binary searches: there the `exp` of
//! each row in the window is the cost, and the index measured no faster
//! (`benches/bench_closeness.py --sensors 5 --targets 100`).

use std::f64::consts::PI;
use std::ops::Range;

/// The bucket index of one scan's sorted angles (held by the caller).
#[derive(Clone, Debug)]
pub(super) struct BucketIndex {
    /// `starts[b]`: the angles of bucket `b` are `[starts[b]..starts[b + 1]]`.
    starts: Vec<usize>,
    /// The smallest angle, and buckets per radian (0 when the angles span none).
    low: f64,
    scale: f64,
}

impl BucketIndex {
    /// The index of `sorted` (ascending by `total_cmp`).
    pub(super) fn new(sorted: &[f64]) -> Self {
        let buckets = sorted.len().next_power_of_two();
        let (low, high) = match (sorted.first(), sorted.last()) {
            (Some(&low), Some(&high)) => (low, high),
            _ => (0.0, 0.0),
        };
        let scale = buckets as f64 / (high - low);
        let mut index = Self {
            starts: vec![0usize; buckets + 1],
            low,
            scale: if scale.is_finite() { scale } else { 0.0 },
        };
        for &angle in sorted {
            let b = index.bucket(angle);
            index.starts[b + 1] += 1;
        }
        for b in 1..index.starts.len() {
            index.starts[b] += index.starts[b - 1];
        }
        index
    }

    /// The first angle not below `x`: `sorted.partition_point(|&a| a < x)`.
    #[inline]
    pub(super) fn first_not_below(&self, sorted: &[f64], x: f64) -> usize {
        self.point(sorted, x, |a| a < x)
    }

    /// The first angle above `x`: `sorted.partition_point(|&a| a <= x)`.
    #[cfg(test)]
    fn first_above(&self, sorted: &[f64], x: f64) -> usize {
        self.point(sorted, x, |a| a <= x)
    }

    /// `sorted.partition_point(|&a| below(a))` for a `below` that holds up to some angle near
    /// `x` and not past it, searched within `x`'s bucket.
    #[inline]
    fn point(&self, sorted: &[f64], x: f64, below: impl Fn(f64) -> bool) -> usize {
        let n = sorted.len();
        let b = self.bucket(x);
        let (mut lo, mut hi) = (self.starts[b], self.starts[b + 1]);
        // Never taken for sorted angles (the buckets are monotone in the angle); a guard, so
        // that the answer is partition_point's whatever the input.
        if lo > 0 && !below(sorted[lo - 1]) {
            lo = 0;
        }
        if hi < n && below(sorted[hi]) {
            hi = n;
        }
        lo + sorted[lo..hi].partition_point(|&a| below(a))
    }

    /// The positions of `sorted` (angles in (−π, π]) within `width` of `centre`, modulo 2π, as
    /// two ranges: those from `centre − width` up, then those past ±π (often empty). Every
    /// position when `width` reaches π or is NaN; none when `centre` is NaN.
    pub(super) fn window(&self, sorted: &[f64], centre: f64, width: f64) -> [Range<usize>; 2] {
        self.spans(sorted, centre, width)
            .map(|span| span.start..span.start + span.len_in(sorted))
    }

    /// [`Self::window`]'s two parts, each as where it starts and where it ends (module doc):
    /// a caller that reads the rows in order can stop at the end itself.
    pub(super) fn spans(&self, sorted: &[f64], centre: f64, width: f64) -> [Span; 2] {
        let span = |lo: f64, hi: f64| Span {
            start: self.first_not_below(sorted, lo),
            hi,
            every: false,
        };
        let none = Span {
            start: sorted.len(),
            hi: f64::NEG_INFINITY,
            every: false,
        };
        let (lo, hi) = (centre - width, centre + width);
        if width >= PI || width.is_nan() {
            let every = Span {
                start: 0,
                hi,
                every: true,
            };
            [every, none]
        } else if lo < -PI {
            [span(-PI, hi), span(lo + 2.0 * PI, PI)]
        } else if hi > PI {
            [span(lo, PI), span(-PI, hi - 2.0 * PI)]
        } else {
            [span(lo, hi), none]
        }
    }

    /// The bucket of angle `x`: monotone in `x`; below the smallest angle and NaN go to the
    /// first, from the largest on to the last.
    #[inline]
    fn bucket(&self, x: f64) -> usize {
        let at = (x - self.low) * self.scale;
        if at >= 0.0 {
            (at as usize).min(self.starts.len() - 2)
        } else {
            0
        }
    }
}

/// How many of `sorted`'s first angles are `≤ hi` (all of them satisfy it up to some point).
#[inline]
fn prefix_within(sorted: &[f64], hi: f64) -> usize {
    sorted.iter().take_while(|&&a| a <= hi).count()
}

/// One part of a window: the angles from `start` (the first not below the part's lower end)
/// on, while they are `≤ hi` (all of them from `start` on when `every`). Its end is found by
/// stepping past the angles in it, which the callers read anyway: a window holds a few rows,
/// and a second search cost more than the steps. The angles `≤ hi` are a prefix of the sorted
/// angles, so the part is `start..first_above(hi).max(start)`, as the unit test checks.
#[derive(Clone, Copy, Debug)]
pub(super) struct Span {
    start: usize,
    hi: f64,
    every: bool,
}

impl Span {
    /// Whether an angle from `start` on, read in order, is still in the span.
    #[inline]
    fn holds(&self, angle: f64) -> bool {
        self.every || angle <= self.hi
    }

    /// The span's length in `sorted`.
    #[inline]
    fn len_in(&self, sorted: &[f64]) -> usize {
        let rest = sorted.get(self.start..).unwrap_or_default();
        match self.every {
            true => rest.len(),
            false => prefix_within(rest, self.hi),
        }
    }
}

/// The rows `[azimuth, elevation]` (wrapped) of one scan, sorted by azimuth, and the index of
/// their azimuths.
pub(super) struct Azimuths {
    rows: Vec<[f64; 2]>,
    azimuths: Vec<f64>,
    index: BucketIndex,
}

impl Azimuths {
    /// Sorts `rows` by azimuth (`total_cmp`) and indexes them.
    pub(super) fn new(mut rows: Vec<[f64; 2]>) -> Self {
        rows.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let azimuths: Vec<f64> = rows.iter().map(|a| a[0]).collect();
        Self {
            index: BucketIndex::new(&azimuths),
            rows,
            azimuths,
        }
    }

    pub(super) fn rows(&self) -> &[[f64; 2]] {
        &self.rows
    }

    /// The first row whose azimuth is not below `x`: `rows.partition_point(|a| a[0] < x)`.
    pub(super) fn first_not_below(&self, x: f64) -> usize {
        self.index.first_not_below(&self.azimuths, x)
    }

    /// The rows within `width` of `centre`, modulo 2π (every row when `width` reaches π or
    /// is NaN): those from `centre − width` up, then those past ±π.
    ///
    /// The rows are read as they are taken, so a caller that stops at the first it wants
    /// reads no further.
    pub(super) fn window(&self, centre: f64, width: f64) -> impl Iterator<Item = &[f64; 2]> {
        let [main, wrapped] = self.index.spans(&self.azimuths, centre, width);
        let part = |span: Span| {
            let rows = self.rows.get(span.start..).unwrap_or_default();
            rows.iter().take_while(move |row| span.holds(row[0]))
        };
        part(main).chain(part(wrapped))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The index's searches equal `partition_point` on scans of 0 to 300 rows (one row alone,
    /// all rows at one azimuth, clustered, spread, with repeated azimuths), probed at the rows'
    /// own azimuths and just above them, between them, at ±π and past it, at the infinities
    /// and at NaN.
    #[test]
    fn the_searches_are_partition_points() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut checked = 0;
        for case in 0..200 {
            let n = case * 3 / 2;
            let clustered = case % 3 == 0;
            let rows: Vec<[f64; 2]> = (0..n)
                .map(|_| {
                    let a = match (case % 7, clustered) {
                        (0, _) => 0.25,
                        (_, true) => 0.3 + rng.random_range(-0.01..0.01),
                        (_, false) => rng.random_range(-PI..=PI),
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
            let (rows, keys) = (index.rows(), &index.azimuths);
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
                    index.index.first_above(keys, x),
                    rows.partition_point(|a| a[0] <= x),
                    "{x}"
                );
                checked += 1;
            }
        }
        assert!(checked > 20_000, "{checked}");
    }

    /// The windows are those of two `partition_point`s a part (`first_not_below(lo)..
    /// first_above(hi).max(start)`), and `Azimuths::window` reads their rows, at widths from 0
    /// past π, centres across ±π, NaN and infinite centres and widths, on scans with repeated
    /// azimuths.
    #[test]
    fn the_windows_are_two_searches_a_part() {
        let reference = |keys: &[f64], centre: f64, width: f64| -> [Range<usize>; 2] {
            let range = |lo: f64, hi: f64| {
                let start = keys.partition_point(|&a| a < lo);
                start..keys.partition_point(|&a| a <= hi).max(start)
            };
            let (lo, hi) = (centre - width, centre + width);
            if width >= PI || width.is_nan() {
                [0..keys.len(), 0..0]
            } else if lo < -PI {
                [range(-PI, hi), range(lo + 2.0 * PI, PI)]
            } else if hi > PI {
                [range(lo, PI), range(-PI, hi - 2.0 * PI)]
            } else {
                [range(lo, hi), 0..0]
            }
        };
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let mut nonempty = 0;
        for case in 0..100 {
            let n = case * 2;
            let rows: Vec<[f64; 2]> = (0..n)
                .map(|k| match case % 4 {
                    0 => [(rng.random_range(-PI..=PI) * 4.0).round() / 4.0, k as f64],
                    _ => [rng.random_range(-PI..=PI), k as f64],
                })
                .collect();
            let index = Azimuths::new(rows);
            let keys = &index.azimuths;
            let mut centres = vec![-PI, PI, 0.0, -0.0, f64::INFINITY, f64::NAN];
            centres.extend(keys.iter().copied());
            centres.extend((0..20).map(|_| rng.random_range(-3.5..3.5)));
            for &centre in &centres {
                for width in [0.0, 0.01, 0.3, 1.0, 3.0, PI, 4.0, f64::NAN, f64::INFINITY] {
                    // Empty parts may sit at any position.
                    let plain = |parts: [Range<usize>; 2]| {
                        parts.map(|r| if r.is_empty() { 0..0 } else { r })
                    };
                    let expected = plain(reference(keys, centre, width));
                    let got = plain(index.index.window(keys, centre, width));
                    assert_eq!(got, expected, "{centre} ± {width}");
                    let rows: Vec<[f64; 2]> = index.window(centre, width).copied().collect();
                    let [a, b] = expected;
                    nonempty += usize::from(!rows.is_empty());
                    assert_eq!(rows, [&index.rows[a], &index.rows[b]].concat());
                }
            }
        }
        assert!(nonempty > 5_000, "{nonempty}");
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
