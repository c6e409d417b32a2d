//! Where a disc robot fits on a map: the lattice of points that keep its radius (the free
//! space a robot's plan is searched in) and, when none joins start and goal, the widest route
//! and its narrowest point.
//!
//! # The lattice
//! Occupied cells are closed squares with corners on the integer lattice (in cells). The
//! clearance `d(p)` of a point is its distance to the nearest of them or to the map's edge.
//! A disc of radius `R` stands clear at `p` exactly when `d(p) > R` (touching a wall is not
//! clear of it), and it can drive from `S` to `T` exactly when a curve joins them along
//! which `d > R`.
//!
//! The robot's free space is sampled on the *half-cell lattice*: cell corners, side midpoints
//! and centres (points `k/2` cells from the origin). Every narrowest point of free space (a
//! saddle of `d`: the midpoint between the two nearest points of two occupied squares, or of
//! a square and the edge) lies on it, because those nearest points are corners or lie on
//! facing sides of squares with integer coordinates. Two lattice neighbours are joined by
//! their segment:
//! - side by side (half a cell) and corner to centre (diagonal), the least clearance of the
//!   segment is at one of its ends (the nearest point of an integer corner or of a cell side
//!   to such a segment is an end), so both ends keeping `R` is enough;
//! - side midpoint to side midpoint (diagonal, round a cell corner), the segment can dip below
//!   its ends: its clearance is computed exactly ([`segment_clearance`]).
//!
//! The planner's grid is the lattice as cells of half a map cell, centred on the lattice
//! points, free where the point keeps `R`; a diagonal join between two free points whose
//! two common neighbours are both blocked is kept by freeing the clearer of the two (a
//! corner of a staircase the disc can round), so the grid's 4-connected regions hold every
//! lattice route. Maps of more than [`crate::MAX_MAP_CELLS`] lattice points use the
//! lattice of cell centres instead, with every diagonal checked exactly.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use homospline_geom::{Point, Real};
use homospline_voronoi::grid::neighbours_8;
use rustc_hash::FxHashMap;

use crate::{GridModel, MAX_MAP_CELLS, OccupancyMap};

/// The lattice a robot's free space is sampled on (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    /// Points across.
    pub cols: usize,
    /// Points up.
    pub rows: usize,
    /// Spacing, map units.
    pub step: Real,
    /// Map coordinates of point `(0, 0)`.
    pub first: Point,
    /// Whether points lie on cell sides and corners too (half-cell lattice), not only at
    /// centres.
    pub half: bool,
}

impl Lattice {
    /// The half-cell lattice of `map`, or its cell centres when the half-cell lattice would
    /// have more than [`MAX_MAP_CELLS`] points.
    pub fn of(map: &OccupancyMap) -> Self {
        let (cols, rows) = (2 * map.width + 1, 2 * map.height + 1);
        if cols.saturating_mul(rows) <= MAX_MAP_CELLS {
            Self {
                cols,
                rows,
                step: 0.5 * map.cell,
                first: map.origin,
                half: true,
            }
        } else {
            Self {
                cols: map.width,
                rows: map.height,
                step: map.cell,
                first: Point::new(map.origin.x + 0.5 * map.cell, map.origin.y + 0.5 * map.cell),
                half: false,
            }
        }
    }

    /// Point `(u, v)` in map coordinates.
    pub fn point(&self, u: usize, v: usize) -> Point {
        Point::new(
            self.first.x + u as Real * self.step,
            self.first.y + v as Real * self.step,
        )
    }

    /// Whether the diagonal from `(u, v)` to `(u + 1, v + 1)` (or from `(u + 1, v)` to
    /// `(u, v + 1)`, the same parity) runs between two side midpoints, where its clearance
    /// can dip below its ends'. On the lattice of centres, every diagonal can.
    fn diagonal_can_dip(&self, u: usize, v: usize) -> bool {
        // Corners have both indices even, centres both odd: a corner-centre diagonal starts
        // at a point whose indices have the same parity.
        !self.half || (u + v) % 2 == 1
    }

    /// The lattice as an occupancy map of cells centred on its points (`free[k]`, row-major,
    /// says the point keeps the radius).
    fn as_map(&self, map: &OccupancyMap, free: &[bool]) -> OccupancyMap {
        OccupancyMap {
            name: map.name.clone(),
            width: self.cols,
            height: self.rows,
            cell: self.step,
            origin: Point::new(
                self.first.x - 0.5 * self.step,
                self.first.y - 0.5 * self.step,
            ),
            occupied: free.iter().map(|&f| !f).collect(),
            y_down: map.y_down,
        }
    }

    /// The point holding `p`'s lattice square's corner nearest the origin, and the four
    /// corners of that square that exist.
    fn around(&self, p: &Point) -> Vec<(usize, usize)> {
        let fx = (p.x - self.first.x) / self.step;
        let fy = (p.y - self.first.y) / self.step;
        let (u0, v0) = (fx.floor(), fy.floor());
        let mut out = Vec::with_capacity(4);
        for dv in 0..2 {
            for du in 0..2 {
                let (u, v) = (u0 + du as Real, v0 + dv as Real);
                if u >= 0.0 && v >= 0.0 && (u as usize) < self.cols && (v as usize) < self.rows {
                    out.push((u as usize, v as usize));
                }
            }
        }
        out
    }
}

/// The exact least clearance of the segment from `a` to `b` on `map`: its distance to the
/// nearest occupied cell (a closed square) or to the map's edge, searched up to `reach` map
/// units (a farther clearance reads as `reach`). 0 where it touches or crosses an occupied
/// cell or leaves the map.
pub fn segment_clearance(map: &OccupancyMap, a: &Point, b: &Point, reach: Real) -> Real {
    let bounds = map.bounds();
    let inside = |p: &Point| {
        p.x >= bounds.min.x && p.x <= bounds.max.x && p.y >= bounds.min.y && p.y <= bounds.max.y
    };
    if !inside(a) || !inside(b) {
        return 0.0;
    }
    // The edge is a line on each side: a segment's distance to it is at an end.
    let edge = |p: &Point| {
        (p.x - bounds.min.x)
            .min(bounds.max.x - p.x)
            .min(p.y - bounds.min.y)
            .min(bounds.max.y - p.y)
    };
    let mut best = edge(a).min(edge(b)).min(reach);
    let c = map.cell;
    let span = best + c;
    let cell_range = |lo: Real, hi: Real, o: Real, n: usize| {
        let i0 = ((lo - span - o) / c).floor().max(0.0) as usize;
        let i1 = (((hi + span - o) / c).floor().max(0.0) as usize).min(n.saturating_sub(1));
        (i0, i1)
    };
    let (i0, i1) = cell_range(a.x.min(b.x), a.x.max(b.x), map.origin.x, map.width);
    let (j0, j1) = cell_range(a.y.min(b.y), a.y.max(b.y), map.origin.y, map.height);
    for j in j0..=j1 {
        for i in i0..=i1 {
            if map.occupied[j * map.width + i] {
                let lo = Point::new(map.origin.x + i as Real * c, map.origin.y + j as Real * c);
                best = best.min(segment_box_distance(a, b, &lo, c));
                if best == 0.0 {
                    return 0.0;
                }
            }
        }
    }
    best
}

/// Distance from the segment `a b` to the closed square `[lo, lo + side]^2`.
fn segment_box_distance(a: &Point, b: &Point, lo: &Point, side: Real) -> Real {
    let hi = Point::new(lo.x + side, lo.y + side);
    homospline_geom::query::distance_segment_aabb(a, b, lo, &hi)
}

/// Per lattice point (row-major), whether it keeps more than `radius` (map units, `> 0`) from every
/// occupied cell and from the edge. `square` is [`OccupancyMap::square_distances`] (squared
/// cells from each cell's square to the nearest obstacle): a point on a cell's closed square
/// is at least that far, and at most a diagonal farther, so only the points between are
/// measured exactly by `truth`.
fn keeps(
    lattice: &Lattice,
    map: &OccupancyMap,
    square: &[i64],
    radius: Real,
    truth: &GridModel,
) -> Vec<bool> {
    let reach = radius / map.cell;
    let mut out = vec![false; lattice.cols * lattice.rows];
    for v in 0..lattice.rows {
        for u in 0..lattice.cols {
            let p = lattice.point(u, v);
            let fx = (p.x - map.origin.x) / map.cell;
            let fy = (p.y - map.origin.y) / map.cell;
            let is = homospline_voronoi::grid::cells_holding(fx, map.width);
            let js = homospline_voronoi::grid::cells_holding(fy, map.height);
            // On the edge: clearance 0 (within `ON_SIDE`, as `cells_holding` counts a side).
            use homospline_voronoi::grid::ON_SIDE;
            let on_edge = fx <= ON_SIDE
                || fy <= ON_SIDE
                || fx >= map.width as Real - ON_SIDE
                || fy >= map.height as Real - ON_SIDE;
            if on_edge {
                continue;
            }
            let mut lower = Real::INFINITY;
            let mut blocked = false;
            for &j in js.iter().flatten() {
                for &i in is.iter().flatten() {
                    let k = j * map.width + i;
                    if map.occupied[k] {
                        blocked = true;
                    }
                    lower = lower.min((square[k] as Real).sqrt());
                }
            }
            if blocked {
                continue;
            }
            // More than the radius: a disc that touches a wall is not clear of it.
            out[v * lattice.cols + u] = if lower > reach {
                true
            } else if lower + std::f64::consts::SQRT_2 <= reach {
                false
            } else {
                truth.exact(&p) > radius
            };
        }
    }
    out
}

/// The robot's free space on `map` for a disc of `radius` (map units, `> 0`): the lattice
/// (see the module docs) as an occupancy map of cells centred on its points, free where the
/// point keeps `radius`, with the clearer common neighbour of every diagonal join that needs
/// one freed. `square` is [`OccupancyMap::square_distances`], `truth` the model of `map`.
pub(crate) fn free_space(
    map: &OccupancyMap,
    square: &[i64],
    radius: Real,
    truth: &GridModel,
) -> OccupancyMap {
    let lattice = Lattice::of(map);
    let keep = keeps(&lattice, map, square, radius, truth);
    let (cols, rows) = (lattice.cols, lattice.rows);
    let mut free = keep.clone();
    let reach = radius + 2.0 * map.cell;
    for v in 0..rows.saturating_sub(1) {
        for u in 0..cols.saturating_sub(1) {
            let k = |du: usize, dv: usize| (v + dv) * cols + u + du;
            // The two diagonals of the lattice square at (u, v): ends, then the common
            // neighbours.
            for ((a, b), (s, t)) in [
                ((k(0, 0), k(1, 1)), (k(1, 0), k(0, 1))),
                ((k(1, 0), k(0, 1)), (k(0, 0), k(1, 1))),
            ] {
                if !(keep[a] && keep[b]) || keep[s] || keep[t] {
                    continue;
                }
                let (pa, pb) = (point_of(&lattice, a), point_of(&lattice, b));
                let joined = !lattice.diagonal_can_dip(u, v)
                    || segment_clearance(map, &pa, &pb, reach) > radius;
                if joined {
                    let (ps, pt) = (point_of(&lattice, s), point_of(&lattice, t));
                    let open = if truth.exact(&ps) >= truth.exact(&pt) {
                        s
                    } else {
                        t
                    };
                    free[open] = true;
                }
            }
        }
    }
    lattice.as_map(map, &free)
}

fn point_of(lattice: &Lattice, k: usize) -> Point {
    lattice.point(k % lattice.cols, k / lattice.cols)
}

/// The widest route between two points: the largest clearance a route can keep all along,
/// and where the widest route found is narrowest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Widest {
    /// The least clearance along the widest route, map units.
    pub clearance: Real,
    /// Where the widest route is narrowest (a lattice point or a point of a lattice segment).
    pub at: Point,
}

/// An entry of [`widest_route`]'s queue: the bottleneck so far (larger first), then the node.
#[derive(Clone, Copy, PartialEq)]
struct Open(Real, usize);

impl Eq for Open {}

impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Open {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0
            .total_cmp(&other.0)
            .then_with(|| other.1.cmp(&self.1))
    }
}

/// The widest route from `start` to `goal` on `map` (`truth` its clearance model): the
/// largest `W` such that a route on the lattice of [`Lattice::of`] (start and goal joined
/// to the corners of the lattice square that holds them by straight segments) keeps `W`
/// from every occupied cell and the edge, with the point where that route is narrowest.
/// Every segment's clearance is exact, so the route is a real one: a disc of radius up to
/// `W` drives it. `W` is at most the clearance of `start` and of `goal`; 0 when no route
/// joins them at all.
///
/// A bottleneck Dijkstra (largest least clearance first) over the lattice's 8 neighbours.
/// The module docs say why the lattice finds the narrowest point of free space exactly.
///
/// # Examples
/// ```
/// use homospline_maps::footprint::widest_route;
/// use homospline_maps::{GridModel, OccupancyMap};
/// use homospline_geom::Point;
/// use homospline_voronoi::DistanceField;
///
/// // A 7 x 5 room with a wall down the middle and a one-cell gap in it.
/// let rows = ["...@...", "...@...", ".......", "...@...", "...@..."];
/// let map = OccupancyMap {
///     name: "gap".into(),
///     width: 7,
///     height: 5,
///     cell: 1.0,
///     origin: Point::origin(),
///     occupied: rows.iter().flat_map(|r| r.chars().map(|c| c == '@')).collect(),
///     y_down: true,
/// };
/// let grid = map.to_grid().unwrap();
/// let truth = GridModel::new(&grid, &DistanceField::build(&grid));
/// let w = widest_route(&map, &truth, Point::new(1.5, 2.5), Point::new(5.5, 2.5));
/// // The gap is one cell wide: the widest route keeps half a cell, in the gap.
/// assert_eq!(w.clearance, 0.5);
/// assert!((3.0..=4.0).contains(&w.at.x) && w.at.y == 2.5);
/// ```
pub fn widest_route(map: &OccupancyMap, truth: &GridModel, start: Point, goal: Point) -> Widest {
    let lattice = Lattice::of(map);
    let n = lattice.cols * lattice.rows;
    // Node ids: lattice points, then start (n) and goal (n + 1).
    let (s_id, g_id) = (n, n + 1);
    let position = |k: usize| match k {
        k if k == s_id => start,
        k if k == g_id => goal,
        k => point_of(&lattice, k),
    };
    let mut clear: FxHashMap<usize, Real> = FxHashMap::default();
    let mut value = |k: usize| -> Real {
        *clear
            .entry(k)
            .or_insert_with(|| truth.exact(&position(k)).max(0.0))
    };
    // A segment's least clearance is at most its ends': searched no farther.
    let segment = |a: usize, b: usize, ends: Real| {
        let (pa, pb) = (position(a), position(b));
        (segment_clearance(map, &pa, &pb, ends), pa, pb)
    };
    let goal_corners = lattice.around(&goal);
    // Per node: the bottleneck of its best route and where that route is narrowest.
    let mut best: FxHashMap<usize, (Real, Point)> = FxHashMap::default();
    let mut heap = BinaryHeap::new();
    let v0 = value(s_id);
    best.insert(s_id, (v0, start));
    heap.push(Open(v0, s_id));
    while let Some(Open(w, k)) = heap.pop() {
        if best.get(&k).is_some_and(|&(b, _)| b > w) {
            continue;
        }
        if k == g_id {
            let (clearance, at) = best[&k];
            return Widest { clearance, at };
        }
        let at_k = best[&k].1;
        // Neighbours, with the segment's least clearance and where it is, when it can dip
        // below its ends.
        let mut next: Vec<(usize, Option<(Real, Point)>)> = Vec::with_capacity(9);
        if k == s_id {
            for (u, v) in lattice.around(&start) {
                next.push((v * lattice.cols + u, None));
            }
        } else {
            let (u, v) = (k % lattice.cols, k / lattice.cols);
            for ((nu, nv), (du, dv)) in neighbours_8(u, v, lattice.cols, lattice.rows) {
                let dips = du != 0 && dv != 0 && lattice.diagonal_can_dip(u.min(nu), v.min(nv));
                next.push((nv * lattice.cols + nu, dips.then_some((0.0, at_k))));
            }
            if goal_corners.contains(&(u, v)) {
                next.push((g_id, Some((0.0, at_k))));
            }
        }
        for (m, dip) in next {
            let mut bottleneck = (w, at_k);
            let vm = value(m);
            if vm < bottleneck.0 {
                bottleneck = (vm, position(m));
            }
            // Joins to start and goal and diagonals round a corner: the segment exactly.
            if (dip.is_some() || k == s_id) && bottleneck.0 > 0.0 {
                let ends = value(k).min(vm);
                let (c, pa, pb) = segment(k, m, ends);
                if c < bottleneck.0 {
                    bottleneck = (c, narrowest_on(truth, &pa, &pb));
                }
            }
            if best.get(&m).is_none_or(|&(b, _)| bottleneck.0 > b) {
                best.insert(m, bottleneck);
                heap.push(Open(bottleneck.0, m));
            }
        }
    }
    Widest {
        clearance: 0.0,
        at: start,
    }
}

/// The point of segment `a b` where `truth` is least, to within a hundredth of the segment
/// (for messages).
fn narrowest_on(truth: &GridModel, a: &Point, b: &Point) -> Point {
    (0..=100)
        .map(|i| a + (b - a) * (i as Real / 100.0))
        .min_by(|p, q| truth.exact(p).total_cmp(&truth.exact(q)))
        .unwrap_or(*a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use homospline_voronoi::DistanceField;

    fn map_of(rows: &[&str]) -> OccupancyMap {
        OccupancyMap {
            name: "t".into(),
            width: rows[0].len(),
            height: rows.len(),
            cell: 1.0,
            origin: Point::origin(),
            occupied: rows
                .iter()
                .flat_map(|r| r.chars().map(|c| c == '@'))
                .collect(),
            y_down: true,
        }
    }

    #[test]
    fn segment_clearance_round_a_corner_dips_below_its_ends() {
        // Occupied cell [1, 2] x [-1, 0] shifted into the map: cell (2, 0) of a 4 x 4 map,
        // corner (2, 1). The segment from (1.5, 1) to (2, 1.5) passes 0.354 from it.
        let map = map_of(&["..@.", "....", "....", "...."]);
        let a = Point::new(1.5, 1.0);
        let b = Point::new(2.0, 1.5);
        let c = segment_clearance(&map, &a, &b, 10.0);
        assert!(
            (c - 0.5 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12,
            "{c}"
        );
        // Both ends keep half a cell.
        let grid = map.to_grid().unwrap();
        let truth = GridModel::new(&grid, &DistanceField::build(&grid));
        assert!((truth.exact(&a) - 0.5).abs() < 1e-12);
        assert!((truth.exact(&b) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn a_segment_through_a_cell_has_clearance_zero() {
        let map = map_of(&["....", ".@..", "....", "...."]);
        let c = segment_clearance(&map, &Point::new(0.5, 1.5), &Point::new(3.5, 1.5), 10.0);
        assert_eq!(c, 0.0);
    }
}
