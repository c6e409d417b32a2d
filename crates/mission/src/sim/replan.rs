//! Re-planning after a discovery: at once when the UGV's path is found blocked (keeping the
//! current class if it is within the margin of the best), else a switch through the
//! hysteresis if a better class opened.

use homospline_geom::{Point, Real, Vector};

use super::config::{MissionConfig, TURN_ANGLE_DEG};
use super::planner::Planner;
use super::record::{EventKind, Record};
use super::route::{Drive, Hold, Polyline, Route};
use super::sense::{admit, discover, take_in_along};
use crate::known::Known;
use homospline_spline::ClearanceModel;

/// The hysteresis: whether a plan of cost `current` that is still valid is given up for
/// another class of cost `candidate`, `since_last_switch` seconds after the last switch. Only
/// if the candidate is cheaper by the relative margin and the last switch is old enough.
pub fn should_switch(
    current: Real,
    candidate: Real,
    since_last_switch: Real,
    cfg: &MissionConfig,
) -> bool {
    candidate < (1.0 - cfg.switch_margin) * current && since_last_switch >= cfg.min_switch_interval
}

/// Whether a path leaves its start more than [`TURN_ANGLE_DEG`] off `heading`: the UGV
/// turns on the spot. A curve planned along the heading leaves exactly along it; one whose
/// class starts backwards, or sideways, is planned from a standstill.
fn turns_on_the_spot(line: &Polyline, heading: Vector) -> bool {
    line.pts.len() > 1 && {
        let d = line.pts[1] - line.pts[0];
        d.dot(&heading) < TURN_ANGLE_DEG.to_radians().cos() * d.norm() * heading.norm()
    }
}

/// Re-plans from where the UGV is at time `t` after the known world changed: at once if
/// its path is blocked, else only to switch to a better class. Whether the mission goes on
/// (`false`: the UGV is stuck, no collision-free class left on the known map).
pub(super) fn replan<K: Known>(
    planner: &mut Planner<'_, K>,
    drive: &mut Drive,
    record: &mut Record,
    t: Real,
    range: Real,
) -> bool {
    let at = drive.position();
    let heading = drive.route.line.heading(drive.s);
    let remaining = drive.route.line.slice(drive.s, drive.route.line.length());
    let mut replan = Replan {
        planner,
        drive,
        record,
        t,
        at,
        heading,
        range,
    };
    if replan.planner.clear(&remaining) {
        replan.maybe_switch();
        true
    } else {
        replan.blocked()
    }
}

/// The route a forced re-plan takes among `routes` (best first): the UGV's `class` if it
/// costs at most `margin` more than the best, else the best.
fn pick(routes: &[Route], class: &str, margin: Real) -> usize {
    let Some(best) = routes.first() else {
        return 0;
    };
    routes
        .iter()
        .position(|r| r.class == class && r.cost <= (1.0 + margin) * best.cost)
        .unwrap_or(0)
}

/// A re-plan at time `t`, the UGV at `at` along `heading`.
struct Replan<'m, 'a, K: Known> {
    planner: &'m mut Planner<'a, K>,
    drive: &'m mut Drive,
    record: &'m mut Record,
    t: Real,
    at: Point,
    heading: Vector,
    /// The UGV's sensor range.
    range: Real,
}

impl<K: Known> Replan<'_, '_, K> {
    fn event(&mut self, kind: EventKind) {
        self.record.event(self.t, self.at, kind);
    }

    /// The routes from the UGV's position (on the move, or `from_standstill`). Before the
    /// UGV has moved (a blockage seen from the start, in the look before it sets off) it
    /// plans as the offline plan does: standing, with every class and the full graph.
    fn routes(&mut self, from_standstill: bool) -> Vec<Route> {
        let standing = self.drive.driven == 0.0;
        let heading = (!from_standstill && !standing).then_some(self.heading);
        let mut routes = self
            .planner
            .routes_from(self.at, heading, !standing, &mut *self.record);
        // Without a prior the routes keep the plan's ranking (which is not by cost alone).
        if self.planner.cfg.blockage_prior > 0.0 {
            for r in &mut routes {
                r.cost *= self.planner.unseen_factor(&r.line, 0.0);
            }
            routes.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        }
        routes
    }

    /// The events of driving `next` instead of the current route: a class switch if the
    /// class changes, and a turn on the spot if `next` leaves off the heading. Whether the
    /// class changed.
    fn switch_events(&mut self, next: &Route) -> bool {
        let switched = next.class != self.drive.route.class;
        if switched {
            let from = self.drive.route.class.clone();
            self.event(EventKind::Switched {
                from,
                to: next.class.clone(),
            });
        }
        if turns_on_the_spot(&next.line, self.heading) {
            self.event(EventKind::TurnedAround);
        }
        switched
    }

    /// Drives `next` from here, the route driven so far abandoned, `alternatives` beside it.
    fn take(&mut self, next: Route, alternatives: Vec<Route>) {
        self.record.abandoned += self.drive.on_route();
        self.drive
            .take(next, alternatives, self.t, &mut self.record.adopted);
    }

    /// The UGV's path is blocked: it re-plans from here and drives the best class, or its
    /// current class if that costs at most the switch margin more. Whether it has a class.
    fn blocked(&mut self) -> bool {
        self.event(EventKind::Blocked {
            class: self.drive.route.class.clone(),
        });
        self.record.replans += 1;
        let mut routes = self.routes(false);
        if routes.is_empty() {
            // No curve leaving along the heading clears what was just found (a blockage
            // close ahead): the UGV stops and plans from a standstill, turning on the spot.
            routes = self.routes(true);
            // One re-plan, one time: both tries count in it.
            let replan_ms = &mut self.record.replan_ms;
            if let (Some(second), Some(first)) = (replan_ms.pop(), replan_ms.last_mut()) {
                *first += second;
            }
        }
        if routes.is_empty() {
            self.event(EventKind::Stuck {
                reason: "no collision-free class on the known map".into(),
            });
            self.record.abandoned += self.drive.on_route();
            return false;
        }
        // Bonus for the current class: kept if within the margin of the best.
        let pick = pick(
            &routes,
            &self.drive.route.class,
            self.planner.cfg.switch_margin,
        );
        let next = routes[pick].clone();
        if self.planner.cfg.policy.get().weighs_driving_on() && self.drives_on(&next) {
            self.event(EventKind::Replanned {
                forced: true,
                classes: routes.len(),
                class: self.drive.route.class.clone(),
            });
            return true;
        }
        self.event(EventKind::Replanned {
            forced: true,
            classes: routes.len(),
            class: next.class.clone(),
        });
        if self.switch_events(&next) {
            self.record.switches += 1;
            self.drive.last_switch = self.t;
        }
        let alternatives = routes
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != pick)
            .map(|(_, r)| r.clone())
            .collect();
        self.take(next, alternatives);
        true
    }

    /// Whether driving on until the UGV would see the blockage itself, and re-planning
    /// there, is shorter than taking `next` now (as a robot without scouts would have to):
    /// then it drives on and re-plans at that point (`Drive::replan_at`). The UGV sees the
    /// blockage where its route first comes within its sensor range (in a straight line) of
    /// the first point the known map blocks; a re-plan from there is planned now, on the
    /// same known map.
    fn drives_on(&mut self, next: &Route) -> bool {
        let Some(sight) = self.sight() else {
            return false;
        };
        let line = &self.drive.route.line;
        let (p, _) = line.at(sight);
        let heading = line.heading(sight);
        let class = self.drive.route.class.clone();
        let later = self
            .planner
            .routes_from(p, Some(heading), true, &mut *self.record);
        // One re-plan, one time: both plans count in it.
        let replan_ms = &mut self.record.replan_ms;
        if let (Some(second), Some(first)) = (replan_ms.pop(), replan_ms.last_mut()) {
            *first += second;
        }
        let Some(then) = later.get(pick(&later, &class, self.planner.cfg.switch_margin)) else {
            return false;
        };
        let on = sight - self.drive.s + then.line.length() < next.line.length();
        if on {
            self.drive.replan_at = Some(sight);
        }
        on
    }

    /// Where along its route the UGV would see the first point the known map blocks, when
    /// that is ahead of where it is (a blockage the scouts found): the first point of the
    /// route within its sensor range (in a straight line) of that point (the obstacle
    /// reaches at least that close). `None` when the UGV sees it already, or the route is
    /// clear.
    fn sight(&self) -> Option<Real> {
        sight(self.drive, self.planner.known.model(), self.range, false).map(|(_, s)| s)
    }

    /// The map changed but the path is still clear: a better class may have opened (a
    /// mapped obstacle gone) or the current one may have become worse (a new obstacle near
    /// it). Switch only through the hysteresis. (A re-plan that finds no class leaves the
    /// valid path as it is and is not counted.)
    fn maybe_switch(&mut self) {
        let routes = self.routes(false);
        if routes.is_empty() {
            // Not a re-plan (below), and so not timed as one.
            self.record.replan_ms.pop();
        }
        let Some(best) = routes.first() else {
            return;
        };
        self.record.replans += 1;
        // The price of staying: the rest of the current path, or the current class as
        // re-planned from here if that is cheaper. A re-plan alone can land in a worse local
        // optimum of the same class than the path being driven (its cost moves by up to 2x
        // between decisions on a tempting world), and switching on that noise is the
        // oscillation the hysteresis is there to prevent.
        let route = &self.drive.route;
        let driving = self
            .planner
            .remaining_cost(route, self.drive.s, self.heading)
            * self.planner.unseen_factor(&route.line, self.drive.s);
        let current = routes
            .iter()
            .find(|r| r.class == route.class)
            .map_or(driving, |r| r.cost.min(driving));
        // A verified detour is kept: the classes a re-plan offers were not seen clear.
        let better = best.class != route.class
            && !self.drive.verified
            && should_switch(
                current,
                best.cost,
                self.t - self.drive.last_switch,
                self.planner.cfg,
            );
        let class = if better {
            best.class.clone()
        } else {
            route.class.clone()
        };
        self.event(EventKind::Replanned {
            forced: false,
            classes: routes.len(),
            class,
        });
        if better {
            let best = best.clone();
            self.switch_events(&best);
            self.record.switches += 1;
            self.drive.last_switch = self.t;
            self.take(best, routes[1..].to_vec());
        } else {
            let class = &self.drive.route.class;
            self.drive.alternatives = routes.into_iter().filter(|r| &r.class != class).collect();
        }
    }
}

/// The UGV holding at time `t` ([`Drive::hold`]; at the start, its one candidate is its own
/// route): the candidates the team's map now blocks are dropped; the best left is taken once
/// the robots have seen it whole (`planner.seen`); when none is left, or the hold's time is
/// up, the UGV takes the first candidate seen whole than which no unseen one is shorter, else
/// drives on as a UGV without scouts would. A hold at the start ends in
/// [`start_on_team_view`] (the UGV sees `range`). Whether it stopped holding.
pub(super) fn settle_hold<K: Known>(
    planner: &mut Planner<'_, K>,
    team: &mut Planner<'_, K>,
    drive: &mut Drive,
    record: &mut Record,
    (t, range): (Real, Real),
) -> bool {
    let Some(mut hold) = drive.hold.take() else {
        return false;
    };
    hold.candidates.retain(|r| team.clear(&r.line.pts));
    let whole = |r: &Route| planner.seen.unseen(&r.line, 0.0).is_empty();
    let pick = match hold.candidates.first() {
        Some(best) if whole(best) => Some(0),
        Some(_) if t < hold.until => {
            if hold.blocked.is_some() {
                drive.alternatives = hold.candidates.clone();
            }
            drive.hold = Some(hold);
            return false;
        }
        // Time is up: a candidate seen whole is taken only if no candidate still unseen
        // is shorter (those are the classes a UGV driving on may yet find open).
        _ => {
            let unverified = hold
                .candidates
                .iter()
                .filter(|r| !whole(r))
                .map(|r| r.line.length())
                .fold(Real::INFINITY, Real::min);
            hold.candidates
                .iter()
                .position(|r| whole(r) && r.line.length() <= unverified)
        }
    };
    let at = drive.position();
    let Some(b) = &hold.blocked else {
        // Holding at the start, the hold is over.
        start_on_team_view(planner, team, drive, record, (t, range));
        return true;
    };
    let Some(k) = pick else {
        drive.alternatives = hold.candidates;
        return true;
    };
    // Leaving its route for the blockage, the UGV's map takes it in.
    admit(planner, b);
    let next = hold.candidates.remove(k);
    take_standing(drive, record, next, hold.candidates, (t, at));
    drive.verified = true;
    true
}

/// The UGV, standing at `at` at time `t`, drives `next` from there with `alternatives`
/// beside it: a `Switched` event when its class changes, `TurnedAround` when `next` leaves
/// off its heading, and the route driven so far counted as abandoned.
fn take_standing(
    drive: &mut Drive,
    record: &mut Record,
    next: Route,
    alternatives: Vec<Route>,
    (t, at): (Real, Point),
) {
    if next.class != drive.route.class {
        record.event(
            t,
            at,
            EventKind::Switched {
                from: drive.route.class.clone(),
                to: next.class.clone(),
            },
        );
        record.switches += 1;
        drive.last_switch = t;
    }
    let heading = drive.route.line.heading(drive.s);
    if turns_on_the_spot(&next.line, heading) {
        record.event(t, at, EventKind::TurnedAround);
    }
    record.abandoned += drive.on_route();
    drive.take(next, alternatives, t, &mut record.adopted);
}

/// The end of a hold at the start ([`ScoutPolicy::holds_at_start`]) with the UGV's route
/// clear on the team's map (one it blocks is left to [`consider_detour`], which weighs a
/// detour against driving on). What the scouts saw beside the route may make another class
/// better: a pebble that blocks nothing, close to the route. The UGV, having driven nothing
/// yet, switches to the shortest of the classes of a plan on the team's map (the offline
/// plan's settings) that are both cheaper than its route there by the hysteresis' margin
/// ([`should_switch`]) and at least [`DETOUR_MARGIN`] shorter. Its map then takes in what
/// it would have seen driving its old route, where the scouts have seen it
/// ([`take_in_along`]), so that no later re-plan takes it back there for want of it. Else
/// it sets off as a UGV without scouts would, its map unchanged.
///
/// [`ScoutPolicy::holds_at_start`]: super::policy::ScoutPolicy::holds_at_start
fn start_on_team_view<K: Known>(
    planner: &mut Planner<'_, K>,
    team: &mut Planner<'_, K>,
    drive: &mut Drive,
    record: &mut Record,
    (t, range): (Real, Real),
) {
    let line = drive.route.line.clone();
    if team.version == 0 || !team.clear(&line.slice(drive.s, line.length())) {
        return;
    }
    let at = drive.position();
    let heading = line.heading(drive.s);
    let staying = team.remaining_cost(&drive.route, drive.s, heading);
    let now = team.routes_from(at, None, false, record);
    record.replans += 1;
    let length = line.length() - drive.s;
    let pick = now
        .iter()
        .filter(|r| {
            r.class != drive.route.class
                && should_switch(staying, r.cost, Real::INFINITY, team.cfg)
                && r.line.length() < (1.0 - DETOUR_MARGIN) * length
        })
        .min_by(|a, b| a.line.length().total_cmp(&b.line.length()));
    record.event(
        t,
        at,
        EventKind::Replanned {
            forced: false,
            classes: now.len(),
            class: pick.map_or(&drive.route.class, |r| &r.class).clone(),
        },
    );
    let Some(best) = pick.cloned() else {
        return;
    };
    let found = take_in_along(planner, &line, drive.s, range);
    if found.any() {
        discover(planner, drive, record, &found, (t, at));
    }
    let rest = now.into_iter().filter(|r| r.class != best.class).collect();
    take_standing(drive, record, best, rest, (t, at));
}

/// How much shorter than driving on a detour must be to be held for: the estimate of
/// driving on (to where the UGV would see the blockage, then the shortest class from there
/// on the team's map) is a lower bound only roughly, as the UGV without scouts re-plans on
/// less and by cost.
const DETOUR_MARGIN: Real = 0.02;

/// Where along its route `drive`'s UGV, seeing `range`, would see the first point of the
/// route that `model` blocks: that point, and the first point of the route within its sensor
/// range (in a straight line) of it, as arc lengths. `None` when the route is clear ahead or
/// the UGV sees that point already.
fn sight(
    drive: &Drive,
    model: &dyn ClearanceModel,
    range: Real,
    fine: bool,
) -> Option<(Real, Real)> {
    let line = &drive.route.line;
    let end = line.length();
    // Probes every quarter of the sensor range (`fine`: 4,000 probes, for a blockage the
    // polyline check found, which may be thinner), and at most 4,000 along the route.
    let coarse = if fine { 0.0 } else { 0.25 * range };
    let step = coarse.max(end / 4000.0).max(1e-9);
    let mut s = drive.s;
    let blocked_at = loop {
        if s >= end {
            return None;
        }
        if model.clearance(&line.at(s).0).0 <= 0.0 {
            break s;
        }
        s += step;
    };
    let b = line.at(blocked_at).0;
    let mut sight = drive.s;
    while sight < blocked_at && (line.at(sight).0 - b).norm() > range {
        sight += step;
    }
    (sight > drive.s + step).then_some((blocked_at, sight))
}

/// For a policy that verifies: when the team's map blocks the UGV's route ahead and the
/// UGV's own map does not (the scouts found the blockage), the classes from here on the
/// team's map that are shorter than driving on until the UGV would see the blockage itself
/// and taking the shortest class from there are candidates; with any, the UGV holds while
/// the scouts verify them ([`settle_hold`]), for as long as driving on would take plus the
/// time a scout flying at `sweep_speed` takes to sweep what is unseen of the best.
/// Otherwise it drives on as a UGV without scouts would, and weighs this route again only
/// when the team's map changes. Whether it holds.
pub(super) fn consider_detour<K: Known>(
    planner: &mut Planner<'_, K>,
    team: &mut Planner<'_, K>,
    drive: &mut Drive,
    record: &mut Record,
    t: Real,
    (range, speed, sweep_speed): (Real, Real, Real),
) -> bool {
    if drive.weighed == Some(team.version) || drive.hold.is_some() {
        return false;
    }
    let line = &drive.route.line;
    let rest = line.slice(drive.s, line.length());
    if rest.len() < 2 || !planner.clear(&rest) || team.clear(&rest) {
        return false;
    }
    drive.weighed = Some(team.version);
    let Some((blocked_at, _)) = sight(drive, team.known.model(), range, true) else {
        return false;
    };
    // Where the UGV would see what the scouts found itself, which may be before the point
    // it blocks: the first point ahead with a find of theirs nearer than the UGV's own map's
    // nearest obstacle, and within its sensor range.
    let (own, theirs) = (planner.known.model(), team.known.model());
    let step = (line.length() / 4000.0).max(1e-3);
    let mut sight = drive.s;
    while sight < blocked_at {
        let q = line.at(sight).0;
        let d = theirs.clearance_value(&q);
        if d < own.clearance_value(&q) && d <= range {
            break;
        }
        sight += step;
    }
    let sight = sight.min(blocked_at);
    let at = drive.position();
    let (p, heading) = (line.at(sight).0, line.heading(sight));
    let d1 = sight - drive.s;
    let timed = record.replan_ms.len();
    // From here: the offline plan's classes (every class, the fine graph, leaving in any
    // direction: the UGV holds first), and the on-the-move re-plan's; of a class found by
    // both, the shorter route.
    let mut now = team.routes_from(at, None, false, record);
    for r in team.routes_from(at, Some(line.heading(drive.s)), true, record) {
        match now.iter_mut().find(|q| q.class == r.class) {
            Some(q) if r.line.length() < q.line.length() => *q = r,
            Some(_) => {}
            None => now.push(r),
        }
    }
    let mut later = team.routes_from(p, Some(heading), true, record);
    if later.is_empty() {
        later = team.routes_from(p, None, true, record);
    }
    // One weighing, one time, counted as a re-plan.
    let ms: Real = record.replan_ms.drain(timed..).sum();
    record.replan_ms.push(ms);
    record.replans += 1;
    let then = later
        .iter()
        .map(|r| r.line.length())
        .fold(Real::INFINITY, Real::min);
    let candidates: Vec<Route> = now
        .into_iter()
        .filter(|r| r.line.length() < (1.0 - DETOUR_MARGIN) * (d1 + then))
        .collect();
    record.event(
        t,
        at,
        EventKind::Replanned {
            forced: true,
            classes: candidates.len(),
            class: drive.route.class.clone(),
        },
    );
    if candidates.is_empty() {
        return false;
    }
    // Long enough for the UGV to have driven on to where it would see the blockage, and for
    // one scout to sweep what is unseen of the best candidate.
    let sweep = planner.seen.unseen_length(&candidates[0].line, 0.0) / sweep_speed;
    // No scout, or one that does not move (a team built in code): no time to wait for it.
    let sweep = if sweep.is_finite() { sweep } else { 0.0 };
    drive.alternatives = candidates.clone();
    drive.hold = Some(Hold {
        candidates,
        blocked: Some(line.at(blocked_at).0),
        until: t + d1 / speed + sweep,
    });
    true
}
