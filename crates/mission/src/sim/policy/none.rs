//! Policy `none`: no scout flies; the UGV finds blockages itself (the baseline).

use super::{Job, ScoutPolicy, Situation};

/// No scouts.
pub struct NoScouts;

impl ScoutPolicy for NoScouts {
    fn name(&self) -> &'static str {
        "none"
    }

    fn summary(&self) -> &'static str {
        "no scouts fly: the UGV finds blockages itself (the baseline)"
    }

    fn flies(&self) -> bool {
        false
    }

    fn assign(&self, _: &Situation<'_>) -> Vec<(usize, Job)> {
        Vec::new()
    }
}
