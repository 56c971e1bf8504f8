//! The initiation's progress reports: what a progress bar is shown.

use super::{run, sim};
use crate::error::CoreError;
use crate::fti::{initiate_reporting, InitiationOptions};
use crate::progress::{Progress, Recorded};

/// Each pass reports its candidate formation, then its search, each from 0 to 1 without going
/// back; the reports change nothing in the answer.
#[test]
fn each_pass_reports_its_stages_in_order_and_the_answer_is_unchanged() {
    for sc in [sim::paper(3, true, 8, 8), sim::planar(3, true, 4, 8)] {
        let options = InitiationOptions::default();
        let sensors = sc.sensors();
        let table = sc.measurements(&sensors);
        let sink = Recorded::default();
        let reported = initiate_reporting(&sensors, &table, &sc.spreads(), 0.0, &options, &sink)
            .expect("runs");
        assert_eq!(reported.labels, run(&sc, &options).expect("runs").labels);
        let reports = sink.reports();
        // Runs of one stage, in the order they came.
        let mut runs: Vec<(&str, Vec<f64>)> = Vec::new();
        for (stage, fraction) in reports {
            match runs.last_mut() {
                Some((last, fractions)) if *last == stage => fractions.push(fraction),
                _ => runs.push((stage, vec![fraction])),
            }
        }
        let stages: Vec<&str> = runs.iter().map(|(stage, _)| *stage).collect();
        assert_eq!(stages, ["candidates", "search", "candidates", "search"]);
        for (stage, fractions) in &runs {
            assert_eq!(fractions.first(), Some(&0.0), "{stage}: {fractions:?}");
            assert_eq!(fractions.last(), Some(&1.0), "{stage}: {fractions:?}");
            assert!(
                fractions.windows(2).all(|w| w[0] <= w[1]),
                "{stage}: {fractions:?}"
            );
        }
    }
}

/// A watcher that cancels at its first report stops the call in its first stage: it ends as
/// interrupted, before any search.
#[test]
fn a_cancelling_watcher_stops_the_call_before_the_search() {
    #[derive(Debug, Default)]
    struct Cancelling(Recorded);

    impl Progress for Cancelling {
        fn report(&self, stage: &'static str, fraction: f64) {
            self.0.report(stage, fraction);
        }

        fn cancelled(&self) -> bool {
            true
        }
    }

    let sc = sim::paper(3, true, 8, 8);
    let sensors = sc.sensors();
    let table = sc.measurements(&sensors);
    let sink = Cancelling::default();
    let options = InitiationOptions::default();
    let outcome = initiate_reporting(&sensors, &table, &sc.spreads(), 0.0, &options, &sink);
    assert!(
        matches!(outcome, Err(CoreError::Interrupted)),
        "{outcome:?}"
    );
    let stages: Vec<&str> = sink.0.reports().iter().map(|(stage, _)| *stage).collect();
    assert!(
        !stages.is_empty() && stages.iter().all(|&s| s == "candidates"),
        "{stages:?}"
    );
}
