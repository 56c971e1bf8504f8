//! Tests of candidate generation as a whole: the batches it fits in change nothing.

use super::sim;
use crate::fti::batch::Batch;
use crate::fti::candidates::generate_at_once;
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
            generate_at_once(&problem, &scans, &slots, None, &options, batch, 1).expect("runs")
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

/// Slots formed and tested several at a time, then queued in order, give the candidates, the
/// counts and the limit of forming them one at a time: in 2-D and 3-D, with every slot formed
/// and with `max_candidates` reached partway (`stop_at_limit`), where the slots tested after
/// the one that reached it are left out.
#[test]
fn slots_tested_together_find_the_same_candidates() {
    for sc in [sim::planar(3, true, 10, 8), sim::paper(4, true, 12, 8)] {
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let problem = sim::problem(sensors, table);
        let scans = Scans::new(&table, sensors.len());
        let every = InitiationOptions::default();
        let pairs = resolve_pairs(every.pairs(), &scans).expect("pairs");
        let slots: Vec<Slot> = (pairs.iter())
            .flat_map(|&p| scans.scan_slots(p, 3, false))
            .map(Slot::untested)
            .collect();
        let batch = Batch::new(&problem, &every, None);
        let whole =
            generate_at_once(&problem, &scans, &slots, None, &every, batch, 1).expect("runs");
        let capped = every
            .clone()
            .with_max_candidates(whole.counts.v_max / 2)
            .expect("valid")
            .with_stop_at_limit(true);
        for (options, reaches) in [(&every, false), (&capped, true)] {
            let run = |at_once: usize| {
                let batch = Batch::new(&problem, options, None);
                generate_at_once(&problem, &scans, &slots, None, options, batch, at_once)
                    .expect("runs")
            };
            let one = run(1);
            assert!(
                one.counts.fitted > 100 && slots.len() >= 9,
                "{:?}",
                one.counts
            );
            assert_eq!(one.limit.is_some(), reaches, "{:?}", one.limit);
            // The limit stops it within a slot: those before it formed in full, not the rest.
            let formed = if reaches {
                1..slots.len()
            } else {
                slots.len()..slots.len() + 1
            };
            assert!(formed.contains(&one.slots_formed), "{}", one.slots_formed);
            for at_once in [2, 3, 4, 64] {
                let together = run(at_once);
                assert_eq!(one.counts, together.counts, "{at_once} at once");
                assert_eq!(one.candidates, together.candidates, "{at_once} at once");
                assert_eq!(one.limit, together.limit, "{at_once} at once");
                assert_eq!(one.slots_formed, together.slots_formed, "{at_once} at once");
            }
        }
        assert!(whole.limit.is_none());
    }
}
