//! Policy `guard`: the scouts look first where a blockage would cost the UGV most, its own
//! route ahead, sweeping the stretches no robot has seen yet from near to far; then they
//! verify the alternatives, best first. When they find the UGV's route blocked ahead, the
//! UGV weighs re-planning now against driving on until it would see the blockage itself
//! (what it would do without scouts) and takes the shorter.

use homospline_geom::{Point, Real};

use super::{Job, Polyline, ScoutPolicy, Situation, leaves_at};

/// The UGV's route first, then the alternatives; re-plans early only when that is shorter.
pub struct Guard;

impl ScoutPolicy for Guard {
    fn name(&self) -> &'static str {
        "guard"
    }

    fn summary(&self) -> &'static str {
        "scouts sweep the unseen rest of the UGV's route, then verify the alternatives; a \
         blockage found ahead makes the UGV re-plan early only when that is shorter"
    }

    fn weighs_driving_on(&self) -> bool {
        true
    }

    fn assign(&self, s: &Situation<'_>) -> Vec<(usize, Job)> {
        let mut idle: Vec<usize> = (0..s.scouts.len())
            .filter(|&i| !s.scouts[i].busy)
            .collect();
        let mut out = Vec::new();
        let busy_on = |label: &str| {
            s.scouts
                .iter()
                .any(|sc| sc.busy && sc.jobs.last().is_some_and(|j| j == label))
        };
        // What to look at, most at stake first: the UGV's route ahead, then each
        // alternative's stretches away from it. Each is one job, to the nearest idle scout.
        let route_unseen = s.seen.unseen(s.route, s.s);
        let mut lanes: Vec<Look<'_>> = Vec::new();
        if !route_unseen.is_empty() && !busy_on("") {
            lanes.push((String::new(), s.route, route_unseen.clone()));
        }
        let rest = s.route.slice(s.s, s.route.length());
        for alt in s.alternatives {
            if alt.class == s.class || busy_on(alt.class) {
                continue;
            }
            let away = away_from(alt.line, &rest, s.ugv_range);
            let unseen = s.seen.unseen(alt.line, away);
            if !unseen.is_empty() {
                lanes.push((alt.class.to_owned(), alt.line, unseen));
            }
        }
        out.extend(to_nearest(s, &mut idle, lanes));
        // Scouts left over help on the route: the far half of what is unseen of it.
        if let (Some(&first), Some(&last)) = (route_unseen.first(), route_unseen.last()) {
            let mid = 0.5 * (first.0 + last.1);
            let far: Vec<(Real, Real)> = route_unseen
                .iter()
                .filter(|&&(_, b)| b >= mid)
                .map(|&(a, b)| (a.max(mid), b))
                .collect();
            for k in idle {
                if s.scouts[k].jobs.is_empty() && !far.is_empty() {
                    out.push((
                        k,
                        Job {
                            waypoints: sweep(s.scouts[k].at, s.route, &far),
                            label: String::new(),
                        },
                    ));
                }
            }
        }
        out
    }
}

/// Something to look at: the job's label, the line and its unseen stretches (arc lengths).
pub(super) type Look<'a> = (String, &'a Polyline, Vec<(Real, Real)>);

/// Arc length along `line` where it first leaves the UGV's `rest` of route by more than
/// `range` (its length when it never does: nothing of it is away from the route).
pub(super) fn away_from(line: &Polyline, rest: &[Point], range: Real) -> Real {
    leaves_at(line, rest, range).map_or(line.length(), |k| line.cum[k])
}

/// Each look, in order, as a sweep of its unseen stretches by the idle scout nearest to
/// where they begin (taken off `idle`), while any is idle.
pub(super) fn to_nearest(
    s: &Situation<'_>,
    idle: &mut Vec<usize>,
    looks: Vec<Look<'_>>,
) -> Vec<(usize, Job)> {
    let mut out = Vec::new();
    for (label, line, stretches) in looks {
        let Some(&(a, _)) = stretches.first() else {
            continue;
        };
        let Some(k) = nearest(s, idle, line.at(a).0) else {
            break;
        };
        idle.retain(|&i| i != k);
        out.push((
            k,
            Job {
                waypoints: sweep(s.scouts[k].at, line, &stretches),
                label,
            },
        ));
    }
    out
}

/// The idle scout nearest to `p`.
pub(super) fn nearest(s: &Situation<'_>, idle: &[usize], p: Point) -> Option<usize> {
    idle.iter()
        .copied()
        .min_by(|&a, &b| {
            (s.scouts[a].at - p)
                .norm()
                .total_cmp(&(s.scouts[b].at - p).norm())
                .then(a.cmp(&b))
        })
}

/// Waypoints from `from` along `line`'s `stretches`, in order.
pub(super) fn sweep(from: Point, line: &Polyline, stretches: &[(Real, Real)]) -> Vec<Point> {
    let mut out = vec![from];
    for &(a, b) in stretches {
        out.extend(line.slice(a, b));
    }
    out
}
