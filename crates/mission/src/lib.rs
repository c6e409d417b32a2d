//! The team's mission (method section 6): a ground robot (UGV) with aerial scouts (UAVs) on
//! an outdated map. The k best homotopy classes are planned offline on the prior map; online,
//! in time steps, the UGV drives its plan, scouts fly their routes, anything within a robot's
//! sensor range is discovered (obstacles not on the map, and mapped obstacles that are gone),
//! and when the UGV's path is found blocked it re-plans at once from where it is, keeping its
//! heading, over the classes still open.
//!
//! - [`world`]: the world file ([`WorldFile`]) and the world ([`MissionWorld`]): the prior
//!   scene, the truth, the team.
//! - [`sim`]: [`simulate`] with a [`MissionConfig`] (scout [`Policy`], hysteresis, time
//!   step) into a [`MissionResult`] (events, tracks, figures against the truth plan).
//!
//! Classes are named by their signature on the rays of the prior map's obstacles that are
//! still known to be there: an obstacle found (not on the map) does not rename classes, so
//! a class stays the same class while the robots discover blockages; a mapped obstacle
//! found gone merges the classes that differed only around it.
//!
//! This crate reads no files: front ends load the world file and its scene.

mod known;
pub mod map;
pub mod sim;
pub mod world;

pub use map::{Change, MapUpdate, MapWorld};
pub use sim::{
    Adopted, Event, EventKind, MissionConfig, MissionConfigError, MissionError, MissionResult,
    MissionSetting, Policy, Robot, ScoutPolicy, Track, replan_scene, should_switch, simulate,
    simulate_map, time_step,
};
pub use world::{AnyWorld, MissionWorld, Team, Uav, Ugv, WorldFile};
