//! Policy `survey` (the default): `verified`, and before it sets off the UGV holds at the
//! start while the scouts sweep its route, so that a blockage on it is found before it has
//! driven anywhere; what they saw beside it may make the UGV set off on a cheaper and
//! shorter class instead (`replan::start_on_team_view`).

use super::verified::Verified;
use super::{Job, ScoutPolicy, Situation};

/// `verified` with a sweep of the route before the UGV sets off.
pub struct Survey;

impl ScoutPolicy for Survey {
    fn name(&self) -> &'static str {
        "survey"
    }

    fn summary(&self) -> &'static str {
        "as verified, and the UGV waits at the start while the scouts sweep its route, then \
         sets off on a cheaper and shorter class if they found one: the least distance, at the \
         price of the wait (the default)"
    }

    fn verifies(&self) -> bool {
        true
    }

    fn holds_at_start(&self) -> bool {
        true
    }

    fn assign(&self, s: &Situation<'_>) -> Vec<(usize, Job)> {
        Verified.assign(s)
    }
}
