//! The world file: a prior scene (the outdated map) and what it does not know (hidden and
//! cleared obstacles), with the team's robots.
//!
//! The data ([`MissionWorld`], [`WorldFile`], [`Team`]) is apart from its reading
//! ([`WorldFile::from_str`], [`load_any`]): the simulation needs the data only.

mod load;
mod parse;
mod scene;
pub(crate) mod types;
mod yaml;

pub use load::{load, load_any};
pub use types::{AnyWorld, MapSpec, MissionWorld, Team, Uav, Ugv, WORLD_VERSION, WorldFile};
