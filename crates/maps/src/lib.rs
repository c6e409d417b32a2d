//! Real maps: MovingAI benchmark grids and ROS map_server occupancy maps, the grid clearance
//! model, and planning on them (the Voronoi graph straight from the grid).
//!
//! - [`movingai`]: `.map` and `.scen` from text, with errors that name the line.
//! - [`ros`]: the map YAML and its PGM or PNG image (nav2's conversion rules).
//! - [`model`]: [`GridModel`], the [`homospline_spline::ClearanceModel`] of a grid.
//! - [`plan_map`]: a plan on an [`OccupancyMap`], with the same result as on a scene.
//!
//! Topological obstacles of a map are the 8-connected components of occupied cells not
//! touching the map's border (those merge with the wall); each is represented by the centre
//! of its first cell in raster order, which is inside it.

mod config;
pub mod footprint;
pub mod input;
mod map;
pub mod model;
pub mod movingai;
mod prepared;
pub mod ros;
pub mod sweep;

pub use config::*;
pub(crate) use map::stem;
pub use map::*;
pub use model::GridModel;
pub use prepared::*;
