//! Policy `verified`: the scouts sweep the UGV's route ahead as `guard`'s do, but the UGV
//! acts on what they find only where it blocks its own route. Then it holds where it is
//! while the scouts verify the classes that would be shorter than driving on until it saw
//! the blockage itself, and takes the first of them seen clear all along; with none, it
//! drives on as a UGV without scouts would.

use super::guard::{Guard, nearest, sweep};
use super::{Job, ScoutPolicy, Situation};

/// The UGV's route first; verified detours only.
pub struct Verified;

impl ScoutPolicy for Verified {
    fn name(&self) -> &'static str {
        "verified"
    }

    fn summary(&self) -> &'static str {
        "scouts sweep the unseen rest of the UGV's route; a blockage found there makes the UGV \
         hold until they have seen a shorter class clear all along, and only what blocks its \
         route changes its plan"
    }

    fn verifies(&self) -> bool {
        true
    }

    fn assign(&self, s: &Situation<'_>) -> Vec<(usize, Job)> {
        if !s.holding {
            return Guard.assign(s);
        }
        // Holding: every idle scout verifies a candidate not yet seen whole and not being
        // verified, best first.
        let mut idle: Vec<usize> = (0..s.scouts.len())
            .filter(|&i| !s.scouts[i].busy)
            .collect();
        let mut out = Vec::new();
        for alt in s.alternatives {
            let taken = s
                .scouts
                .iter()
                .any(|sc| sc.busy && sc.jobs.last().is_some_and(|j| j == alt.class));
            let unseen = s.seen.unseen(alt.line, 0.0);
            if taken || unseen.is_empty() {
                continue;
            }
            let Some(k) = nearest(s, &idle, alt.line.at(unseen[0].0).0) else {
                break;
            };
            idle.retain(|&i| i != k);
            out.push((
                k,
                Job {
                    waypoints: sweep(s.scouts[k].at, alt.line, &unseen),
                    label: alt.class.to_owned(),
                },
            ));
        }
        out
    }
}
