//! Which candidate formation an initiation runs ([`Formation`], the `candidates` option), and
//! what `auto` stands for in a given network. The formations themselves are module
//! `pipeline`'s passes over module `formation_slots`' slots.

use crate::error::{parse_option, UnknownOption};
use crate::geometry::model::Space;

/// Where the candidates come from: see module `candidates`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formation {
    /// With three or more sensors that have two scans or more, [`Formation::Rounds`] in 3-D
    /// and [`Formation::Witnessed`] in 2-D (where any two bearings meet, so the short-baseline
    /// rounds give poor candidates); [`Formation::Witnessed`] with fewer (its slots are the
    /// paper's, witnessed by the pair's own other scans).
    Auto,
    /// The paper's (eq. 20–22): the first and last scans of each sensor pair.
    Paper,
    /// Consecutive rounds of each sensor pair (a project extension): the short-baseline
    /// 4-tuples of two neighbouring scans of each sensor, with the other sensor's scans
    /// nearest in time, tested against the pair's neighbouring rounds (module `round_gate`)
    /// and the other sensors' scans (module `witness_gate`) before their fit.
    Rounds,
    /// The paper's slots (a project extension): each candidate tested before its fit (module
    /// `witness_gate`) against every scan of the sensors outside its pair, or, with fewer than
    /// three sensors that scan twice or more, against the pair's own scans outside the slot,
    /// as many of which must see it as detection will need (module `formation_slots`); the
    /// paper's without `prefit_gates` or the support gate.
    Witnessed,
}

impl Formation {
    /// The formation `Auto` stands for in a `space` where `sensors_with_scans` sensors have
    /// two scans or more; the others stand for themselves.
    pub fn resolve(self, space: Space, sensors_with_scans: usize) -> Self {
        match self {
            Self::Auto if sensors_with_scans >= 3 => match space {
                Space::Spatial => Self::Rounds,
                Space::Planar => Self::Witnessed,
            },
            Self::Auto => Self::Witnessed,
            other => other,
        }
    }

    /// The name the option takes.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Paper => "paper",
            Self::Rounds => "rounds",
            Self::Witnessed => "witnessed",
        }
    }
}

impl std::str::FromStr for Formation {
    type Err = UnknownOption;

    /// `"auto"`, `"paper"`, `"rounds"` or `"witnessed"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        let choices = [
            ("auto", Self::Auto),
            ("paper", Self::Paper),
            ("rounds", Self::Rounds),
            ("witnessed", Self::Witnessed),
        ];
        parse_option(value, &choices, "'auto', 'paper', 'rounds' or 'witnessed'")
    }
}
