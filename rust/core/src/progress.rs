//! Progress of a long core call, for a progress bar: the call reports which stage it is in and
//! how far through it, and the caller decides what to show (the Python binding forwards the
//! reports to a `tqdm` bar a few times a second). The core stays free of any UI: a report is
//! one virtual call, and [`Silent`] ignores them.

use std::fmt::Debug;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Where a report goes. Reports may come from any thread of the pool, often; a sink that does
/// real work per report should limit its own rate.
pub trait Progress: Sync + Debug {
    /// `stage` is `fraction` (in [0, 1]) done.
    fn report(&self, stage: &'static str, fraction: f64);

    /// Whether the watcher wants the call to stop (the binding's: its callable raised). The
    /// long loops poll it where they poll Ctrl-C, and the call then ends as interrupted.
    fn cancelled(&self) -> bool {
        false
    }
}

/// Ignores every report: the sink of calls nobody watches.
#[derive(Debug, Default, Clone, Copy)]
pub struct Silent;

impl Progress for Silent {
    fn report(&self, _stage: &'static str, _fraction: f64) {}
}

/// Ignores the reports but passes on a watcher's wish to stop: for work done alongside other
/// work of the same stage, whose own fractions would make the stage's progress jump about.
#[derive(Debug, Clone, Copy)]
pub struct Muted<'a>(pub &'a dyn Progress);

impl Progress for Muted<'_> {
    fn report(&self, _stage: &'static str, _fraction: f64) {}

    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// Counts the units of one stage as threads finish them, and reports the fraction done.
///
/// One thread reports at a time, under a lock it only tries: a thread that finds another
/// reporting goes on with its work (the sink may be slow: the binding calls Python), and its
/// units are in the next report. A report reads the count under the lock, so reports never go
/// back; [`finish`](Self::finish) reports the end whoever held the lock last.
#[derive(Debug)]
pub struct Tally<'a> {
    sink: &'a dyn Progress,
    stage: &'static str,
    total: u64,
    done: AtomicU64,
    reported: Mutex<u64>,
}

impl<'a> Tally<'a> {
    /// A stage of `total` units, reported as begun.
    pub fn new(sink: &'a dyn Progress, stage: &'static str, total: u64) -> Self {
        Self::resumed(sink, stage, 0, total)
    }

    /// A stage of `total` units of which `done` are done, reported so.
    pub fn resumed(sink: &'a dyn Progress, stage: &'static str, done: u64, total: u64) -> Self {
        sink.report(stage, fraction(done, total));
        Self {
            sink,
            stage,
            total,
            done: AtomicU64::new(done),
            reported: Mutex::new(done),
        }
    }

    /// `units` more are done.
    pub fn advance(&self, units: u64) {
        self.done.fetch_add(units, Ordering::Relaxed);
        // Busy (another thread is reporting) or poisoned (a panic in a report): skip this one.
        if let Ok(reported) = self.reported.try_lock() {
            self.report_locked(reported);
        }
    }

    /// Reports the count now, waiting for the lock: the stage's last report.
    pub fn finish(&self) {
        if let Ok(reported) = self.reported.lock() {
            self.report_locked(reported);
        }
    }

    fn report_locked(&self, mut reported: std::sync::MutexGuard<'_, u64>) {
        let done = self.done.load(Ordering::Relaxed);
        if done > *reported {
            *reported = done;
            self.sink.report(self.stage, fraction(done, self.total));
        }
    }

    /// Unit `index` is `part` (in [0, 1]) done, the units before it all done: for stages
    /// whose units are done one after another, each in steps.
    pub fn within(&self, index: u64, part: f64) {
        let done = index as f64 + part.clamp(0.0, 1.0);
        self.sink
            .report(self.stage, (done / self.total.max(1) as f64).min(1.0));
    }

    /// Unit `index` as a sink of its own: a report of `part` of it done is the stage's units
    /// before it plus that part ([`within`](Self::within)), whatever stage it names.
    pub fn unit(&self, index: u64) -> Unit<'_> {
        Unit { tally: self, index }
    }
}

/// One unit of a [`Tally`], reporting its own progress (see [`Tally::unit`]).
#[derive(Debug)]
pub struct Unit<'a> {
    tally: &'a Tally<'a>,
    index: u64,
}

impl Progress for Unit<'_> {
    fn report(&self, _stage: &'static str, part: f64) {
        self.tally.within(self.index, part);
    }

    fn cancelled(&self) -> bool {
        self.tally.sink.cancelled()
    }
}

fn fraction(done: u64, total: u64) -> f64 {
    if total == 0 {
        return 1.0;
    }
    (done as f64 / total as f64).min(1.0)
}

/// A sink that keeps every report, for tests.
#[cfg(test)]
#[derive(Debug, Default)]
pub(crate) struct Recorded(Mutex<Vec<(&'static str, f64)>>);

#[cfg(test)]
impl Recorded {
    pub(crate) fn reports(self) -> Vec<(&'static str, f64)> {
        self.0.into_inner().expect("not poisoned")
    }
}

#[cfg(test)]
impl Progress for Recorded {
    fn report(&self, stage: &'static str, fraction: f64) {
        self.0.lock().expect("not poisoned").push((stage, fraction));
    }
}

#[cfg(test)]
mod tests {
    use super::{Recorded, Tally};

    #[test]
    fn a_tally_reports_fractions_of_its_stage() {
        let sink = Recorded::default();
        let tally = Tally::new(&sink, "search", 4);
        tally.advance(1);
        tally.advance(3);
        tally.finish(); // nothing new since the last report: no report
        let steps = Tally::new(&sink, "candidates", 2);
        steps.within(1, 0.5);
        steps.within(1, 7.0); // a part past 1 counts as the unit done
        let got = sink.reports();
        let expected = [
            ("search", 0.0),
            ("search", 0.25),
            ("search", 1.0),
            ("candidates", 0.0),
            ("candidates", 0.75),
            ("candidates", 1.0),
        ];
        assert_eq!(got, expected);
    }
}
