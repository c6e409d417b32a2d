//! What a mission records: its events, the robots' tracks, the paths the UGV adopted, and
//! the result they make up.

use homospline_geom::{Point, Real};

use super::policy::Policy;
use crate::known::map::MapUpdate;

/// Who saw something.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Robot {
    /// The ground robot.
    Ugv,
    /// Scout `i`.
    Uav(usize),
}

/// What happened.
#[derive(Clone, Debug, PartialEq)]
pub enum EventKind {
    /// The offline plan on the prior map.
    Planned {
        /// Collision-free classes found.
        classes: usize,
        /// The class chosen.
        class: String,
    },
    /// An obstacle not on the map (`hidden`), or the absence of one that is, was seen.
    Discovered {
        /// Its name.
        obstacle: String,
        /// `true`: a new obstacle; `false`: a mapped obstacle found gone.
        hidden: bool,
        /// Who saw it.
        by: Robot,
    },
    /// A class other than the UGV's was found blocked.
    ClassClosed {
        /// The class.
        class: String,
    },
    /// The UGV's path was found blocked.
    Blocked {
        /// Its class.
        class: String,
    },
    /// A re-plan from the UGV's position.
    Replanned {
        /// Blocked path (`true`) or a discovery that may open a better class.
        forced: bool,
        /// Collision-free classes found.
        classes: usize,
        /// The class driven next.
        class: String,
    },
    /// The UGV changed class.
    Switched {
        /// From.
        from: String,
        /// To.
        to: String,
    },
    /// The new path leaves more than [`TURN_ANGLE_DEG`] off the heading (it starts backwards
    /// or sideways): the UGV turns on the spot.
    ///
    /// [`TURN_ANGLE_DEG`]: crate::sim::TURN_ANGLE_DEG
    TurnedAround,
    /// The goal is reached.
    Reached,
    /// The mission stopped without reaching the goal.
    Stuck {
        /// Why.
        reason: String,
    },
}

/// An event at a time and place (the UGV's position).
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Seconds from the start.
    pub t: Real,
    /// The UGV's position.
    pub at: Point,
    /// What.
    pub kind: EventKind,
}

/// A robot's positions over time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Track {
    /// `ugv` or `uav-I`.
    pub name: String,
    /// `(t, position)`, one per time step while moving, and the last one.
    pub samples: Vec<(Real, Point)>,
}

/// A path the UGV adopted.
#[derive(Clone, Debug, PartialEq)]
pub struct Adopted {
    /// When.
    pub t: Real,
    /// Its class (signature on the prior map's rays).
    pub class: String,
    /// The sampled curve.
    pub path: Vec<Point>,
}

/// The outcome of a mission.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionResult {
    /// World name.
    pub world: String,
    /// Policy used.
    pub policy: Policy,
    /// Scouts flown.
    pub scouts: usize,
    /// The goal was reached.
    pub reached: bool,
    /// Seconds until the goal (or until the mission stopped).
    pub time: Real,
    /// The time step the mission ran at: [`MissionConfig::dt`], or less where a robot would
    /// travel more than half its sensor range between two looks ([`time_step`]).
    ///
    /// [`MissionConfig::dt`]: crate::sim::MissionConfig::dt
    /// [`time_step`]: crate::sim::time_step
    pub dt: Real,
    /// Distance the UGV drove.
    pub ugv_distance: Real,
    /// Length of the best plan on the true world from the start (`None` if it has none).
    pub truth_plan_length: Option<Real>,
    /// Re-plans after the offline plan.
    pub replans: usize,
    /// Class changes.
    pub switches: usize,
    /// Distance driven on paths later abandoned (blocked or switched away from), counted
    /// from when each was adopted.
    pub abandoned_distance: Real,
    /// Distance flown by all scouts.
    pub uav_distance: Real,
    /// Everything that happened, in time order.
    pub events: Vec<Event>,
    /// The UGV's track.
    pub ugv: Track,
    /// Each scout's track.
    pub uavs: Vec<Track>,
    /// Every path the UGV adopted.
    pub adopted: Vec<Adopted>,
    /// Wall time of each re-plan (map update, classes, optimisation), milliseconds: not part
    /// of the deterministic outcome.
    pub replan_ms: Vec<Real>,
    /// On maps, each update of the known map (what was updated locally, wall times); empty
    /// on scenes.
    pub map_updates: Vec<MapUpdate>,
}

impl MissionResult {
    /// What is the same from run to run and for any thread count: this result with every
    /// wall time left out (`replan_ms` emptied; each map update's times zeroed, what it
    /// changed and how kept).
    pub fn outcome(&self) -> MissionResult {
        MissionResult {
            replan_ms: Vec::new(),
            map_updates: self
                .map_updates
                .iter()
                .map(|u| MapUpdate {
                    field_ms: 0.0,
                    graph_ms: 0.0,
                    model_ms: 0.0,
                    ..u.clone()
                })
                .collect(),
            ..self.clone()
        }
    }

    /// UGV distance over the truth plan's length.
    pub fn distance_ratio(&self) -> Option<Real> {
        self.truth_plan_length
            .filter(|&l| l > 0.0 && self.reached)
            .map(|l| self.ugv_distance / l)
    }

    /// Mission time over the truth plan's driving time.
    pub fn time_ratio(&self, ugv_speed: Real) -> Option<Real> {
        self.truth_plan_length
            .filter(|&l| l > 0.0 && self.reached)
            .map(|l| self.time / (l / ugv_speed))
    }
}

/// The record of a mission while it runs: what goes into its [`MissionResult`] besides the
/// robots' state.
pub(super) struct Record {
    /// Everything that happened, in time order.
    pub(super) events: Vec<Event>,
    /// The UGV's track.
    pub(super) ugv: Track,
    /// Every path the UGV adopted.
    pub(super) adopted: Vec<Adopted>,
    /// Wall time of each re-plan, ms.
    pub(super) replan_ms: Vec<Real>,
    /// Re-plans after the offline plan.
    pub(super) replans: usize,
    /// Class changes.
    pub(super) switches: usize,
    /// Distance driven on paths later abandoned.
    pub(super) abandoned: Real,
}

impl Record {
    /// An empty record of a UGV starting at `start`.
    pub(super) fn new(start: Point) -> Self {
        Self {
            events: Vec::new(),
            ugv: Track {
                name: "ugv".into(),
                samples: vec![(0.0, start)],
            },
            adopted: Vec::new(),
            replan_ms: Vec::new(),
            replans: 0,
            switches: 0,
            abandoned: 0.0,
        }
    }

    /// Records `kind` at time `t`, the UGV at `at`.
    pub(super) fn event(&mut self, t: Real, at: Point, kind: EventKind) {
        self.events.push(Event { t, at, kind });
    }
}
