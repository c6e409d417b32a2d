//! One query on a prepared map's complete graph, without copying it: [`QueryGraph`].
//!
//! The graph a query searches is the complete graph's 2-core (prepared once), the ways from
//! start and goal to it, the edges their anchors split and their connectors. A query holds
//! only what it adds: a few nodes and edges, the links of the nodes they touch, and the set
//! of dead-end edges that lead to start or goal. It is the graph
//! [`MapGraph::with_endpoints`] builds, numbered as before its pruning renumbers it (the
//! complete graph's nodes and edges keep their ids; what the query adds comes after), so a
//! search walks both in the same order.

use homospline_geom::{Point, Real};
use rustc_hash::FxHashSet;

use crate::attach::{Anchor, MapGraph, endpoint_parts, goal_anchor, halves, split_node};
use crate::field::DistanceField;
use crate::graph::{Edge, GraphError, Node, NodeKind, VoronoiGraph};
use crate::grid::Grid;

/// A prepared map's complete graph with start and goal joined, for one query
/// ([`MapGraph::query`]). Nodes and edges are numbered as in the complete graph, then what
/// the query adds; [`QueryGraph::links`] lists only the query's edges (the 2-core and the ways
/// to start and goal), so dead ends that lead to neither are never walked.
///
/// # Examples
///
/// ```
/// use homospline_geom::Point;
/// use homospline_voronoi::{DistanceField, Grid, MapGraph};
///
/// // An 8 x 8 room with a pillar in the middle.
/// let occupied: Vec<bool> = (0..64).map(|k| matches!((k % 8, k / 8), (3..=4, 3..=4))).collect();
/// let grid = Grid::from_occupancy(8, 8, Point::origin(), 1.0, occupied)?;
/// let field = DistanceField::build(&grid);
/// let map = MapGraph::build(&grid, &field);
/// let q = map.query(&grid, &field, Point::new(1.5, 1.5), Point::new(6.5, 6.5))?;
/// // Two ways round the pillar: start and goal each join the ring.
/// assert_eq!(q.links(q.start()).count(), 1);
/// assert_eq!(q.node(q.goal()).at, [6.5, 6.5]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # See also
/// [`MapGraph::with_endpoints`], the same graph as a [`VoronoiGraph`] of its own (a copy).
pub struct QueryGraph<'a> {
    map: &'a MapGraph,
    /// Nodes the query adds (ids from the complete graph's count on).
    nodes: Vec<Node>,
    /// Edges the query adds (ids from the complete graph's count on).
    edges: Vec<Edge>,
    /// Complete-graph edges the query replaced (by the head of their split).
    replaced: Vec<(usize, Edge)>,
    /// The complete graph's nodes that an added or replaced edge touches: their links are
    /// worked out afresh.
    touched: Vec<usize>,
    /// Edges of the query that are not on the 2-core as prepared: the ways from start and
    /// goal to the core, and the halves of a core edge split by an anchor.
    kept: FxHashSet<usize>,
    /// The halves of core edges split by an anchor (on the core).
    core_halves: Vec<usize>,
    start: usize,
    goal: usize,
    /// The length of the grid's diagonal, map units.
    diagonal: Real,
}

impl MapGraph {
    /// The graph of one query: start and goal joined to the complete graph along
    /// maximum-clearance routes (splitting the edge they reach), and only the edges that lead
    /// to them walked: [`MapGraph::with_endpoints`] without copying the complete graph (the
    /// query's work is the routes, the splits and the ways from start and goal to the core).
    /// Errors as [`MapGraph::with_endpoints`].
    pub fn query<'a>(
        &'a self,
        grid: &Grid,
        field: &DistanceField,
        start: Point,
        goal: Point,
    ) -> Result<QueryGraph<'a>, GraphError> {
        let (rs, rg) = self.routes(grid, field, start, goal)?;
        let mut q = QueryGraph {
            map: self,
            nodes: Vec::new(),
            edges: Vec::new(),
            replaced: Vec::new(),
            touched: Vec::new(),
            kept: FxHashSet::default(),
            core_halves: Vec::new(),
            start: usize::MAX,
            goal: usize::MAX,
            diagonal: grid.cell() * ((grid.width().pow(2) + grid.height().pow(2)) as Real).sqrt(),
        };
        let ns = q.split(grid, field, rs.1);
        let ag = goal_anchor(rs.1, rg.1, ns, q.edge_count() - 1);
        let ng = q.split(grid, field, ag);
        q.start = q.endpoint(grid, field, start, &rs.0, ns, NodeKind::Start);
        q.goal = q.endpoint(grid, field, goal, &rg.0, ng, NodeKind::Goal);
        let (s, t) = (q.start, q.goal);
        q.keep_way(s, t);
        q.keep_way(t, s);
        Ok(q)
    }
}

impl QueryGraph<'_> {
    /// Cells per map unit.
    pub fn resolution(&self) -> Real {
        self.map.graph.resolution
    }

    /// How many nodes: the complete graph's and the query's.
    pub fn node_count(&self) -> usize {
        self.map.graph.nodes.len() + self.nodes.len()
    }

    /// How many edges: the complete graph's and the query's.
    pub fn edge_count(&self) -> usize {
        self.map.graph.edges.len() + self.edges.len()
    }

    /// Node `k`.
    pub fn node(&self, k: usize) -> &Node {
        let base = self.map.graph.nodes.len();
        if k < base {
            &self.map.graph.nodes[k]
        } else {
            &self.nodes[k - base]
        }
    }

    /// Edge `e` (as the query has it: an edge split by start or goal is its head).
    pub fn edge(&self, e: usize) -> &Edge {
        let base = self.map.graph.edges.len();
        if e >= base {
            return &self.edges[e - base];
        }
        match self.replaced.iter().find(|r| r.0 == e) {
            Some((_, head)) => head,
            None => &self.map.graph.edges[e],
        }
    }

    /// The straight distance from start to goal as a share of the map's diagonal: how much
    /// of the map a search between them can be expected to cover.
    pub fn reach(&self) -> Real {
        let (a, b) = (self.node(self.start).at, self.node(self.goal).at);
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
            / self.diagonal.max(Real::MIN_POSITIVE)
    }

    /// The start's node.
    pub fn start(&self) -> usize {
        self.start
    }

    /// The goal's node.
    pub fn goal(&self) -> usize {
        self.goal
    }

    /// Whether edge `e` is one of the query's: on the 2-core or on a way to start or goal.
    pub fn in_query(&self, e: usize) -> bool {
        self.prepared_core(e) || self.kept.contains(&e)
    }

    /// Whether edge `e` is a complete-graph edge on the 2-core as prepared, and the query
    /// has not split it.
    fn prepared_core(&self, e: usize) -> bool {
        e < self.map.graph.edges.len()
            && self.map.core[e]
            && !self.replaced.iter().any(|r| r.0 == e)
    }

    /// Node `k`'s links among the query's edges, `(other end, edge, walked from -> to)`, in
    /// edge order (a loop once).
    pub fn links(&self, k: usize) -> impl Iterator<Item = (usize, usize, bool)> + '_ {
        self.links_of(k).filter(|l| self.in_query(l.1))
    }

    /// Node `k`'s links among all edges, the complete graph's dead ends that are not the
    /// query's too (a caller that knows which edges are the query's, [`QueryGraph::in_query`],
    /// filters them itself), each handed to `f`: no iterator to step through, as the
    /// search's Dijkstra calls this for every node of the map.
    #[inline]
    pub fn for_each_link(&self, k: usize, mut f: impl FnMut(usize, usize, bool)) {
        match self.links_of(k) {
            Links::Base(links) => links.for_each(|(m, e, fwd)| f(m, e, fwd)),
            Links::Listed(links) => links.for_each(|(m, e, fwd)| f(m, e, fwd)),
        }
    }

    /// Node `k`'s links among all edges ([`QueryGraph::for_each_link`]).
    fn links_of(&self, k: usize) -> Links<'_> {
        let base_nodes = self.map.graph.nodes.len();
        if k < base_nodes && !self.touched.contains(&k) {
            return Links::Base(self.map.adjacency.of(k));
        }
        let mut links: Vec<(usize, usize, bool)> = Vec::new();
        if k < base_nodes {
            for (m, e, fwd) in self.map.adjacency.of(k) {
                match self.replaced.iter().find(|r| r.0 == e) {
                    Some((_, head)) => links.extend(link_of(head, e, k)),
                    None => links.push((m, e, fwd)),
                }
            }
        } else {
            // A node the query added: its links are on the edges it added or replaced.
            let mut heads: Vec<&(usize, Edge)> = self.replaced.iter().collect();
            heads.sort_by_key(|r| r.0);
            for (e, head) in heads {
                links.extend(link_of(head, *e, k));
            }
        }
        let base_edges = self.map.graph.edges.len();
        for (i, edge) in self.edges.iter().enumerate() {
            links.extend(link_of(edge, base_edges + i, k));
        }
        Links::Listed(links.into_iter())
    }

    /// Makes the anchor a node, splitting its edge; the node's id.
    fn split(&mut self, grid: &Grid, field: &DistanceField, a: Anchor) -> usize {
        let Anchor::Edge { edge, seg, at, .. } = a else {
            let Anchor::Node(n) = a else { unreachable!() };
            return n;
        };
        let n = self.node_count();
        self.nodes.push(split_node(grid, field, at, n));
        let old = self.edge(edge).clone();
        let (head, tail) = halves(&old, seg, at, n);
        // The halves of a core edge are on the core.
        let on_core = self.in_query(edge);
        self.touch(&old);
        let base = self.map.graph.edges.len();
        if edge >= base {
            self.edges[edge - base] = head;
        } else if let Some(r) = self.replaced.iter_mut().find(|r| r.0 == edge) {
            r.1 = head;
        } else {
            self.replaced.push((edge, head));
        }
        self.edges.push(tail);
        if on_core {
            for e in [edge, self.edge_count() - 1] {
                self.kept.insert(e);
                self.core_halves.push(e);
            }
        }
        n
    }

    /// Adds the start or goal node and its connector along `cells` to node `to`; its id.
    fn endpoint(
        &mut self,
        grid: &Grid,
        field: &DistanceField,
        p: Point,
        cells: &[usize],
        to: usize,
        kind: NodeKind,
    ) -> usize {
        let id = self.node_count();
        let at = self.node(to).at;
        let (node, edge) = endpoint_parts(grid, field, p, cells, (to, at), id, kind);
        self.nodes.push(node);
        self.touch(&edge);
        self.edges.push(edge);
        id
    }

    /// Marks the complete graph's nodes at `e`'s ends as touched.
    fn touch(&mut self, e: &Edge) {
        let base = self.map.graph.nodes.len();
        for k in [e.from, e.to] {
            if k < base && !self.touched.contains(&k) {
                self.touched.push(k);
            }
        }
    }

    /// Whether edge `e` is on the 2-core as prepared (or half of such an edge).
    fn on_core_edge(&self, e: usize) -> bool {
        self.prepared_core(e) || self.core_halves.contains(&e)
    }

    /// Keeps the way from `from` to the 2-core or, in a tree (no core), to `other`: breadth
    /// first over the edges off the core, then the path found marked kept. Both endpoints'
    /// ways together are what pruning the dead ends leaves: in a tree hanging off the core,
    /// the union of two paths to the node where it hangs is the least subtree that joins
    /// both to the core.
    fn keep_way(&mut self, from: usize, other: usize) {
        let mut parent: rustc_hash::FxHashMap<usize, (usize, usize)> = Default::default();
        parent.insert(from, (usize::MAX, usize::MAX));
        let mut queue = std::collections::VecDeque::from([from]);
        let mut core = None;
        while let Some(k) = queue.pop_front() {
            if self.links_of(k).any(|l| self.on_core_edge(l.1)) {
                core = Some(k);
                break;
            }
            for (m, e, _) in self.links_of(k) {
                if self.on_core_edge(e) || parent.contains_key(&m) {
                    continue;
                }
                parent.insert(m, (k, e));
                queue.push_back(m);
            }
        }
        let mut k = core.unwrap_or(other);
        while let Some(&(p, e)) = parent.get(&k) {
            if p == usize::MAX {
                break;
            }
            self.kept.insert(e);
            k = p;
        }
    }

    /// The query's graph as a [`VoronoiGraph`] of its own: the query's edges and the nodes
    /// they use, renumbered in order (for a picture or a saved file; a copy).
    pub fn to_graph(&self) -> VoronoiGraph {
        let n = self.node_count();
        let mut map = vec![usize::MAX; n];
        let edges: Vec<usize> = (0..self.edge_count())
            .filter(|&e| self.in_query(e))
            .collect();
        for &e in &edges {
            let edge = self.edge(e);
            map[edge.from] = 0;
            map[edge.to] = 0;
        }
        map[self.start] = 0;
        map[self.goal] = 0;
        let mut nodes = Vec::new();
        for (k, slot) in map.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = nodes.len();
                nodes.push(Node {
                    id: nodes.len(),
                    ..self.node(k).clone()
                });
            }
        }
        VoronoiGraph {
            resolution: self.resolution(),
            nodes,
            edges: edges
                .iter()
                .map(|&e| {
                    let edge = self.edge(e);
                    Edge {
                        from: map[edge.from],
                        to: map[edge.to],
                        ..edge.clone()
                    }
                })
                .collect(),
            start: Some(map[self.start]),
            goal: Some(map[self.goal]),
            obstacles: self.map.graph.obstacles.clone(),
            built_for: None,
        }
    }
}

/// The link at node `k` of edge `edge` (id `e`), if it ends there.
fn link_of(edge: &Edge, e: usize, k: usize) -> Option<(usize, usize, bool)> {
    if edge.from == k {
        Some((edge.to, e, true))
    } else if edge.to == k {
        Some((edge.from, e, false))
    } else {
        None
    }
}

/// A node's links: straight from the prepared adjacency, or worked out for a touched node.
enum Links<'a> {
    Base(crate::graph::AdjacencyLinks<'a>),
    Listed(std::vec::IntoIter<(usize, usize, bool)>),
}

impl Iterator for Links<'_> {
    type Item = (usize, usize, bool);
    fn next(&mut self) -> Option<Self::Item> {
        match self {
            Links::Base(i) => i.next(),
            Links::Listed(i) => i.next(),
        }
    }
}
