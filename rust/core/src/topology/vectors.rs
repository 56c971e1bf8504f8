//! Reference-topology vectors (METHODS §4 "Topology matrix", "Diffusion").
//!
//! Around each track, the disc of radius `R_ref` is cut into M rings of equal width × N
//! sectors of equal angle; sector 0 starts at north (or at the track's heading) and sectors
//! run clockwise. A cell is occupied (1) when another track of the same source lies in it.
//! Neighbours come from an R*-tree query per track (`rstar`), not an all-pairs loop, so a
//! scan costs O(n log n + n·k) for k neighbours within `R_ref`. A neighbour exactly on the
//! disc's edge counts in the outer ring; one at the track's own position (no bearing) in
//! sector 0. A track with zero velocity has no heading: its grid starts at north.
//!
//! Diffusion spreads occupancy to the neighbouring cells of the same sector (ring ± 1, +Δ)
//! and of the same ring (sector ± 1, wrapping, +Δ′), computed from the occupancy alone (no
//! cascade); additive sums are clipped at 1, "at least" takes the maximum. Occupied cells
//! stay 1. Vectors are row-major (rings are rows) and `f32`: the closeness sums at most
//! `M·N` terms in [0, 1], far inside `f32`'s precision, and half the width doubles the
//! closeness kernel's throughput.

use std::f64::consts::TAU;

use rayon::prelude::*;
use rstar::primitives::GeomWithData;
use rstar::RTree;

use super::options::{Diffusion, Reference, TopologyOptions};
use super::scan::ScanTracks;

type Located = GeomWithData<[f64; 2], usize>;

/// Fewer tracks than this are done on the calling thread: handing a paper-sized scan (20
/// tracks) to the pool costs more than computing it.
const PARALLEL_MIN_TRACKS: usize = 256;

/// The topology vector of every track of `tracks`, `(n, M·N)` row-major. The result does
/// not depend on the thread count.
pub fn topology_vectors(tracks: &ScanTracks<'_>, options: &TopologyOptions) -> Vec<f32> {
    let cells = options.cells();
    let tree = RTree::bulk_load(
        (0..tracks.len())
            .map(|k| Located::new(tracks.position(k), k))
            .collect(),
    );
    let mut out = vec![0.0f32; tracks.len() * cells];
    let fill = |(k, row): (usize, &mut [f32])| {
        let occupied = occupancy(tracks, &tree, k, options);
        diffuse(&occupied, row, options);
    };
    if tracks.len() < PARALLEL_MIN_TRACKS {
        out.chunks_mut(cells.max(1)).enumerate().for_each(fill);
    } else {
        out.par_chunks_mut(cells.max(1)).enumerate().for_each(fill);
    }
    out
}

/// The occupied cells of track `k`'s grid, row-major.
fn occupancy(
    tracks: &ScanTracks<'_>,
    tree: &RTree<Located>,
    k: usize,
    options: &TopologyOptions,
) -> Vec<bool> {
    let (m, n) = (options.rings(), options.sectors());
    let radius = options.radius();
    let here = tracks.position(k);
    let origin = match options.reference() {
        Reference::North => 0.0,
        Reference::Heading => tracks.velocity(k).map_or(0.0, compass_of_vector),
    };
    let mut occupied = vec![false; m * n];
    for neighbour in tree.locate_within_distance(here, radius * radius) {
        if neighbour.data == k {
            continue;
        }
        let p = neighbour.geom();
        let (dx, dy) = (p[0] - here[0], p[1] - here[1]);
        let ring = (((dx.hypot(dy) / radius) * m as f64) as usize).min(m - 1);
        let angle = (compass_of_vector([dx, dy]) - origin).rem_euclid(TAU);
        let sector = ((angle / TAU * n as f64) as usize).min(n - 1);
        occupied[ring * n + sector] = true;
    }
    occupied
}

/// Compass bearing of a planar vector: clockwise from north (+y), in [0, 2π); 0 for the
/// zero vector.
fn compass_of_vector(v: [f64; 2]) -> f64 {
    if v[0] == 0.0 && v[1] == 0.0 {
        return 0.0;
    }
    v[0].atan2(v[1]).rem_euclid(TAU)
}

/// Writes the diffused values of one grid into `row`.
fn diffuse(occupied: &[bool], row: &mut [f32], options: &TopologyOptions) {
    let (m, n) = (options.rings(), options.sectors());
    let (delta, delta_prime) = (options.delta(), options.delta_prime());
    for ring in 0..m {
        for sector in 0..n {
            let cell = ring * n + sector;
            if occupied[cell] {
                row[cell] = 1.0;
                continue;
            }
            let radial = [ring.checked_sub(1), (ring + 1 < m).then_some(ring + 1)]
                .into_iter()
                .flatten()
                .filter(|&r| occupied[r * n + sector])
                .count();
            // Sectors wrap; with N = 1 or 2 a side is the cell itself or both sides are one
            // cell, counted once.
            let (left, right) = ((sector + n - 1) % n, (sector + 1) % n);
            let lateral = [(left, true), (right, right != left)]
                .into_iter()
                .filter(|&(s, distinct)| distinct && s != sector && occupied[ring * n + s])
                .count();
            let value = match options.diffusion() {
                Diffusion::Additive => radial as f64 * delta + lateral as f64 * delta_prime,
                Diffusion::AtLeast => {
                    let r = if radial > 0 { delta } else { 0.0 };
                    let l = if lateral > 0 { delta_prime } else { 0.0 };
                    r.max(l)
                }
            };
            row[cell] = value.min(1.0) as f32;
        }
    }
}
