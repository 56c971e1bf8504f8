//! Which sensors the Lagrangian relaxation keeps in its 2-D problem and which it relaxes.

use crate::assign::SdProblem;
use crate::error::{parse_option, UnknownOption};

/// Which sensors' "at most once" constraints the relaxation moves into the objective. The
/// dual bound converges to the same LP value whatever the choice, but not equally fast.
///
/// Relaxing the S = 3 sensor with the most reports converged much closer to that value, in the
/// same or less time, on `reproduce intensity` scans: `python benches/bench_sensor_order.py`
/// compares both orders with the LP bound from `scipy.optimize.linprog` (docs/performance.md).
/// A likely reason, not measured: the 2-D problem between the two smaller sensors caps the
/// number of tuples the relaxed solution picks, so the largest sensor's reports are the least
/// contested and the fewest of its constraints are violated. At S = 4 no gain has been
/// measured, so there the given order stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SensorOrder {
    /// S = 3: relax the sensor with the most reports (on a tie the later one) and keep the
    /// other two, in their given order, as the 2-D problem. S != 3: as given.
    #[default]
    Auto,
    /// Sensors 0 and 1 form the 2-D problem, sensors 2.. are relaxed: the textbook layout.
    Given,
}

impl std::str::FromStr for SensorOrder {
    type Err = UnknownOption;

    /// `"auto"` or `"given"`.
    fn from_str(value: &str) -> Result<Self, UnknownOption> {
        parse_option(
            value,
            &[("auto", Self::Auto), ("given", Self::Given)],
            "'auto' or 'given'",
        )
    }
}

/// The sensor order the solver works in, or `None` when it is the given one.
pub(super) fn working_order(problem: &SdProblem, choice: SensorOrder) -> Option<Vec<usize>> {
    let sizes = problem.sizes();
    if choice == SensorOrder::Given || sizes.len() != 3 {
        return None;
    }
    // max_by_key returns the last maximum: a tie keeps the later sensor relaxed.
    let relaxed = (0..3).max_by_key(|&s| sizes[s])?;
    if relaxed == 2 {
        return None;
    }
    let mut order: Vec<usize> = (0..3).filter(|&s| s != relaxed).collect();
    order.push(relaxed);
    Some(order)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sized(sizes: Vec<usize>) -> SdProblem {
        let s = sizes.len();
        SdProblem::new(vec![1; s], s, vec![-1.0], sizes).expect("valid")
    }

    #[test]
    fn relaxes_the_largest_of_three_sensors() {
        assert_eq!(
            working_order(&sized(vec![5, 9, 7]), SensorOrder::Auto),
            Some(vec![0, 2, 1])
        );
        assert_eq!(
            working_order(&sized(vec![9, 5, 7]), SensorOrder::Auto),
            Some(vec![1, 2, 0])
        );
        assert_eq!(
            working_order(&sized(vec![5, 7, 9]), SensorOrder::Auto),
            None
        );
        // Ties keep the later sensor relaxed, so equal sizes keep the given order.
        assert_eq!(
            working_order(&sized(vec![9, 9, 9]), SensorOrder::Auto),
            None
        );
        assert_eq!(
            working_order(&sized(vec![9, 9, 5]), SensorOrder::Auto),
            Some(vec![0, 2, 1])
        );
    }

    #[test]
    fn keeps_the_given_order_when_asked_or_not_three_sensors() {
        assert_eq!(
            working_order(&sized(vec![9, 5, 7]), SensorOrder::Given),
            None
        );
        assert_eq!(working_order(&sized(vec![9, 5]), SensorOrder::Auto), None);
        assert_eq!(
            working_order(&sized(vec![9, 5, 7, 3]), SensorOrder::Auto),
            None
        );
    }
}
