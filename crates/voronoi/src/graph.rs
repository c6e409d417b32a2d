//! The graph a query searches, [`VoronoiGraph`]: nodes, edges and the obstacles inside the
//! wall; MessagePack (versioned) and the JSON of `docs/formats.md`; cycle rank and
//! connectivity. Plain data with its checks: the algorithms that make a graph build on this
//! module and it uses none of them.
//!
//! [`VoronoiGraph::build`] (module `assemble`) makes the crack graph of a rasterised scene
//! (the paper's GVG), in steps that each have a module: the cracks between the
//! nearest-obstacle regions (`crack`, with `regions` cleaning up stray cells), traced into
//! nodes and chains (`trace`), the chains' polylines (`simplify`), then start and goal joined
//! to it ([`crate::attach`]). Pruning is in `prune`; the complete graph of a map is
//! [`crate::skeleton`] and [`crate::attach::MapGraph`].

use std::sync::Arc;

use homospline_geom::Real;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::field::DistanceField;
use crate::grid::Grid;
use crate::union_find::find_root;

/// Edge polylines stay within this many cells of their crack chains (Douglas-Peucker): a
/// chain along an obstacle's side must not be simplified into the obstacle.
pub const POLYLINE_TOLERANCE: Real = 0.3;

/// Version of the serialised graph ([`VoronoiGraph::to_msgpack`]).
pub const GRAPH_FORMAT_VERSION: u32 = 1;

/// What a node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NodeKind {
    /// Three or more regions meet (or the anchor of a loop).
    Junction,
    /// A spur's end.
    DeadEnd,
    /// The start point.
    Start,
    /// The goal point.
    Goal,
}

/// A node of the graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// Index in `nodes`.
    pub id: usize,
    /// Position in map coordinates.
    pub at: [Real; 2],
    /// Clearance in map units.
    pub clearance: Real,
    /// Kind.
    pub kind: NodeKind,
}

/// An arc of the graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Edge {
    /// Node index.
    pub from: usize,
    /// Node index (equal to `from` on a loop).
    pub to: usize,
    /// Length of the polyline, map units.
    pub length: Real,
    /// Smallest clearance along it, map units.
    pub min_clearance: Real,
    /// Mean clearance along it, map units.
    pub mean_clearance: Real,
    /// From `from` to `to`, map coordinates. Shared by the copies of a graph: a prepared
    /// map's query graph ([`MapGraph::with_endpoints`](crate::MapGraph::with_endpoints))
    /// copies the complete graph's edges, not their polylines.
    pub polyline: Arc<[[Real; 2]]>,
}

/// An obstacle of the grid (an 8-connected component of occupied cells other than the wall).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridObstacle {
    /// Key in the distance field.
    pub key: u32,
    /// A point strictly inside it: the centre of its key cell.
    pub representative: [Real; 2],
}

impl GridObstacle {
    /// The obstacles of `field` inside the wall, each represented by its key cell's centre.
    pub fn of_field(grid: &Grid, field: &DistanceField) -> Vec<GridObstacle> {
        field
            .obstacles()
            .filter(|&k| k != field.wall_key())
            .map(|key| {
                let (i, j) = (key as usize % grid.width(), key as usize / grid.width());
                let p = grid.center(i, j);
                GridObstacle {
                    key,
                    representative: [p.x, p.y],
                }
            })
            .collect()
    }
}

/// The graph, with start and goal attached when they were given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VoronoiGraph {
    /// Cells per map unit.
    pub resolution: Real,
    /// Nodes.
    pub nodes: Vec<Node>,
    /// Edges.
    pub edges: Vec<Edge>,
    /// The node the start is (kind `start`).
    pub start: Option<usize>,
    /// The node the goal is (kind `goal`).
    pub goal: Option<usize>,
    /// The obstacles inside the wall, with representative points.
    #[serde(default)]
    pub obstacles: Vec<GridObstacle>,
    /// For a scene's graph, the geometry it was built from ([`crate::build`]), so that a saved
    /// graph is not reused on another scene; `None` for a map's graph (checked by its
    /// obstacles and resolution) and for graphs saved before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub built_for: Option<BuiltFor>,
}

/// The geometry a scene's Voronoi graph depends on: the bounds (the grid's wall) and the
/// circles inflated by the robot radius, in the scene's order. Compared exactly: a graph
/// read back is reused only on the scene it was built for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BuiltFor {
    /// `[[min x, min y], [max x, max y]]`.
    pub bounds: [[Real; 2]; 2],
    /// `[x, y, r]`, inflated by the robot radius.
    pub circles: Vec<[Real; 3]>,
}

impl BuiltFor {
    /// What a graph of `scene` is built from.
    pub fn of(scene: &homospline_geom::Scene) -> Self {
        let b = scene.bounds;
        Self {
            bounds: [[b.min.x, b.min.y], [b.max.x, b.max.y]],
            circles: scene
                .circles()
                .iter()
                .map(|c| [c.center.x, c.center.y, c.radius])
                .collect(),
        }
    }
}

/// Why a graph cannot be made.
#[derive(Debug, Error, PartialEq)]
pub enum GraphError {
    /// The point is outside the grid.
    #[error("the {0} [{1}, {2}] is outside the grid")]
    Outside(&'static str, Real, Real),
    /// The point falls in an occupied cell at this resolution.
    #[error(
        "the {0} [{1}, {2}] falls in an occupied cell at this resolution: raise the resolution"
    )]
    Occupied(&'static str, Real, Real),
    /// Start and goal are in different free regions.
    #[error("start and goal are in different free regions: no path joins them")]
    DifferentRegions,
    /// A scene's start and goal are walled apart: every gap between its circles and the
    /// bounds is open on the grid ([`crate::apart`]), and the grid joins them nowhere.
    /// `obstacles` names the touching obstacles that wall them apart on their own, when
    /// one group does.
    #[error(
        "no route: start and goal are walled apart by {}: their circles (grown by the robot's radius) touch one another or the bounds, and no gap between them lets a path through",
        obstacles.as_deref().unwrap_or("the obstacles together")
    )]
    Walled {
        /// The walling obstacles, in words.
        obstacles: Option<String>,
    },
    /// A scene's start and goal are apart on its grid, and a gap narrower than
    /// [`crate::apart::GAP_CELLS`] of its cells (or an end that close to an obstacle) may
    /// join them; the grid that would tell is over [`crate::apart::REFINE_MAX_CELLS`]: no
    /// verdict either way.
    #[error(
        "start and goal are apart at {} cells per unit, but {between} leave a gap of {} that this grid cannot resolve and that may join them, so no plan is claimed: {}",
        homospline_geom::math::Num(significant(*resolution)),
        homospline_geom::math::Num(significant(*width)),
        if *fits {
            format!("--resolution {} resolves it", homospline_geom::math::Num(significant_up(*needed)))
        } else {
            "it needs a grid over the limit; scale the scene's units up or widen the gap".to_owned()
        }
    )]
    Unresolved {
        /// The resolution tried.
        resolution: Real,
        /// The narrowest place's width.
        width: Real,
        /// What it lies between.
        between: String,
        /// The resolution that resolves it.
        needed: Real,
        /// Whether that grid is within the grid's limit.
        fits: bool,
    },
    /// A scene's start or goal is closer to a circle than a grid within
    /// [`crate::apart::REFINE_MAX_CELLS`] can tell (or touches it): no grid was built.
    #[error(
        "the {what} [{}, {}] {} obstacle{obstacle}, closer than a grid of {} cells per unit can tell: {}",
        homospline_geom::math::Num(at[0]),
        homospline_geom::math::Num(at[1]),
        if *clearance > 0.0 {
            format!("is {} from", homospline_geom::math::Num(significant(*clearance)))
        } else {
            "touches".to_owned()
        },
        homospline_geom::math::Num(significant(*resolution)),
        if *fits {
            format!("--resolution {} plans it", homospline_geom::math::Num(significant_up(*needed)))
        } else if *clearance > 0.0 {
            "it needs a grid over the limit; move it farther from the obstacle or scale the scene's units up".to_owned()
        } else {
            "move it off the obstacle".to_owned()
        }
    )]
    TooClose {
        /// `start` or `goal`.
        what: &'static str,
        /// Where it is.
        at: [Real; 2],
        /// Its clearance from the circles.
        clearance: Real,
        /// The nearest obstacle's name, quoted with a space before it (empty if unknown).
        obstacle: String,
        /// The resolution tried.
        resolution: Real,
        /// The resolution that plans it.
        needed: Real,
        /// Whether that grid is within the grid's limit.
        fits: bool,
    },
    /// A serialised graph could not be read.
    #[error("cannot read the graph: {0}")]
    Decode(String),
    /// A serialised graph has another format version.
    #[error("graph format version {0} is not supported (this build reads {GRAPH_FORMAT_VERSION})")]
    Version(u32),
}

/// `x` to 4 significant digits, for messages.
fn significant(x: Real) -> Real {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powf(x.abs().log10().floor() - 3.0);
    (x / scale).round() * scale
}

/// `x` rounded up to 3 significant digits: a resolution at least `x`.
fn significant_up(x: Real) -> Real {
    if x <= 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powf(x.log10().floor() - 2.0);
    (x / scale).ceil() * scale
}

impl GraphError {
    /// Whether this is an answer, not a fault: start and goal are walled apart
    /// ([`GraphError::Walled`]), so there is no route (a front end's "no plan").
    pub fn is_no_route(&self) -> bool {
        matches!(self, GraphError::Walled { .. })
    }
}

/// The edges at each node in one array: node `k`'s are `links[first[k]..first[k + 1]]`, as
/// `(other end, edge, walked from -> to)`, in edge order (a loop once, at its node). A graph
/// of a whole map has millions of nodes, and a list each cost more than the search or the
/// pruning that used it. Stored in 32 bits (the edge and the direction in one word), a third
/// of the memory of machine words: a graph has fewer than [`MAX_EDGES`] edges.
#[derive(Clone, Debug, Default)]
pub struct Adjacency {
    first: Vec<u32>,
    /// `(other end, edge << 1 | walked from -> to)`.
    links: Vec<(u32, u32)>,
}

/// A node's links in an [`Adjacency`] ([`Adjacency::of`]): `(other end, edge, walked from
/// -> to)`.
#[derive(Clone, Debug)]
pub struct AdjacencyLinks<'a>(std::slice::Iter<'a, (u32, u32)>);

impl Iterator for AdjacencyLinks<'_> {
    type Item = (usize, usize, bool);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        self.0
            .next()
            .map(|&(m, e)| (m as usize, (e >> 1) as usize, e & 1 == 1))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.0.size_hint()
    }
}

impl ExactSizeIterator for AdjacencyLinks<'_> {}

impl Adjacency {
    /// Node `k`'s links, `(other end, edge, walked from -> to)`.
    #[inline]
    pub fn of(&self, k: usize) -> AdjacencyLinks<'_> {
        let (a, b) = (self.first[k] as usize, self.first[k + 1] as usize);
        AdjacencyLinks(self.links[a..b].iter())
    }
}

/// As many edges or nodes as this, or more, is not a graph this program builds (a grid holds at most
/// [`crate::grid::MAX_CELLS`] cells) nor reads ([`VoronoiGraph::validate`]): [`Adjacency`]
/// numbers them in 31 bits.
pub const MAX_EDGES: usize = 1 << 31;

impl VoronoiGraph {
    /// Whether nodes `a` and `b` are joined by edges.
    pub fn connected(&self, a: usize, b: usize) -> bool {
        self.connected_by(a, b, |_| true)
    }

    /// Whether nodes `a` and `b` are joined by edges that `keep` takes.
    pub fn connected_by(&self, a: usize, b: usize, keep: impl Fn(&Edge) -> bool) -> bool {
        let mut parent: Vec<usize> = (0..self.nodes.len()).collect();
        for e in self.edges.iter().filter(|e| keep(e)) {
            let (x, y) = (find_root(&mut parent, e.from), find_root(&mut parent, e.to));
            parent[x] = y;
        }
        find_root(&mut parent, a) == find_root(&mut parent, b)
    }

    /// A copy with room for `nodes` more nodes and `edges` more edges without reallocating.
    pub(crate) fn clone_with_room(&self, nodes: usize, edges: usize) -> Self {
        let mut copy_nodes = Vec::with_capacity(self.nodes.len() + nodes);
        copy_nodes.extend_from_slice(&self.nodes);
        let mut copy_edges = Vec::with_capacity(self.edges.len() + edges);
        copy_edges.extend_from_slice(&self.edges);
        Self {
            resolution: self.resolution,
            nodes: copy_nodes,
            edges: copy_edges,
            start: self.start,
            goal: self.goal,
            obstacles: self.obstacles.clone(),
            built_for: self.built_for.clone(),
        }
    }

    /// The adjacency of the edges that `keep` accepts.
    pub fn adjacency(&self, keep: impl Fn(usize) -> bool) -> Adjacency {
        // Both fewer than MAX_EDGES (2^31): built graphs by the grid's size, read ones by
        // `validate`; so every index and count below fits its 32 bits.
        debug_assert!(self.nodes.len() < MAX_EDGES && self.edges.len() < MAX_EDGES);
        let n = self.nodes.len();
        let mut first = vec![0u32; n + 1];
        for (i, e) in self.edges.iter().enumerate() {
            if keep(i) {
                first[e.from + 1] += 1;
                if e.from != e.to {
                    first[e.to + 1] += 1;
                }
            }
        }
        for k in 0..n {
            first[k + 1] += first[k];
        }
        let mut fill = first.clone();
        let mut links = vec![(0u32, 0u32); first[n] as usize];
        for (i, e) in self.edges.iter().enumerate() {
            if keep(i) {
                let edge = (i as u32) << 1;
                links[fill[e.from] as usize] = (e.to as u32, edge | 1);
                fill[e.from] += 1;
                if e.from != e.to {
                    links[fill[e.to] as usize] = (e.from as u32, edge);
                    fill[e.to] += 1;
                }
            }
        }
        Adjacency { first, links }
    }

    /// Independent cycles: `E - V + C` (loops count one each).
    pub fn cycle_rank(&self) -> usize {
        cycle_rank(self.nodes.len(), self.edges.iter().map(|e| (e.from, e.to)))
    }

    /// The graph as the JSON of `docs/formats.md`.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// The graph as MessagePack with its format version, for building offline.
    pub fn to_msgpack(&self) -> Vec<u8> {
        #[derive(Serialize)]
        struct File<'a> {
            format_version: u32,
            graph: &'a VoronoiGraph,
        }
        rmp_serde::to_vec_named(&File {
            format_version: GRAPH_FORMAT_VERSION,
            graph: self,
        })
        .unwrap_or_default()
    }

    /// Reads [`VoronoiGraph::to_msgpack`] output.
    pub fn from_msgpack(bytes: &[u8]) -> Result<Self, GraphError> {
        #[derive(Deserialize)]
        struct Head {
            format_version: u32,
        }
        #[derive(Deserialize)]
        struct File {
            graph: VoronoiGraph,
        }
        // The decoder's own words name its Rust types ("expected struct Head", "wrong
        // msgpack marker FixStr(31)"): the message says what the file is not instead. A file
        // that starts as `to_msgpack` writes (a map of two keys, `format_version` first) but
        // does not decode was saved and then cut short or altered: the decoder reads the
        // whole map before it yields the version, so this is said before the version check.
        let saved_start: &[u8] = b"\x82\xaeformat_version";
        let head: Head = rmp_serde::from_slice(bytes).map_err(|_| {
            GraphError::Decode(if bytes.starts_with(saved_start) {
                "damaged: a graph saved by `homospline graph --out`, but cut short or altered \
                 (its MessagePack does not decode)"
                    .to_owned()
            } else {
                "not a graph saved by `homospline graph --out` (no MessagePack map with a \
                 format_version)"
                    .to_owned()
            })
        })?;
        if head.format_version != GRAPH_FORMAT_VERSION {
            return Err(GraphError::Version(head.format_version));
        }
        let f: File = rmp_serde::from_slice(bytes).map_err(|_| {
            GraphError::Decode(
                "damaged: its MessagePack does not decode as a graph (a field missing, of \
                 the wrong type, or cut short)"
                    .to_owned(),
            )
        })?;
        f.graph.validate()?;
        Ok(f.graph)
    }

    /// Checks a graph read from outside: a positive finite resolution, nodes numbered in
    /// order, edges between existing nodes with at least one edge, finite non-negative
    /// lengths and clearances, finite polyline points (at least two per edge), start and
    /// goal among the nodes, finite obstacle representatives. A graph that fails any of these
    /// sent the class search out of bounds or into an endless loop (negative lengths), or
    /// gave "no plan" where the file was at fault.
    pub fn validate(&self) -> Result<(), GraphError> {
        let bad = |what: String| Err(GraphError::Decode(what));
        if !(self.resolution.is_finite() && self.resolution > 0.0) {
            return bad(format!(
                "resolution {} is not a positive number",
                self.resolution
            ));
        }
        let n = self.nodes.len();
        if n >= MAX_EDGES || self.edges.len() >= MAX_EDGES {
            return bad(format!(
                "{n} nodes and {} edges: at most {} of each",
                self.edges.len(),
                MAX_EDGES - 1
            ));
        }
        for (i, node) in self.nodes.iter().enumerate() {
            if node.id != i {
                return bad(format!(
                    "node {i} has id {}: nodes must be numbered in order",
                    node.id
                ));
            }
            if !(node.at.iter().all(|v| v.is_finite())
                && node.clearance.is_finite()
                && node.clearance >= 0.0)
            {
                return bad(format!(
                    "node {i}: its position or clearance is not a finite number (clearance >= 0)"
                ));
            }
        }
        if self.edges.is_empty() {
            return bad("the graph has no edge".into());
        }
        for (k, e) in self.edges.iter().enumerate() {
            if e.from >= n || e.to >= n {
                return bad(format!(
                    "edge {k} joins nodes {} and {}, but the graph has {n} nodes",
                    e.from, e.to
                ));
            }
            for (what, v) in [
                ("length", e.length),
                ("min_clearance", e.min_clearance),
                ("mean_clearance", e.mean_clearance),
            ] {
                if !(v.is_finite() && v >= 0.0) {
                    return bad(format!("edge {k}: {what} {v} is not a finite number >= 0"));
                }
            }
            if e.polyline.len() < 2 || !e.polyline.iter().flatten().all(|v| v.is_finite()) {
                return bad(format!(
                    "edge {k}: its polyline needs at least two finite points"
                ));
            }
        }
        for (what, end) in [("start", self.start), ("goal", self.goal)] {
            if let Some(i) = end
                && i >= n
            {
                return bad(format!(
                    "the {what} is node {i}, but the graph has {n} nodes"
                ));
            }
        }
        if !self
            .obstacles
            .iter()
            .flat_map(|o| o.representative)
            .all(|v| v.is_finite())
        {
            return bad("an obstacle's representative point is not finite".into());
        }
        // A graph is built with its start and goal joined (or refused): one whose edges no
        // longer join them was changed since, and would plan "no class" without a reason.
        if let (Some(s), Some(g)) = (self.start, self.goal)
            && !self.connected(s, g)
        {
            return bad(format!(
                "its edges do not join the start (node {s}) and the goal (node {g}), as every \
                 graph homospline builds does: it was changed after it was saved"
            ));
        }
        Ok(())
    }
}

/// Independent cycles of a multigraph with `nodes` nodes and these edges: `E - V + C`.
pub(crate) fn cycle_rank(nodes: usize, edges: impl Iterator<Item = (usize, usize)>) -> usize {
    let mut parent: Vec<usize> = (0..nodes).collect();
    let (mut components, mut n_edges) = (nodes, 0);
    for (a, b) in edges {
        let (x, y) = (find_root(&mut parent, a), find_root(&mut parent, b));
        if x != y {
            parent[x] = y;
            components -= 1;
        }
        n_edges += 1;
    }
    n_edges + components - nodes
}
