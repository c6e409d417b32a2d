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

use crate::field::DistanceField;
use crate::graph::{Edge, Node, NodeKind};
use crate::grid::Grid;
use crate::regions::{local_strays, regions};
use crate::simplify::{edge_along, simplify};
use crate::trace::{Chain, Lattice, Traced, trace};

/// Crack bitsets: `v[j * (w + 1) + i]` is the side between cells `(i - 1, j)` and `(i, j)`
/// (corner `(i, j)` to `(i, j + 1)`); `h[j * (w + 1) + i]` the side between `(i, j - 1)` and
/// `(i, j)` (corner `(i, j)` to `(i + 1, j)`).
pub(crate) struct Cracks {
    /// Corners across (`w + 1`).
    pub(crate) cw: usize,
    /// Corners up (`h + 1`).
    pub(crate) ch: usize,
    /// Vertical cracks, by their lower corner.
    pub(crate) v: Vec<bool>,
    /// Horizontal cracks, by their left corner.
    pub(crate) h: Vec<bool>,
    /// Cracks meeting at each corner.
    pub(crate) deg: Vec<u8>,
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

    /// The first corner (in the order left, right, lower, upper side) of a crack on a side of
    /// cell `(ci, cj)`.
    pub(crate) fn corner_of_cell(&self, ci: usize, cj: usize) -> Option<usize> {
        let cw = self.cw;
        [
            (self.v[cj * cw + ci], cj * cw + ci),
            (ci + 1 < cw && self.v[cj * cw + ci + 1], cj * cw + ci + 1),
            (self.h[cj * cw + ci], cj * cw + ci),
            (
                cj + 1 < self.ch && self.h[(cj + 1) * cw + ci],
                (cj + 1) * cw + ci,
            ),
        ]
        .into_iter()
        .find_map(|(crack, corner)| crack.then_some(corner))
    }
}

/// Corners are the sites, cracks the steps (crack id `2 * corner + 0` vertical, `+ 1`
/// horizontal, by the crack's lower or left corner).
impl Lattice for Cracks {
    fn sites(&self) -> usize {
        self.deg.len()
    }

    fn member(&self, c: usize) -> bool {
        self.deg[c] > 0
    }

    fn degree(&self, c: usize) -> u8 {
        self.deg[c]
    }

    /// In the order up, right, down, left.
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
