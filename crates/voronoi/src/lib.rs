//! Grid brushfire distance field and the hierarchical generalized Voronoi graph (method.md
//! section 5.1).
//!
//! - [`grid`]: [`Grid`], occupancy with the bounds as a wall ring; rasterised from a scene or
//!   given directly (occupancy maps). Knows nothing of circles beyond rasterising them.
//! - [`field`]: [`DistanceField`], the exact Euclidean brushfire with the nearest obstacle of
//!   every cell, and its local updates.
//! - [`graph`]: [`VoronoiGraph`], the generalized Voronoi graph with start and goal attached.
//! - [`skeleton`]: the complete graph's ridge, by distance-ordered homotopic thinning: the
//!   medial axis of free space wherever an obstacle faces another *or itself*.
//! - [`attach`]: [`MapGraph`], a complete graph prepared once, and start and goal joined to it
//!   along maximum-clearance routes for each query.
//!
//! [`build`] does all three for a scene.

pub mod attach;
pub mod field;
pub mod graph;
pub mod grid;
pub mod skeleton;

pub use attach::{MapGraph, build_complete, complete_graph};
pub use field::{DistanceField, UpdateError};
pub use graph::{Edge, GraphError, GridObstacle, Node, NodeKind, VoronoiGraph};
pub use grid::{Grid, GridError};

use homospline_geom::{Real, Scene};
use thiserror::Error;

/// Union-find: the root of `i` in the forest `parent`, halving the path on the way.
pub(crate) fn find_root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Why [`build`] failed.
#[derive(Debug, Error, PartialEq)]
pub enum BuildError {
    /// The grid.
    #[error(transparent)]
    Grid(#[from] GridError),
    /// The graph.
    #[error(transparent)]
    Graph(#[from] GraphError),
}

/// The Voronoi graph of `scene` at `resolution` cells per map unit, start and goal attached;
/// with the grid and field it was built from.
pub fn build(
    scene: &Scene,
    resolution: Real,
) -> Result<(Grid, DistanceField, VoronoiGraph), BuildError> {
    let grid = Grid::from_scene(scene, resolution)?;
    let field = DistanceField::build(&grid);
    let graph = VoronoiGraph::build(&grid, &field, Some(scene.start), Some(scene.goal))?;
    Ok((grid, field, graph))
}
