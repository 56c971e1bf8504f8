//! The exact bearing window of the enumeration.
//!
//! A prefix's ML point passes the gate only if every ray's azimuth residual is at most
//! `w = √γ·σ`, i.e. only if its horizontal projection lies in every ray's *wedge* — the cone of
//! half-angle w around the measured azimuth, apex at the sensor. Any extension's ML point must
//! lie in the wedges of the prefix's first two rays too, so a report of a further sensor q can
//! only pass if its azimuth is within `w_q` of some bearing under which q sees the intersection
//! of those two wedges. For w < π/2 the wedges are convex; their intersection is bounded when
//! the two cones share no direction, and is then a convex polygon whose vertices are the
//! crossings of the wedges' edges and any apex inside the other wedge. The bearings of a convex
//! polygon seen from outside span less than π and are bounded by its vertices' bearings.
//!
//! Everything is inclusive with a margin, so the window can only be too wide, never too narrow;
//! whenever a case is not clear-cut (unbounded intersection, q inside or near it, wide wedges)
//! there is no window and every report is fitted.

use std::f64::consts::PI;

use crate::geometry::angles::wrap;
use crate::geometry::fastmath::atan2_any;
use crate::geometry::los::intersect_bearings;

/// Wedges wider than this (half-angle, rad) are not used: convexity needs < π/2.
const MAX_HALF_WIDTH: f64 = 1.0;
/// Extra angle (rad) added to every comparison.
const ANGLE_MARGIN: f64 = 1e-9;

/// One ray's wedge in the horizontal plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Wedge {
    pub apex: [f64; 2],
    pub bearing: f64,
    pub half_width: f64,
}

impl Wedge {
    fn contains(&self, point: &[f64; 2], margin: f64) -> bool {
        let (dx, dy) = (point[0] - self.apex[0], point[1] - self.apex[1]);
        if dx == 0.0 && dy == 0.0 {
            return true;
        }
        wrap(atan2_any(dy, dx) - self.bearing).abs() <= self.half_width + margin
    }
}

/// The intersection of the first two rays' wedges, by its vertices.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Window {
    wedges: [Wedge; 2],
    vertices: [[f64; 2]; 6],
    count: usize,
}

impl Window {
    /// The bounded intersection of two wedges, or `None` when there is no usable window.
    pub fn new(a: Wedge, b: Wedge) -> Option<Window> {
        if a.half_width >= MAX_HALF_WIDTH || b.half_width >= MAX_HALF_WIDTH {
            return None;
        }
        let baseline = (a.apex[0] - b.apex[0]).hypot(a.apex[1] - b.apex[1]);
        if baseline.is_nan() || baseline <= 1e-6 {
            return None;
        }
        // Shared recession direction ⇒ unbounded intersection (covers parallel rays too).
        if wrap(a.bearing - b.bearing).abs() <= a.half_width + b.half_width + 1e-6 {
            return None;
        }
        let mut window = Window {
            wedges: [a, b],
            vertices: [[0.0; 2]; 6],
            count: 0,
        };
        let tolerance = 1e-9 * baseline;
        for ea in [a.bearing - a.half_width, a.bearing + a.half_width] {
            for eb in [b.bearing - b.half_width, b.bearing + b.half_width] {
                if let Some((p, ra, rb)) = intersect_bearings(&a.apex, ea, &b.apex, eb) {
                    if ra >= -tolerance && rb >= -tolerance {
                        window.push(p);
                    }
                }
            }
        }
        if b.contains(&a.apex, ANGLE_MARGIN) {
            window.push(a.apex);
        }
        if a.contains(&b.apex, ANGLE_MARGIN) {
            window.push(b.apex);
        }
        (window.count > 0
            && window.vertices[..window.count]
                .iter()
                .all(|v| v[0].is_finite() && v[1].is_finite()))
        .then_some(window)
    }

    fn push(&mut self, p: [f64; 2]) {
        if self.count < self.vertices.len() {
            self.vertices[self.count] = p;
            self.count += 1;
        }
    }

    /// The azimuth interval `[lo, hi]` (hi − lo < 2π, lo unwrapped) a report of the sensor at
    /// `q` with gate half-width `half_width` must fall in, or `None` for "any azimuth".
    pub fn azimuth_interval(&self, q: &[f64; 2], half_width: f64) -> Option<(f64, f64)> {
        // q inside (or on the edge of) the region sees it under every bearing.
        if self.wedges.iter().all(|w| w.contains(q, 1e-6)) {
            return None;
        }
        let vertices = &self.vertices[..self.count];
        let bearing = |v: &[f64; 2]| atan2_any(v[1] - q[1], v[0] - q[0]);
        let reference = bearing(vertices.first()?);
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for v in vertices {
            if (v[0] - q[0]).hypot(v[1] - q[1]) <= 1e-6 {
                return None;
            }
            let rel = wrap(bearing(v) - reference);
            lo = lo.min(rel);
            hi = hi.max(rel);
        }
        if hi - lo >= PI - 1e-3 {
            return None;
        }
        let pad = half_width + ANGLE_MARGIN;
        let (lo, hi) = (reference + lo - pad, reference + hi + pad);
        (hi - lo < 2.0 * PI - 1e-9).then_some((lo, hi))
    }
}

/// Positions (ascending, into `sorted`) of the entries whose wrapped bearing lies in `[lo, hi]`.
/// `sorted` holds `(wrapped bearing, local index)` in ascending bearing.
pub(crate) fn select(sorted: &[(f64, u32)], lo: f64, hi: f64, out: &mut Vec<u32>) {
    let start = out.len();
    let lo_w = wrap(lo);
    let hi_w = lo_w + (hi - lo);
    let mut take = |a: f64, b: f64| {
        let first = sorted.partition_point(|e| e.0 < a);
        let last = sorted.partition_point(|e| e.0 <= b);
        if first < last {
            out.extend(sorted[first..last].iter().map(|e| e.1));
        }
    };
    if hi_w <= PI {
        take(lo_w, hi_w);
    } else {
        take(lo_w, PI);
        take(-PI, hi_w - 2.0 * PI);
    }
    out[start..].sort_unstable();
}
