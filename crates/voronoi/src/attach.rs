//! Start and goal on a prepared (complete) graph: each joins the ridge along a
//! maximum-clearance route, the graph is pruned of every dead end that leads to neither, and
//! the result is the graph a query searches. The prepared graph itself is not changed, so one
//! map serves many queries.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use homospline_geom::math::douglas_peucker;
use homospline_geom::{Point, Real};
use rustc_hash::FxHashMap;

use crate::field::DistanceField;
use crate::graph::{Edge, GraphError, Node, NodeKind, POLYLINE_TOLERANCE, VoronoiGraph};
use crate::grid::Grid;
use crate::skeleton::{skeleton_cells, trace};

/// How strongly the route from start or goal to the ridge avoids walls: a step of length `l`
/// into a cell of clearance `c` cells costs `l (1 + WALL_AVERSION / c)`.
pub const WALL_AVERSION: Real = 4.0;

/// Where a cell of the ridge lies on the graph.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Anchor {
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
    index: FxHashMap<usize, Anchor>,
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
        let mut index = FxHashMap::default();
        let step = 0.25 * grid.cell();
        for (ei, e) in graph.edges.iter().enumerate() {
            for (seg, s) in e.polyline.windows(2).enumerate() {
                let (a, b) = (Point::new(s[0][0], s[0][1]), Point::new(s[1][0], s[1][1]));
                let n = ((b - a).norm() / step).ceil().max(1.0) as usize;
                for k in 0..=n {
                    let t = k as Real / n as Real;
                    let at = a + (b - a) * t;
                    if let Some((i, j)) = grid.cell_of(&at)
                        && !grid.occupied(i, j)
                    {
                        index.entry(grid.index(i, j)).or_insert(Anchor::Edge {
                            edge: ei,
                            seg,
                            t,
                            at,
                        });
                    }
                }
            }
        }
        for n in &graph.nodes {
            if let Some((i, j)) = grid.cell_of(&Point::new(n.at[0], n.at[1])) {
                index.insert(grid.index(i, j), Anchor::Node(n.id));
            }
        }
        Self { graph, index }
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
        let rs = self.route(grid, field, start, "start")?;
        let rg = self.route(grid, field, goal, "goal")?;
        let mut g = self.graph.clone();
        let ns = split(&mut g, field, grid, rs.1);
        // The goal's anchor, moved onto the halves when it was on the start's edge.
        let ag = match (rs.1, rg.1) {
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
                        edge: g.edges.len() - 1,
                        seg: seg - ss,
                        t,
                        at,
                    }
                }
            }
            (_, a) => a,
        };
        let ng = split(&mut g, field, grid, ag);
        let s = endpoint(&mut g, grid, field, start, &rs.0, ns, NodeKind::Start);
        let t = endpoint(&mut g, grid, field, goal, &rg.0, ng, NodeKind::Goal);
        g.start = Some(s);
        g.goal = Some(t);
        g.prune_dead_ends(|_, _, _| true);
        if !g.connected(
            g.start.ok_or(GraphError::DifferentRegions)?,
            g.goal.ok_or(GraphError::DifferentRegions)?,
        ) {
            return Err(GraphError::DifferentRegions);
        }
        Ok(g)
    }

    /// The cheapest route (Dijkstra, 8-connected without corner cutting, steps weighted by
    /// [`WALL_AVERSION`]) from the cell of `p` to a cell of the ridge: its cells and where it
    /// reaches the graph.
    fn route(
        &self,
        grid: &Grid,
        field: &DistanceField,
        p: Point,
        what: &'static str,
    ) -> Result<(Vec<usize>, Anchor), GraphError> {
        let (i0, j0) = grid
            .cell_of(&p)
            .ok_or(GraphError::Outside(what, p.x, p.y))?;
        if grid.occupied(i0, j0) {
            return Err(GraphError::Occupied(what, p.x, p.y));
        }
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
            if let Some(&a) = self.index.get(&c) {
                let mut path = vec![c];
                let mut cur = c;
                while best[&cur].1 != cur {
                    cur = best[&cur].1;
                    path.push(cur);
                }
                path.reverse();
                return Ok((path, a));
            }
            let (ci, cj) = ((c % w) as i64, (c / w) as i64);
            for (di, dj) in [
                (1i64, 0i64),
                (0, 1),
                (-1, 0),
                (0, -1),
                (1, 1),
                (-1, 1),
                (-1, -1),
                (1, -1),
            ] {
                let (ni, nj) = (ci + di, cj + dj);
                if ni < 0 || nj < 0 || ni >= w as i64 || nj >= h as i64 {
                    continue;
                }
                let n = nj as usize * w + ni as usize;
                if occ[n] {
                    continue;
                }
                if di != 0
                    && dj != 0
                    && (occ[cj as usize * w + ni as usize] || occ[nj as usize * w + ci as usize])
                {
                    continue;
                }
                let len = if di != 0 && dj != 0 {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                };
                let c_n = field.clearance_cells(ni as usize, nj as usize).max(0.5);
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

/// Makes the anchor a node: splits its edge at the anchor's point (both halves keep the
/// edge's clearances, lower bounds of their own); the node's id.
fn split(g: &mut VoronoiGraph, field: &DistanceField, grid: &Grid, a: Anchor) -> usize {
    let Anchor::Edge { edge, seg, at, .. } = a else {
        let Anchor::Node(n) = a else { unreachable!() };
        return n;
    };
    let n = g.nodes.len();
    let clearance = grid
        .cell_of(&at)
        .map_or(0.0, |(i, j)| field.clearance_cells(i, j) * grid.cell());
    g.nodes.push(Node {
        id: n,
        at: [at.x, at.y],
        clearance,
        kind: NodeKind::Junction,
    });
    let old = g.edges[edge].clone();
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
    g.edges[edge] = Edge {
        to: n,
        length: len(&head),
        polyline: head,
        ..old.clone()
    };
    g.edges.push(Edge {
        from: n,
        length: len(&tail),
        polyline: tail,
        ..old
    });
    n
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
    let w = grid.width();
    let id = g.nodes.len();
    let cl = |c: usize| field.clearance_cells(c % w, c / w) * grid.cell();
    g.nodes.push(Node {
        id,
        at: [p.x, p.y],
        clearance: cl(cells[0]),
        kind,
    });
    // Cell centres, then the anchor's point (inside the last cell); the start or goal itself
    // is outside the simplification, so the first segment stays inside its cell.
    let mut pts: Vec<Point> = cells.iter().map(|&c| grid.center(c % w, c / w)).collect();
    let target = g.nodes[to].at;
    pts.push(Point::new(target[0], target[1]));
    let mut poly = vec![p];
    poly.extend(douglas_peucker(
        &pts,
        POLYLINE_TOLERANCE * grid.cell(),
        usize::MAX,
    ));
    poly.dedup();
    if poly.len() == 1 {
        poly.push(p);
    }
    let clears: Vec<Real> = cells.iter().map(|&c| cl(c)).collect();
    g.edges.push(Edge {
        from: id,
        to,
        length: poly.windows(2).map(|s| (s[1] - s[0]).norm()).sum(),
        min_clearance: clears.iter().copied().fold(Real::INFINITY, Real::min),
        mean_clearance: clears.iter().sum::<Real>() / clears.len() as Real,
        polyline: poly.iter().map(|q| [q.x, q.y]).collect(),
    });
    id
}

impl VoronoiGraph {
    /// Removes dead ends, leaf first, while `removable(graph, edge, leaf node)` says so. Start
    /// and goal are never removed, nor the last edge of a component (both of its ends
    /// leaves), so every piece of the graph keeps at least one edge. Drops the nodes this
    /// leaves without edges (nodes that had none to begin with stay).
    pub fn prune_dead_ends(&mut self, removable: impl Fn(&VoronoiGraph, usize, usize) -> bool) {
        let n = self.nodes.len();
        let mut degree = vec![0usize; n];
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, e) in self.edges.iter().enumerate() {
            degree[e.from] += 1;
            degree[e.to] += 1;
            incident[e.from].push(k);
            if e.to != e.from {
                incident[e.to].push(k);
            }
        }
        let had_edges: Vec<bool> = degree.iter().map(|&d| d > 0).collect();
        let protected = |k: usize, g: &VoronoiGraph| {
            matches!(g.nodes[k].kind, NodeKind::Start | NodeKind::Goal)
        };
        let mut alive = vec![true; self.edges.len()];
        let mut queue: Vec<usize> = (0..n)
            .filter(|&k| degree[k] == 1 && !protected(k, self))
            .rev()
            .collect();
        while let Some(leaf) = queue.pop() {
            if degree[leaf] != 1 {
                continue;
            }
            let Some(&e) = incident[leaf].iter().find(|&&e| alive[e]) else {
                continue;
            };
            let edge = &self.edges[e];
            let other = if edge.from == leaf {
                edge.to
            } else {
                edge.from
            };
            if degree[other] == 1 || !removable(self, e, leaf) {
                continue;
            }
            alive[e] = false;
            degree[leaf] = 0;
            degree[other] -= 1;
            if degree[other] == 1 && !protected(other, self) {
                queue.push(other);
            }
        }
        let keep_node: Vec<bool> = (0..n).map(|k| degree[k] > 0 || !had_edges[k]).collect();
        let mut k = 0;
        self.edges.retain(|_| {
            k += 1;
            alive[k - 1]
        });
        self.keep_nodes(keep_node);
    }
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
