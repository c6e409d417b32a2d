//! Policy `ahead`: after each (re-)plan the scouts share the far half of what is left of the
//! UGV's route, one equal part each, and then hold.

use homospline_geom::Point;

use super::{Job, ScoutPolicy, Situation};

/// The far half of the UGV's route.
pub struct Ahead;

impl ScoutPolicy for Ahead {
    fn name(&self) -> &'static str {
        "ahead"
    }

    fn summary(&self) -> &'static str {
        "scouts inspect the far half of the UGV's route, one part each"
    }

    fn assign(&self, s: &Situation<'_>) -> Vec<(usize, Job)> {
        far_half(s, |_| true)
    }
}

/// The idle scouts with no job since the last (re-)plan, and those `also` admits, share the
/// far half of what is left of the UGV's route: the `j`-th of `n` takes the `j`-th of `n`
/// equal parts.
pub(super) fn far_half(s: &Situation<'_>, also: impl Fn(usize) -> bool) -> Vec<(usize, Job)> {
    let takers: Vec<usize> = s
        .scouts
        .iter()
        .enumerate()
        .filter(|&(i, sc)| !sc.busy && sc.jobs.is_empty() && also(i))
        .map(|(i, _)| i)
        .collect();
    let n = takers.len();
    takers
        .iter()
        .enumerate()
        .map(|(part, &i)| {
            (
                i,
                Job {
                    waypoints: part_of_far_half(s, s.scouts[i].at, part, n),
                    label: String::new(),
                },
            )
        })
        .collect()
}

/// The `j`-th of `n` equal parts of the far half of the route left, from `from`.
fn part_of_far_half(s: &Situation<'_>, from: Point, j: usize, n: usize) -> Vec<Point> {
    let left = s.route.length() - s.s;
    let a = s.s + left * (0.5 + 0.5 * j as f64 / n as f64);
    let b = s.s + left * (0.5 + 0.5 * (j + 1) as f64 / n as f64);
    let mut out = vec![from];
    out.extend(s.route.slice(a, b));
    out
}
