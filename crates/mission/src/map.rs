//! Missions on occupancy maps: a prior map and a truth map of the same size. The cells whose
//! state differs are grouped into changes (8-connected cells that became occupied, or
//! free); a change is discovered when one of its cells comes within a robot's sensor range.
//! The known map is then updated locally: the brushfire by
//! [`DistanceField::add_cells`] (a blockage, even across a passage) or
//! [`DistanceField::remove_obstacle`] (a whole obstacle gone), else rebuilt; the clearance
//! model is rebuilt from the updated field. After blockages only, the complete Voronoi graph
//! is kept and its edges through the blocked cells are closed to the class search (a
//! rebuild would take the whole re-plan budget; measured: docs/performance.md,
//! "Measurements behind the defaults"); freed cells, and a
//! re-plan that finds no collision-free class on the kept graph, rebuild it from the field.
//!
//! [`DistanceField::add_cells`]: homospline_voronoi::DistanceField::add_cells
//! [`DistanceField::remove_obstacle`]: homospline_voronoi::DistanceField::remove_obstacle

mod changes;
mod join;

pub use crate::known::map::MapUpdate;
pub use crate::world::types::{Change, MapWorld};
