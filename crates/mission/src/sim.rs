//! The mission simulation: the k best classes on the prior map offline, then time steps in
//! which the UGV drives its plan, the scouts fly their routes, discoveries update the map,
//! and the UGV re-plans from where it is, keeping its heading, when its path is blocked.
//!
//! - `config`: the settings ([`MissionConfig`]) and their ranges.
//! - [`policy`]: the scout policies ([`ScoutPolicy`], one module each) and their registry
//!   ([`Policy::all`]); `coverage`: what the robots have seen.
//! - `mission`: the mission's state and one tick of it (sense, discover, re-plan, assign
//!   scouts, move, record), run until it is done.
//! - `sense`, `replan`, `scouts`: the phases of a tick.
//! - `planner`, `route`, `scene`: the planner on the known world, the routes driven, the
//!   known world of a scene.
//! - `record`: the events, tracks and the [`MissionResult`].
//! - `simulate`: [`simulate`] and [`simulate_map`].

mod config;
mod coverage;
mod mission;
mod planner;
pub mod policy;
mod record;
mod replan;
mod route;

mod scouts;
mod sense;
mod simulate;

pub use crate::known::scene::replan_scene;
pub use config::{
    MAX_SCOUTS, MAX_STEPS, MIN_DT, MissionConfig, MissionConfigError, MissionError, MissionSetting,
    TURN_ANGLE_DEG, time_step,
};
pub use mission::check_team;
pub use policy::{Policy, ScoutPolicy};
pub use record::{Adopted, Event, EventKind, MissionResult, Robot, Track};
pub use replan::should_switch;
pub use simulate::{simulate, simulate_map};
