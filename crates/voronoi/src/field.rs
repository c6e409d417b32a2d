//! The brushfire: exact Euclidean distance from every cell to the nearest obstacle cell, and
//! which obstacle that is, with local updates when obstacles appear or vanish.
//!
//! Obstacles are the 8-connected components of occupied cells (the wall ring is one of
//! them); each is keyed by the smallest raster index among its cells, a key that does not
//! change when other obstacles come and go. Every cell stores
//! `K |c - o|^2 + key(o)` minimised over all occupied cells `o` (`K = 2^25 > key`): the
//! exact squared distance in cells and, among equally near obstacles, the one with the
//! smallest key. That is a pure function of the occupancy, so a local update and a full
//! rebuild agree bit for bit.
//!
//! It is computed with the separable transform of Felzenszwalb and Huttenlocher (a column
//! pass, then the lower envelope of parabolas along each row) in exact integer arithmetic:
//! distances have no error with respect to cell centres (the clearance in map units is
//! `(sqrt(d2) - 1/2) h`, within `(sqrt 2 - 1) h / 2` of the distance to the nearest occupied
//! cell's square).

use thiserror::Error;

use rayon::prelude::*;

use crate::grid::Grid;
use crate::union_find::find_root;

/// `K` of the packed value: keys are raster indices below `2^25`.
pub const KEY_BITS: u32 = 25;
const KEY_MASK: i64 = (1 << KEY_BITS) - 1;
const NONE: i64 = i64::MAX;

/// Why an update cannot be applied locally.
#[derive(Debug, Error, PartialEq)]
pub enum UpdateError {
    /// A cell is out of the grid or on the wall ring.
    #[error("cell ({0}, {1}) is outside the grid's interior")]
    OutOfGrid(usize, usize),
    /// The new obstacle touches an existing one (they would merge into one obstacle).
    #[error("the new obstacle touches an existing obstacle at cell ({0}, {1}): rebuild instead")]
    Touches(usize, usize),
    /// No obstacle has that key.
    #[error("no obstacle has key {0}")]
    NoSuchObstacle(u32),
    /// The wall cannot be removed.
    #[error("the wall ring cannot be removed")]
    Wall,
}

/// Distance and nearest obstacle of every cell.
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceField {
    width: usize,
    height: usize,
    val: Vec<i64>,
    /// Upper bound of every cell's squared distance.
    max_d2: i64,
    /// Per obstacle key: bounding box of its cells `(i0, j0, i1, j1)`.
    boxes: Boxes,
}

/// Key of each occupied cell (`u32::MAX` for free cells): 8-connected components keyed by
/// their smallest raster index.
pub fn obstacle_keys(grid: &Grid) -> Vec<u32> {
    keys_and_boxes(grid).0
}

/// Bounding box `(i0, j0, i1, j1)` of each obstacle's cells, by key.
/// A bounding box of cells `(i0, j0, i1, j1)`.
type Bbox = (usize, usize, usize, usize);

type Boxes = std::collections::BTreeMap<u32, Bbox>;

/// [`obstacle_keys`] and the obstacles' bounding boxes, both from the runs of occupied cells.
fn keys_and_boxes(grid: &Grid) -> (Vec<u32>, Boxes) {
    let (w, h) = (grid.width(), grid.height());
    let occ = grid.occupancy();
    // Runs of occupied cells along each row: (first cell's raster index, end column).
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut row_start = vec![0usize; h + 1];
    for j in 0..h {
        row_start[j] = runs.len();
        let row = &occ[j * w..(j + 1) * w];
        let mut i = 0;
        while i < w {
            if !row[i] {
                i += 1;
                continue;
            }
            let b = i;
            while i < w && row[i] {
                i += 1;
            }
            runs.push((j * w + b, i));
        }
    }
    row_start[h] = runs.len();
    // Union-find over runs; the root is the run whose first cell has the smallest raster
    // index, which is the component's key.
    let mut parent: Vec<usize> = (0..runs.len()).collect();
    for j in 1..h {
        let (mut a, a_end) = (row_start[j - 1], row_start[j]);
        for r in row_start[j]..row_start[j + 1] {
            let (b0, b1) = (runs[r].0 - j * w, runs[r].1);
            // 8-connected: runs touch when their column spans, widened by one, overlap.
            while a < a_end && runs[a].1 < b0 {
                a += 1;
            }
            let mut k = a;
            while k < a_end {
                let (c0, c1) = (runs[k].0 - (j - 1) * w, runs[k].1);
                if c0 > b1 {
                    break;
                }
                if c1 >= b0 {
                    let (x, y) = (find_root(&mut parent, r), find_root(&mut parent, k));
                    if x != y {
                        let (lo, hi) = if runs[x].0 < runs[y].0 {
                            (x, y)
                        } else {
                            (y, x)
                        };
                        parent[hi] = lo;
                    }
                }
                k += 1;
            }
        }
    }
    let mut keys = vec![u32::MAX; w * h];
    // Each component's box, held by its root run (a map of random cells has millions of
    // obstacles: one ordered-map update per run was a twentieth of a map's preparation).
    let mut by_root: Vec<[u32; 4]> = vec![[u32::MAX, u32::MAX, 0, 0]; runs.len()];
    for j in 0..h {
        for r in row_start[j]..row_start[j + 1] {
            let root = find_root(&mut parent, r);
            let key = runs[root].0 as u32;
            let start = runs[r].0;
            let (i0, i1) = (start - j * w, runs[r].1);
            keys[start..start + (i1 - i0)]
                .iter_mut()
                .for_each(|k| *k = key);
            let b = &mut by_root[root];
            b[0] = b[0].min(i0 as u32);
            b[1] = b[1].min(j as u32);
            b[2] = b[2].max((i1 - 1) as u32);
            b[3] = b[3].max(j as u32);
        }
    }
    // Roots in run order are in key order: the map is built from sorted entries.
    let boxes = (0..runs.len())
        .filter(|&r| parent[r] == r)
        .map(|r| {
            let b = by_root[r];
            (
                runs[r].0 as u32,
                (b[0] as usize, b[1] as usize, b[2] as usize, b[3] as usize),
            )
        })
        .collect();
    (keys, boxes)
}

/// The exact transform over the window `[i0, i1) x [j0, j1)` with sources given row by
/// row: `key_row(y, out)` writes the keys of window row `y` (`u32::MAX` where there is no
/// source). Returns packed values row-major over the window (`NONE` where no source is in
/// the window) and the largest squared distance among the rows that have a source.
///
/// Both passes run in parallel (rayon) on large windows: the column pass by strips of
/// columns, the row pass by rows. Each strip and each row is computed alone, so the result is
/// the same for any number of threads.
fn transform(
    i0: usize,
    i1: usize,
    j0: usize,
    j1: usize,
    key_row: impl Fn(usize, &mut [u32]) + Sync,
) -> (Vec<i64>, i64) {
    let (w, h) = (i1 - i0, j1 - j0);
    if w == 0 || h == 0 {
        return (Vec::new(), 0);
    }
    // Strips of columns for the column pass: one per thread's share of the work, and none on
    // a small window (the threads' start-up would cost more than they save).
    let parallel = w * h >= PARALLEL_CELLS;
    let strips = if parallel {
        rayon::current_num_threads().clamp(1, w.div_ceil(STRIP_MIN))
    } else {
        1
    };
    let bounds: Vec<(usize, usize)> = (0..strips)
        .map(|s| (w * s / strips, w * (s + 1) / strips))
        .collect();
    let mut g: Vec<i64> = vec![0; w * h];
    {
        // Each strip's piece of every row, so that the strips are written in place.
        let mut pieces: Vec<Vec<&mut [i64]>> = (0..strips).map(|_| Vec::with_capacity(h)).collect();
        for row in g.chunks_mut(w) {
            let mut rest = row;
            for (strip, &(c0, c1)) in pieces.iter_mut().zip(&bounds) {
                let (piece, tail) = rest.split_at_mut(c1 - c0);
                strip.push(piece);
                rest = tail;
            }
        }
        let column_pass = |(rows, &(c0, c1)): (Vec<&mut [i64]>, &(usize, usize))| {
            column_strip(rows, w, c0, c1, &key_row)
        };
        if strips > 1 {
            pieces
                .into_par_iter()
                .zip(bounds.par_iter())
                .for_each(column_pass);
        } else {
            pieces.into_iter().zip(bounds.iter()).for_each(column_pass);
        }
    }
    // Row pass: each row's lower envelope in place.
    let max_d2 = if parallel {
        g.par_chunks_mut(w)
            .map_init(|| Envelope::new(w), |scratch, row| scratch.apply(row))
            .reduce(|| 0, i64::max)
    } else {
        let mut scratch = Envelope::new(w);
        g.chunks_mut(w)
            .map(|row| scratch.apply(row))
            .fold(0, i64::max)
    };
    (g, max_d2)
}

/// Windows of at least this many cells are transformed in parallel. The threshold stays
/// small: a graph build alone runs a paper scene's grid a little faster serially, but inside
/// the plan, whose pool is awake from its classes, the parallel transform makes the plans
/// faster (measured: docs/performance.md, "Measurements behind the defaults").
pub const PARALLEL_CELLS: usize = 1 << 14;

/// The narrowest strip of columns worth a thread of its own.
const STRIP_MIN: usize = 64;

/// The column pass over columns `[c0, c1)` of a window `w` wide, written into `rows` (the
/// strip's piece of each window row), as two row-major sweeps (nearest source above, then
/// below, in each column, lexicographic in `(dy^2, key)`).
fn column_strip(
    mut rows: Vec<&mut [i64]>,
    w: usize,
    c0: usize,
    c1: usize,
    key_row: &(impl Fn(usize, &mut [u32]) + Sync),
) {
    let h = rows.len();
    let mut sweep = Sweep {
        krow: vec![u32::MAX; w],
        last_y: vec![-1; c1 - c0],
        last_k: vec![0; c1 - c0],
        c0,
        c1,
    };
    sweep.run(&mut rows, 0..h, key_row, true);
    sweep.last_y.iter_mut().for_each(|l| *l = -1);
    sweep.run(&mut rows, (0..h).rev(), key_row, false);
}

/// One sweep of the column pass: per column of the strip, the row of the last source seen
/// (-1: none yet) and its key.
struct Sweep {
    krow: Vec<u32>,
    last_y: Vec<i64>,
    last_k: Vec<i64>,
    c0: usize,
    c1: usize,
}

impl Sweep {
    /// Visits `rows` in `order`; each slot takes the packed value of the nearest source seen
    /// so far in its column (`first`: it is set, else it keeps the lesser of the two).
    fn run(
        &mut self,
        rows: &mut [&mut [i64]],
        order: impl Iterator<Item = usize>,
        key_row: &(impl Fn(usize, &mut [u32]) + Sync),
        first: bool,
    ) {
        let k = 1i64 << KEY_BITS;
        for y in order {
            key_row(y, &mut self.krow);
            let yy = y as i64;
            for (((slot, &kk), ly), lk) in rows[y]
                .iter_mut()
                .zip(self.krow[self.c0..self.c1].iter())
                .zip(self.last_y.iter_mut())
                .zip(self.last_k.iter_mut())
            {
                let here = kk != u32::MAX;
                *ly = if here { yy } else { *ly };
                *lk = if here { kk as i64 } else { *lk };
                let d = yy - *ly;
                let v = if *ly >= 0 { k * d * d + *lk } else { NONE };
                *slot = if first { v } else { (*slot).min(v) };
            }
        }
    }
}

/// The row pass's scratch: the lower envelope of `f_q(x) = K (x - q)^2 + G(q)`. Piece `t` of
/// the envelope is parabola `v` (with `F = G + K q^2` in `fv`), starting at
/// `s_t = zn / (2 K zq)` (piece 0 starts at -inf; its `zn`, `zq` are not read).
struct Envelope {
    pieces: Vec<Piece>,
}

/// One piece of an [`Envelope`].
#[derive(Clone, Copy, Default)]
struct Piece {
    v: usize,
    fv: i64,
    zn: i64,
    zq: i64,
}

impl Envelope {
    fn new(w: usize) -> Self {
        Self {
            pieces: vec![Piece::default(); w],
        }
    }

    /// Replaces the column pass's values of `row` by the transform's, in place; returns the
    /// row's largest squared distance (0 for a row without a source).
    fn apply(&mut self, row: &mut [i64]) -> i64 {
        let k = 1i64 << KEY_BITS;
        let pieces = &mut self.pieces[..row.len()];
        let mut top = 0usize;
        for (q, &gq) in row.iter().enumerate() {
            if gq == NONE {
                continue;
            }
            let fq = gq + k * (q * q) as i64;
            // Drop pieces that the new parabola hides: where it meets the last piece,
            // s = (F(q) - F(p)) / (2 K (q - p)), is not after that piece's start.
            while top > 1 {
                let last = pieces[top - 1];
                if le_ratio(fq - last.fv, (q - last.v) as i64, last.zn, last.zq) {
                    top -= 1;
                } else {
                    break;
                }
            }
            let (zn, zq) = match top {
                0 => (0, 0),
                _ => {
                    let last = pieces[top - 1];
                    (fq - last.fv, (q - last.v) as i64)
                }
            };
            pieces[top] = Piece {
                v: q,
                fv: fq,
                zn,
                zq,
            };
            top += 1;
        }
        if top == 0 {
            return 0;
        }
        // In place: a piece's G(q) is F(q) - K q^2, so the row is no longer read.
        let pieces = &pieces[..top];
        let mut idx = 0;
        let mut here = pieces[0];
        let mut row_max = 0;
        for (x, o) in row.iter_mut().enumerate() {
            // s < x  <=>  zn < 2 K zq x, far inside i64 for any grid whose values fit.
            while let Some(next) = pieces.get(idx + 1)
                && next.zn < ((x as i64 * next.zq) << (KEY_BITS + 1))
            {
                idx += 1;
                here = *next;
            }
            let q = here.v as i64;
            let dx = x as i64 - q;
            *o = k * dx * dx + (here.fv - k * q * q);
            row_max = row_max.max(*o >> KEY_BITS);
        }
        row_max
    }
}

/// `a / b <= c / d` for `b, d > 0`, exactly: in `i64` while the products fit (grids up to
/// 4096 cells across), else in `i128`.
#[inline]
fn le_ratio(a: i64, b: i64, c: i64, d: i64) -> bool {
    match (a.checked_mul(d), c.checked_mul(b)) {
        (Some(l), Some(r)) => l <= r,
        _ => (a as i128) * (d as i128) <= (c as i128) * (b as i128),
    }
}

impl DistanceField {
    /// The field of `grid`, built from scratch.
    pub fn build(grid: &Grid) -> Self {
        let (keys, boxes) = keys_and_boxes(grid);
        let (w, h) = (grid.width(), grid.height());
        let (val, max_d2) = transform(0, w, 0, h, |y, out| {
            out.copy_from_slice(&keys[y * w..(y + 1) * w]);
        });
        Self {
            width: w,
            height: h,
            val,
            max_d2,
            boxes,
        }
    }

    /// Cells across.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Cells up.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Squared distance, in cells, from `(i, j)`'s centre to the nearest occupied cell's
    /// centre (0 on obstacles).
    #[inline]
    pub fn d2(&self, i: usize, j: usize) -> i64 {
        self.val[j * self.width + i] >> KEY_BITS
    }

    /// [`DistanceField::d2`] of the cell with raster index `k = j * width + i`.
    #[inline]
    pub fn d2_at(&self, k: usize) -> i64 {
        self.val[k] >> KEY_BITS
    }

    /// Key of the nearest obstacle (its own key on an occupied cell).
    #[inline]
    pub fn nearest(&self, i: usize, j: usize) -> u32 {
        (self.val[j * self.width + i] & KEY_MASK) as u32
    }

    /// [`DistanceField::d2`] of every cell of row `j`, written to `out` (`width` long).
    pub fn d2_row(&self, j: usize, out: &mut [i64]) {
        let row = &self.val[j * self.width..(j + 1) * self.width];
        for (o, v) in out.iter_mut().zip(row) {
            *o = v >> KEY_BITS;
        }
    }

    /// [`DistanceField::nearest`] of every cell of row `j`, written to `out` (`width` long).
    pub fn nearest_row(&self, j: usize, out: &mut [u32]) {
        let row = &self.val[j * self.width..(j + 1) * self.width];
        for (o, v) in out.iter_mut().zip(row) {
            *o = (v & KEY_MASK) as u32;
        }
    }

    /// [`DistanceField::nearest`] of the cell with raster index `k = j * width + i`.
    #[inline]
    pub fn nearest_at(&self, k: usize) -> u32 {
        (self.val[k] & KEY_MASK) as u32
    }

    /// Clearance of `(i, j)` in cells: `sqrt(d2) - 1/2` on free cells, 0 on obstacles.
    #[inline]
    pub fn clearance_cells(&self, i: usize, j: usize) -> f64 {
        let d2 = self.d2(i, j);
        if d2 == 0 {
            0.0
        } else {
            (d2 as f64).sqrt() - 0.5
        }
    }

    /// The obstacle keys present.
    pub fn obstacles(&self) -> impl Iterator<Item = u32> + '_ {
        self.boxes.keys().copied()
    }

    /// Key of the wall ring (the obstacle holding cell (0, 0)).
    pub fn wall_key(&self) -> u32 {
        0
    }

    /// Marks `cells` occupied in `grid` as one or more new obstacles and updates the field
    /// locally: only cells within `sqrt(max d2) + 1` of the new cells are visited, since a
    /// cell can only get nearer to the new obstacle than to its old one if it was that far
    /// from every obstacle. Returns the number of cells visited. The new cells may not touch
    /// an existing obstacle (they would merge with it): rebuild for that.
    pub fn add_obstacle(
        &mut self,
        grid: &mut Grid,
        cells: &[(usize, usize)],
    ) -> Result<usize, UpdateError> {
        let (w, h) = (self.width, self.height);
        for &(i, j) in cells {
            if i == 0 || j == 0 || i + 1 >= w || j + 1 >= h {
                return Err(UpdateError::OutOfGrid(i, j));
            }
        }
        let new: std::collections::HashSet<(usize, usize)> = cells.iter().copied().collect();
        if let Some(&(i, j)) = cells.iter().find(|&&(i, j)| grid.occupied(i, j)) {
            return Err(UpdateError::Touches(i, j));
        }
        for &(i, j) in cells {
            for dj in -1i64..=1 {
                for di in -1i64..=1 {
                    let (ni, nj) = ((i as i64 + di) as usize, (j as i64 + dj) as usize);
                    if grid.occupied(ni, nj) && !new.contains(&(ni, nj)) {
                        return Err(UpdateError::Touches(ni, nj));
                    }
                }
            }
        }
        if cells.is_empty() {
            return Ok(0);
        }
        for &(i, j) in cells {
            grid.set(i, j, true);
        }
        // Components of the new cells alone (they touch nothing else).
        let mut key_of: std::collections::HashMap<(usize, usize), u32> =
            std::collections::HashMap::new();
        let mut sorted: Vec<(usize, usize)> = new.iter().copied().collect();
        sorted.sort_by_key(|&(i, j)| (j, i));
        for &start in &sorted {
            if key_of.contains_key(&start) {
                continue;
            }
            let key = grid.index(start.0, start.1) as u32;
            let mut stack = vec![start];
            key_of.insert(start, key);
            let mut bx = (start.0, start.1, start.0, start.1);
            while let Some((i, j)) = stack.pop() {
                bx = (bx.0.min(i), bx.1.min(j), bx.2.max(i), bx.3.max(j));
                for dj in -1i64..=1 {
                    for di in -1i64..=1 {
                        let n = ((i as i64 + di) as usize, (j as i64 + dj) as usize);
                        if new.contains(&n) && !key_of.contains_key(&n) {
                            key_of.insert(n, key);
                            stack.push(n);
                        }
                    }
                }
            }
            self.boxes.insert(key, bx);
        }
        Ok(self.lower_towards(cells, &key_of))
    }

    /// Marks `cells` occupied in `grid` and updates the field locally, like
    /// [`DistanceField::add_obstacle`], but the new cells may also join an existing obstacle
    /// (a blockage across a passage touches the passage's walls). Each group of new cells
    /// (8-connected among themselves) that touches no obstacle becomes an obstacle of its
    /// own; one that touches exactly one obstacle whose key is below the raster index of
    /// every cell of the group joins it under that key. Then no obstacle is renamed, so every
    /// cell's value can only fall to its distance to the new cells, and only cells within
    /// `sqrt(max d2) + 1` of them are visited. Cells already occupied are ignored. Refused
    /// with [`UpdateError::Touches`], before anything changes, when a group joins two
    /// obstacles or would become an obstacle's smallest cell (obstacles renamed: rebuild).
    /// Returns the number of cells visited.
    pub fn add_cells(
        &mut self,
        grid: &mut Grid,
        cells: &[(usize, usize)],
    ) -> Result<usize, UpdateError> {
        let (w, h) = (self.width, self.height);
        for &(i, j) in cells {
            if i == 0 || j == 0 || i + 1 >= w || j + 1 >= h {
                return Err(UpdateError::OutOfGrid(i, j));
            }
        }
        let mut sorted: Vec<(usize, usize)> = cells
            .iter()
            .copied()
            .filter(|&(i, j)| !grid.occupied(i, j))
            .collect();
        sorted.sort_by_key(|&(i, j)| (j, i));
        sorted.dedup();
        if sorted.is_empty() {
            return Ok(0);
        }
        let new: std::collections::HashSet<(usize, usize)> = sorted.iter().copied().collect();
        // Groups of new cells, in raster order of their first cell, with the key each takes.
        let mut key_of: std::collections::HashMap<(usize, usize), u32> =
            std::collections::HashMap::new();
        // (key, bounding box, joined an existing obstacle)
        let mut groups: Vec<(u32, Bbox, bool)> = Vec::new();
        for &start in &sorted {
            if key_of.contains_key(&start) {
                continue;
            }
            let own = grid.index(start.0, start.1) as u32;
            let mut members = vec![start];
            key_of.insert(start, own);
            let mut touched: Option<(u32, (usize, usize))> = None;
            let mut k = 0;
            while k < members.len() {
                let (i, j) = members[k];
                k += 1;
                for dj in -1i64..=1 {
                    for di in -1i64..=1 {
                        let n = ((i as i64 + di) as usize, (j as i64 + dj) as usize);
                        if new.contains(&n) {
                            if let std::collections::hash_map::Entry::Vacant(e) = key_of.entry(n) {
                                e.insert(own);
                                members.push(n);
                            }
                        } else if grid.occupied(n.0, n.1) {
                            let other = self.nearest(n.0, n.1);
                            match touched {
                                Some((t, _)) if t != other => {
                                    return Err(UpdateError::Touches(n.0, n.1));
                                }
                                _ => touched = Some((other, n)),
                            }
                        }
                    }
                }
            }
            let mut bx = (start.0, start.1, start.0, start.1);
            for &(i, j) in &members {
                bx = (bx.0.min(i), bx.1.min(j), bx.2.max(i), bx.3.max(j));
            }
            // `own` is the group's smallest raster index (its first cell in raster order).
            let key = match touched {
                None => own,
                Some((t, _)) if t < own => t,
                Some((_, (i, j))) => return Err(UpdateError::Touches(i, j)),
            };
            for m in &members {
                key_of.insert(*m, key);
            }
            groups.push((key, bx, touched.is_some()));
        }
        for &(i, j) in &sorted {
            grid.set(i, j, true);
        }
        for (key, bx, joined) in groups {
            let b = if joined {
                let o = self.boxes.get(&key).copied().unwrap_or(bx);
                (o.0.min(bx.0), o.1.min(bx.1), o.2.max(bx.2), o.3.max(bx.3))
            } else {
                bx
            };
            self.boxes.insert(key, b);
        }
        Ok(self.lower_towards(&sorted, &key_of))
    }

    /// The common end of [`DistanceField::add_obstacle`] and [`DistanceField::add_cells`]:
    /// every cell within `sqrt(max d2) + 1` of the box of `cells` takes the lesser of its
    /// value and its (squared distance, key) to the new cells `key_of`, found by one exact
    /// transform over that window. Returns the number of cells visited.
    fn lower_towards(
        &mut self,
        cells: &[(usize, usize)],
        key_of: &std::collections::HashMap<(usize, usize), u32>,
    ) -> usize {
        let (w, h) = (self.width, self.height);
        let (mut i0, mut j0, mut i1, mut j1) = (w, h, 0, 0);
        for &(i, j) in cells {
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        }
        let r = (self.max_d2 as f64).sqrt().ceil() as usize + 1;
        let (wi0, wj0) = (i0.saturating_sub(r), j0.saturating_sub(r));
        let (wi1, wj1) = ((i1 + r + 1).min(w), (j1 + r + 1).min(h));
        let ww = wi1 - wi0;
        // The new cells as a dense source array over the window.
        let mut src = vec![u32::MAX; ww * (wj1 - wj0)];
        for (&(i, j), &kk) in key_of {
            src[(j - wj0) * ww + (i - wi0)] = kk;
        }
        let (vals, _) = transform(wi0, wi1, wj0, wj1, |y, out| {
            out.copy_from_slice(&src[y * ww..(y + 1) * ww]);
        });
        for y in wj0..wj1 {
            for x in wi0..wi1 {
                let nv = vals[(y - wj0) * ww + (x - wi0)];
                let c = &mut self.val[y * w + x];
                if nv < *c {
                    *c = nv;
                }
            }
        }
        ww * (wj1 - wj0)
    }

    /// Removes the obstacle with `key` from `grid` and updates the field locally: only the
    /// cells whose nearest obstacle it was change, and they are recomputed from the
    /// obstacles in a window around them, grown until every answer is provably the nearest.
    /// Returns the number of cells visited.
    pub fn remove_obstacle(&mut self, grid: &mut Grid, key: u32) -> Result<usize, UpdateError> {
        if key == self.wall_key() {
            return Err(UpdateError::Wall);
        }
        let (w, h) = (self.width, self.height);
        let bx = self
            .boxes
            .remove(&key)
            .ok_or(UpdateError::NoSuchObstacle(key))?;
        // Its cells lie in its box; the cells it was nearest to lie within sqrt(max d2).
        let r = (self.max_d2 as f64).sqrt().ceil() as usize + 1;
        let (ri0, rj0) = (bx.0.saturating_sub(r), bx.1.saturating_sub(r));
        let (ri1, rj1) = ((bx.2 + r + 1).min(w), (bx.3 + r + 1).min(h));
        let mut region = Vec::new();
        let (mut a0, mut b0, mut a1, mut b1) = (w, h, 0, 0);
        let mut visited = (ri1 - ri0) * (rj1 - rj0);
        for j in rj0..rj1 {
            for i in ri0..ri1 {
                if self.nearest(i, j) == key {
                    if self.d2(i, j) == 0 {
                        grid.set(i, j, false);
                    }
                    region.push((i, j));
                    (a0, b0, a1, b1) = (a0.min(i), b0.min(j), a1.max(i), b1.max(j));
                }
            }
        }
        if region.is_empty() {
            return Ok(visited);
        }
        // Keys of the remaining occupied cells near the region.
        let mut m = r.max(4);
        loop {
            let (wi0, wj0) = (a0.saturating_sub(m), b0.saturating_sub(m));
            let (wi1, wj1) = ((a1 + m + 1).min(w), (b1 + m + 1).min(h));
            let val = &self.val;
            let (vals, _) = transform(wi0, wi1, wj0, wj1, |y, out| {
                let row = &val[(wj0 + y) * w + wi0..(wj0 + y) * w + wi1];
                for (o, &v) in out.iter_mut().zip(row) {
                    *o = if v >> KEY_BITS == 0 && (v & KEY_MASK) as u32 != key {
                        (v & KEY_MASK) as u32
                    } else {
                        u32::MAX
                    };
                }
            });
            visited += (wi1 - wi0) * (wj1 - wj0);
            let ww = wi1 - wi0;
            // A cell k steps inside the window has no outside source nearer than k + 1; a
            // side on the grid's edge has none at all.
            let exact = region.iter().all(|&(i, j)| {
                let v = vals[(j - wj0) * ww + (i - wi0)];
                let mut reach = i64::MAX;
                if wi0 > 0 {
                    reach = reach.min((i - wi0 + 1) as i64);
                }
                if wj0 > 0 {
                    reach = reach.min((j - wj0 + 1) as i64);
                }
                if wi1 < w {
                    reach = reach.min((wi1 - i) as i64);
                }
                if wj1 < h {
                    reach = reach.min((wj1 - j) as i64);
                }
                v != NONE && (reach == i64::MAX || (v >> KEY_BITS) < reach * reach)
            });
            if exact {
                for &(i, j) in &region {
                    let nv = vals[(j - wj0) * ww + (i - wi0)];
                    self.val[j * w + i] = nv;
                    self.max_d2 = self.max_d2.max(nv >> KEY_BITS);
                }
                return Ok(visited);
            }
            m *= 2;
        }
    }
}
