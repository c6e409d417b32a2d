//! `DiscIndex`: the discs bucketed on a uniform grid, so that the tangent graph's
//! feasibility tests read the discs near a segment instead of all of them.

use super::enters;
use crate::math::{Point, Real, Vector};
use crate::shape::Circle;

/// The discs on a uniform grid of buckets, each disc in every bucket its box (widened by a
/// millionth of a bucket) meets, so that a feasibility test reads the discs near a point,
/// box or segment instead of all of them: the tangent graph's `O(n^2)` candidate segments
/// each test a few buckets (a blocked one stops at the first disc it enters) where they
/// tested every disc, `O(n^3)` in all, too slow for scenes of thousands of circles
/// (measured: docs/performance.md, "Measurements behind the defaults"). The
/// buckets only choose which discs are tested: every disc that can meet the query is among
/// them, so the answers are the same.
#[derive(Clone, Debug)]
pub(super) struct DiscIndex {
    pub(super) lo: Point,
    /// The corner of the discs' box opposite `lo`.
    pub(super) hi: Point,
    /// Bucket side.
    pub(super) side: Real,
    pub(super) nx: usize,
    pub(super) ny: usize,
    /// Bucket `b` holds `items[start[b]..start[b + 1]]`.
    pub(super) start: Vec<u32>,
    pub(super) items: Vec<u32>,
}

impl DiscIndex {
    pub(super) fn new(discs: &[Circle]) -> Self {
        let (mut lo, mut hi) = (Point::new(0.0, 0.0), Point::new(0.0, 0.0));
        if let Some(d) = discs.first() {
            (lo, hi) = (d.center, d.center);
        }
        let mut diameters = 0.0;
        for d in discs {
            let r = Vector::new(d.radius, d.radius);
            lo = lo.inf(&(d.center - r));
            hi = hi.sup(&(d.center + r));
            diameters += 2.0 * d.radius;
        }
        let n = discs.len().max(1);
        let (wx, wy) = ((hi.x - lo.x).max(1e-12), (hi.y - lo.y).max(1e-12));
        // About one disc per bucket, and no smaller than the mean diameter (a disc in a few
        // buckets); at most 1024 buckets a side.
        let side = (wx * wy / n as Real)
            .sqrt()
            .max(diameters / n as Real)
            .max(wx.max(wy) / 1024.0);
        let nx = ((wx / side) as usize + 1).min(1024);
        let ny = ((wy / side) as usize + 1).min(1024);
        let mut index = Self {
            lo,
            hi,
            side,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        let ranges: Vec<_> = discs
            .iter()
            .map(|d| {
                let pad = d.radius + 1e-6 * side;
                let r = Vector::new(pad, pad);
                index.range(&(d.center - r), &(d.center + r))
            })
            .collect();
        for &((i0, i1), (j0, j1)) in &ranges {
            for j in j0..=j1 {
                for i in i0..=i1 {
                    index.start[j * nx + i + 1] += 1;
                }
            }
        }
        for b in 0..nx * ny {
            index.start[b + 1] += index.start[b];
        }
        let mut fill = index.start.clone();
        index.items = vec![0; index.start[nx * ny] as usize];
        for (k, &((i0, i1), (j0, j1))) in ranges.iter().enumerate() {
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let b = j * nx + i;
                    index.items[fill[b] as usize] = k as u32;
                    fill[b] += 1;
                }
            }
        }
        index
    }

    /// The column or row of coordinate `v` (offset from the grid's corner), clamped.
    pub(super) fn cell(&self, v: Real, n: usize) -> usize {
        let c = (v / self.side).floor();
        if c <= 0.0 || c.is_nan() {
            0
        } else {
            (c as usize).min(n - 1)
        }
    }

    /// The buckets' columns and rows that the box `[lo, hi]` meets.
    pub(super) fn range(&self, lo: &Point, hi: &Point) -> ((usize, usize), (usize, usize)) {
        (
            (
                self.cell(lo.x - self.lo.x, self.nx),
                self.cell(hi.x - self.lo.x, self.nx),
            ),
            (
                self.cell(lo.y - self.lo.y, self.ny),
                self.cell(hi.y - self.lo.y, self.ny),
            ),
        )
    }

    pub(super) fn bucket(&self, i: usize, j: usize) -> &[u32] {
        let b = j * self.nx + i;
        &self.items[self.start[b] as usize..self.start[b + 1] as usize]
    }

    /// The discs whose box may hold `p` (each once).
    pub(super) fn near_point(&self, p: &Point) -> impl Iterator<Item = usize> + '_ {
        let ((i, _), (j, _)) = self.range(p, p);
        self.bucket(i, j).iter().map(|&k| k as usize)
    }

    /// The discs whose box may meet the box `[lo, hi]` (a disc may come more than once).
    pub(super) fn near_box(&self, lo: &Point, hi: &Point) -> impl Iterator<Item = usize> + '_ {
        let ((i0, i1), (j0, j1)) = self.range(lo, hi);
        (j0..=j1)
            .flat_map(move |j| (i0..=i1).flat_map(move |i| self.bucket(i, j)))
            .map(|&k| k as usize)
    }

    /// Whether the segment `[a, b]` enters an open disc, past the slack: the discs of the
    /// buckets it crosses, column by column (each column's rows from the segment's least to
    /// greatest y over it, widened by a millionth of a bucket).
    pub(super) fn blocked(&self, discs: &[Circle], a: &Point, b: &Point) -> bool {
        let (p, q) = if a.x <= b.x { (a, b) } else { (b, a) };
        let (i0, i1) = (
            self.cell(p.x - self.lo.x, self.nx),
            self.cell(q.x - self.lo.x, self.nx),
        );
        let pad = 1e-6 * self.side;
        let y_at = |x: Real| {
            if q.x > p.x {
                p.y + (q.y - p.y) * ((x - p.x) / (q.x - p.x)).clamp(0.0, 1.0)
            } else {
                p.y
            }
        };
        (i0..=i1).any(|i| {
            // The segment's part over column i (the whole of it at its ends' columns).
            let x0 = if i == i0 {
                p.x
            } else {
                self.lo.x + i as Real * self.side
            };
            let x1 = if i == i1 {
                q.x
            } else {
                self.lo.x + (i + 1) as Real * self.side
            };
            let (ya, yb) = if i0 == i1 {
                (p.y, q.y)
            } else {
                (y_at(x0), y_at(x1))
            };
            let (j0, j1) = (
                self.cell(ya.min(yb) - pad - self.lo.y, self.ny),
                self.cell(ya.max(yb) + pad - self.lo.y, self.ny),
            );
            (j0..=j1).any(|j| {
                self.bucket(i, j)
                    .iter()
                    .any(|&k| enters(&discs[k as usize], a, b))
            })
        })
    }
}
