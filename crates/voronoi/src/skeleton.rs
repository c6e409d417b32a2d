//! The complete generalized Voronoi graph of a grid: the ridge (medial axis) of the whole free
//! space, where obstacles face each other *and* where one obstacle faces itself across a
//! corridor or a room, traced into nodes and edges.
//!
//! The crack graph of [`crate::graph`] holds only the boundaries between different obstacles'
//! regions; on a map, where every wall touching the border is one obstacle, corridors and
//! rooms have none. Here the ridge comes from distance-ordered homotopic thinning (Pudney
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
//! The traced graph has a node at every skeleton cell whose number of neighbours is not two,
//! an edge per chain between them, and polylines through cell centres simplified to within
//! [`crate::graph::POLYLINE_TOLERANCE`] cell: every polyline point lies in a free cell.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use homospline_geom::math::douglas_peucker;
use homospline_geom::{Point, Real};

use crate::field::DistanceField;
use crate::graph::{Edge, GridObstacle, Node, NodeKind, POLYLINE_TOLERANCE, VoronoiGraph};
use crate::grid::Grid;

/// Neighbour offsets in ring order, starting east, counter-clockwise in (i, j); even entries
/// are the 4-neighbours.
const RING: [(i64, i64); 8] = [
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
    (0, -1),
    (1, -1),
];

/// Whether a free cell whose free 8-neighbours are the set bits of `mask` (bit k: `RING[k]`)
/// is simple for (4, 8) topology.
fn simple_from_mask(mask: u8) -> bool {
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
fn on_ridge(field: &DistanceField, d2: &[i64], w: usize, c: usize) -> bool {
    let d = d2[c];
    let off = |o: (i64, i64)| (c as i64 + o.0 + o.1 * w as i64) as usize;
    for k in 0..4 {
        let (a, b) = (d2[off(RING[k])], d2[off(RING[k + 4])]);
        if d >= a && d >= b && (d > a || d > b) {
            return true;
        }
    }
    let own = field.nearest_at(c);
    [0, 2, 4, 6].iter().any(|&k| {
        let n = off(RING[k]);
        d2[n] > 0 && field.nearest_at(n) != own
    })
}

/// The skeleton: `true` for the free cells that distance-ordered homotopic thinning keeps.
/// Every free cell of the grid must have all eight neighbours inside it (the wall ring).
pub fn skeleton_cells(grid: &Grid, field: &DistanceField) -> Vec<bool> {
    let (w, h) = (grid.width(), grid.height());
    let occ = grid.occupancy();
    let mut d2 = vec![0i64; w * h];
    for j in 0..h {
        field.d2_row(j, &mut d2[j * w..(j + 1) * w]);
    }
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
    let mut queued = vec![false; w * h];
    let mut heap = BinaryHeap::new();
    // Start from the free cells that touch an occupied one; the rest enter as the front
    // reaches them.
    for c in 0..w * h {
        if keep[c] && interior(c) && mask_of(&keep, c) != 0xff {
            queued[c] = true;
            heap.push(Reverse((d2[c], c as u32)));
        }
    }
    while let Some(Reverse((_, c))) = heap.pop() {
        let c = c as usize;
        queued[c] = false;
        if !keep[c] {
            continue;
        }
        let m = mask_of(&keep, c);
        if !table[m as usize] {
            continue;
        }
        let four = (0..4).filter(|k| m >> (2 * k) & 1 == 1).count();
        if four == 1 && on_ridge(field, &d2, w, c) {
            continue;
        }
        keep[c] = false;
        for &o in &offs {
            let n = (c as isize + o) as usize;
            if keep[n] && !queued[n] && interior(n) {
                queued[n] = true;
                heap.push(Reverse((d2[n], n as u32)));
            }
        }
    }
    keep
}

/// The neighbours of skeleton cell `c` in the traced graph: its 4-neighbours in the skeleton,
/// except that every full 2 x 2 block loses its lower horizontal edge (a block encloses no
/// occupied cell, so it must not count as a cycle; the block stays connected through its
/// other three edges).
fn neighbours(keep: &[bool], w: usize, c: usize, out: &mut Vec<usize>) {
    out.clear();
    let full_above = |a: usize| keep[a + w] && keep[a + w + 1];
    // East: edge (c, c + 1) is broken when the block above it is full.
    if keep[c + 1] && !full_above(c) {
        out.push(c + 1);
    }
    if keep[c + w] {
        out.push(c + w);
    }
    if keep[c - 1] && !full_above(c - 1) {
        out.push(c - 1);
    }
    if keep[c - w] {
        out.push(c - w);
    }
}

/// Traces the skeleton into a graph (no start or goal): nodes where the number of neighbours
/// is not two, one node on each cycle that has none, edges along the chains between them.
pub fn trace(grid: &Grid, field: &DistanceField, keep: &[bool]) -> VoronoiGraph {
    let w = grid.width();
    let n_cells = keep.len();
    let mut nb = Vec::with_capacity(4);
    let mut degree = vec![0u8; n_cells];
    for c in 0..n_cells {
        if keep[c] {
            neighbours(keep, w, c, &mut nb);
            degree[c] = nb.len() as u8;
        }
    }
    let mut node_of = vec![u32::MAX; n_cells];
    let mut node_cells = Vec::new();
    for c in 0..n_cells {
        if keep[c] && degree[c] != 2 {
            node_of[c] = node_cells.len() as u32;
            node_cells.push(c);
        }
    }
    let cell = grid.cell();
    let centre = |c: usize| grid.center(c % w, c / w);
    let clear = |c: usize| field.clearance_cells(c % w, c / w) * cell;
    // Visited (cell, neighbour) steps, as the smaller cell and the direction to the larger.
    let mut used = vec![0u8; n_cells];
    let dir_bit = |a: usize, b: usize| -> (usize, u8) {
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        (lo, if hi == lo + 1 { 1 } else { 2 })
    };
    let mut chains: Vec<(usize, usize, Vec<usize>)> = Vec::new();
    let walk = |from_cell: usize,
                first: usize,
                node_of: &mut Vec<u32>,
                node_cells: &mut Vec<usize>,
                used: &mut Vec<u8>,
                chains: &mut Vec<(usize, usize, Vec<usize>)>| {
        let (lo, bit) = dir_bit(from_cell, first);
        if used[lo] & bit != 0 {
            return;
        }
        used[lo] |= bit;
        let mut cells = vec![from_cell, first];
        let (mut prev, mut cur) = (from_cell, first);
        let mut nb = Vec::with_capacity(4);
        while node_of[cur] == u32::MAX {
            neighbours(keep, w, cur, &mut nb);
            let next = if nb[0] != prev { nb[0] } else { nb[1] };
            let (lo, bit) = dir_bit(cur, next);
            if used[lo] & bit != 0 {
                // Back at the start of a cycle without nodes.
                break;
            }
            used[lo] |= bit;
            cells.push(next);
            prev = cur;
            cur = next;
        }
        if node_of[cur] == u32::MAX {
            node_of[cur] = node_cells.len() as u32;
            node_cells.push(cur);
        }
        chains.push((node_of[from_cell] as usize, node_of[cur] as usize, cells));
    };
    let mut k = 0;
    while k < node_cells.len() {
        let c = node_cells[k];
        neighbours(keep, w, c, &mut nb);
        for &n in &nb.clone() {
            walk(c, n, &mut node_of, &mut node_cells, &mut used, &mut chains);
        }
        k += 1;
    }
    // Cycles without any node: a node at their first cell in raster order.
    for c in 0..n_cells {
        if keep[c] && degree[c] == 2 && node_of[c] == u32::MAX {
            neighbours(keep, w, c, &mut nb);
            let (lo, bit) = dir_bit(c, nb[0]);
            if used[lo] & bit != 0 {
                continue;
            }
            node_of[c] = node_cells.len() as u32;
            node_cells.push(c);
            let first = nb[0];
            walk(
                c,
                first,
                &mut node_of,
                &mut node_cells,
                &mut used,
                &mut chains,
            );
        }
    }
    let nodes = node_cells
        .iter()
        .enumerate()
        .map(|(id, &c)| {
            let p = centre(c);
            Node {
                id,
                at: [p.x, p.y],
                clearance: clear(c),
                kind: if degree[c] == 1 {
                    NodeKind::DeadEnd
                } else {
                    NodeKind::Junction
                },
            }
        })
        .collect();
    let edges = chains
        .iter()
        .map(|(from, to, cells)| {
            let pts: Vec<Point> = cells.iter().map(|&c| centre(c)).collect();
            let poly = douglas_peucker(&pts, POLYLINE_TOLERANCE * cell, usize::MAX);
            let cl: Vec<Real> = cells.iter().map(|&c| clear(c)).collect();
            Edge {
                from: *from,
                to: *to,
                length: poly.windows(2).map(|s| (s[1] - s[0]).norm()).sum(),
                min_clearance: cl.iter().copied().fold(Real::INFINITY, Real::min),
                mean_clearance: cl.iter().sum::<Real>() / cl.len() as Real,
                polyline: poly.iter().map(|p| [p.x, p.y]).collect(),
            }
        })
        .collect();
    VoronoiGraph {
        resolution: grid.resolution(),
        nodes,
        edges,
        start: None,
        goal: None,
        obstacles: GridObstacle::of_field(grid, field),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_points_of_known_neighbourhoods() {
        // Isolated: removing it deletes a component.
        assert!(!simple_from_mask(0));
        // Interior: removing it makes a hole.
        assert!(!simple_from_mask(0xff));
        // End of a line (east neighbour only).
        assert!(simple_from_mask(0b0000_0001));
        // Middle of a horizontal line (east and west): removing it splits the line.
        assert!(!simple_from_mask(0b0001_0001));
        // East and north, not joined through north-east: two 4-components.
        assert!(!simple_from_mask(0b0000_0101));
        // East, north-east, north: one component.
        assert!(simple_from_mask(0b0000_0111));
        // Only a diagonal neighbour: not 4-adjacent, so removing it changes nothing but it
        // is a component of its own (T4 = 0): not simple.
        assert!(!simple_from_mask(0b0000_0010));
    }
}
