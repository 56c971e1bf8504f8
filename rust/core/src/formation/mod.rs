//! Passive location of formation targets with emitter attributes (METHODS §3, paper 004): the
//! modified baseline least-distance method, with the Dempster-Shafer attribute test of
//! [`crate::evidence`] pruning the baseline intersections.
//!
//! Several 2-D bearing sensors see a close formation; each report is a bearing plus emitter
//! attributes. For every report of the baseline sensor, its line of sight is met by every
//! line of every other sensor (`subsets`); the meetings that survive the attribute,
//! range and region tests form one subset per sensor. Each point of a reference subset is
//! completed with the nearest point of every other subset, and the line set whose pairwise
//! intersections cluster tightest (eq. 6) is that report's association (`choice`), located
//! by ML triangulation ([`locate`](fn@locate)). Baseline reports are decided independently
//! (a line may serve two, as in the paper) or, as an option, one-to-one.

mod choice;
mod labels;
mod locate;
mod options;
mod subsets;
#[cfg(test)]
mod tests;

pub use locate::{locate, locate_reporting, FormationOutput};
pub use options::{
    triangulation_fit_options, ClusterRadius, FormationOptions, Reference, Region,
    DEFAULT_MAX_PAIRS,
};
pub use subsets::PruneCounts;
