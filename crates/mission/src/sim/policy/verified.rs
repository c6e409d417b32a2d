//! Policy `verified`: the scouts sweep the UGV's route ahead as `guard`'s do, but the UGV
//! acts on what they find only where it blocks its own route. Then it holds where it is
//! while the scouts verify the classes that would be shorter than driving on until it saw
//! the blockage itself, and takes the first of them seen clear all along; with none, it
//! drives on as a UGV without scouts would.

use super::guard::{Guard, Look, to_nearest};
use homospline_geom::Real;

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
        // Holding: each idle scout verifies a candidate not yet seen whole and not being
        // verified, best first; when there are more idle scouts than such candidates, the
        // best one's unseen stretches are split between two of them, near half and far half.
        let mut idle: Vec<usize> = (0..s.scouts.len())
            .filter(|&i| !s.scouts[i].busy)
            .collect();
        let mut todo: Vec<Look<'_>> = Vec::new();
        for alt in s.alternatives {
            let taken = s
                .scouts
                .iter()
                .any(|sc| sc.busy && sc.jobs.last().is_some_and(|j| j == alt.class));
            let unseen = s.seen.unseen(alt.line, 0.0);
            if !taken && !unseen.is_empty() {
                todo.push((alt.class.to_owned(), alt.line, unseen));
            }
        }
        if idle.len() > todo.len()
            && let Some((class, line, unseen)) = todo.first().cloned()
        {
            let (first, last) = (unseen[0].0, unseen[unseen.len() - 1].1);
            let mid = 0.5 * (first + last);
            let near: Vec<(Real, Real)> = unseen
                .iter()
                .filter(|&&(a, _)| a < mid)
                .map(|&(a, b)| (a, b.min(mid)))
                .collect();
            let far: Vec<(Real, Real)> = unseen
                .iter()
                .filter(|&&(_, b)| b >= mid)
                .map(|&(a, b)| (a.max(mid), b))
                .collect();
            todo[0] = (class.clone(), line, near);
            if !far.is_empty() {
                todo.insert(1, (class, line, far));
            }
        }
        to_nearest(s, &mut idle, todo)
    }
}
