//! The scouts: their flight along waypoints, and their jobs after each (re-)plan (policy
//! `ahead`: the far half of the UGV's route; `alternatives`: the next best classes).

use homospline_geom::{Point, Real};

use super::config::{MissionConfig, Policy};
use super::record::Track;
use super::route::{Drive, Route};
use crate::world::types::{Team, Uav};

/// A scout in flight.
pub(super) struct Scout {
    pub(super) uav: Uav,
    pub(super) pos: Point,
    /// Waypoints still to reach.
    pub(super) route: Vec<Point>,
    pub(super) flown: Real,
    pub(super) track: Track,
    /// Jobs since the last (re-)plan: the classes verified (policy `alternatives`), or ""
    /// for a part of the UGV's route.
    jobs: Vec<String>,
}

impl Scout {
    /// Flies toward the waypoints for `dt`; the track records the position at `t` if it
    /// had any to fly to.
    pub(super) fn step(&mut self, dt: Real, t: Real) {
        let mut budget = self.uav.speed * dt;
        let moved = !self.route.is_empty();
        while budget > 0.0 && !self.route.is_empty() {
            let d = self.route[0] - self.pos;
            let n = d.norm();
            if n <= budget {
                self.pos = self.route.remove(0);
                budget -= n;
                self.flown += n;
            } else {
                self.pos += d * (budget / n);
                self.flown += budget;
                budget = 0.0;
            }
        }
        if moved {
            self.track.samples.push((t, self.pos));
        }
    }
}

/// The scouts the policy flies, on the ground: the team's UAVs, and beyond them scouts at
/// the UGV's `start` with speed 3 and sensor range 10 ([`MissionConfig::scouts`]).
pub(super) fn launch(team: &Team, cfg: &MissionConfig, start: Point) -> Vec<Scout> {
    let n_scouts = match cfg.policy {
        Policy::None => 0,
        _ => cfg.scouts.unwrap_or(team.uavs.len()),
    };
    (0..n_scouts)
        .map(|i| {
            let uav = team.uavs.get(i).cloned().unwrap_or(Uav {
                start,
                speed: 3.0,
                sensor_range: 10.0,
            });
            Scout {
                pos: uav.start,
                uav,
                route: Vec::new(),
                flown: 0.0,
                track: Track {
                    name: format!("uav-{i}"),
                    samples: vec![(0.0, team.uavs.get(i).map_or(start, |u| u.start))],
                },
                jobs: Vec::new(),
            }
        })
        .collect()
}

/// The part of the route a scout `ahead` inspects: scout `j` of `n` takes the `j`-th of `n`
/// equal parts of the far half of what is left.
fn ahead_route(from: Point, route: &Route, s: Real, j: usize, n: usize) -> Vec<Point> {
    let left = route.line.length() - s;
    let a = s + left * (0.5 + 0.5 * j as Real / n as Real);
    let b = s + left * (0.5 + 0.5 * (j + 1) as Real / n as Real);
    let mut out = vec![from];
    out.extend(route.line.slice(a, b));
    out
}

/// An alternative's route for a scout: to where it leaves the UGV's route (farther than the
/// UGV's sensor range from it), then along it to the goal.
fn alternative_route(from: Point, alt: &Route, route: &Route, s: Real, range: Real) -> Vec<Point> {
    let rest = route.line.slice(s, route.line.length());
    let far = |p: &Point| {
        rest.windows(2)
            .map(|w| homospline_geom::math::distance_point_segment(p, &w[0], &w[1]))
            .fold(Real::INFINITY, Real::min)
            > range
    };
    let k = alt.line.pts.iter().position(far).unwrap_or(0);
    let mut out = vec![from];
    out.extend(alt.line.pts[k..].iter().copied());
    out
}

/// Routes for every scout after a (re-)plan of the UGV's `drive`; `range`: the UGV's sensor
/// range.
pub(super) fn assign(scouts: &mut [Scout], policy: Policy, drive: &Drive, range: Real) {
    for sc in scouts.iter_mut() {
        sc.route.clear();
        sc.jobs.clear();
    }
    assign_idle(scouts, policy, drive, range);
}

/// Routes for the scouts that have none: an alternative no scout has taken since the last
/// (re-)plan (policy `alternatives`), else, for a scout with no job yet, a part of the far
/// half of the UGV's route; a scout whose job is done and has nothing left holds.
pub(super) fn assign_idle(scouts: &mut [Scout], policy: Policy, drive: &Drive, range: Real) {
    if policy == Policy::None {
        return;
    }
    let (route, s, alts) = (&drive.route, drive.s, &drive.alternatives);
    let mut taken: Vec<String> = scouts
        .iter()
        .flat_map(|sc| sc.jobs.iter().cloned())
        .collect();
    // First the alternatives, one scout each; then the scouts left without a job share the
    // far half of the UGV's route between them.
    let mut ahead = Vec::new();
    for (j, sc) in scouts.iter_mut().enumerate() {
        if !sc.route.is_empty() {
            continue;
        }
        if policy == Policy::Alternatives
            && let Some(alt) = alts
                .iter()
                .find(|a| !taken.contains(&a.class) && a.class != route.class)
        {
            sc.route = alternative_route(sc.pos, alt, route, s, range);
            sc.jobs.push(alt.class.clone());
            taken.push(alt.class.clone());
        } else if sc.jobs.is_empty() {
            ahead.push(j);
        }
    }
    let n = ahead.len();
    for (part, &j) in ahead.iter().enumerate() {
        let sc = &mut scouts[j];
        sc.route = ahead_route(sc.pos, route, s, part, n);
        sc.jobs.push(String::new());
    }
}
