//! The grid clearance model: obstacles of an occupancy map as the cost and the checks see them.
//!
//! Two distances, for two purposes:
//! - for the cost, a smooth one: the clearance at cell centres (`(sqrt(d2) - 1/2) h` from
//!   the exact brushfire, `-h/2` inside obstacles) interpolated bilinearly, with its gradient;
//! - for verification, the exact Euclidean distance from a point to the nearest occupied
//!   cell (a closed square), found by a ring search bounded by the brushfire. It is
//!   1-Lipschitz, so `min(d(a), d(b)) - |ab| / 2` is a rigorous lower bound of the clearance
//!   along a segment: that is what certification and the reported `min_clearance` use.

use homospline_geom::{Point, Real, Vector};
use homospline_spline::field::{ClearanceModel, FieldSample};
use homospline_voronoi::{DistanceField, Grid};

/// Rings of depth inside obstacles that the smooth clearance tells apart.
pub const DEPTH_RINGS: u8 = 6;

/// Clearance model of an occupancy grid.
#[derive(Clone, Debug)]
pub struct GridModel {
    w: usize,
    h: usize,
    origin: Point,
    cell: Real,
    occ: Vec<bool>,
    /// Signed clearance at cell centres, map units.
    d: Vec<Real>,
    /// Squared brushfire distance at each cell, cells.
    d2: Vec<i64>,
}

impl GridModel {
    /// The model of `grid`, whose brushfire is `field`. Inside obstacles the clearance is
    /// minus the depth in cells, by rings from the free space (4-connected, up to
    /// [`DEPTH_RINGS`]), so that its gradient points out.
    pub fn new(grid: &Grid, field: &DistanceField) -> Self {
        let (w, h) = (grid.width(), grid.height());
        let cell = grid.cell();
        let occ = grid.occupancy();
        let mut d = vec![0.0; w * h];
        let mut d2 = vec![0; w * h];
        let mut ring = vec![0u8; w * h];
        let mut frontier = Vec::new();
        for j in 0..h {
            for i in 0..w {
                let k = j * w + i;
                d2[k] = field.d2(i, j);
                if !occ[k] {
                    d[k] = field.clearance_cells(i, j) * cell;
                } else if (i > 0 && !occ[k - 1])
                    || (i + 1 < w && !occ[k + 1])
                    || (j > 0 && !occ[k - w])
                    || (j + 1 < h && !occ[k + w])
                {
                    ring[k] = 1;
                    frontier.push(k);
                }
            }
        }
        let mut r = 1u8;
        while !frontier.is_empty() && r < DEPTH_RINGS {
            let mut next = Vec::new();
            for &k in &frontier {
                let (i, j) = (k % w, k / w);
                let around = [
                    (i > 0).then(|| k - 1),
                    (i + 1 < w).then(|| k + 1),
                    (j > 0).then(|| k - w),
                    (j + 1 < h).then(|| k + w),
                ];
                for n in around.into_iter().flatten() {
                    if occ[n] && ring[n] == 0 {
                        ring[n] = r + 1;
                        next.push(n);
                    }
                }
            }
            frontier = next;
            r += 1;
        }
        for k in 0..w * h {
            if occ[k] {
                let depth = if ring[k] == 0 { DEPTH_RINGS } else { ring[k] };
                d[k] = -(depth as Real - 0.5) * cell;
            }
        }
        Self {
            w,
            h,
            origin: grid.origin(),
            cell,
            occ: occ.to_vec(),
            d,
            d2,
        }
    }

    /// Smooth clearance and gradient (bilinear over cell centres).
    pub fn smooth(&self, p: &Point) -> (Real, Vector) {
        let fx = (p.x - self.origin.x) / self.cell - 0.5;
        let fy = (p.y - self.origin.y) / self.cell - 0.5;
        let i0 = (fx.floor().max(0.0) as usize).min(self.w - 2);
        let j0 = (fy.floor().max(0.0) as usize).min(self.h - 2);
        let tx = (fx - i0 as Real).clamp(0.0, 1.0);
        let ty = (fy - j0 as Real).clamp(0.0, 1.0);
        let at = |i: usize, j: usize| self.d[j * self.w + i];
        let (a, b, c, e) = (
            at(i0, j0),
            at(i0 + 1, j0),
            at(i0, j0 + 1),
            at(i0 + 1, j0 + 1),
        );
        let v =
            a * (1.0 - tx) * (1.0 - ty) + b * tx * (1.0 - ty) + c * (1.0 - tx) * ty + e * tx * ty;
        let gx = ((b - a) * (1.0 - ty) + (e - c) * ty) / self.cell;
        let gy = ((c - a) * (1.0 - tx) + (e - b) * tx) / self.cell;
        (v, Vector::new(gx, gy))
    }

    fn cell_of(&self, p: &Point) -> Option<(usize, usize)> {
        let fx = (p.x - self.origin.x) / self.cell;
        let fy = (p.y - self.origin.y) / self.cell;
        if !(fx >= 0.0 && fy >= 0.0) {
            return None;
        }
        let (i, j) = (fx as usize, fy as usize);
        (i < self.w && j < self.h).then_some((i, j))
    }

    /// Exact distance from `p` to the nearest occupied cell (negative inside one: minus the
    /// distance to its nearest side). Outside the grid: the distance to the grid (the wall).
    pub fn exact(&self, p: &Point) -> Real {
        let Some((ci, cj)) = self.cell_of(p) else {
            return 0.0;
        };
        let h = self.cell;
        if self.occ[cj * self.w + ci] {
            let x0 = self.origin.x + ci as Real * h;
            let y0 = self.origin.y + cj as Real * h;
            return -(p.x - x0).min(x0 + h - p.x).min(p.y - y0).min(y0 + h - p.y);
        }
        // The brushfire's nearest occupied centre is within sqrt(d2) cells of this cell's
        // centre: an occupied square lies within (sqrt(d2) + 1) h of p.
        let bound = ((self.d2[cj * self.w + ci] as Real).sqrt() + 1.0) * h;
        let mut best = bound;
        let square = |i: usize, j: usize| {
            let x0 = self.origin.x + i as Real * h;
            let y0 = self.origin.y + j as Real * h;
            let dx = (x0 - p.x).max(p.x - x0 - h).max(0.0);
            let dy = (y0 - p.y).max(p.y - y0 - h).max(0.0);
            (dx * dx + dy * dy).sqrt()
        };
        let mut r = 1usize;
        // Cells on Chebyshev ring r are at least (r - 1) h away.
        while ((r - 1) as Real) * h <= best {
            let (i0, i1) = (ci as i64 - r as i64, ci as i64 + r as i64);
            let (j0, j1) = (cj as i64 - r as i64, cj as i64 + r as i64);
            for j in j0..=j1 {
                if j < 0 || j >= self.h as i64 {
                    continue;
                }
                let on_edge = j == j0 || j == j1;
                let mut i = i0;
                while i <= i1 {
                    if i >= 0 && (i as usize) < self.w && self.occ[j as usize * self.w + i as usize]
                    {
                        best = best.min(square(i as usize, j as usize));
                    }
                    i = if on_edge || i == i1 { i + 1 } else { i1 };
                }
            }
            r += 1;
            if r > self.w + self.h {
                break;
            }
        }
        best
    }
}

impl ClearanceModel for GridModel {
    fn clearance(&self, p: &Point) -> (Real, Vector) {
        self.smooth(p)
    }

    fn field_batch(&self, pts: &[Point], alpha: Real, _allowance: Real, out: &mut [FieldSample]) {
        for (p, o) in pts.iter().zip(out.iter_mut()) {
            let (d, g) = self.smooth(p);
            // U = 1 + tanh(-alpha d) = 2 / (1 + exp(2 alpha d)); dU/dd = -alpha U (2 - U).
            let u = 2.0 / (1.0 + (2.0 * alpha * d).exp());
            *o = FieldSample {
                potential: u,
                potential_grad: g * (-alpha * u * (2.0 - u)),
                clearance: d,
                clearance_grad: g,
            };
        }
    }

    fn line_of_sight(&self, a: &Point, b: &Point) -> bool {
        let n = (((b - a).norm() / (0.25 * self.cell)).ceil() as usize).max(1);
        (0..=n).all(|k| {
            let p = a + (b - a) * (k as Real / n as Real);
            self.cell_of(&p)
                .is_some_and(|(i, j)| !self.occ[j * self.w + i])
        })
    }

    fn segment_clearance(&self, a: &Point, b: &Point) -> Real {
        self.exact(a).min(self.exact(b)) - 0.5 * (b - a).norm()
    }

    fn exact_clearance(&self, p: &Point) -> Real {
        self.exact(p)
    }
}
