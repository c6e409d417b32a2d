//! The complete generalized Voronoi graph of a grid: the ridge (medial axis) of the whole free
//! space, where obstacles face each other *and* where one obstacle faces itself across a
//! corridor or a room, traced into nodes and edges.
//!
//! The crack graph of [`VoronoiGraph::build`] holds only the boundaries between different
//! obstacles' regions; on a map, where every wall touching the border is one obstacle,
//! corridors and rooms have none. Here the ridge comes from distance-ordered homotopic thinning (Pudney
//! 1998): free cells are removed in order of increasing clearance while their removal keeps
//! the topology of free space, so what remains
//! - is homotopy equivalent to the free space: one connected piece per free component
//!   (start and goal are joined whenever free cells join them) and one independent cycle per
//!   obstacle hole;
//! - runs where the clearance is highest, since low cells go first;
//! - keeps the ridge's spurs: a cell on a ridge (a strict local maximum of the brushfire
//!   distance along a row, a column or a diagonal, or next to another obstacle's region: the
//!   criterion of Lau, Sprunk and Burgard's dynamic Voronoi) is kept once it is an end point.
//!
//! Topology is the MovingAI rule: free cells are 4-connected (8-connected moves without corner
//! cutting join the same cells), occupied cells 8-connected, as the field keys obstacles.
//! A cell is simple for that pair when its 4-connected free neighbours touching it form one
//! component and its occupied neighbours one 8-component (Bertrand's topological numbers),
//! read from a 256-entry table.
//!
//! The traced graph (by the crack graph's tracer, the private `trace` module) has a node at
//! every skeleton cell whose number of neighbours is not two, an edge per chain between them,
//! and polylines through cell centres simplified to within
//! [`crate::graph::POLYLINE_TOLERANCE`] cell: every polyline point lies in a free cell.

use homospline_geom::{Point, Real};
use rayon::prelude::*;

use crate::field::DistanceField;
use crate::graph::{GridObstacle, Node, NodeKind, VoronoiGraph};
use crate::grid::Grid;
use crate::simplify::{edge_along, simplify};
use crate::trace::{self as chains, Lattice};

/// Neighbour offsets in ring order, starting east, counter-clockwise.
use crate::grid::NEIGHBOURS_8 as RING;

/// Whether a free cell whose free 8-neighbours are the set bits of `mask` is *simple* for
/// (4, 8) topology: removing it from the free cells (4-connected) changes neither their
/// components nor those of the occupied cells (8-connected). The thinning that makes the
/// skeleton removes only simple cells.
///
/// Bit `k` of `mask` is the neighbour at `k` eighths of a turn counter-clockwise from east
/// in (column, row): bit 0 east, 1 north-east, 2 north, 3 north-west, 4 west, 5
/// south-west, 6 south, 7 south-east.
///
/// # Examples
///
/// ```
/// use homospline_voronoi::skeleton::simple_from_mask;
///
/// // Isolated: removing it deletes a component.
/// assert!(!simple_from_mask(0));
/// // Interior: removing it makes a hole.
/// assert!(!simple_from_mask(0xff));
/// // The end of a line (east neighbour only).
/// assert!(simple_from_mask(0b0000_0001));
/// // The middle of a horizontal line (east and west): removing it splits the line.
/// assert!(!simple_from_mask(0b0001_0001));
/// // East and north, not joined through north-east: two 4-components.
/// assert!(!simple_from_mask(0b0000_0101));
/// // East, north-east, north: one component.
/// assert!(simple_from_mask(0b0000_0111));
/// // Only a diagonal neighbour: not 4-adjacent, so the cell is a component of its own.
/// assert!(!simple_from_mask(0b0000_0010));
/// ```
pub fn simple_from_mask(mask: u8) -> bool {
    let fg = |k: usize| mask >> k & 1 == 1;
    // Components by flood fill over the ring's 8 cells with the given adjacency.
    let count = |member: &dyn Fn(usize) -> bool,
                 adjacent: &dyn Fn(usize, usize) -> bool,
                 counts: &dyn Fn(&[usize]) -> bool| {
        let mut seen = [false; 8];
        let mut n = 0;
        for s in 0..8 {
            if seen[s] || !member(s) {
                continue;
            }
            let mut comp = vec![s];
            seen[s] = true;
            let mut k = 0;
            while k < comp.len() {
                let a = comp[k];
                for (b, sb) in seen.iter_mut().enumerate() {
                    if !*sb && member(b) && adjacent(a, b) {
                        *sb = true;
                        comp.push(b);
                    }
                }
                k += 1;
            }
            if counts(&comp) {
                n += 1;
            }
        }
        n
    };
    let diff = |a: usize, b: usize| {
        let (p, q) = (RING[a], RING[b]);
        ((p.0 - q.0).abs(), (p.1 - q.1).abs())
    };
    let adj4 = |a: usize, b: usize| {
        let (dx, dy) = diff(a, b);
        dx + dy == 1
    };
    let adj8 = |a: usize, b: usize| {
        let (dx, dy) = diff(a, b);
        dx.max(dy) == 1
    };
    let t4 = count(&fg, &adj4, &|c: &[usize]| c.iter().any(|k| k % 2 == 0));
    let t8 = count(&|k| !fg(k), &adj8, &|_| true);
    t4 == 1 && t8 == 1
}

/// [`simple_from_mask`] for every mask.
fn simple_table() -> [bool; 256] {
    let mut t = [false; 256];
    for (m, v) in t.iter_mut().enumerate() {
        *v = simple_from_mask(m as u8);
    }
    t
}

/// Whether free cell `c` is on a ridge of the brushfire: a strict local maximum of the
/// squared distance along a row, a column or a diagonal (not below either neighbour and
/// above one), or next to a cell nearest to another obstacle.
fn on_ridge(field: &DistanceField, w: usize, c: usize) -> bool {
    let d = field.d2_at(c);
    let off = |o: (i64, i64)| (c as i64 + o.0 + o.1 * w as i64) as usize;
    for k in 0..4 {
        let (a, b) = (field.d2_at(off(RING[k])), field.d2_at(off(RING[k + 4])));
        if d >= a && d >= b && (d > a || d > b) {
            return true;
        }
    }
    let own = field.nearest_at(c);
    [0, 2, 4, 6].iter().any(|&k| {
        let n = off(RING[k]);
        field.d2_at(n) > 0 && field.nearest_at(n) != own
    })
}

/// The thinning's queue: a set of cells popped in increasing `(d2, raster index)`. That
/// order is fixed per cell, so each free cell gets its rank in it once (a counting sort by
/// `d2`, raster order within), and the set is a bitset over ranks with summary levels (a
/// bit of level `l + 1` is set when its word of level `l` is not zero): insert, membership
/// and pop-min in a few word operations, where a binary heap of `(d2, cell)` spent a fifth
/// of a map's preparation. The pops are the heap's, one for one.
struct CellQueue {
    /// Rank of every cell (`u32::MAX`: never queued).
    rank: Vec<u32>,
    /// Cell of every rank.
    cell: Vec<u32>,
    /// `levels[0]`: one bit per rank; each next level summarises the one below.
    levels: Vec<Vec<u64>>,
}

impl CellQueue {
    /// Ranks for the cells where `member` holds, by `(d2, index)`.
    fn new(n: usize, member: impl Fn(usize) -> bool, d2: impl Fn(usize) -> i64) -> Self {
        let mut count: Vec<u32> = Vec::new();
        let mut members = 0usize;
        for c in 0..n {
            if member(c) {
                let d = d2(c) as usize;
                if d >= count.len() {
                    count.resize(d + 1, 0);
                }
                count[d] += 1;
                members += 1;
            }
        }
        // Exclusive prefix sums: the first rank of each d2.
        let mut next = 0u32;
        for k in count.iter_mut() {
            let here = *k;
            *k = next;
            next += here;
        }
        let mut rank = vec![u32::MAX; n];
        let mut cell = vec![0u32; members];
        for (c, r) in rank.iter_mut().enumerate() {
            if member(c) {
                let slot = &mut count[d2(c) as usize];
                *r = *slot;
                cell[*slot as usize] = c as u32;
                *slot += 1;
            }
        }
        let mut levels = Vec::new();
        let mut len = members.max(1);
        loop {
            let words = len.div_ceil(64);
            levels.push(vec![0u64; words]);
            if words == 1 {
                break;
            }
            len = words;
        }
        Self { rank, cell, levels }
    }

    /// Whether cell `c` is in the queue.
    fn contains(&self, c: usize) -> bool {
        let r = self.rank[c];
        r != u32::MAX && self.levels[0][r as usize / 64] >> (r % 64) & 1 == 1
    }

    /// Adds cell `c` (which has a rank).
    fn insert(&mut self, c: usize) {
        let mut r = self.rank[c] as usize;
        for level in &mut self.levels {
            let word = &mut level[r / 64];
            let was = *word;
            *word |= 1 << (r % 64);
            if was != 0 {
                break;
            }
            r /= 64;
        }
    }

    /// Removes and returns the cell of least `(d2, index)`.
    fn pop(&mut self) -> Option<usize> {
        let top = self.levels.len() - 1;
        if self.levels[top][0] == 0 {
            return None;
        }
        let mut r = 0usize;
        for l in (0..=top).rev() {
            r = r * 64 + self.levels[l][r].trailing_zeros() as usize;
        }
        let mut k = r;
        for level in &mut self.levels {
            let word = &mut level[k / 64];
            *word &= !(1 << (k % 64));
            if *word != 0 {
                break;
            }
            k /= 64;
        }
        Some(self.cell[r] as usize)
    }
}

/// The skeleton: `true` for the free cells that distance-ordered homotopic thinning keeps.
/// Every free cell of the grid must have all eight neighbours inside it (the wall ring).
pub fn skeleton_cells(grid: &Grid, field: &DistanceField) -> Vec<bool> {
    let (w, h) = (grid.width(), grid.height());
    let occ = grid.occupancy();
    let table = simple_table();
    let mut keep: Vec<bool> = occ.iter().map(|&o| !o).collect();
    // A free cell on the border (possible only without a wall ring) is never removed.
    let interior = |c: usize| {
        let (i, j) = (c % w, c / w);
        i > 0 && j > 0 && i + 1 < w && j + 1 < h
    };
    let offs: Vec<isize> = RING
        .iter()
        .map(|&(di, dj)| (di + dj * w as i64) as isize)
        .collect();
    let mask_of = |keep: &[bool], c: usize| -> u8 {
        let mut m = 0u8;
        for (k, &o) in offs.iter().enumerate() {
            if keep[(c as isize + o) as usize] {
                m |= 1 << k;
            }
        }
        m
    };
    let mut queue = CellQueue::new(w * h, |c| keep[c] && interior(c), |c| field.d2_at(c));
    // Start from the free cells that touch an occupied one; the rest enter as the front
    // reaches them.
    for c in 0..w * h {
        if keep[c] && interior(c) && mask_of(&keep, c) != 0xff {
            queue.insert(c);
        }
    }
    while let Some(c) = queue.pop() {
        if !keep[c] {
            continue;
        }
        let m = mask_of(&keep, c);
        if !table[m as usize] {
            continue;
        }
        let four = (0..4).filter(|k| m >> (2 * k) & 1 == 1).count();
        if four == 1 && on_ridge(field, w, c) {
            continue;
        }
        keep[c] = false;
        for &o in &offs {
            let n = (c as isize + o) as usize;
            if keep[n] && interior(n) && !queue.contains(n) {
                queue.insert(n);
            }
        }
    }
    keep
}

/// The skeleton as a network of cells: the 4-neighbours in the skeleton, except that every full
/// 2 x 2 block loses its lower horizontal edge (a block encloses no occupied cell, so it must
/// not count as a cycle; the block stays connected through its other three edges).
struct Skeleton<'a> {
    keep: &'a [bool],
    w: usize,
    /// Neighbours of every skeleton cell.
    degree: Vec<u8>,
}

impl<'a> Skeleton<'a> {
    fn new(keep: &'a [bool], w: usize) -> Self {
        let mut s = Self {
            keep,
            w,
            degree: vec![0; keep.len()],
        };
        let mut nb = Vec::with_capacity(4);
        for (c, &k) in keep.iter().enumerate() {
            if k {
                s.neighbours(c, &mut nb);
                s.degree[c] = nb.len() as u8;
            }
        }
        s
    }
}

/// Cells are the sites, cell sides the steps (`2 * c` to the east of `c`, `2 * c + 1` to the
/// north).
impl Lattice for Skeleton<'_> {
    fn sites(&self) -> usize {
        self.keep.len()
    }

    fn member(&self, c: usize) -> bool {
        self.keep[c]
    }

    fn degree(&self, c: usize) -> u8 {
        self.degree[c]
    }

    /// In the order east, north, west, south.
    fn neighbours(&self, c: usize, out: &mut Vec<(usize, usize)>) {
        let (keep, w) = (self.keep, self.w);
        out.clear();
        let full_above = |a: usize| keep[a + w] && keep[a + w + 1];
        // East: edge (c, c + 1) is broken when the block above it is full.
        if keep[c + 1] && !full_above(c) {
            out.push((c + 1, 2 * c));
        }
        if keep[c + w] {
            out.push((c + w, 2 * c + 1));
        }
        if keep[c - 1] && !full_above(c - 1) {
            out.push((c - 1, 2 * (c - 1)));
        }
        if keep[c - w] {
            out.push((c - w, 2 * (c - w) + 1));
        }
    }
}

/// Traces the skeleton into a graph (no start or goal): nodes where the number of neighbours
/// is not two, one node on each cycle that has none, edges along the chains between them.
pub fn trace(grid: &Grid, field: &DistanceField, keep: &[bool]) -> VoronoiGraph {
    let w = grid.width();
    let skeleton = Skeleton::new(keep, w);
    let (net, node_of) = chains::trace_flat(&skeleton);
    drop(node_of);
    let cell = grid.cell();
    let centre = |c: usize| grid.center(c % w, c / w);
    let clear = |c: usize| field.clearance_cells(c % w, c / w) * cell;
    let nodes = net
        .node_sites
        .iter()
        .enumerate()
        .map(|(id, &c)| {
            let p = centre(c);
            Node {
                id,
                at: [p.x, p.y],
                clearance: clear(c),
                kind: if skeleton.degree[c] == 1 {
                    NodeKind::DeadEnd
                } else {
                    NodeKind::Junction
                },
            }
        })
        .collect();
    drop(skeleton);
    // Each chain's edge alone, in parallel (the order of `collect` is the chains' for any
    // number of threads), with each thread's scratch for the points and clearances.
    let edges = (0..net.chains.len())
        .into_par_iter()
        .map_init(
            || (Vec::new(), Vec::new()),
            |(pts, cl): &mut (Vec<Point>, Vec<Real>), k| {
                let sites = net.chain_sites(k);
                pts.clear();
                pts.extend(sites.iter().map(|&c| centre(c as usize)));
                cl.clear();
                cl.extend(sites.iter().map(|&c| clear(c as usize)));
                let (from, to, _, _) = net.chains[k];
                edge_along(from, to, &simplify(pts, cell), cl)
            },
        )
        .collect();
    VoronoiGraph {
        resolution: grid.resolution(),
        nodes,
        edges,
        start: None,
        goal: None,
        obstacles: GridObstacle::of_field(grid, field),
        built_for: None,
    }
}
