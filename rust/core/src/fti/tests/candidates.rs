//! Tests of candidate generation as a whole: the batches it fits in change nothing.

use super::sim;
use crate::fti::batch::Batch;
use crate::fti::candidates::generate_in;
use crate::fti::options::InitiationOptions;
use crate::fti::scans::{resolve_pairs, Scans, Slot};

/// Batches of 7 that let go of their ray pairs at every scan pair find the candidates, in the
/// same order, and the counts of one batch per 16 384: in 2-D and 3-D, over the slots of
/// pass 2 (many scan pairs, most with few survivors).
#[test]
fn small_batches_find_the_same_candidates() {
    for sc in [sim::planar(3, true, 10, 8), sim::paper(4, true, 12, 8)] {
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::problem(sensors, table);
        let options = InitiationOptions::default();
        let scans = Scans::new(&table, sensors.len());
        let pairs = resolve_pairs(options.pairs(), &scans).expect("pairs");
        let slots: Vec<Slot> = (pairs.iter())
            .flat_map(|&p| scans.scan_slots(p, 3, false))
            .map(Slot::untested)
            .collect();
        let run = |batch: Batch<'_>| {
            generate_in(&problem, &scans, &slots, None, &options, batch).expect("runs")
        };
        let whole = run(Batch::new(&problem, &options, None));
        let small = run(Batch::new(&problem, &options, None).with_limits(7, 0));
        assert!(
            whole.counts.fitted > 100 && slots.len() >= 9,
            "{:?}",
            whole.counts
        );
        assert_eq!(whole.counts, small.counts);
        assert_eq!(whole.candidates, small.candidates);
    }
}
