//! The generalized Voronoi graph: where the brushfire fronts of two obstacles meet.
//!
//! Every cell belongs to the region of its nearest obstacle ([`DistanceField::nearest`]).
//! The generalized Voronoi diagram is the set of *cracks*, the cell sides between cells of
//! different regions: a one-cell-wide, 4-connected curve network on the lattice of cell
//! corners, with no thinning needed and no breaks, since it is the boundary of a partition of
//! the plane. Corners where three or more cracks meet are junctions. For a connected free
//! space with `k` obstacles inside the wall, the regions are `k` bounded faces and the outer
//! one, so the network has exactly `k` independent cycles.
//!
//! The topological layer: nodes (junctions, plus one anchor on each crack loop that meets no
//! junction) and edges (the crack chains between them, with length, minimum and mean
//! clearance, and a polyline simplified to within [`POLYLINE_TOLERANCE`] cell of the chain).

use homospline_geom::math::douglas_peucker;
use homospline_geom::{Point, Real};
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::field::DistanceField;
use crate::find_root;
use crate::grid::Grid;

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
    /// From `from` to `to`, map coordinates.
    pub polyline: Vec<[Real; 2]>,
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
    /// A serialised graph could not be read.
    #[error("cannot read the graph: {0}")]
    Decode(String),
    /// A serialised graph has another format version.
    #[error("graph format version {0} is not supported (this build reads {GRAPH_FORMAT_VERSION})")]
    Version(u32),
}

/// Crack bitsets: `v[j * (w + 1) + i]` is the side between cells `(i - 1, j)` and `(i, j)`
/// (corner `(i, j)` to `(i, j + 1)`); `h[j * (w + 1) + i]` the side between `(i, j - 1)` and
/// `(i, j)` (corner `(i, j)` to `(i + 1, j)`).
struct Cracks {
    cw: usize,
    ch: usize,
    v: Vec<bool>,
    h: Vec<bool>,
    /// Cracks meeting at each corner.
    deg: Vec<u8>,
}

/// Largest stray component [`local_strays`] looks for.
const STRAY_LIMIT: usize = 16;

/// The small stray components (at most [`STRAY_LIMIT`] cells, holding no obstacle cell) of
/// the nearest-obstacle regions, each with the label of the neighbouring region it joins,
/// as `(cell, label)` pairs. Fills start from the cells on each side of every crack and stop
/// at a cell already known to belong to a large component.
fn local_strays(grid: &Grid, field: &DistanceField, cracks: &Cracks) -> Vec<(usize, u32)> {
    let (w, h) = (field.width(), field.height());
    let lab = |c: usize| field.nearest_at(c);
    let occ = grid.occupancy();
    // 0 unknown, 1 in a large or obstacle-holding component, 2 stray.
    let mut state = vec![0u8; w * h];
    let mut strays: Vec<Vec<usize>> = Vec::new();
    let mut fill = Vec::with_capacity(STRAY_LIMIT + 1);
    let mut stack = Vec::new();
    let cw = cracks.cw;
    // Every component's first cell in raster order has cracks on its left and lower sides
    // (its neighbours there are outside it, hence of another label): only such cells start
    // fills, which finds every component at a tenth of the work of starting from every crack.
    for (cc, ci, cj) in (0..h).flat_map(|cj| (0..w).map(move |ci| (cj * cw + ci, ci, cj))) {
        if cracks.deg[cc] < 2 || !(cracks.v[cc] && cracks.h[cc]) {
            continue;
        }
        {
            let start = cj * w + ci;
            if state[start] != 0 {
                continue;
            }
            let l = lab(start);
            fill.clear();
            stack.clear();
            stack.push((start, ci, cj));
            state[start] = 3; // in the current fill
            let mut large = false;
            while let Some((c, i, j)) = stack.pop() {
                fill.push(c);
                if occ[c] || fill.len() > STRAY_LIMIT {
                    large = true;
                    break;
                }
                for (n, ni, nj) in [
                    (i + 1 < w).then(|| (c + 1, i + 1, j)),
                    (j + 1 < h).then(|| (c + w, i, j + 1)),
                    (i > 0).then(|| (c - 1, i - 1, j)),
                    (j > 0).then(|| (c - w, i, j - 1)),
                ]
                .into_iter()
                .flatten()
                {
                    if lab(n) != l {
                        continue;
                    }
                    match state[n] {
                        0 => {
                            state[n] = 3;
                            stack.push((n, ni, nj));
                        }
                        1 => large = true,
                        _ => {}
                    }
                }
                if large {
                    break;
                }
            }
            let mark = if large { 1 } else { 2 };
            for &c in fill.iter().chain(stack.iter().map(|(c, _, _)| c)) {
                state[c] = mark;
            }
            if !large {
                let mut comp = fill.clone();
                comp.sort_unstable();
                strays.push(comp);
            }
        }
    }
    let mut out = Vec::new();
    for comp in &strays {
        // The first neighbour, in raster order of the component's cells, outside it.
        let l = lab(comp[0]);
        let new = comp.iter().find_map(|&c| {
            let (i, j) = (c % w, c / w);
            [
                (i + 1 < w).then(|| c + 1),
                (j + 1 < h).then(|| c + w),
                (i > 0).then(|| c - 1),
                (j > 0).then(|| c - w),
            ]
            .into_iter()
            .flatten()
            .map(|n| {
                out.iter()
                    .find(|&&(x, _)| x == n)
                    .map_or_else(|| lab(n), |&(_, m)| m)
            })
            .find(|&m| m != l)
        });
        if let Some(m) = new {
            out.extend(comp.iter().map(|&c| (c, m)));
        }
    }
    out
}

/// The region of every cell: its nearest obstacle, except that cells cut off from the rest
/// of their obstacle's region (the discrete regions can have stray cells that touch it only
/// diagonally) join the region of a 4-neighbour, so that every region is 4-connected and
/// holds its obstacle.
///
/// Two-pass connected-component labelling of equal-label cells (4-connected) with
/// union-find; a component is kept when it holds an occupied cell. Stray cells then take
/// the label of a kept neighbour, breadth-first from the kept cells that border them, in
/// raster order: deterministic.
fn regions(grid: &Grid, field: &DistanceField) -> Vec<u32> {
    let (w, h) = (field.width(), field.height());
    let mut label: Vec<u32> = (0..w * h).map(|c| field.nearest_at(c)).collect();
    let occ = grid.occupancy();
    let mut comp = vec![0u32; w * h];
    let mut parent: Vec<u32> = Vec::new();
    let mut keep: Vec<bool> = Vec::new();
    fn root(p: &mut [u32], mut i: u32) -> u32 {
        while p[i as usize] != i {
            p[i as usize] = p[p[i as usize] as usize];
            i = p[i as usize];
        }
        i
    }
    for j in 0..h {
        for i in 0..w {
            let c = j * w + i;
            let l = label[c];
            let left = (i > 0 && label[c - 1] == l).then(|| comp[c - 1]);
            let up = (j > 0 && label[c - w] == l).then(|| comp[c - w]);
            let id = match (left, up) {
                (Some(a), Some(b)) => {
                    let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                    if ra != rb {
                        let (lo, hi) = (ra.min(rb), ra.max(rb));
                        parent[hi as usize] = lo;
                        keep[lo as usize] |= keep[hi as usize];
                    }
                    ra.min(rb)
                }
                (Some(a), None) => a,
                (None, Some(b)) => b,
                (None, None) => {
                    parent.push(parent.len() as u32);
                    keep.push(false);
                    (parent.len() - 1) as u32
                }
            };
            comp[c] = id;
            if occ[c] {
                let r = root(&mut parent, id);
                keep[r as usize] = true;
            }
        }
    }
    let mut kept = vec![true; w * h];
    let mut any_stray = false;
    for c in 0..w * h {
        let r = root(&mut parent, comp[c]);
        if !keep[r as usize] {
            kept[c] = false;
            any_stray = true;
        }
    }
    if !any_stray {
        return label;
    }
    let neighbours = |c: usize| {
        let (i, j) = (c % w, c / w);
        [
            (i + 1 < w).then(|| c + 1),
            (j + 1 < h).then(|| c + w),
            (i > 0).then(|| c - 1),
            (j > 0).then(|| c - w),
        ]
    };
    let mut queue: std::collections::VecDeque<usize> = (0..w * h)
        .filter(|&c| kept[c] && neighbours(c).into_iter().flatten().any(|n| !kept[n]))
        .collect();
    while let Some(c) = queue.pop_front() {
        for n in neighbours(c).into_iter().flatten() {
            if !kept[n] {
                kept[n] = true;
                label[n] = label[c];
                queue.push_back(n);
            }
        }
    }
    label
}

impl Cracks {
    /// The cracks of a labelling given row by row: `row(j, out)` writes the labels of row
    /// `j` to `out`.
    fn new(w: usize, h: usize, row: impl Fn(usize, &mut [u32])) -> Self {
        let (cw, ch) = (w + 1, h + 1);
        let mut v = vec![false; cw * ch];
        let mut hz = vec![false; cw * ch];
        // Cracks first, comparing whole rows (the loops vectorise), then the degrees.
        let (mut below, mut cur) = (vec![0u32; w], vec![0u32; w]);
        for j in 0..h {
            row(j, &mut cur);
            let c = j * cw;
            for (x, pair) in v[c + 1..c + w].iter_mut().zip(cur.windows(2)) {
                *x = pair[0] != pair[1];
            }
            if j > 0 {
                for ((x, a), b) in hz[c..c + w].iter_mut().zip(&cur).zip(&below) {
                    *x = a != b;
                }
            }
            std::mem::swap(&mut below, &mut cur);
        }
        // A corner meets the vertical cracks above and below it and the horizontal ones to
        // its right and left.
        let mut deg = vec![0u8; cw * ch];
        for cj in 0..ch {
            let c = cj * cw;
            for ci in 0..cw {
                let up = u8::from(v[c + ci]);
                let down = if cj > 0 { u8::from(v[c + ci - cw]) } else { 0 };
                let right = u8::from(hz[c + ci]);
                let left = if ci > 0 { u8::from(hz[c + ci - 1]) } else { 0 };
                deg[c + ci] = up + down + right + left;
            }
        }
        Self {
            cw,
            ch,
            v,
            h: hz,
            deg,
        }
    }

    /// Recomputes the cracks on the four sides of each of `cells` under `label`.
    fn patch(&mut self, w: usize, h: usize, cells: &[usize], label: impl Fn(usize) -> u32) {
        let cw = self.cw;
        let set_v = |this: &mut Self, i: usize, j: usize| {
            // Side between (i - 1, j) and (i, j), corner (i, j) to (i, j + 1).
            if i == 0 || i >= w {
                return;
            }
            let c = j * cw + i;
            let now = label(j * w + i - 1) != label(j * w + i);
            if now != this.v[c] {
                this.v[c] = now;
                let d = if now { 1 } else { u8::MAX };
                this.deg[c] = this.deg[c].wrapping_add(d);
                this.deg[c + cw] = this.deg[c + cw].wrapping_add(d);
            }
        };
        let set_h = |this: &mut Self, i: usize, j: usize, label: &dyn Fn(usize) -> u32| {
            if j == 0 || j >= h {
                return;
            }
            let c = j * cw + i;
            let now = label((j - 1) * w + i) != label(j * w + i);
            if now != this.h[c] {
                this.h[c] = now;
                let d = if now { 1 } else { u8::MAX };
                this.deg[c] = this.deg[c].wrapping_add(d);
                this.deg[c + 1] = this.deg[c + 1].wrapping_add(d);
            }
        };
        for &cell in cells {
            let (i, j) = (cell % w, cell / w);
            set_v(self, i, j);
            set_v(self, i + 1, j);
            set_h(self, i, j, &label);
            set_h(self, i, j + 1, &label);
        }
    }

    /// Column and row of corner `c`, by 32-bit division (corner indices fit: keys are below
    /// 2^25 cells).
    #[inline]
    fn split(&self, c: usize) -> (usize, usize) {
        let (c32, cw32) = (c as u32, self.cw as u32);
        ((c32 % cw32) as usize, (c32 / cw32) as usize)
    }

    /// The corners joined to corner `c` by a crack, in the order up, right, down, left,
    /// with the crack id (`2 * corner + 0` vertical, `+ 1` horizontal).
    fn neighbours(&self, c: usize, out: &mut Vec<(usize, usize)>) {
        out.clear();
        // No bounds arithmetic: a vertical crack starts only below the top corner row and a
        // horizontal one only left of the last corner column, so `v[c]` and `h[c]` imply that
        // the corner above or to the right exists, and `h` of the last corner of a row
        // (reached by `c - 1` from a row's first corner) is always false.
        if self.v[c] {
            out.push((c + self.cw, 2 * c));
        }
        if self.h[c] {
            out.push((c + 1, 2 * c + 1));
        }
        if c >= self.cw && self.v[c - self.cw] {
            out.push((c - self.cw, 2 * (c - self.cw)));
        }
        if c >= 1 && self.h[c - 1] {
            out.push((c - 1, 2 * (c - 1) + 1));
        }
    }
}

struct Builder<'a> {
    grid: &'a Grid,
    field: &'a DistanceField,
    cracks: Cracks,
}

impl Builder<'_> {
    fn corner_point(&self, c: usize) -> Point {
        let (i, j) = self.cracks.split(c);
        self.grid.corner(i, j)
    }

    /// Clearance of a crack: the smaller of its two cells', in map units.
    fn crack_clearance(&self, crack: usize) -> Real {
        let c = crack / 2;
        let (i, j) = self.cracks.split(c);
        let (a, b) = if crack.is_multiple_of(2) {
            ((i - 1, j), (i, j))
        } else {
            ((i, j - 1), (i, j))
        };
        self.field
            .clearance_cells(a.0, a.1)
            .min(self.field.clearance_cells(b.0, b.1))
            * self.grid.cell()
    }

    /// Clearance at a corner: the smallest of the cells around it.
    fn corner_clearance(&self, c: usize) -> Real {
        let (i, j) = self.cracks.split(c);
        let mut m = Real::INFINITY;
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            if i >= di && j >= dj && i - di < self.field.width() && j - dj < self.field.height() {
                m = m.min(self.field.clearance_cells(i - di, j - dj));
            }
        }
        m * self.grid.cell()
    }
}

/// The crack network traced into chains between nodes.
struct Network {
    cracks: Cracks,
    node_corners: Vec<usize>,
    node_of: FxHashMap<usize, usize>,
    chains: Vec<Chain>,
}

impl Network {
    fn trace(cracks: Cracks) -> Self {
        let mut nb = Vec::with_capacity(4);
        // Nodes: corners of degree other than 2.
        let mut node_of = FxHashMap::default();
        let mut node_corners = Vec::new();
        let mut crack_corners = Vec::new();
        for (c, &d) in cracks.deg.iter().enumerate() {
            if d == 0 {
                continue;
            }
            crack_corners.push(c);
            if d != 2 {
                node_of.insert(c, node_corners.len());
                node_corners.push(c);
            }
        }
        let mut used = vec![false; 2 * cracks.deg.len()];
        let mut chains = Vec::new();
        let trace = |from_node: usize,
                     c0: usize,
                     first: (usize, usize),
                     used: &mut Vec<bool>,
                     node_of: &FxHashMap<usize, usize>,
                     nb: &mut Vec<(usize, usize)>|
         -> Chain {
            let mut corners = vec![c0];
            let mut cracks_on = vec![first.1];
            used[first.1] = true;
            let mut cur = first.0;
            loop {
                corners.push(cur);
                // Nodes have degree other than 2, but for loop anchors, which a trace only
                // meets as its own end, where the fallback below returns the same chain.
                if cracks.deg[cur] != 2
                    && let Some(&n) = node_of.get(&cur)
                {
                    return Chain {
                        from: from_node,
                        to: n,
                        corners,
                        cracks: cracks_on,
                    };
                }
                cracks.neighbours(cur, nb);
                let Some(&next) = nb.iter().find(|(_, k)| !used[*k]) else {
                    // Back at a loop's anchor through its last crack.
                    return Chain {
                        from: from_node,
                        to: from_node,
                        corners,
                        cracks: cracks_on,
                    };
                };
                used[next.1] = true;
                cracks_on.push(next.1);
                cur = next.0;
            }
        };
        for (n, &c) in node_corners.iter().enumerate() {
            cracks.neighbours(c, &mut nb);
            let starts: Vec<(usize, usize)> = nb.clone();
            for s in starts {
                if !used[s.1] {
                    chains.push(trace(n, c, s, &mut used, &node_of, &mut nb));
                }
            }
        }
        // Loops that meet no junction: anchor each at its first corner in raster order.
        for &c in &crack_corners {
            cracks.neighbours(c, &mut nb);
            if let Some(&s) = nb.iter().find(|(_, k)| !used[*k]) {
                let n = node_corners.len();
                node_of.insert(c, n);
                node_corners.push(c);
                chains.push(trace(n, c, s, &mut used, &node_of, &mut nb));
            }
        }
        Self {
            cracks,
            node_corners,
            node_of,
            chains,
        }
    }

    /// Independent cycles of the traced network.
    fn cycle_rank(&self) -> usize {
        cycle_rank(
            self.node_corners.len(),
            self.chains.iter().map(|ch| (ch.from, ch.to)),
        )
    }
}

/// Independent cycles of a multigraph with `nodes` nodes and these edges: `E - V + C`.
fn cycle_rank(nodes: usize, edges: impl Iterator<Item = (usize, usize)>) -> usize {
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

/// A traced chain of corners between two nodes, before simplification.
struct Chain {
    from: usize,
    to: usize,
    corners: Vec<usize>,
    cracks: Vec<usize>,
}

impl VoronoiGraph {
    /// The graph of `field` over `grid`; start and goal attached when given.
    pub fn build(
        grid: &Grid,
        field: &DistanceField,
        start: Option<Point>,
        goal: Option<Point>,
    ) -> Result<Self, GraphError> {
        let width = field.width();
        let raw = Cracks::new(width, field.height(), |j, out| field.nearest_row(j, out));
        let mut net = Network::trace(raw);
        // Stray cells of a region add a face each; only then clean the regions up (rare).
        let inside = field.obstacles().filter(|&k| k != field.wall_key()).count();
        if net.cycle_rank() != inside {
            // Small strays are found by bounded fills from the cells along the cracks; the
            // full labelling is the fallback when that does not account for every face.
            let strays = local_strays(grid, field, &net.cracks);
            if !strays.is_empty() {
                let relabel: FxHashMap<usize, u32> = strays.iter().copied().collect();
                let cells: Vec<usize> = strays.iter().map(|&(c, _)| c).collect();
                let mut cracks = net.cracks;
                cracks.patch(width, field.height(), &cells, |c| {
                    relabel
                        .get(&c)
                        .copied()
                        .unwrap_or_else(|| field.nearest_at(c))
                });
                net = Network::trace(cracks);
            }
            if net.cycle_rank() != inside {
                let label = regions(grid, field);
                net = Network::trace(Cracks::new(width, field.height(), |j, out| {
                    out.copy_from_slice(&label[j * width..(j + 1) * width]);
                }));
            }
        }
        let Network {
            cracks,
            node_corners,
            mut node_of,
            mut chains,
        } = net;
        let b = Builder {
            grid,
            field,
            cracks,
        };
        let mut nb = Vec::with_capacity(4);
        let mut g = VoronoiGraph {
            resolution: grid.resolution(),
            nodes: node_corners
                .iter()
                .enumerate()
                .map(|(id, &c)| {
                    let p = b.corner_point(c);
                    b.cracks.neighbours(c, &mut nb);
                    let kind = if nb.len() == 1 {
                        NodeKind::DeadEnd
                    } else {
                        NodeKind::Junction
                    };
                    Node {
                        id,
                        at: [p.x, p.y],
                        clearance: b.corner_clearance(c),
                        kind,
                    }
                })
                .collect(),
            edges: Vec::new(),
            start: None,
            goal: None,
            obstacles: GridObstacle::of_field(grid, field),
        };
        // Attach start and goal by splitting chains at the crack corner they reach.
        let mut attach = |g: &mut VoronoiGraph,
                          chains: &mut Vec<Chain>,
                          p: Point,
                          what: &'static str,
                          kind: NodeKind|
         -> Result<usize, GraphError> {
            let (path, corner) = attach_path(&b, p, what)?;
            let at_node = match node_of.get(&corner) {
                Some(&n) => n,
                None => {
                    // Split the chain through `corner`.
                    let (ci, k) = chains
                        .iter()
                        .enumerate()
                        .find_map(|(ci, ch)| {
                            ch.corners
                                .iter()
                                .position(|&x| x == corner)
                                .map(|k| (ci, k))
                        })
                        .ok_or(GraphError::DifferentRegions)?;
                    let n = g.nodes.len();
                    let q = b.corner_point(corner);
                    g.nodes.push(Node {
                        id: n,
                        at: [q.x, q.y],
                        clearance: b.corner_clearance(corner),
                        kind: NodeKind::Junction,
                    });
                    node_of.insert(corner, n);
                    let old = chains.swap_remove(ci);
                    let tail = Chain {
                        from: n,
                        to: old.to,
                        corners: old.corners[k..].to_vec(),
                        cracks: old.cracks[k..].to_vec(),
                    };
                    let head = Chain {
                        from: old.from,
                        to: n,
                        corners: old.corners[..=k].to_vec(),
                        cracks: old.cracks[..k].to_vec(),
                    };
                    chains.insert(ci.min(chains.len()), head);
                    chains.push(tail);
                    n
                }
            };
            let id = g.nodes.len();
            g.nodes.push(Node {
                id,
                at: [p.x, p.y],
                clearance: b.field_clearance_at(&p),
                kind,
            });
            g.edges.push(connector(&b, id, at_node, &path, corner));
            Ok(id)
        };
        if let (Some(s), Some(t)) = (start, goal)
            && let Some(path) = direct_path(&b, s, t)?
        {
            // No crack in the free region that holds both: it has no obstacle inside, so
            // there is one class, and the free-cell path between them is its seed.
            let (ns, nt) = (g.nodes.len(), g.nodes.len() + 1);
            g.nodes.push(Node {
                id: ns,
                at: [s.x, s.y],
                clearance: b.field_clearance_at(&s),
                kind: NodeKind::Start,
            });
            g.nodes.push(Node {
                id: nt,
                at: [t.x, t.y],
                clearance: b.field_clearance_at(&t),
                kind: NodeKind::Goal,
            });
            g.start = Some(ns);
            g.goal = Some(nt);
            let mut e = connector(&b, ns, nt, &path, 0);
            let last = e.polyline.len() - 1;
            e.polyline[last] = [t.x, t.y];
            e.polyline[0] = [s.x, s.y];
            g.edges = chains.iter().map(|ch| b.edge(ch)).collect();
            g.edges.push(e);
            return Ok(g);
        }
        if let Some(s) = start {
            g.start = Some(attach(&mut g, &mut chains, s, "start", NodeKind::Start)?);
        }
        if let Some(t) = goal {
            g.goal = Some(attach(&mut g, &mut chains, t, "goal", NodeKind::Goal)?);
        }
        let connectors = std::mem::take(&mut g.edges);
        g.edges = chains.iter().map(|ch| b.edge(ch)).collect();
        g.edges.extend(connectors);
        if let (Some(s), Some(t)) = (g.start, g.goal)
            && !g.connected(s, t)
        {
            return Err(GraphError::DifferentRegions);
        }
        Ok(g)
    }

    /// Whether nodes `a` and `b` are joined by edges.
    pub fn connected(&self, a: usize, b: usize) -> bool {
        let mut parent: Vec<usize> = (0..self.nodes.len()).collect();
        for e in &self.edges {
            let (x, y) = (find_root(&mut parent, e.from), find_root(&mut parent, e.to));
            parent[x] = y;
        }
        find_root(&mut parent, a) == find_root(&mut parent, b)
    }

    /// Independent cycles: `E - V + C` (loops count one each).
    pub fn cycle_rank(&self) -> usize {
        cycle_rank(self.nodes.len(), self.edges.iter().map(|e| (e.from, e.to)))
    }

    /// Removes dead-end spurs shorter than `min_length` (map units), repeatedly, and merges
    /// the degree-2 nodes this leaves. Start and goal are never removed.
    pub fn prune_spurs(&mut self, min_length: Real) {
        loop {
            let mut degree = vec![0usize; self.nodes.len()];
            for e in &self.edges {
                degree[e.from] += 1;
                degree[e.to] += 1;
            }
            let removable = |n: usize| {
                degree[n] == 1 && !matches!(self.nodes[n].kind, NodeKind::Start | NodeKind::Goal)
            };
            let before = self.edges.len();
            self.edges.retain(|e| {
                !(e.length < min_length && e.from != e.to && (removable(e.from) || removable(e.to)))
            });
            if self.edges.len() == before {
                break;
            }
        }
        self.compact();
    }

    /// Drops nodes no edge uses and renumbers.
    fn compact(&mut self) {
        let mut used = vec![false; self.nodes.len()];
        for e in &self.edges {
            used[e.from] = true;
            used[e.to] = true;
        }
        self.keep_nodes(used);
    }

    /// Keeps the nodes marked in `keep` (and start and goal) and renumbers; every edge's ends
    /// must be kept.
    pub(crate) fn keep_nodes(&mut self, mut keep: Vec<bool>) {
        for n in [self.start, self.goal].into_iter().flatten() {
            keep[n] = true;
        }
        let mut map = vec![usize::MAX; self.nodes.len()];
        let mut nodes = Vec::new();
        for (i, n) in self.nodes.iter().enumerate() {
            if keep[i] {
                map[i] = nodes.len();
                nodes.push(Node {
                    id: nodes.len(),
                    ..n.clone()
                });
            }
        }
        for e in &mut self.edges {
            e.from = map[e.from];
            e.to = map[e.to];
        }
        self.start = self.start.map(|s| map[s]);
        self.goal = self.goal.map(|s| map[s]);
        self.nodes = nodes;
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
        let head: Head =
            rmp_serde::from_slice(bytes).map_err(|e| GraphError::Decode(e.to_string()))?;
        if head.format_version != GRAPH_FORMAT_VERSION {
            return Err(GraphError::Version(head.format_version));
        }
        let f: File =
            rmp_serde::from_slice(bytes).map_err(|e| GraphError::Decode(e.to_string()))?;
        Ok(f.graph)
    }
}

impl Builder<'_> {
    fn field_clearance_at(&self, p: &Point) -> Real {
        self.grid.cell_of(p).map_or(0.0, |(i, j)| {
            self.field.clearance_cells(i, j) * self.grid.cell()
        })
    }

    fn edge(&self, ch: &Chain) -> Edge {
        let pts: Vec<Point> = ch.corners.iter().map(|&c| self.corner_point(c)).collect();
        let simplified = douglas_peucker(&pts, POLYLINE_TOLERANCE * self.grid.cell(), usize::MAX);
        let length = simplified.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        let cl: Vec<Real> = ch.cracks.iter().map(|&k| self.crack_clearance(k)).collect();
        let min_clearance = cl.iter().copied().fold(Real::INFINITY, Real::min);
        let mean_clearance = if cl.is_empty() {
            0.0
        } else {
            cl.iter().sum::<Real>() / cl.len() as Real
        };
        Edge {
            from: ch.from,
            to: ch.to,
            length,
            min_clearance: if min_clearance.is_finite() {
                min_clearance
            } else {
                0.0
            },
            mean_clearance,
            polyline: simplified.iter().map(|p| [p.x, p.y]).collect(),
        }
    }
}

/// The cell holding `p`, which must be free.
fn free_cell(grid: &Grid, p: Point, what: &'static str) -> Result<(usize, usize), GraphError> {
    let (i, j) = grid
        .cell_of(&p)
        .ok_or(GraphError::Outside(what, p.x, p.y))?;
    if grid.occupied(i, j) {
        return Err(GraphError::Occupied(what, p.x, p.y));
    }
    Ok((i, j))
}

/// The first corner (in the order left, right, lower, upper side) of a crack on a side of
/// cell `(ci, cj)`.
fn crack_corner_of_cell(cracks: &Cracks, ci: usize, cj: usize) -> Option<usize> {
    let cw = cracks.cw;
    [
        (cracks.v[cj * cw + ci], cj * cw + ci),
        (ci + 1 < cw && cracks.v[cj * cw + ci + 1], cj * cw + ci + 1),
        (cracks.h[cj * cw + ci], cj * cw + ci),
        (
            cj + 1 < cracks.ch && cracks.h[(cj + 1) * cw + ci],
            (cj + 1) * cw + ci,
        ),
    ]
    .into_iter()
    .find_map(|(crack, corner)| crack.then_some(corner))
}

/// Breadth-first over free cells (4-connected, fixed neighbour order: deterministic) from
/// `start` to the first cell where `stop` answers; that cell's path from `start` and the
/// answer. `None` when the free region is exhausted first.
fn free_bfs<T>(
    grid: &Grid,
    start: (usize, usize),
    mut stop: impl FnMut(usize, usize) -> Option<T>,
) -> Option<(Vec<(usize, usize)>, T)> {
    let (w, h) = (grid.width(), grid.height());
    let mut parent = FxHashMap::default();
    let mut queue = std::collections::VecDeque::new();
    parent.insert(start, start);
    queue.push_back(start);
    while let Some((ci, cj)) = queue.pop_front() {
        if let Some(answer) = stop(ci, cj) {
            let mut path = vec![(ci, cj)];
            let mut cur = (ci, cj);
            while parent[&cur] != cur {
                cur = parent[&cur];
                path.push(cur);
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
            if !grid.occupied(n.0, n.1) && !parent.contains_key(&n) {
                parent.insert(n, (ci, cj));
                queue.push_back(n);
            }
        }
    }
    None
}

/// The free-cell path from `p` to the nearest cell that borders a crack, and the crack
/// corner it reaches.
fn attach_path(
    b: &Builder<'_>,
    p: Point,
    what: &'static str,
) -> Result<(Vec<(usize, usize)>, usize), GraphError> {
    let start = free_cell(b.grid, p, what)?;
    free_bfs(b.grid, start, |ci, cj| {
        crack_corner_of_cell(&b.cracks, ci, cj)
    })
    .ok_or(GraphError::DifferentRegions)
}

/// When start and goal share a free region without any crack (no obstacle inside it), the
/// free-cell path from start to goal; `None` when the region has a crack.
fn direct_path(
    b: &Builder<'_>,
    s: Point,
    t: Point,
) -> Result<Option<Vec<(usize, usize)>>, GraphError> {
    let start = free_cell(b.grid, s, "start")?;
    let goal = free_cell(b.grid, t, "goal")?;
    let found = free_bfs(b.grid, start, |ci, cj| {
        if crack_corner_of_cell(&b.cracks, ci, cj).is_some() {
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

fn connector(
    b: &Builder<'_>,
    from: usize,
    to: usize,
    path: &[(usize, usize)],
    corner: usize,
) -> Edge {
    let grid = b.grid;
    let mut pts: Vec<Point> = Vec::with_capacity(path.len() + 2);
    let first = grid.center(path[0].0, path[0].1);
    pts.push(first);
    pts.extend(path.iter().skip(1).map(|&(i, j)| grid.center(i, j)));
    pts.push(b.corner_point(corner));
    let simplified = douglas_peucker(&pts, POLYLINE_TOLERANCE * grid.cell(), usize::MAX);
    let cl: Vec<Real> = path
        .iter()
        .map(|&(i, j)| b.field.clearance_cells(i, j) * grid.cell())
        .collect();
    Edge {
        from,
        to,
        length: simplified.windows(2).map(|w| (w[1] - w[0]).norm()).sum(),
        min_clearance: cl.iter().copied().fold(Real::INFINITY, Real::min),
        mean_clearance: cl.iter().sum::<Real>() / cl.len().max(1) as Real,
        polyline: simplified.iter().map(|p| [p.x, p.y]).collect(),
    }
}
