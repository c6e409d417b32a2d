//! The crack graph of a rasterised scene: where the brushfire fronts of two obstacles meet.
//!
//! Every cell belongs to the region of its nearest obstacle ([`DistanceField::nearest`]).
//! The generalized Voronoi diagram is the set of *cracks*, the cell sides between cells of
//! different regions: a one-cell-wide, 4-connected curve network on the lattice of cell
//! corners, with no thinning needed and no breaks, since it is the boundary of a partition of
//! the plane. Corners where three or more cracks meet are junctions. For a connected free
//! space with `k` obstacles inside the wall, the regions are `k` bounded faces and the outer
//! one, so the network has exactly `k` independent cycles; when stray cells of a region add
//! faces, the regions are cleaned up first ([`crate::regions`]).
//!
//! The network is traced ([`crate::trace`]) into nodes (junctions, plus one anchor on each
//! crack loop that meets no junction) and chains, which become edges with length, minimum and
//! mean clearance, and a polyline simplified to within
//! [`POLYLINE_TOLERANCE`](crate::graph::POLYLINE_TOLERANCE) cell of the chain.

use homospline_geom::{Point, Real};
use rustc_hash::FxHashMap;

use crate::crack_bits::Cracks;
use crate::field::DistanceField;
use crate::graph::{Edge, Node, NodeKind};
use crate::grid::Grid;
use crate::regions::{local_strays, regions};
use crate::simplify::{edge_along, simplify};
use crate::trace::{Chain, Traced, trace};

/// The crack network of a grid traced into nodes and chains, before start and goal; chains
/// are split (and nodes added) as they are attached.
pub(crate) struct CrackGraph<'a> {
    /// The grid.
    pub(crate) grid: &'a Grid,
    /// Its brushfire.
    pub(crate) field: &'a DistanceField,
    /// The cracks.
    pub(crate) cracks: Cracks,
    /// Nodes (corners), chains, and the node at each corner.
    pub(crate) net: Traced,
}

impl<'a> CrackGraph<'a> {
    /// The cracks between the nearest-obstacle regions of `field`, traced. Stray cells of a
    /// region add a face each: when the cycles do not match the obstacles inside the wall, the
    /// strays join a neighbouring region (rare).
    pub(crate) fn build(grid: &'a Grid, field: &'a DistanceField) -> Self {
        let width = field.width();
        let mut cracks = Cracks::new(width, field.height(), |j, out| field.nearest_row(j, out));
        let mut net = trace(&cracks);
        let inside = field.obstacles().filter(|&k| k != field.wall_key()).count();
        if net.cycle_rank() != inside {
            // Small strays are found by bounded fills from the cells along the cracks; the
            // full labelling is the fallback when that does not account for every face.
            let strays = local_strays(grid, field, &cracks);
            if !strays.is_empty() {
                let relabel: FxHashMap<usize, u32> = strays.iter().copied().collect();
                let cells: Vec<usize> = strays.iter().map(|&(c, _)| c).collect();
                cracks.patch(width, field.height(), &cells, |c| {
                    relabel
                        .get(&c)
                        .copied()
                        .unwrap_or_else(|| field.nearest_at(c))
                });
                net = trace(&cracks);
            }
            if net.cycle_rank() != inside {
                let label = regions(grid, field);
                cracks = Cracks::new(width, field.height(), |j, out| {
                    out.copy_from_slice(&label[j * width..(j + 1) * width]);
                });
                net = trace(&cracks);
            }
        }
        Self {
            grid,
            field,
            cracks,
            net,
        }
    }

    /// Corner `c` in map coordinates.
    pub(crate) fn corner_point(&self, c: usize) -> Point {
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
    pub(crate) fn corner_clearance(&self, c: usize) -> Real {
        let (i, j) = self.cracks.split(c);
        let mut m = Real::INFINITY;
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            if i >= di && j >= dj && i - di < self.field.width() && j - dj < self.field.height() {
                m = m.min(self.field.clearance_cells(i - di, j - dj));
            }
        }
        m * self.grid.cell()
    }

    /// The traced nodes: dead ends where one crack ends, junctions (and loop anchors) else.
    pub(crate) fn nodes(&self) -> Vec<Node> {
        self.net
            .node_sites
            .iter()
            .enumerate()
            .map(|(id, &c)| {
                let p = self.corner_point(c);
                let kind = if self.cracks.deg[c] == 1 {
                    NodeKind::DeadEnd
                } else {
                    NodeKind::Junction
                };
                Node {
                    id,
                    at: [p.x, p.y],
                    clearance: self.corner_clearance(c),
                    kind,
                }
            })
            .collect()
    }

    /// The edge of a chain: its corners simplified, the clearances of its cracks.
    pub(crate) fn edge(&self, ch: &Chain) -> Edge {
        let pts: Vec<Point> = ch.sites.iter().map(|&c| self.corner_point(c)).collect();
        let cl: Vec<Real> = ch.steps.iter().map(|&k| self.crack_clearance(k)).collect();
        edge_along(ch.from, ch.to, &simplify(&pts, self.grid.cell()), &cl)
    }

    /// The edges of every chain.
    pub(crate) fn edges(&self) -> Vec<Edge> {
        self.net.chains.iter().map(|ch| self.edge(ch)).collect()
    }
}
