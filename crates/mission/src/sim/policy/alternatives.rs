//! Policy `alternatives`: each scout verifies one of the next best classes, from where it
//! leaves the UGV's route; scouts left without one fly `ahead`.

use homospline_geom::Point;

use super::ahead::far_half;
use super::{Job, Lane, ScoutPolicy, Situation, leaves_at};

/// The next best classes.
pub struct Alternatives;

impl ScoutPolicy for Alternatives {
    fn name(&self) -> &'static str {
        "alternatives"
    }

    fn summary(&self) -> &'static str {
        "scouts verify the next best classes, one each; scouts left over fly ahead"
    }

    fn assign(&self, s: &Situation<'_>) -> Vec<(usize, Job)> {
        let mut taken: Vec<&str> = s
            .scouts
            .iter()
            .flat_map(|sc| sc.jobs.iter().map(String::as_str))
            .collect();
        let mut out = Vec::new();
        for (i, sc) in s.scouts.iter().enumerate() {
            if sc.busy {
                continue;
            }
            if let Some(alt) = s
                .alternatives
                .iter()
                .find(|a| !taken.contains(&a.class) && a.class != s.class)
            {
                out.push((
                    i,
                    Job {
                        waypoints: from_where_it_leaves(sc.at, alt, s),
                        label: alt.class.to_owned(),
                    },
                ));
                taken.push(alt.class);
            }
        }
        let given: Vec<usize> = out.iter().map(|&(i, _)| i).collect();
        out.extend(far_half(s, |i| !given.contains(&i)));
        out
    }
}

/// An alternative's route for a scout at `from`: to where it leaves the UGV's route
/// (farther than the UGV's sensor range from it), then along it to the goal.
fn from_where_it_leaves(from: Point, alt: &Lane<'_>, s: &Situation<'_>) -> Vec<Point> {
    let rest = s.route.slice(s.s, s.route.length());
    let k = leaves_at(alt.line, &rest, s.ugv_range).unwrap_or(0);
    let mut out = vec![from];
    out.extend(alt.line.pts[k..].iter().copied());
    out
}
