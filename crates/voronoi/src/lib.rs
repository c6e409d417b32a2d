//! Grid brushfire distance field and the hierarchical generalized Voronoi graph (method.md
//! section 5.1).
//!
//! - [`grid`]: [`Grid`], occupancy with the bounds as a wall ring; rasterised from a scene or
//!   given directly (occupancy maps). Knows nothing of circles beyond rasterising them.
//! - [`field`]: [`DistanceField`], the exact Euclidean brushfire with the nearest obstacle of
//!   every cell, and its local updates.
//! - [`graph`]: [`VoronoiGraph`], the generalized Voronoi graph with start and goal attached:
//!   the format (nodes, edges, MessagePack, JSON), its checks and connectivity; the data
//!   every algorithm below builds on.
//! - `assemble` (private): [`VoronoiGraph::build`], the crack graph of a scene with start and
//!   goal attached.
//! - `crack` (private): the cracks between the nearest-obstacle regions, the crack graph's
//!   network; `crack_bits` (private): the cracks of a labelling as bitsets; `regions`
//!   (private): stray cells of a region joined to a neighbour first.
//! - `trace` (private): one tracer of a network into nodes and chains, for both graphs.
//! - `simplify` (private): chains into edge polylines (geom's Douglas-Peucker) with lengths
//!   and clearances.
//! - `prune` (private): spurs and dead ends off a graph.
//! - [`skeleton`]: the complete graph's ridge, by distance-ordered homotopic thinning: the
//!   medial axis of free space wherever an obstacle faces another *or itself*.
//! - [`attach`]: start and goal joined to a graph: [`MapGraph`], a complete graph prepared
//!   once, joined along maximum-clearance routes for each query; and the crack graph's
//!   breadth-first joins.
//! - [`query`]: [`QueryGraph`], one query on a prepared map's complete graph without copying
//!   it: the 2-core prepared once, and what the query adds.
//! - `union_find` (private): the union-find root shared by the field, the regions and the
//!   graph.
//!
//! [`build`] does grid, field and graph for a scene.

pub mod apart;
mod assemble;
pub mod attach;
mod crack;
mod crack_bits;
mod exact;
pub mod field;
pub mod graph;
pub mod grid;
mod prune;
pub mod query;
mod regions;
mod simplify;
pub mod skeleton;
mod trace;
mod union_find;

pub use attach::{MapGraph, build_complete, complete_graph};
pub use field::{DistanceField, UpdateError};
pub use graph::{
    Adjacency, AdjacencyLinks, BuiltFor, Edge, GraphError, GridObstacle, Node, NodeKind,
    VoronoiGraph,
};
pub use grid::{Grid, GridError};
pub use query::QueryGraph;

use homospline_geom::{Bounds, Point, Real, Scene};
use thiserror::Error;

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
///
/// # Examples
///
/// ```
/// use homospline_geom::Scene;
///
/// let scene = Scene::from_str(
///     "name: two\nbounds: {min: [0, 0], max: [40, 20]}\nstart: [2, 10]\ngoal: [38, 10]\n\
///      obstacles:\n  - name: a\n    circles: [[14, 10, 3]]\n  - name: b\n    circles: [[26, 10, 3]]\n",
///     "two.yaml",
/// )?;
/// let (grid, _field, graph) = homospline_voronoi::build(&scene, 4.0)?;
/// assert_eq!(grid.width(), 40 * 4 + 2); // the bounds, and a wall ring
/// let (s, t) = (graph.start.unwrap(), graph.goal.unwrap());
/// assert!(graph.connected(s, t));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// See also [`build_within`] (a finer grid's cells limited), [`MapGraph`] (the complete
/// graph of a map, prepared once for many queries).
pub fn build(
    scene: &Scene,
    resolution: Real,
) -> Result<(Grid, DistanceField, VoronoiGraph), BuildError> {
    build_within(scene, resolution, apart::REFINE_MAX_CELLS)
}

/// [`build`], with a finer grid (for a gap narrower than a few cells that may join start
/// and goal, or an end closer to a circle than a cell) of at most `max_cells` cells: a front
/// end gives the cells its process's memory allows (the first grid is its to check), so
/// that a refinement is refused with its message rather than run out of memory. At most
/// [`apart::REFINE_MAX_CELLS`] either way.
///
/// # Examples
///
/// ```
/// use homospline_geom::Scene;
/// use homospline_voronoi::{BuildError, GraphError};
///
/// // A start 0.15 from the rock, in a cell whose centre is in it at 2 cells per unit: the
/// // finer grid it needs (about 50,000 cells) is over a limit of 10,000.
/// let scene = Scene::from_str(
///     "bounds: {min: [0, 0], max: [60, 60]}\nstart: [10.05, 30]\ngoal: [55, 30]\n\
///      obstacles:\n  - name: rock\n    circles: [[20.2, 30, 10]]\n",
///     "near.yaml",
/// )?;
/// let refused = homospline_voronoi::build_within(&scene, 2.0, 10_000);
/// assert!(matches!(refused, Err(BuildError::Graph(GraphError::TooClose { .. }))));
/// assert!(homospline_voronoi::build_within(&scene, 2.0, 1 << 20).is_ok());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn build_within(
    scene: &Scene,
    resolution: Real,
    max_cells: usize,
) -> Result<(Grid, DistanceField, VoronoiGraph), BuildError> {
    let max_cells = max_cells.min(apart::REFINE_MAX_CELLS);
    let grid = match build_at(scene, resolution) {
        Ok(built) => return Ok(built),
        // A start or goal closer to a circle than this grid's cells can tell (its cell's
        // centre inside the circle): a grid fine enough for it, built once.
        Err(BuildAtError::Other(BuildError::Graph(GraphError::Occupied(what, x, y)))) => {
            return build_for_ends(scene, resolution, what, Point::new(x, y), max_cells);
        }
        Err(BuildAtError::Other(e)) => return Err(e),
        Err(BuildAtError::Apart(grid)) => grid,
    };
    build_apart(scene, resolution, grid, max_cells)
}

/// [`build`] on a grid whose cells are at most the ends' clearance across, after `what` at
/// `p` fell in an occupied cell at `resolution`. A cell is occupied when its centre lies in
/// a circle; on that grid the centre of the cell holding an end is within `0.71 h` of it,
/// so outside every circle: the end's cell is free. Refused, naming the end, its clearance
/// and the `--resolution` that plans it, when that grid is over
/// `max_cells` (or the end touches a circle).
fn build_for_ends(
    scene: &Scene,
    resolution: Real,
    what: &'static str,
    p: Point,
    max_cells: usize,
) -> Result<(Grid, DistanceField, VoronoiGraph), BuildError> {
    let set = scene.circle_set();
    let clear = |q: &Point| set.clearance(q).map_or(Real::INFINITY, |c| c.distance);
    // The end nearer a circle decides the grid, and the message names it.
    let (what, p) = if clear(&scene.goal) < clear(&scene.start) {
        ("goal", scene.goal)
    } else if clear(&scene.start) < clear(&p) {
        ("start", scene.start)
    } else {
        (what, p)
    };
    let c = clear(&p);
    let finer = (1.0001 / c).max(resolution);
    let cells = grid::scene_cells(scene, finer);
    let owner = set
        .clearance(&p)
        .and_then(|n| scene.circle_owners().get(n.nearest).copied())
        .and_then(|o| scene.obstacles.get(o))
        .map_or_else(String::new, |o| format!(" '{}'", o.name));
    if !(c > 0.0 && finer.is_finite() && cells <= max_cells as Real) {
        return Err(GraphError::TooClose {
            what,
            at: [p.x, p.y],
            clearance: c,
            obstacle: owner,
            resolution,
            needed: finer,
            fits: c > 0.0 && finer.is_finite() && cells <= grid::MAX_CELLS as Real,
        }
        .into());
    }
    match build_at(scene, finer) {
        Ok(built) => Ok(built),
        Err(BuildAtError::Other(e)) => Err(e),
        Err(BuildAtError::Apart(grid)) => build_apart(scene, finer, grid, max_cells),
    }
}

/// [`build`] once start and goal came out apart on `grid` (built at `resolution`).
fn build_apart(
    scene: &Scene,
    resolution: Real,
    grid: Grid,
    max_cells: usize,
) -> Result<(Grid, DistanceField, VoronoiGraph), BuildError> {
    // Apart on this grid: a gap narrower than a few cells may be closed here and open
    // between the circles. Judged from the circles ([`apart`]): walled apart, or built again
    // on a grid fine enough for the narrowest gap (once: that grid opens every gap, so being
    // apart there is the circles' verdict).
    let n = match apart::judge(scene, &grid) {
        apart::Apart::Walled(obstacles) => return Err(GraphError::Walled { obstacles }.into()),
        apart::Apart::Narrow(n) => n,
    };
    // A hair finer than the need, so that the grid is sure to meet it.
    let finer = 1.0001 / n.need;
    let cells = grid::scene_cells(scene, finer);
    if cells > max_cells as Real {
        // The finest grid within the limit may open the gap all the same (the exact pass
        // round the circles opens gaps narrower than a cell, and a route may not need the
        // narrowest place); a plan on it is certified like any other. Only if start and
        // goal are apart there too is no verdict claimed.
        // Its join counts only inside the bounds: the grid's border cells straddle them, and
        // a circle that overhangs the bounds by less than a cell left a false way round it
        // there.
        let within = finer * (max_cells as Real / cells).sqrt() * 0.999;
        if within > resolution * 1.5
            && grid::scene_cells(scene, within) <= max_cells as Real
            && let Ok(built) = build_at(scene, within)
            && joined_inside(&built.2, &scene.bounds)
        {
            return Ok(built);
        }
        return Err(GraphError::Unresolved {
            resolution,
            width: n.width,
            between: n.between,
            needed: finer,
            fits: cells <= grid::MAX_CELLS as Real,
        }
        .into());
    }
    match build_at(scene, finer) {
        Ok(built) => Ok(built),
        Err(BuildAtError::Other(e)) => Err(e),
        Err(BuildAtError::Apart(grid)) => Err(GraphError::Walled {
            obstacles: match apart::judge(scene, &grid) {
                apart::Apart::Walled(o) => o,
                apart::Apart::Narrow(_) => None,
            },
        }
        .into()),
    }
}

/// Whether the graph joins its start and goal by edges whose polylines lie inside `bounds`.
fn joined_inside(graph: &VoronoiGraph, bounds: &Bounds) -> bool {
    let (Some(start), Some(goal)) = (graph.start, graph.goal) else {
        return false;
    };
    graph.connected_by(start, goal, |e| {
        e.polyline
            .iter()
            .all(|p| bounds.contains(&Point::new(p[0], p[1])))
    })
}

/// Why [`build_at`] failed: start and goal apart on the grid (which it returns), or
/// another error.
enum BuildAtError {
    Apart(Grid),
    Other(BuildError),
}

impl From<GridError> for BuildAtError {
    fn from(e: GridError) -> Self {
        BuildAtError::Other(e.into())
    }
}

impl From<GraphError> for BuildAtError {
    fn from(e: GraphError) -> Self {
        BuildAtError::Other(e.into())
    }
}

/// [`build`] at `resolution` as it stands: start and goal apart on its grid is
/// [`BuildAtError::Apart`].
fn build_at(
    scene: &Scene,
    resolution: Real,
) -> Result<(Grid, DistanceField, VoronoiGraph), BuildAtError> {
    let grid = Grid::from_scene(scene, resolution)?;
    let field = DistanceField::build(&grid);
    let mut graph = match VoronoiGraph::build(&grid, &field, Some(scene.start), Some(scene.goal)) {
        // The crack graph runs between *different* obstacles. Where free space runs between an
        // obstacle and itself (one that touches the wall, two joined by a blockage) it has no
        // crack, and it can come apart inside one free region. The complete graph (the ridge
        // of free space, as on maps) joins start and goal whenever their region does.
        Err(GraphError::DifferentRegions) => {
            match build_complete(&grid, &field, scene.start, scene.goal) {
                Err(GraphError::DifferentRegions) => return Err(BuildAtError::Apart(grid)),
                other => other?,
            }
        }
        other => other?,
    };
    // A thousandth of a cell of clearance for every point moved out of a circle.
    exact::keep_out_of_circles(&mut graph, &scene.circle_set(), 1e-3 / resolution);
    graph.built_for = Some(BuiltFor::of(scene));
    Ok((grid, field, graph))
}
