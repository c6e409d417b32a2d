//! Start and goal joined to a graph, both ways.
//!
//! - On a prepared (complete) graph, [`MapGraph`]: each joins the ridge along a
//!   maximum-clearance route, the graph is pruned of every dead end that leads to neither, and
//!   the result is the graph a query searches. The prepared graph itself is not changed, so
//!   one map serves many queries.
//! - On the crack graph of a scene ([`VoronoiGraph::build`]): each joins the nearest crack
//!   along the breadth-first free-cell path, splitting the chain it reaches; when start and
//!   goal share a free region without any crack, the path between them is the graph.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use homospline_geom::{Point, Real};
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::sync::atomic::{AtomicU32, Ordering};

use crate::crack::CrackGraph;
use crate::field::DistanceField;
use crate::graph::{Adjacency, Edge, GraphError, Node, NodeKind, VoronoiGraph};
use crate::grid::Grid;
use crate::simplify::{edge_along, simplify};
use crate::skeleton::{skeleton_cells, trace};
use crate::trace::{Chain, NO_NODE};

/// How strongly the route from start or goal to the ridge avoids walls: a step of length `l`
/// into a cell of clearance `c` cells costs `l (1 + WALL_AVERSION / c)`.
pub const WALL_AVERSION: Real = 4.0;

/// Where a cell of the ridge lies on the graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Anchor {
    /// At a node.
    Node(usize),
    /// On segment `seg` of an edge's polyline, at parameter `t`, point `at` (inside the cell).
    Edge {
        edge: usize,
        seg: usize,
        t: Real,
        at: Point,
    },
}

/// A prepared complete graph: the graph of the whole map (no start or goal) and, for every
/// grid cell its polylines pass through, where on the graph that is.
#[derive(Clone, Debug)]
pub struct MapGraph {
    /// The complete graph, without start or goal.
    pub graph: VoronoiGraph,
    /// The links of every node of the complete graph: a query ([`MapGraph::query`]) walks
    /// them without building its own.
    pub(crate) adjacency: Adjacency,
    /// Per edge: on the graph's 2-core, what is left when every dead end is peeled off,
    /// leaf first, to the last edge. A query's graph is the core and the ways from start
    /// and goal to it ([`crate::query`]).
    pub(crate) core: Vec<bool>,
    /// Per grid cell: [`NOT_ON_GRAPH`], a node (`ON_NODE | id`) or the first edge whose
    /// polyline, sampled every quarter cell, lands in the cell (its anchor is that edge's
    /// first sample there, found again when asked: [`MapGraph::anchor_at`]). Four bytes a
    /// cell, where a hash map of anchors took about sixty per indexed cell.
    pub(crate) index: Vec<u32>,
    /// Per node, a representative of its connected component: a query whose start and
    /// goal reach different components is refused before the graph is copied (the check
    /// ran over the whole query graph).
    pub(crate) component: Vec<u32>,
}

/// In [`MapGraph`]'s index: no polyline passes through the cell.
const NOT_ON_GRAPH: u32 = u32::MAX;

/// In [`MapGraph`]'s index: the bit that marks a node's id.
const ON_NODE: u32 = 1 << 31;

/// The samples of edge `e`'s polyline every quarter cell (at most), each end of every
/// segment included, that land in a free cell: `(segment, t, point, cell index)` in order.
fn samples<'a>(
    grid: &'a Grid,
    e: &'a Edge,
) -> impl Iterator<Item = (usize, Real, Point, usize)> + 'a {
    let step = 0.25 * grid.cell();
    e.polyline.windows(2).enumerate().flat_map(move |(seg, s)| {
        let (a, b) = (Point::new(s[0][0], s[0][1]), Point::new(s[1][0], s[1][1]));
        let n = ((b - a).norm() / step).ceil().max(1.0) as usize;
        (0..=n).filter_map(move |k| {
            let t = k as Real / n as Real;
            let at = a + (b - a) * t;
            match grid.cell_of(&at) {
                Some((i, j)) if !grid.occupied(i, j) => Some((seg, t, at, grid.index(i, j))),
                _ => None,
            }
        })
    })
}

/// The complete generalized Voronoi graph of `grid` (see [`crate::skeleton`]), without start
/// or goal; short spurs (no longer than the clearance where they branch off plus two cells:
/// the wiggles of a rough wall) are pruned.
pub fn complete_graph(grid: &Grid, field: &DistanceField) -> VoronoiGraph {
    let keep = skeleton_cells(grid, field);
    let mut g = trace(grid, field, &keep);
    let cell = grid.cell();
    g.prune_dead_ends(|g, e, leaf| {
        let edge = &g.edges[e];
        let junction = if edge.from == leaf {
            edge.to
        } else {
            edge.from
        };
        edge.length <= g.nodes[junction].clearance + 2.0 * cell
    });
    g
}

impl MapGraph {
    /// Builds the complete graph of `grid` and its index.
    pub fn build(grid: &Grid, field: &DistanceField) -> Self {
        Self::from_graph(grid, complete_graph(grid, field))
    }

    /// Indexes a complete graph built before (for example read back from MessagePack).
    pub fn from_graph(grid: &Grid, graph: VoronoiGraph) -> Self {
        // The first edge to reach a cell keeps it: the least index of those that reach it,
        // whatever the order the threads sample them in.
        let first: Vec<AtomicU32> = (0..grid.width() * grid.height())
            .map(|_| AtomicU32::new(NOT_ON_GRAPH))
            .collect();
        graph.edges.par_iter().enumerate().for_each(|(ei, e)| {
            for (_, _, _, c) in samples(grid, e) {
                first[c].fetch_min(ei as u32, Ordering::Relaxed);
            }
        });
        let mut index: Vec<u32> = first.into_iter().map(AtomicU32::into_inner).collect();
        for n in &graph.nodes {
            if let Some((i, j)) = grid.cell_of(&Point::new(n.at[0], n.at[1])) {
                index[grid.index(i, j)] = ON_NODE | n.id as u32;
            }
        }
        let mut parent: Vec<usize> = (0..graph.nodes.len()).collect();
        for e in &graph.edges {
            let (x, y) = (
                crate::union_find::find_root(&mut parent, e.from),
                crate::union_find::find_root(&mut parent, e.to),
            );
            parent[x] = y;
        }
        let component = (0..graph.nodes.len())
            .map(|k| crate::union_find::find_root(&mut parent, k) as u32)
            .collect();
        let adjacency = graph.adjacency(|_| true);
        let core = two_core(&graph, &adjacency);
        Self {
            graph,
            adjacency,
            core,
            index,
            component,
        }
    }

    /// Where cell `c` lies on the graph, if a polyline passes through it.
    pub(crate) fn anchor_at(&self, grid: &Grid, c: usize) -> Option<Anchor> {
        match self.index[c] {
            NOT_ON_GRAPH => None,
            a if a & ON_NODE != 0 => Some(Anchor::Node((a & !ON_NODE) as usize)),
            ei => samples(grid, &self.graph.edges[ei as usize])
                .find(|s| s.3 == c)
                .map(|(seg, t, at, _)| Anchor::Edge {
                    edge: ei as usize,
                    seg,
                    t,
                    at,
                }),
        }
    }

    /// The graph for one query: start and goal joined to the ridge along maximum-clearance
    /// routes (splitting the edge they reach), then every dead end that leads to neither
    /// pruned. Errors when a point is outside the grid or occupied, or when no free cells
    /// join start and goal.
    pub fn with_endpoints(
        &self,
        grid: &Grid,
        field: &DistanceField,
        start: Point,
        goal: Point,
    ) -> Result<VoronoiGraph, GraphError> {
        let (rs, rg) = self.routes(grid, field, start, goal)?;
        // Room for what the two splits and the two endpoints add (a node and an edge each):
        // a plain clone has none, and its first push would double both arrays, a map-sized
        // allocation held through the whole query.
        let mut g = self.graph.clone_with_room(4, 4);
        let ns = split(&mut g, field, grid, rs.1);
        let ag = goal_anchor(rs.1, rg.1, ns, g.edges.len() - 1);
        let ng = split(&mut g, field, grid, ag);
        let s = endpoint(&mut g, grid, field, start, &rs.0, ns, NodeKind::Start);
        let t = endpoint(&mut g, grid, field, goal, &rg.0, ng, NodeKind::Goal);
        g.start = Some(s);
        g.goal = Some(t);
        g.prune_dead_ends(|_, _, _| true);
        debug_assert!(
            matches!((g.start, g.goal), (Some(s), Some(t)) if g.connected(s, t)),
            "start and goal in one component"
        );
        Ok(g)
    }

    /// The routes from start and from goal to the graph ([`MapGraph::route`]); refused when
    /// they reach different components. Start and goal join the complete graph at their
    /// anchors, and pruning dead ends never parts them: they are connected exactly when the
    /// anchors are.
    #[allow(clippy::type_complexity)]
    pub(crate) fn routes(
        &self,
        grid: &Grid,
        field: &DistanceField,
        start: Point,
        goal: Point,
    ) -> Result<((Vec<usize>, Anchor), (Vec<usize>, Anchor)), GraphError> {
        let rs = self.route(grid, field, start, "start")?;
        let rg = self.route(grid, field, goal, "goal")?;
        let node_of = |a: &Anchor| match *a {
            Anchor::Node(n) => n,
            Anchor::Edge { edge, .. } => self.graph.edges[edge].from,
        };
        if self.component[node_of(&rs.1)] != self.component[node_of(&rg.1)] {
            return Err(GraphError::DifferentRegions);
        }
        Ok((rs, rg))
    }

    /// The cheapest route (Dijkstra, 8-connected without corner cutting, steps weighted by
    /// [`WALL_AVERSION`]) from the cell of `p` to a cell of the ridge: its cells and where it
    /// reaches the graph.
    pub(crate) fn route(
        &self,
        grid: &Grid,
        field: &DistanceField,
        p: Point,
        what: &'static str,
    ) -> Result<(Vec<usize>, Anchor), GraphError> {
        let (i0, j0) = free_cell(grid, p, what)?;
        let (w, h) = (grid.width(), grid.height());
        let occ = grid.occupancy();
        let start = grid.index(i0, j0);
        let mut best: FxHashMap<usize, (Real, usize)> = FxHashMap::default();
        let mut heap = BinaryHeap::new();
        best.insert(start, (0.0, start));
        heap.push(Reverse((0u64, start)));
        while let Some(Reverse((bits, c))) = heap.pop() {
            let d = Real::from_bits(bits);
            if best.get(&c).is_some_and(|&(b, _)| b < d) {
                continue;
            }
            if let Some(a) = self.anchor_at(grid, c) {
                let mut path = vec![c];
                let mut cur = c;
                while best[&cur].1 != cur {
                    cur = best[&cur].1;
                    path.push(cur);
                }
                path.reverse();
                return Ok((path, a));
            }
            let (ci, cj) = (c % w, c / w);
            for ((ni, nj), (di, dj)) in crate::grid::neighbours_8(ci, cj, w, h) {
                let n = nj * w + ni;
                if occ[n] {
                    continue;
                }
                if di != 0 && dj != 0 && (occ[cj * w + ni] || occ[nj * w + ci]) {
                    continue;
                }
                let len = if di != 0 && dj != 0 {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                };
                let c_n = field.clearance_cells(ni, nj).max(0.5);
                let nd = d + len * (1.0 + WALL_AVERSION / c_n);
                if best.get(&n).is_none_or(|&(b, _)| nd < b) {
                    best.insert(n, (nd, c));
                    heap.push(Reverse((nd.to_bits(), n)));
                }
            }
        }
        Err(GraphError::DifferentRegions)
    }
}

/// The goal's anchor `goal` after the start's anchor `start` became node `ns`: moved onto
/// the halves of the edge split there (its tail is edge `tail`) when it was on that edge.
pub(crate) fn goal_anchor(start: Anchor, goal: Anchor, ns: usize, tail: usize) -> Anchor {
    match (start, goal) {
        (
            Anchor::Edge {
                edge: es,
                seg: ss,
                t: ts,
                ..
            },
            Anchor::Edge { edge, seg, t, at },
        ) if edge == es => {
            if (seg, t) == (ss, ts) {
                Anchor::Node(ns)
            } else if (seg, t) < (ss, ts) {
                Anchor::Edge { edge, seg, t, at }
            } else {
                Anchor::Edge {
                    edge: tail,
                    seg: seg - ss,
                    t,
                    at,
                }
            }
        }
        (_, a) => a,
    }
}

/// Makes the anchor a node: splits its edge at the anchor's point (both halves keep the
/// edge's clearances, lower bounds of their own); the node's id.
fn split(g: &mut VoronoiGraph, field: &DistanceField, grid: &Grid, a: Anchor) -> usize {
    let Anchor::Edge { edge, seg, at, .. } = a else {
        let Anchor::Node(n) = a else { unreachable!() };
        return n;
    };
    let n = g.nodes.len();
    g.nodes.push(split_node(grid, field, at, n));
    let (head, tail) = halves(&g.edges[edge], seg, at, n);
    g.edges[edge] = head;
    g.edges.push(tail);
    n
}

/// The node `n` that splits an edge at `at`.
pub(crate) fn split_node(grid: &Grid, field: &DistanceField, at: Point, n: usize) -> Node {
    Node {
        id: n,
        at: [at.x, at.y],
        clearance: clearance_at(grid, field, &at),
        kind: NodeKind::Junction,
    }
}

/// Edge `old` split at `at` on its segment `seg` by node `n`: the head (from `old.from` to
/// `n`, which takes `old`'s place) and the tail (from `n` to `old.to`, added last). Both keep
/// `old`'s clearances, lower bounds of their own.
pub(crate) fn halves(old: &Edge, seg: usize, at: Point, n: usize) -> (Edge, Edge) {
    let q = [at.x, at.y];
    let mut head: Vec<[Real; 2]> = old.polyline[..=seg].to_vec();
    head.push(q);
    let mut tail = vec![q];
    tail.extend_from_slice(&old.polyline[seg + 1..]);
    let len = |p: &[[Real; 2]]| -> Real {
        p.windows(2)
            .map(|s| ((s[1][0] - s[0][0]).powi(2) + (s[1][1] - s[0][1]).powi(2)).sqrt())
            .sum()
    };
    (
        Edge {
            to: n,
            length: len(&head),
            polyline: head.into(),
            ..old.clone()
        },
        Edge {
            from: n,
            length: len(&tail),
            polyline: tail.into(),
            ..old.clone()
        },
    )
}

/// Adds the start or goal node and its connector along `cells` to node `to`; its id.
fn endpoint(
    g: &mut VoronoiGraph,
    grid: &Grid,
    field: &DistanceField,
    p: Point,
    cells: &[usize],
    to: usize,
    kind: NodeKind,
) -> usize {
    let id = g.nodes.len();
    let (node, edge) = endpoint_parts(grid, field, p, cells, (to, g.nodes[to].at), id, kind);
    g.nodes.push(node);
    g.edges.push(edge);
    id
}

/// The start or goal node `id` (of `kind`, at `p`) and its connector along `cells` to node
/// `to` (`(id, position)`).
pub(crate) fn endpoint_parts(
    grid: &Grid,
    field: &DistanceField,
    p: Point,
    cells: &[usize],
    to: (usize, [Real; 2]),
    id: usize,
    kind: NodeKind,
) -> (Node, Edge) {
    let w = grid.width();
    let cl = |c: usize| field.clearance_cells(c % w, c / w) * grid.cell();
    let node = Node {
        id,
        at: [p.x, p.y],
        clearance: cl(cells[0]),
        kind,
    };
    // Cell centres, then the anchor's point (inside the last cell); the start or goal itself
    // is outside the simplification, so the first segment stays inside its cell.
    let mut pts: Vec<Point> = cells.iter().map(|&c| grid.center(c % w, c / w)).collect();
    let target = to.1;
    pts.push(Point::new(target[0], target[1]));
    let mut poly = vec![p];
    poly.extend(simplify(&pts, grid.cell()));
    poly.dedup();
    if poly.len() == 1 {
        poly.push(p);
    }
    let clears: Vec<Real> = cells.iter().map(|&c| cl(c)).collect();
    (node, edge_along(id, to.0, &poly, &clears))
}

/// Per edge of `g`, whether it is on the 2-core: every dead end peeled off, leaf first, to
/// the last edge (a tree leaves nothing).
fn two_core(g: &VoronoiGraph, adjacency: &Adjacency) -> Vec<bool> {
    let mut degree = vec![0u32; g.nodes.len()];
    for e in &g.edges {
        degree[e.from] += 1;
        degree[e.to] += 1;
    }
    let mut alive = vec![true; g.edges.len()];
    let mut queue: Vec<usize> = (0..g.nodes.len()).filter(|&k| degree[k] == 1).collect();
    while let Some(leaf) = queue.pop() {
        if degree[leaf] != 1 {
            continue;
        }
        let Some((other, e, _)) = adjacency.of(leaf).find(|l| alive[l.1]) else {
            continue;
        };
        alive[e] = false;
        degree[leaf] = 0;
        degree[other] -= 1;
        if degree[other] == 1 {
            queue.push(other);
        }
    }
    alive
}

/// The complete graph with start and goal attached, built from scratch (for one query; use
/// [`MapGraph`] to serve many).
pub fn build_complete(
    grid: &Grid,
    field: &DistanceField,
    start: Point,
    goal: Point,
) -> Result<VoronoiGraph, GraphError> {
    MapGraph::build(grid, field).with_endpoints(grid, field, start, goal)
}

/// The cell holding `p`, which must be free; or, where `p` lies on a side or corner of its
/// cell (within a billionth of a cell), a free neighbour whose closed square holds it. A
/// point on a scene's bounds lies on the side of the grid's wall ring wherever the
/// resolution divides the bounds evenly: it was refused at some resolutions and not others.
pub(crate) fn free_cell(
    grid: &Grid,
    p: Point,
    what: &'static str,
) -> Result<(usize, usize), GraphError> {
    let (i, j) = grid
        .cell_of(&p)
        .ok_or(GraphError::Outside(what, p.x, p.y))?;
    if !grid.occupied(i, j) {
        return Ok((i, j));
    }
    let fx = (p.x - grid.origin().x) / grid.cell();
    let fy = (p.y - grid.origin().y) / grid.cell();
    let (is, js) = (
        crate::grid::cells_holding(fx, grid.width()),
        crate::grid::cells_holding(fy, grid.height()),
    );
    js.iter()
        .flatten()
        .flat_map(|&j| is.iter().flatten().map(move |&i| (i, j)))
        .find(|&(i, j)| !grid.occupied(i, j))
        .ok_or(GraphError::Occupied(what, p.x, p.y))
}

/// The clearance of the cell holding `p` in map units (0 outside the grid).
pub(crate) fn clearance_at(grid: &Grid, field: &DistanceField, p: &Point) -> Real {
    grid.cell_of(p)
        .map_or(0.0, |(i, j)| field.clearance_cells(i, j) * grid.cell())
}

/// Joins `p` to the crack graph `cg` of `g`: along the breadth-first free-cell path to the
/// nearest cell that borders a crack, to the crack corner it reaches (a node, or a new one
/// splitting the chain through it). Adds the node of `p` (of `kind`) and its connector to
/// `g`; the node's id.
pub(crate) fn attach_to_cracks(
    cg: &mut CrackGraph<'_>,
    g: &mut VoronoiGraph,
    p: Point,
    what: &'static str,
    kind: NodeKind,
) -> Result<usize, GraphError> {
    let start = free_cell(cg.grid, p, what)?;
    let (path, corner) = free_bfs(cg.grid, start, |ci, cj| cg.cracks.corner_of_cell(ci, cj))
        .ok_or(GraphError::DifferentRegions)?;
    let at_node = match cg.net.node_of[corner] {
        NO_NODE => split_chain(cg, g, corner)?,
        n => n as usize,
    };
    let id = g.nodes.len();
    g.nodes.push(Node {
        id,
        at: [p.x, p.y],
        clearance: clearance_at(cg.grid, cg.field, &p),
        kind,
    });
    g.edges.push(connector(
        cg,
        id,
        at_node,
        None,
        &path,
        cg.corner_point(corner),
    ));
    Ok(id)
}

/// Makes `corner` a node of `g` by splitting the (first) chain through it: the head keeps the
/// chain's place, the tail goes last. The node's id.
fn split_chain(
    cg: &mut CrackGraph<'_>,
    g: &mut VoronoiGraph,
    corner: usize,
) -> Result<usize, GraphError> {
    let (ci, k) = cg
        .net
        .chains
        .iter()
        .enumerate()
        .find_map(|(ci, ch)| ch.sites.iter().position(|&x| x == corner).map(|k| (ci, k)))
        .ok_or(GraphError::DifferentRegions)?;
    let n = g.nodes.len();
    let q = cg.corner_point(corner);
    g.nodes.push(Node {
        id: n,
        at: [q.x, q.y],
        clearance: cg.corner_clearance(corner),
        kind: NodeKind::Junction,
    });
    cg.net.node_of[corner] = n as u32;
    let chains = &mut cg.net.chains;
    let old = chains.swap_remove(ci);
    let tail = Chain {
        from: n,
        to: old.to,
        sites: old.sites[k..].to_vec(),
        steps: old.steps[k..].to_vec(),
    };
    let head = Chain {
        from: old.from,
        to: n,
        sites: old.sites[..=k].to_vec(),
        steps: old.steps[..k].to_vec(),
    };
    chains.insert(ci.min(chains.len()), head);
    chains.push(tail);
    Ok(n)
}

/// When start and goal share a free region without any crack (no obstacle inside it, so
/// one class), adds both to `g` and returns the edge along the free-cell path between them:
/// their graph. `None` (and `g` unchanged) when the region has a crack.
pub(crate) fn join_directly(
    cg: &CrackGraph<'_>,
    g: &mut VoronoiGraph,
    s: Point,
    t: Point,
) -> Result<Option<Edge>, GraphError> {
    let Some(path) = direct_path(cg, s, t)? else {
        return Ok(None);
    };
    let (ns, nt) = (g.nodes.len(), g.nodes.len() + 1);
    g.nodes.push(Node {
        id: ns,
        at: [s.x, s.y],
        clearance: clearance_at(cg.grid, cg.field, &s),
        kind: NodeKind::Start,
    });
    g.nodes.push(Node {
        id: nt,
        at: [t.x, t.y],
        clearance: clearance_at(cg.grid, cg.field, &t),
        kind: NodeKind::Goal,
    });
    g.start = Some(ns);
    g.goal = Some(nt);
    // From the start through the path's cell centres to the goal. (It used to go on to crack
    // corner 0, the grid's lower-left corner, which took part in the simplification and the
    // length: the edge's length took in the way to that corner, and the simplified polyline
    // could overshoot the goal.)
    Ok(Some(connector(cg, ns, nt, Some(s), &path, t)))
}

/// Breadth-first over free cells (4-connected, fixed neighbour order: deterministic) from
/// `start` to the first cell where `stop` answers; that cell's path from `start` and the
/// answer. `None` when the free region is exhausted first.
pub(crate) fn free_bfs<T>(
    grid: &Grid,
    start: (usize, usize),
    mut stop: impl FnMut(usize, usize) -> Option<T>,
) -> Option<(Vec<(usize, usize)>, T)> {
    let (w, h) = (grid.width(), grid.height());
    // Parents by raster index (a dense array: the search may sweep most of the grid, where a
    // hash map spent more time growing than searching).
    const UNSEEN: u32 = u32::MAX;
    let mut parent = vec![UNSEEN; w * h];
    let at = |(i, j): (usize, usize)| j * w + i;
    let cell = |k: usize| (k % w, k / w);
    let mut queue = std::collections::VecDeque::new();
    parent[at(start)] = at(start) as u32;
    queue.push_back(start);
    while let Some((ci, cj)) = queue.pop_front() {
        if let Some(answer) = stop(ci, cj) {
            let mut path = vec![(ci, cj)];
            let mut cur = at((ci, cj));
            while parent[cur] as usize != cur {
                cur = parent[cur] as usize;
                path.push(cell(cur));
            }
            path.reverse();
            return Some((path, answer));
        }
        for (di, dj) in [(1i64, 0i64), (0, 1), (-1, 0), (0, -1)] {
            let (ni, nj) = (ci as i64 + di, cj as i64 + dj);
            if ni < 0 || nj < 0 || ni as usize >= w || nj as usize >= h {
                continue;
            }
            let n = (ni as usize, nj as usize);
            if !grid.occupied(n.0, n.1) && parent[at(n)] == UNSEEN {
                parent[at(n)] = at((ci, cj)) as u32;
                queue.push_back(n);
            }
        }
    }
    None
}

/// When start and goal share a free region without any crack (no obstacle inside it), the
/// free-cell path from start to goal; `None` when the region has a crack.
fn direct_path(
    cg: &CrackGraph<'_>,
    s: Point,
    t: Point,
) -> Result<Option<Vec<(usize, usize)>>, GraphError> {
    let start = free_cell(cg.grid, s, "start")?;
    let goal = free_cell(cg.grid, t, "goal")?;
    let found = free_bfs(cg.grid, start, |ci, cj| {
        if cg.cracks.corner_of_cell(ci, cj).is_some() {
            Some(false)
        } else {
            ((ci, cj) == goal).then_some(true)
        }
    });
    match found {
        Some((path, true)) => Ok(Some(path)),
        Some((_, false)) => Ok(None),
        // The region holds no crack and not the goal: they are apart.
        None => Err(GraphError::DifferentRegions),
    }
}

/// The edge from node `from` (at `first`, when given, before the path) along the free cells
/// of `path` (their centres) to `last`, node `to`, with the cells' clearances.
fn connector(
    cg: &CrackGraph<'_>,
    from: usize,
    to: usize,
    first: Option<Point>,
    path: &[(usize, usize)],
    last: Point,
) -> Edge {
    let grid = cg.grid;
    let mut pts: Vec<Point> = Vec::with_capacity(path.len() + 2);
    pts.extend(first);
    pts.extend(path.iter().map(|&(i, j)| grid.center(i, j)));
    pts.push(last);
    let cl: Vec<Real> = path
        .iter()
        .map(|&(i, j)| cg.field.clearance_cells(i, j) * grid.cell())
        .collect();
    edge_along(from, to, &simplify(&pts, grid.cell()), &cl)
}
