//! The grid clearance model: obstacles of an occupancy map as the cost and the checks see them.
//!
//! One distance serves the cost and the checks: the exact Euclidean distance from a point to
//! the nearest occupied cell (a closed square), found by a search over the cells that can be
//! nearest (bounded by the brushfire), with its gradient (the unit vector from the nearest
//! point of that cell). It is 1-Lipschitz, so `(d(a) + d(b) - |ab|) / 2` is a rigorous lower
//! bound of the clearance along a segment: that is what certification and the reported
//! `min_clearance` use. Distance to a square is convex with a Hessian of at most `1 / d`, as
//! a disc of radius 0 has, so the cost's search for the least clearance between its nodes
//! has the circles' bound ([`ClearanceModel::bend_radius`] 0).
//!
//! The cost once read a smooth stand-in, the brushfire's clearance at cell centres
//! interpolated bilinearly: it reads about a quarter cell at the corner of an occupied cell
//! (three free centres at +1/2, one occupied at -1/2) where the true clearance is 0, and map
//! paths passed door frames and corners at 1e-4 cells.

use homospline_geom::{Point, Real, Vector};
use homospline_spline::clearance_model::{ClearanceModel, FieldSample, exp_fast};
use homospline_voronoi::{DistanceField, Grid};
use rustc_hash::FxHashMap;
use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, PoisonError, RwLock};

/// Ids of [`GridModel`]s, one per grid built.
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// Slots of the per-thread memo of candidate lists ([`MEMO`]).
const MEMO_SLOTS: usize = 1024;

/// A slot of [`MEMO`]: `(model id, cell, list)`.
type MemoSlot = Option<(u64, u32, Arc<[u32]>)>;

thread_local! {
    /// Per thread, the candidate lists its queries used last, direct-mapped by cell: the
    /// quadrature nodes of a curve's evaluations meet the same few hundred cells again and
    /// again, and the memo spares them the shared cache's lock and hash.
    static MEMO: RefCell<Vec<MemoSlot>> = RefCell::new(vec![None; MEMO_SLOTS]);
}

/// A candidate cell `(i, j)` packed in a list: `i` in the low 16 bits, `j` in the high
/// (grids are at most 4098 cells across with their wall ring).
#[inline]
fn unpack(o: u32) -> (usize, usize) {
    ((o & 0xffff) as usize, (o >> 16) as usize)
}

/// Shards of [`GridModel`]'s cache of candidates (cell `k` in shard `k % CACHE_SHARDS`).
const CACHE_SHARDS: usize = 64;

/// Clearance model of an occupancy grid.
#[derive(Debug)]
pub struct GridModel {
    w: usize,
    h: usize,
    origin: Point,
    cell: Real,
    /// Squared brushfire distance at each cell, cells (0 exactly on occupied cells; clamped
    /// to `u32::MAX`, far beyond any grid's `w^2 + h^2`).
    d2: Vec<u32>,
    /// Per free cell met by a query, filled on first use: the occupied cells that can be
    /// nearest to some point of the cell (the annulus of [`GridModel::exact`]), as row-major
    /// indices. The verification queries of one map meet the same cells again and again,
    /// but only a few of a large map's cells: hash maps behind sharded locks hold just
    /// those (a lazily filled slot per cell took 24 bytes of every cell). The lists are pure
    /// functions of the grid, so the cache never changes an answer.
    candidates: Vec<RwLock<FxHashMap<u32, Arc<[u32]>>>>,
    /// Tells this model's lists from another's in the per-thread memo of lists ([`MEMO`]):
    /// models with one id have the same grid.
    id: u64,
    /// Subtracted from every clearance the model reports as a [`ClearanceModel`]: the
    /// robot's radius, so that clearances are the robot body's (0 for a point).
    offset: Real,
}

impl Clone for GridModel {
    fn clone(&self) -> Self {
        Self {
            w: self.w,
            h: self.h,
            origin: self.origin,
            cell: self.cell,
            d2: self.d2.clone(),
            candidates: self
                .candidates
                .iter()
                .map(|s| RwLock::new(s.read().unwrap_or_else(PoisonError::into_inner).clone()))
                .collect(),
            offset: self.offset,
            id: self.id,
        }
    }
}

impl GridModel {
    /// The model of `grid`, whose brushfire is `field`.
    pub fn new(grid: &Grid, field: &DistanceField) -> Self {
        let (w, h) = (grid.width(), grid.height());
        let mut d2 = vec![0u32; w * h];
        let mut row = vec![0i64; w];
        for j in 0..h {
            field.d2_row(j, &mut row);
            for (o, &q) in d2[j * w..(j + 1) * w].iter_mut().zip(&row) {
                *o = q.clamp(0, u32::MAX as i64) as u32;
            }
        }
        Self {
            w,
            h,
            origin: grid.origin(),
            cell: grid.cell(),
            d2,
            candidates: (0..CACHE_SHARDS)
                .map(|_| RwLock::new(FxHashMap::default()))
                .collect(),
            offset: 0.0,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// The same model for a disc robot of radius `radius`: as a [`ClearanceModel`] every
    /// clearance is less by `radius` (the distance from the robot's body); [`GridModel::exact`]
    /// stays the distance from the point.
    pub fn for_radius(mut self, radius: Real) -> Self {
        self.offset = radius;
        self
    }

    /// Whether cell `k` (row-major) is occupied: its squared distance is 0.
    #[inline]
    fn occupied(&self, k: usize) -> bool {
        self.d2[k] == 0
    }

    fn cell_of(&self, p: &Point) -> Option<(usize, usize)> {
        homospline_voronoi::grid::cell_holding(&self.origin, self.cell, self.w, self.h, p)
    }

    /// Exact distance from `p` to the nearest occupied cell (negative inside one: minus the
    /// distance to its nearest side). Outside the grid: the distance to the grid (the wall).
    pub fn exact(&self, p: &Point) -> Real {
        let Some((ci, cj)) = self.cell_of(p) else {
            return 0.0;
        };
        let h = self.cell;
        if self.occupied(cj * self.w + ci) {
            let x0 = self.origin.x + ci as Real * h;
            let y0 = self.origin.y + cj as Real * h;
            return -(p.x - x0).min(x0 + h - p.x).min(p.y - y0).min(y0 + h - p.y);
        }
        let d2 = self.d2[cj * self.w + ci] as i64;
        if d2 > (self.w * self.w + self.h * self.h) as i64 {
            // No occupied cell at all.
            return self.exact_by_rings(p, ci, cj, Real::INFINITY);
        }
        // Only the cells of the annulus (see `annulus`) can be nearest; the first query in a
        // cell lists them.
        let dc = (d2 as Real).sqrt();
        let bound = (dc + std::f64::consts::FRAC_1_SQRT_2 - 0.5) * h;
        self.with_candidates(ci, cj, d2, |candidates| {
            let least = candidates.iter().fold(Real::INFINITY, |b, &o| {
                let (i, j) = unpack(o);
                b.min(self.square_distance2(p, i, j))
            });
            // The same as the least of the distances: the square root is monotone.
            if least < bound * bound {
                least.sqrt().min(bound)
            } else {
                bound
            }
        })
    }

    /// `f` of the candidates of free cell `(ci, cj)` (squared distance `d2`): from the
    /// cache, or listed and cached.
    fn with_candidates<R>(&self, ci: usize, cj: usize, d2: i64, f: impl Fn(&[u32]) -> R) -> R {
        let k = (cj * self.w + ci) as u32;
        let slot = (k as usize ^ (self.id as usize).wrapping_mul(0x9e37_79b9)) % MEMO_SLOTS;
        let memo = MEMO.with_borrow(|memo| match &memo[slot] {
            Some((id, cell, list)) if *id == self.id && *cell == k => Some(f(list)),
            _ => None,
        });
        if let Some(out) = memo {
            return out;
        }
        let shard = &self.candidates[k as usize % CACHE_SHARDS];
        let cached = shard
            .read()
            .unwrap_or_else(PoisonError::into_inner)
            .get(&k)
            .cloned();
        let list = match cached {
            Some(list) => list,
            None => {
                let list: Arc<[u32]> = self.annulus(ci, cj, d2).into();
                shard
                    .write()
                    .unwrap_or_else(PoisonError::into_inner)
                    .entry(k)
                    .or_insert(list)
                    .clone()
            }
        };
        let out = f(&list);
        MEMO.with_borrow_mut(|memo| memo[slot] = Some((self.id, k, list)));
        out
    }

    /// [`GridModel::exact`] and its gradient: the unit vector from the nearest point of the
    /// nearest occupied cell to `p` (inside one, the outward normal of its nearest side); zero
    /// where the distance has none (outside the grid, on an obstacle's boundary).
    pub fn exact_with_gradient(&self, p: &Point) -> (Real, Vector) {
        let Some((ci, cj)) = self.cell_of(p) else {
            return (0.0, Vector::zeros());
        };
        let h = self.cell;
        let k = cj * self.w + ci;
        if self.occupied(k) {
            let x0 = self.origin.x + ci as Real * h;
            let y0 = self.origin.y + cj as Real * h;
            let sides = [
                (p.x - x0, Vector::new(-1.0, 0.0)),
                (x0 + h - p.x, Vector::new(1.0, 0.0)),
                (p.y - y0, Vector::new(0.0, -1.0)),
                (y0 + h - p.y, Vector::new(0.0, 1.0)),
            ];
            let (d, n) = sides
                .into_iter()
                .fold((Real::INFINITY, Vector::zeros()), |b, s| {
                    if s.0 < b.0 { s } else { b }
                });
            return (-d, n);
        }
        let d2 = self.d2[k] as i64;
        if d2 > (self.w * self.w + self.h * self.h) as i64 {
            return (
                self.exact_by_rings(p, ci, cj, Real::INFINITY),
                Vector::zeros(),
            );
        }
        self.with_candidates(ci, cj, d2, |candidates| {
            let (mut best, mut towards) = (Real::INFINITY, Vector::zeros());
            for &o in candidates {
                let (i, j) = unpack(o);
                let x0 = self.origin.x + i as Real * h;
                let y0 = self.origin.y + j as Real * h;
                let v = Vector::new(p.x - p.x.clamp(x0, x0 + h), p.y - p.y.clamp(y0, y0 + h));
                let n = v.norm_squared();
                if n < best {
                    best = n;
                    towards = v;
                }
            }
            let best = best.sqrt();
            let g = if best > 0.0 {
                towards / best
            } else {
                Vector::zeros()
            };
            (best, g)
        })
    }

    /// The occupied cells that can be nearest to a point of free cell `(ci, cj)`, whose
    /// squared brushfire distance is `d2`. In cells (h = 1): every occupied centre o has
    /// |c - o|^2 >= d2 (the exact brushfire of centre c), and the nearest one, o*, has
    /// |c - o*| = D = sqrt(d2). A square holds the disc of radius 1/2 around its centre, so
    /// the answer is at most |p - o*| - 1/2 <= D + sqrt(2)/2 - 1/2. A square at o is at least
    /// |p - o| - sqrt(2)/2 >= |c - o| - sqrt(2) away, so only centres with
    /// |c - o| <= D + sqrt(2)/2 - 1/2 + sqrt(2) can beat it: an annulus of width 1.62
    /// instead of the whole disc; of its occupied cells, only those beside a free cell
    /// ([`GridModel::on_boundary`]).
    fn annulus(&self, ci: usize, cj: usize, d2: i64) -> Box<[u32]> {
        let dc = (d2 as Real).sqrt();
        let best0 = dc + std::f64::consts::FRAC_1_SQRT_2 - 0.5;
        let outer = best0 + std::f64::consts::SQRT_2 + 1e-9;
        let outer2 = outer * outer;
        let reach = outer as i64; // truncation is floor here: all >= 0
        let mut out = Vec::new();
        for dy in -reach..=reach {
            let j = cj as i64 + dy;
            if j < 0 || j >= self.h as i64 {
                continue;
            }
            let dy2 = dy * dy;
            let rest = outer2 - dy2 as Real;
            if rest < 0.0 {
                continue;
            }
            let hi = rest.sqrt() as i64;
            // Smallest dx >= 0 with dx^2 + dy^2 >= d2, in integers.
            let mut lo = ((d2 - dy2).max(0) as Real).sqrt() as i64;
            while lo * lo + dy2 < d2 {
                lo += 1;
            }
            while lo > 0 && (lo - 1) * (lo - 1) + dy2 >= d2 {
                lo -= 1;
            }
            for dx in lo..=hi {
                for i in [ci as i64 + dx, ci as i64 - dx] {
                    if i >= 0 && (i as usize) < self.w {
                        let k = j as usize * self.w + i as usize;
                        if self.occupied(k) && self.on_boundary(i as usize, j as usize) {
                            out.push(i as u32 | (j as u32) << 16);
                        }
                    }
                    if dx == 0 {
                        break;
                    }
                }
            }
        }
        out.into_boxed_slice()
    }

    /// Whether occupied cell `(i, j)` has a free 4-neighbour. Only such cells can hold the
    /// nearest occupied point to a free point: that point lies on a side shared with a free
    /// cell, or is a corner, which it shares with a cell beside a free cell.
    fn on_boundary(&self, i: usize, j: usize) -> bool {
        let k = j * self.w + i;
        (i > 0 && !self.occupied(k - 1))
            || (i + 1 < self.w && !self.occupied(k + 1))
            || (j > 0 && !self.occupied(k - self.w))
            || (j + 1 < self.h && !self.occupied(k + self.w))
    }

    /// Distance from `p` to the closed square of cell `(i, j)`.
    fn square_distance(&self, p: &Point, i: usize, j: usize) -> Real {
        self.square_distance2(p, i, j).sqrt()
    }

    /// Its square.
    #[inline]
    fn square_distance2(&self, p: &Point, i: usize, j: usize) -> Real {
        let h = self.cell;
        let x0 = self.origin.x + i as Real * h;
        let y0 = self.origin.y + j as Real * h;
        let dx = (x0 - p.x).max(p.x - x0 - h).max(0.0);
        let dy = (y0 - p.y).max(p.y - y0 - h).max(0.0);
        dx * dx + dy * dy
    }

    /// The field at each of `pts`, one after the other ([`ClearanceModel::field_batch`]).
    fn field_serial(&self, pts: &[Point], alpha: Real, out: &mut [FieldSample]) {
        for (p, o) in pts.iter().zip(out.iter_mut()) {
            let (d, g) = self.exact_with_gradient(p);
            let d = d - self.offset;
            // U = 1 + tanh(-alpha d) = 2 / (1 + exp(2 alpha d)); dU/dd = -alpha U (2 - U).
            let u = 2.0 / (1.0 + exp_fast(2.0 * alpha * d));
            *o = FieldSample {
                potential: u,
                potential_grad: g * (-alpha * u * (2.0 - u)),
                clearance: d,
                clearance_grad: g,
            };
        }
    }

    /// [`GridModel::exact`] by Chebyshev rings around cell `(ci, cj)` from the nearest out,
    /// starting from the upper bound `best`: the reference the annulus search is tested on,
    /// and the answer on a grid without occupied cells.
    fn exact_by_rings(&self, p: &Point, ci: usize, cj: usize, mut best: Real) -> Real {
        let h = self.cell;
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
                    if i >= 0
                        && (i as usize) < self.w
                        && self.occupied(j as usize * self.w + i as usize)
                    {
                        best = best.min(self.square_distance(p, i as usize, j as usize));
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

/// From this many samples on, [`GridModel`]'s field is evaluated in parallel (half as many
/// to a job): a curve across a 4096 x 4096 map has tens of thousands.
const PARALLEL_SAMPLES: usize = 4096;

impl ClearanceModel for GridModel {
    fn clearance(&self, p: &Point) -> (Real, Vector) {
        let (d, g) = self.exact_with_gradient(p);
        (d - self.offset, g)
    }

    fn field_batch(&self, pts: &[Point], alpha: Real, _allowance: Real, out: &mut [FieldSample]) {
        // A long curve's samples (a route across a large map) in parallel: each sample's
        // value is its own, so the result is the same on any number of threads.
        if pts.len() >= PARALLEL_SAMPLES {
            use rayon::prelude::*;
            pts.par_chunks(PARALLEL_SAMPLES / 2)
                .zip(out.par_chunks_mut(PARALLEL_SAMPLES / 2))
                .for_each(|(p, o)| self.field_serial(p, alpha, o));
        } else {
            self.field_serial(pts, alpha, out);
        }
    }

    fn line_of_sight(&self, a: &Point, b: &Point) -> bool {
        let n = (((b - a).norm() / (0.25 * self.cell)).ceil() as usize).max(1);
        (0..=n).all(|k| {
            let p = a + (b - a) * (k as Real / n as Real);
            self.cell_of(&p).is_some_and(|(i, j)| {
                !self.occupied(j * self.w + i)
                    && (self.offset == 0.0 || self.exact(&p) >= self.offset)
            })
        })
    }

    fn segment_clearance(&self, a: &Point, b: &Point) -> Real {
        self.segment_clearance_between(a, b, self.exact_clearance(a), self.exact_clearance(b))
    }

    fn polyline_clearance(&self, pts: &[Point]) -> Real {
        // The same bound segment by segment, with each point's exact distance found once.
        let at: Vec<Real> = pts.iter().map(|p| self.exact_clearance(p)).collect();
        (1..pts.len())
            .map(|i| self.segment_clearance_between(&pts[i - 1], &pts[i], at[i - 1], at[i]))
            .fold(Real::INFINITY, Real::min)
    }

    fn segment_clearance_between(&self, a: &Point, b: &Point, da: Real, db: Real) -> Real {
        // At distance s from a along the segment, d >= max(da - s, db - (|ab| - s)), whose
        // least value over s is their average: (da + db - |ab|) / 2, never below
        // min(da, db) - |ab| / 2 and equal to it only when da = db.
        0.5 * (da + db - (b - a).norm())
    }

    fn exact_clearance(&self, p: &Point) -> Real {
        self.exact(p) - self.offset
    }

    fn bend_radius(&self) -> Option<Real> {
        Some(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The annulus search finds exactly what the full ring search finds, anywhere on a
        /// random grid (free and occupied cells, near walls, far from them).
        #[test]
        fn annulus_search_equals_ring_search(
            seed in any::<u64>(),
            density in 0.0..0.3f64,
            cell in 0.05..2.0f64,
        ) {
            let (w, h) = (29, 23);
            let mut state = seed | 1;
            let mut next = move || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as Real / (1u64 << 53) as Real
            };
            let occ = (0..w * h).map(|_| next() < density * 0.3).collect();
            let origin = Point::new(-3.0, 1.5);
            let grid = Grid::from_occupancy(w, h, origin, cell, occ).unwrap();
            let model = GridModel::new(&grid, &DistanceField::build(&grid));
            for _ in 0..200 {
                let p = Point::new(
                    origin.x + next() * w as Real * cell,
                    origin.y + next() * h as Real * cell,
                );
                let (ci, cj) = model.cell_of(&p).unwrap();
                let rings = if model.occupied(cj * w + ci) {
                    model.exact(&p)
                } else {
                    model.exact_by_rings(&p, ci, cj, Real::INFINITY)
                };
                prop_assert_eq!(model.exact(&p), rings, "at {}", p);
            }
        }
    }
}
