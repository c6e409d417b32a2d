//! The scouts: their flight along waypoints, and their jobs after each (re-)plan, as the
//! scout policy ([`super::policy`]) gives them.

use homospline_geom::{Point, Real};

use super::config::MissionConfig;
use super::policy::{Coverage, Lane, Policy, ScoutView, Situation};
use super::record::Track;
use super::route::Drive;
use crate::world::types::{Team, Uav};

/// A scout in flight.
pub(super) struct Scout {
    pub(super) uav: Uav,
    pub(super) pos: Point,
    /// Waypoints still to reach.
    pub(super) route: Vec<Point>,
    pub(super) flown: Real,
    pub(super) track: Track,
    /// Jobs since the last (re-)plan: the classes verified, or "" for a part of the UGV's
    /// route.
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
    let n_scouts = if cfg.policy.get().flies() {
        cfg.scouts.unwrap_or(team.uavs.len())
    } else {
        0
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

/// Routes for every scout after a (re-)plan of the UGV's `drive`: every job is given up
/// and the policy assigns them afresh. `range`: the UGV's sensor range.
pub(super) fn assign(
    scouts: &mut [Scout],
    policy: Policy,
    drive: &Drive,
    range: Real,
    seen: &Coverage,
) {
    for sc in scouts.iter_mut() {
        sc.route.clear();
        sc.jobs.clear();
    }
    assign_idle(scouts, policy, drive, range, seen);
}

/// Routes for the scouts that have none, as the policy decides ([`super::policy::ScoutPolicy::assign`]);
/// a scout given none holds.
pub(super) fn assign_idle(
    scouts: &mut [Scout],
    policy: Policy,
    drive: &Drive,
    range: Real,
    seen: &Coverage,
) {
    if scouts.is_empty() {
        return;
    }
    let lanes: Vec<Lane<'_>> = drive
        .alternatives
        .iter()
        .map(|a| Lane {
            class: &a.class,
            line: &a.line,
        })
        .collect();
    let views: Vec<ScoutView<'_>> = scouts
        .iter()
        .map(|sc| ScoutView {
            at: sc.pos,
            uav: &sc.uav,
            busy: !sc.route.is_empty(),
            jobs: &sc.jobs,
        })
        .collect();
    let situation = Situation {
        ugv_range: range,
        route: &drive.route.line,
        s: drive.s,
        class: &drive.route.class,
        alternatives: &lanes,
        scouts: &views,
        seen,
        holding: drive.hold.as_ref().is_some_and(|h| h.blocked.is_some()),
    };
    let jobs = policy.get().assign(&situation);
    for (i, job) in jobs {
        if let Some(sc) = scouts.get_mut(i).filter(|sc| sc.route.is_empty()) {
            sc.route = job.waypoints;
            sc.jobs.push(job.label);
        }
    }
}
