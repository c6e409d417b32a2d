//! The mission: its state, one tick of it ([`Mission::step`]), and the loop that runs it
//! from the offline plan to the goal, a dead end or the time limit.

use homospline_geom::{Point, Real};
use homospline_homotopy::Rays;

use super::config::{MissionConfig, MissionError, check_steps, time_step};
use super::coverage::Coverage;
use super::planner::Planner;
use super::record::{EventKind, MissionResult, Record};
use super::replan::{consider_detour, replan, settle_hold};
use super::route::{Drive, Hold, Route};
use super::scouts::{Scout, assign, assign_idle, launch};
use super::sense::{Found, discover, look};
use crate::known::Known;
use crate::world::types::{Team, Ugv};

/// The side of the cells that record what the robots have seen: a quarter of the least
/// sensor range, so that a look marks most of its disc; at least a 32nd of the largest, so
/// that one look marks at most about 4,500 cells whatever the ranges.
fn coverage_cell(ugv: &Ugv, scouts: &[Scout]) -> Real {
    let ranges = || {
        scouts
            .iter()
            .map(|sc| sc.uav.sensor_range)
            .chain(std::iter::once(ugv.sensor_range))
            .filter(|r| r.is_finite() && *r > 0.0)
    };
    let least = ranges().fold(Real::INFINITY, Real::min).min(1e6);
    let most = ranges().fold(0.0, Real::max);
    (0.25 * least).max(most / 32.0)
}

/// A mission in progress, on any known world.
pub(super) struct Mission<'a, K: Known> {
    cfg: &'a MissionConfig,
    /// The known world and the planner on it: what the UGV plans on.
    planner: Planner<'a, K>,
    /// For a policy that [`verifies`](super::policy::ScoutPolicy::verifies): everything the
    /// team has found, of which the UGV's own map takes in only what blocks its route.
    team: Option<Planner<'a, K>>,
    /// The ground robot.
    ugv: Ugv,
    /// The UGV's route and its progress.
    drive: Drive,
    scouts: Vec<Scout>,
    /// Events, the UGV's track, the adopted paths, the counts.
    record: Record,
    /// Seconds from the start.
    t: Real,
    /// The time step.
    dt: Real,
    /// The time limit.
    max_time: Real,
    truth_plan_length: Option<Real>,
    reached: bool,
    /// The goal is reached, the UGV is stuck, or the time is up.
    done: bool,
}

/// The mission's time limit and time step, once the limit is known to fit in [`super::MAX_STEPS`]
/// steps of it ([`check_steps`]): `cfg.max_time`, or 20 times the straight drive from
/// `start` to `goal` and a minute.
fn steps_fit(
    team: &Team,
    cfg: &MissionConfig,
    start: Point,
    goal: Point,
    scouts: &[Scout],
) -> Result<(Real, Real), MissionError> {
    let max_time = cfg
        .max_time
        .unwrap_or_else(|| 20.0 * (goal - start).norm() / team.ugv.speed + 60.0);
    let dt = time_step(cfg.dt, &team.ugv, scouts.iter().map(|sc| &sc.uav));
    check_steps(cfg, max_time, dt)?;
    Ok((max_time, dt))
}

/// Whether a mission of `team` from `start` to `goal` can run under `cfg` as set up: its
/// time steps within [`super::MAX_STEPS`] (what `homospline check` asks of a world before
/// `simulate` would refuse it).
pub fn check_team(
    team: &Team,
    cfg: &MissionConfig,
    start: Point,
    goal: Point,
) -> Result<(), MissionError> {
    steps_fit(team, cfg, start, goal, &launch(team, cfg, start)).map(|_| ())
}

impl<'a, K: Known> Mission<'a, K> {
    /// The mission on `known` with `team`, planned offline: the classes are named on
    /// `rays`; `truth_plan_length` is the best plan's on the true world.
    pub(super) fn new(
        known: K,
        team_known: Option<K>,
        rays: Rays,
        team: &Team,
        truth_plan_length: Option<Real>,
        cfg: &'a MissionConfig,
    ) -> Result<Self, MissionError> {
        let (start, goal) = (known.start(), known.goal());
        let scouts = launch(team, cfg, start);
        let (max_time, dt) = steps_fit(team, cfg, start, goal, &scouts)?;
        let cell = coverage_cell(&team.ugv, &scouts);
        let team_known = team_known.filter(|_| cfg.policy.get().verifies());
        let mut mission = Self {
            cfg,
            team: team_known.map(|known| Planner {
                cfg,
                known,
                rays: rays.clone(),
                pending_ms: 0.0,
                // What the robots have seen is the UGV planner's `seen`.
                seen: Coverage::new(cell),
                version: 0,
            }),
            planner: Planner {
                cfg,
                known,
                rays,
                pending_ms: 0.0,
                seen: Coverage::new(cell),
                version: 0,
            },
            ugv: team.ugv.clone(),
            drive: Drive::new(Route::standing(start), Vec::new()),
            scouts,
            record: Record::new(start),
            t: 0.0,
            dt,
            max_time,
            // Start and goal at one point: the best path is to stay (a plan's curve through
            // them has a length of rounding, and time over it read 166463).
            truth_plan_length: if start == goal {
                Some(0.0)
            } else {
                truth_plan_length
            },
            reached: false,
            done: false,
        };
        mission.plan_offline(start, goal);
        Ok(mission)
    }

    /// The offline plan on the prior map: the best class is driven, the others are its
    /// alternatives, the scouts take their jobs. Done at once if there is no class, or if
    /// the UGV starts at the goal.
    fn plan_offline(&mut self, start: Point, goal: Point) {
        let offline = self
            .planner
            .routes_from(start, None, false, &mut self.record);
        self.record.replan_ms.clear();
        let Some(first) = offline.first().cloned() else {
            self.record.event(
                0.0,
                start,
                EventKind::Stuck {
                    reason: "no collision-free class on the prior map".into(),
                },
            );
            self.done = true;
            return;
        };
        self.record.event(
            0.0,
            start,
            EventKind::Planned {
                classes: offline.len(),
                class: first.class.clone(),
            },
        );
        self.drive
            .take(first, offline[1..].to_vec(), 0.0, &mut self.record.adopted);
        self.look_around();
        self.hold_at_start();
        self.assign_all();
        if start == goal {
            // Already there: reached before anything moves.
            self.record.event(0.0, start, EventKind::Reached);
            self.reached = true;
            self.done = true;
        }
    }

    /// The speed at which the slowest scout sweeps (infinite with no scout).
    fn sweep_speed(&self) -> Real {
        self.scouts
            .iter()
            .map(|sc| sc.uav.speed)
            .fold(Real::INFINITY, Real::min)
    }

    /// A policy that [holds at the start](super::policy::ScoutPolicy::holds_at_start) holds
    /// the UGV there while the scouts sweep its route: until they have seen it whole or found
    /// it blocked (the UGV then weighs the blockage as on the move, with all the way to it
    /// ahead), for at most the time one scout takes to sweep it.
    fn hold_at_start(&mut self) {
        let sweep_speed = self.sweep_speed();
        if self.team.is_none()
            || !self.cfg.policy.get().holds_at_start()
            || !sweep_speed.is_finite()
            || sweep_speed <= 0.0
        {
            return;
        }
        let route = self.drive.route.clone();
        let unseen = self.planner.seen.unseen_length(&route.line, 0.0);
        self.drive.hold = Some(Hold {
            candidates: vec![route],
            blocked: None,
            until: unseen / sweep_speed,
        });
    }

    /// Whether the mission is over.
    pub(super) fn done(&self) -> bool {
        self.done
    }

    /// One tick. The robots look around (sense); what they found updates the known world
    /// (discover) and may make the UGV re-plan (re-plan), after which the scouts take new
    /// jobs (assign scouts); a scout done with its job takes the next. Then, unless the
    /// time is up, every robot moves one time step (move) and the tracks record it
    /// (record). The robots look around before anyone moves: a blockage within sensor range
    /// of the start is known before the UGV drives into it.
    pub(super) fn step(&mut self) {
        let at = self.drive.position();
        let found = self.sense(at);
        self.look_around();
        let due = self.drive.replan_at.is_some_and(|s| self.drive.s >= s);
        if due {
            self.drive.replan_at = None;
        }
        let range = self.ugv.sensor_range;
        let sweep_speed = self.sweep_speed();
        if found.any() || due {
            let (planner, drive, record) = (&mut self.planner, &mut self.drive, &mut self.record);
            if found.any() {
                discover(planner, drive, record, &found, (self.t, at));
            }
            if !replan(planner, drive, record, self.t, range) {
                self.done = true;
                return;
            }
            self.assign_all();
        } else if let Some(team) = self.team.as_mut()
            && (self.drive.hold.is_some()
                || consider_detour(
                    &mut self.planner,
                    team,
                    &mut self.drive,
                    &mut self.record,
                    self.t,
                    (range, self.ugv.speed, sweep_speed),
                ))
        {
            if settle_hold(
                &mut self.planner,
                team,
                &mut self.drive,
                &mut self.record,
                (self.t, range),
            ) {
                self.assign_all();
            } else {
                self.assign_idle();
            }
        } else if self.scouts.iter().any(|sc| sc.route.is_empty()) {
            self.assign_idle();
        }
        if self.t >= self.max_time {
            self.time_out();
        } else {
            self.move_robots();
        }
    }

    /// Every scout gives up its job and the policy assigns them afresh.
    fn assign_all(&mut self) {
        assign(
            &mut self.scouts,
            self.cfg.policy,
            &self.drive,
            self.ugv.sensor_range,
            &self.planner.seen,
        );
    }

    /// The idle scouts take jobs.
    fn assign_idle(&mut self) {
        assign_idle(
            &mut self.scouts,
            self.cfg.policy,
            &self.drive,
            self.ugv.sensor_range,
            &self.planner.seen,
        );
    }

    /// The robots look around, the UGV at `at`: what they find goes on the known world.
    /// With a team map (a policy that verifies), the UGV's own finds go on both maps, the
    /// scouts' on the team's only, and the UGV's map takes in what of theirs blocks its
    /// route ([`admit`]).
    fn sense(&mut self, at: Point) -> Found {
        let range = self.ugv.sensor_range;
        let Some(team) = &mut self.team else {
            return look(
                &mut self.planner.known,
                (at, Some(range)),
                &self.scouts,
                &mut self.record,
                self.t,
            );
        };
        let own = look(
            &mut self.planner.known,
            (at, Some(range)),
            &[],
            &mut self.record,
            self.t,
        );
        // The UGV's finds are recorded once, above.
        let mut unrecorded = Record::new(at);
        let mine = look(
            &mut team.known,
            (at, Some(range)),
            &[],
            &mut unrecorded,
            self.t,
        );
        let theirs = look(
            &mut team.known,
            (at, None),
            &self.scouts,
            &mut self.record,
            self.t,
        );
        let changed = mine.or(theirs);
        if changed.any() {
            // The team map's upkeep counts in the next re-plan's time.
            self.planner.pending_ms += team.known.update();
            team.version += 1;
            if changed.cleared()
                && let Some(rays) = team.known.renamed()
            {
                team.rays = rays;
            }
        }
        own
    }

    /// What every robot sees now is marked seen.
    fn look_around(&mut self) {
        let seen = &mut self.planner.seen;
        seen.look(&self.drive.position(), self.ugv.sensor_range);
        for sc in &self.scouts {
            seen.look(&sc.pos, sc.uav.sensor_range);
        }
    }

    /// The time is up: the mission stops where the UGV is.
    fn time_out(&mut self) {
        self.record.event(
            self.t,
            self.drive.position(),
            EventKind::Stuck {
                reason: format!("time limit {:.0} s", self.max_time),
            },
        );
        self.done = true;
    }

    /// Every robot moves one time step, its track recording it; done if the UGV reaches
    /// the goal.
    fn move_robots(&mut self) {
        self.t += self.dt;
        let step = self.ugv.speed * self.dt;
        let arrived = if self.drive.hold.is_some() {
            // Holding: the UGV stays where it is.
            let at = self.drive.position();
            self.record.ugv.samples.push((self.t, at));
            false
        } else {
            self.drive
                .advance(step, self.dt, self.t, &mut self.record.ugv)
        };
        for sc in &mut self.scouts {
            sc.step(self.dt, self.t);
        }
        if arrived {
            self.reached = true;
            self.record
                .event(self.t, self.drive.position(), EventKind::Reached);
            self.done = true;
        }
    }

    /// The outcome of world `name` (each scout's track ends at the mission's end), and the
    /// known world as the mission left it.
    pub(super) fn result(mut self, name: &str) -> (MissionResult, K) {
        let t = self.t;
        for sc in &mut self.scouts {
            let last = sc.track.samples.last().copied();
            if last.is_none_or(|(lt, _)| lt < t) {
                sc.track.samples.push((t, sc.pos));
            }
        }
        let record = self.record;
        let result = MissionResult {
            world: name.to_owned(),
            policy: self.cfg.policy,
            scouts: self.scouts.len(),
            reached: self.reached,
            time: t,
            dt: self.dt,
            ugv_distance: self.drive.driven,
            truth_plan_length: self.truth_plan_length,
            replans: record.replans,
            switches: record.switches,
            abandoned_distance: record.abandoned,
            uav_distance: self.scouts.iter().fold(0.0, |acc, s| acc + s.flown),
            events: record.events,
            ugv: record.ugv,
            uavs: self.scouts.into_iter().map(|s| s.track).collect(),
            adopted: record.adopted,
            replan_ms: record.replan_ms,
            map_updates: Vec::new(),
        };
        (result, self.planner.known)
    }
}

/// The mission loop, on any known world: the offline plan, then time steps of sensing, map
/// updates, re-checks, re-plans, driving and flying until the mission is done.
pub(super) fn run_mission<K: Known>(
    known: K,
    team_known: Option<K>,
    rays: Rays,
    name: &str,
    team: &Team,
    truth_plan_length: Option<Real>,
    cfg: &MissionConfig,
) -> Result<(MissionResult, K), MissionError> {
    let mut mission = Mission::new(known, team_known, rays, team, truth_plan_length, cfg)?;
    while !mission.done() {
        mission.step();
    }
    Ok(mission.result(name))
}
