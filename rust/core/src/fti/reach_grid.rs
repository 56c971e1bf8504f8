//! The last pairs' meetings in a uniform grid, queried with the ball of radius
//! `v_max · max(t_last − t_first)` (the *reach*) around a first pair's meeting: the last pairs
//! that may pass `v_max` with it (module `combine`).
//!
//! Cells are cubes half a reach wide ([`CELLS_PER_REACH`]). A query looks only at the cells the
//! ball may reach: along x and y those within a reach of the centre, and in each such column of
//! cells only the z range the ball spans at the column's nearest point. Each of those cells'
//! meetings is tested against the ball, reading only its position (a compact array of its
//! own); the record the tests read is fetched for the meetings in the ball. That tests about
//! half the meetings that cells a reach wide (the 3 × 3 × 3 around the centre's) did
//! (CHANGELOG.md, *The reach grid*, has the count on the ring 5 × 100 scene). The cell is
//! widened where the scene would need more than [`MAX_CELLS_PER_AXIS`] of them along an axis
//! (a tiny reach in a large scene), which only puts more meetings in each tested cell. Plain
//! arithmetic, where an R*-tree's walk cost more per meeting found, and the visits need
//! no sorting (the survivors of a visit are sorted instead, and they are few).

use rayon::prelude::*;

use super::motion_gate::Motion;
use super::ray_pairs::RayPair;
use crate::geometry::model::Space;

/// Below this many reaches along the scene's longest side the grid prunes too little to pay.
const MIN_CELLS_ACROSS: f64 = 4.0;

/// Cells per reach along an axis (where [`MAX_CELLS_PER_AXIS`] allows).
const CELLS_PER_REACH: f64 = 2.0;

/// Cells along one axis at most: 64³ cells of offsets in 3-D (2 MB) at the very worst.
const MAX_CELLS_PER_AXIS: usize = 64;

/// Slack, in cells, on the ball's extent when choosing cells: a cell's bounds and a
/// meeting's cell are each computed with rounding (of the coordinates, which may be large
/// beside a cell: ECEF metres in a scene of metres), so a meeting at a cell's edge is never
/// left out by it. The exact test against the ball decides those meetings.
const SLACK: f64 = 1e-6;

pub(super) struct Grid {
    reach2: f64,
    origin: [f64; 3],
    /// A cell's side, and cells per unit of length (one over it).
    side: f64,
    scale: f64,
    cells: [usize; 3],
    /// The meetings of cell `c` are `entries[starts[c]..starts[c + 1]]`.
    starts: Vec<usize>,
    /// The meetings' points, in `entries` order: all a test against the ball reads.
    points: Vec<[f64; 3]>,
    /// Last pair index and what the tests read of it, by cell, ascending within a cell: a
    /// visit reads the cells' records in memory order.
    entries: Vec<(usize, Motion)>,
}

impl Grid {
    /// `None` when it cannot prune: no `v_max`, no meeting, an unbounded or non-positive
    /// reach, or a scene fewer than [`MIN_CELLS_ACROSS`] reaches across.
    pub(super) fn new(
        space: Space,
        firsts: &[RayPair],
        lasts: &[RayPair],
        v_max: Option<f64>,
    ) -> Option<Self> {
        let v_max = v_max?;
        let times = |pairs: &[RayPair], pick: fn(f64, f64) -> f64, start: f64| {
            (pairs.iter().filter_map(|p| p.meeting.map(|m| m.time))).fold(start, pick)
        };
        let earliest = times(firsts, f64::min, f64::INFINITY);
        let latest = times(lasts, f64::max, f64::NEG_INFINITY);
        let reach = v_max * (latest - earliest);
        if !(reach.is_finite() && reach > 0.0) {
            return None;
        }
        let dims = space.position_dim();
        let (lo, hi) = bulk(firsts.iter().chain(lasts), dims)?;
        let longest = (0..dims).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let across = longest / reach;
        if !across.is_finite() || across < MIN_CELLS_ACROSS {
            return None;
        }
        let side = (reach / CELLS_PER_REACH).max(longest / (MAX_CELLS_PER_AXIS - 1) as f64);
        let scale = 1.0 / side;
        let cells: [usize; 3] =
            std::array::from_fn(|k| ((hi[k] - lo[k]) * scale).floor() as usize + 1);
        let mut grid = Self {
            // A hair wider than the reach: the speed test decides the pairs at its edge.
            reach2: (reach * (1.0 + 1e-9)).powi(2),
            origin: lo,
            side,
            scale,
            cells,
            starts: Vec::new(),
            points: Vec::new(),
            entries: Vec::new(),
        };
        let located: Vec<Option<(usize, Motion)>> = (lasts.par_iter())
            .map(|pair| Motion::of(pair).map(|m| (grid.cell_of(&m.point), m)))
            .collect();
        let mut starts = vec![0usize; cells.iter().product::<usize>() + 1];
        for &(cell, _) in located.iter().flatten() {
            starts[cell + 1] += 1;
        }
        for c in 1..starts.len() {
            starts[c] += starts[c - 1];
        }
        // A counting sort by cell, ascending `l` within a cell, in linear serial time (the
        // records are located in parallel above): the pairs in `entries` order.
        let mut next = starts.clone();
        let mut order = vec![0usize; starts[starts.len() - 1]];
        for (l, x) in located.iter().enumerate() {
            if let Some((cell, _)) = x {
                order[next[*cell]] = l;
                next[*cell] += 1;
            }
        }
        grid.starts = starts;
        grid.entries = (order.into_iter())
            .filter_map(|l| Some((l, located[l]?.1)))
            .collect();
        grid.points = grid.entries.iter().map(|(_, m)| m.point).collect();
        Some(grid)
    }

    /// The cell of a point, clamped into the grid. Clamping keeps two points within a cell's
    /// side of each other in the same or neighbouring cells, so the meetings outside the bulk
    /// (far meetings of nearly parallel rays) are still found: in the edge cells.
    fn cell_of(&self, point: &[f64; 3]) -> usize {
        let [i, j, k] = std::array::from_fn(|a| self.index_on(a, point[a]));
        (i * self.cells[1] + j) * self.cells[2] + k
    }

    /// The cell of coordinate `x` along axis `a`, clamped: NaN and negative cells go to 0,
    /// far ones to the last. Monotone in `x`.
    fn index_on(&self, a: usize, x: f64) -> usize {
        let at = ((x - self.origin[a]) * self.scale).floor();
        (at.max(0.0) as usize).min(self.cells[a] - 1)
    }

    /// The cells along axis `a` that hold coordinates within `half` of `x` (and [`SLACK`]).
    fn cells_within(&self, a: usize, x: f64, half: f64) -> std::ops::RangeInclusive<usize> {
        let half = half + SLACK * self.side;
        self.index_on(a, x - half)..=self.index_on(a, x + half)
    }

    /// How far `x` lies outside cell `i` along axis `a` (0 inside it), less [`SLACK`]. The
    /// edge cells reach to infinity: they hold the clamped meetings beyond the bulk.
    fn outside(&self, a: usize, i: usize, x: f64) -> f64 {
        let lo = match i {
            0 => f64::NEG_INFINITY,
            _ => self.origin[a] + i as f64 * self.side,
        };
        let hi = match i + 1 == self.cells[a] {
            true => f64::INFINITY,
            false => self.origin[a] + (i + 1) as f64 * self.side,
        };
        ((lo - x).max(x - hi) - SLACK * self.side).max(0.0)
    }

    /// Calls `visit(l, motion)` for every last pair whose meeting lies within reach of
    /// `point` (a first pair's meeting), in no particular order.
    pub(super) fn for_each_near(&self, point: &[f64; 3], mut visit: impl FnMut(usize, &Motion)) {
        let reach = self.reach2.sqrt();
        for i in self.cells_within(0, point[0], reach) {
            let dx = self.outside(0, i, point[0]);
            for j in self.cells_within(1, point[1], reach) {
                let dy = self.outside(1, j, point[1]);
                let dxy2 = dx * dx + dy * dy;
                if dxy2 > self.reach2 {
                    continue; // no cell of this column comes within reach
                }
                let ks = self.cells_within(2, point[2], (self.reach2 - dxy2).max(0.0).sqrt());
                let row = (i * self.cells[1] + j) * self.cells[2];
                let cells = self.starts[row + ks.start()]..self.starts[row + ks.end() + 1];
                for (at, p) in (cells.clone()).zip(&self.points[cells]) {
                    let d2 = (0..3).map(|k| (p[k] - point[k]).powi(2)).sum::<f64>();
                    if d2 <= self.reach2 {
                        let (l, motion) = &self.entries[at];
                        visit(*l, motion);
                    }
                }
            }
        }
    }

    /// How many last pairs [`Self::for_each_near`] visits for `f` (none without a meeting:
    /// it fails `v_max` anyway).
    pub(super) fn count_near(&self, f: &RayPair) -> usize {
        let mut count = 0;
        if let Some(m) = f.meeting {
            self.for_each_near(&m.point, |_, _| count += 1);
        }
        count
    }
}

/// The box that holds the bulk of the pairs' meetings: per axis, from the 1 % to the 99 %
/// quantile (a few far meetings of nearly parallel rays would otherwise stretch the cells);
/// `None` without a meeting.
fn bulk<'a>(pairs: impl Iterator<Item = &'a RayPair>, dims: usize) -> Option<([f64; 3], [f64; 3])> {
    let points: Vec<[f64; 3]> = pairs.filter_map(|p| p.meeting.map(|m| m.point)).collect();
    if points.is_empty() {
        return None;
    }
    let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
    let mut axis = vec![0.0; points.len()];
    let (low, high) = (points.len() / 100, points.len() - 1 - points.len() / 100);
    for k in 0..dims {
        for (value, p) in axis.iter_mut().zip(&points) {
            *value = p[k];
        }
        lo[k] = *axis.select_nth_unstable_by(low, f64::total_cmp).1;
        hi[k] = *axis.select_nth_unstable_by(high, f64::total_cmp).1;
    }
    Some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fti::options::InitiationOptions;
    use crate::fti::ray_pairs::ray_pairs;
    use crate::fti::scans::Scans;
    use crate::fti::tests::sim;

    /// The first and last ray pairs of the outer scans of sensors 0 and 1 in a cluttered
    /// 2-D (`planar`) or 3-D simulated scene, and the scene's space.
    fn outer_pairs(seed: u64, planar: bool) -> (Space, Vec<RayPair>, Vec<RayPair>) {
        let sc = match planar {
            true => sim::planar(seed, true, 20, 8),
            false => sim::paper(seed, true, 16, 8),
        };
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::problem(sensors, table);
        let scans = Scans::new(&table, sensors.len());
        let options = InitiationOptions::default();
        let ((a1, a2), (b1, b2)) = (
            scans.first_last(0).expect("scans"),
            scans.first_last(1).expect("scans"),
        );
        let pairs = |a: usize, b: usize| {
            ray_pairs(&problem, scans.scan(a), scans.scan(b), &options)
                .expect("fits")
                .0
        };
        (sc.space, pairs(a1, b1), pairs(a2, b2))
    }

    /// `pairs` with their meetings moved by `shift`.
    fn shifted(pairs: &[RayPair], shift: [f64; 3]) -> Vec<RayPair> {
        (pairs.iter())
            .map(|p| {
                let mut p = *p;
                if let Some(m) = p.meeting.as_mut() {
                    m.point = std::array::from_fn(|k| m.point[k] + shift[k]);
                }
                p
            })
            .collect()
    }

    /// Every first pair visits exactly the last pairs within reach, found by brute force, in
    /// 2-D and 3-D, with far meetings (nearly parallel rays) among both firsts and lasts,
    /// meetings at the ball's edge, and all of them again in coordinates far larger than the
    /// scene.
    #[test]
    fn the_grid_visits_exactly_the_meetings_within_reach() {
        for (seed, planar) in [(1, true), (3, false)] {
            let (space, mut firsts, mut lasts) = outer_pairs(seed, planar);
            // Far meetings: one far out in each direction, and one near another far one.
            for (k, far) in [[1e7, 0.0, 0.0], [-1e7, -3e6, 0.0], [1e7, 5.0, 0.0]]
                .iter()
                .enumerate()
            {
                let list = if k % 2 == 0 { &mut lasts } else { &mut firsts };
                let mut pair = list[k];
                if let Some(m) = pair.meeting.as_mut() {
                    m.point = *far;
                }
                list.push(pair);
            }
            let mut far_first = firsts[0];
            if let Some(m) = far_first.meeting.as_mut() {
                m.point = [1e7, 1.0, 0.0];
            }
            firsts.push(far_first);
            let v_max = Some(60.0);
            // Meetings at the ball's edge of a first one: a reach away along each axis and
            // on a diagonal (a column's corner), the reach known from a first grid.
            let reach = Grid::new(space, &firsts, &lasts, v_max)
                .expect("prunes")
                .reach2
                .sqrt();
            let centre = firsts[1].meeting.expect("met").point;
            let diagonal = reach / 3f64.sqrt();
            let edges = [[reach, 0.0, 0.0], [0.0, -reach, 0.0], [0.0, 0.0, reach]];
            for offset in edges.into_iter().chain([[diagonal, diagonal, -diagonal]]) {
                let mut pair = lasts[0];
                if let Some(m) = pair.meeting.as_mut() {
                    m.point = std::array::from_fn(|k| centre[k] + offset[k] * (1.0 - 1e-12));
                }
                lasts.push(pair);
            }
            // The same meetings in coordinates far larger than the scene (ECEF-like metres).
            for shift in [[0.0; 3], [6.4e6, -3.1e6, 2.2e6]] {
                let (firsts, lasts) = (shifted(&firsts, shift), shifted(&lasts, shift));
                let grid = Grid::new(space, &firsts, &lasts, v_max).expect("prunes");
                let mut visited_all = 0;
                for f in &firsts {
                    let mut visited = Vec::new();
                    let m = f.meeting.expect("met");
                    grid.for_each_near(&m.point, |l, _| visited.push(l));
                    visited.sort_unstable();
                    let brute: Vec<usize> = (lasts.iter().enumerate())
                        .filter(|(_, l)| {
                            l.meeting.is_some_and(|q| {
                                (0..3)
                                    .map(|k| (q.point[k] - m.point[k]).powi(2))
                                    .sum::<f64>()
                                    <= grid.reach2
                            })
                        })
                        .map(|(l, _)| l)
                        .collect();
                    assert_eq!(visited, brute, "seed {seed}, shift {shift:?}");
                    visited_all += visited.len();
                }
                assert!(visited_all > 0 && visited_all < firsts.len() * lasts.len() / 2);
            }
        }
    }

    /// The columns and z ranges a query leaves out never hold a meeting within reach, at the
    /// worst place for rounding: each meeting moved onto the lowest coordinate of its cell
    /// (as the grid assigns cells) along an axis, and queried from just under the reach
    /// below it, in a scene's own coordinates and shifted far out.
    #[test]
    fn meetings_on_cell_faces_are_found_from_a_reach_away() {
        let (space, firsts, lasts) = outer_pairs(3, false);
        let mut checked = 0;
        for shift in [[0.0; 3], [6.4e6; 3]] {
            let (firsts, lasts) = (shifted(&firsts, shift), shifted(&lasts, shift));
            let mut grid = Grid::new(space, &firsts, &lasts, Some(60.0)).expect("prunes");
            let reach = grid.reach2.sqrt();
            for at in 0..grid.points.len() {
                for axis in 0..3 {
                    let q = grid.points[at];
                    let cell = grid.index_on(axis, q[axis]);
                    if cell == 0 {
                        continue; // the first cell has no lower face
                    }
                    // The lowest coordinate the grid puts in this cell.
                    let (mut below, mut face) = (q[axis] - 2.0 * grid.side, q[axis]);
                    while below.next_up() < face {
                        let mid = below + (face - below) / 2.0;
                        let mid = if mid <= below || mid >= face {
                            below.next_up()
                        } else {
                            mid
                        };
                        if grid.index_on(axis, mid) == cell {
                            face = mid;
                        } else {
                            below = mid;
                        }
                    }
                    let mut on_face = q;
                    on_face[axis] = face;
                    grid.points[at] = on_face;
                    grid.entries[at].1.point = on_face;
                    let mut from = on_face;
                    from[axis] = face - reach;
                    while (on_face[axis] - from[axis]).powi(2) > grid.reach2 {
                        from[axis] = from[axis].next_up();
                    }
                    let mut found = false;
                    grid.for_each_near(&from, |l, _| found |= l == grid.entries[at].0);
                    assert!(found, "shift {shift:?}, meeting {at}, axis {axis}");
                    grid.points[at] = q;
                    grid.entries[at].1.point = q;
                    checked += 1;
                }
            }
        }
        assert!(checked > 100, "{checked} faces checked");
    }
}
