//! Occupancy-map helpers (feature `maps`): random and hand-made maps, and the exact
//! clearance of a track over a map's cells.

use homospline_geom::{Point, Real};
use homospline_maps::OccupancyMap;

use crate::{random_occupancy, segment_square};

/// The `n x n` map of [`random_occupancy`] at 20 % (seed 43), unit cells, y down.
pub fn random_map(n: usize) -> OccupancyMap {
    OccupancyMap {
        name: format!("random{n}-20"),
        width: n,
        height: n,
        cell: 1.0,
        origin: Point::origin(),
        occupied: random_occupancy(n, 0.2, 43),
        y_down: true,
    }
}

/// The centre of the first cell on `map`'s diagonal from `(at, at)` (stepping by `step`)
/// whose 3 x 3 block is free: the corner-to-corner query of the large-map benches.
///
/// # Panics
/// When the walk leaves the map before finding one (a test helper).
pub fn free_diagonal_centre(map: &OccupancyMap, at: usize, step: isize) -> Point {
    let n = map.width;
    let free = |x: usize, y: usize| {
        (y - 1..=y + 1).all(|yy| (x - 1..=x + 1).all(|xx| !map.occupied[yy * n + xx]))
    };
    let mut k = at;
    while !free(k, k) {
        k = k
            .checked_add_signed(step)
            .filter(|&k| k >= 1 && k + 1 < n)
            .expect("a free block on the diagonal");
    }
    Point::new(k as f64 + 0.5, k as f64 + 0.5)
}

/// The least distance from the polyline `track` to an occupied cell of `map` or to its
/// edge, exact (every cell within `reach` of each segment's box measured).
pub fn track_clearance(map: &OccupancyMap, track: &[Point], reach: Real) -> Real {
    let b = map.bounds();
    let mut best = Real::INFINITY;
    for p in track {
        best = best.min(
            (p.x - b.min.x)
                .min(b.max.x - p.x)
                .min(p.y - b.min.y)
                .min(b.max.y - p.y),
        );
    }
    for w in track.windows(2) {
        let cell = |v: Real, o: Real, n: usize| {
            (((v - o) / map.cell).floor().max(0.0) as usize).min(n - 1)
        };
        let r = reach + map.cell;
        let (i0, i1) = (
            cell(w[0].x.min(w[1].x) - r, map.origin.x, map.width),
            cell(w[0].x.max(w[1].x) + r, map.origin.x, map.width),
        );
        let (j0, j1) = (
            cell(w[0].y.min(w[1].y) - r, map.origin.y, map.height),
            cell(w[0].y.max(w[1].y) + r, map.origin.y, map.height),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                if map.occupied[j * map.width + i] {
                    best = best.min(segment_square(
                        w[0],
                        w[1],
                        map.origin.x + i as Real * map.cell,
                        map.origin.y + j as Real * map.cell,
                        map.cell,
                    ));
                }
            }
        }
    }
    best
}

/// A 16 x 10 map split by a wall with a diagonal door: column 7 from row 0 to row 3, column
/// 9 from row 5 to row 9 (cell `(i, j)` is the square `[i, i + 1] x [j, j + 1]`), so the only
/// way across is the gap between the corners (8, 4) and (9, 5), `sqrt 2` wide: a disc of
/// radius up to 0.7071 passes, turning in it. `extra`: one more occupied cell.
pub fn diagonal_door_map(extra: Option<(usize, usize)>) -> OccupancyMap {
    grid_map("diagonal-door", (16, 10), true, |i, j| {
        (i == 7 && j <= 3) || (i == 9 && j >= 5) || Some((i, j)) == extra
    })
}

/// A map of `w x h` cells of side 1 from the origin, cell `(i, j)` occupied where
/// `occupied(i, j)`; `y_down` as MovingAI (rows down) or ROS (rows up).
pub fn grid_map(
    name: &str,
    (w, h): (usize, usize),
    y_down: bool,
    occupied: impl Fn(usize, usize) -> bool,
) -> OccupancyMap {
    OccupancyMap {
        name: name.into(),
        width: w,
        height: h,
        cell: 1.0,
        origin: Point::origin(),
        occupied: (0..w * h).map(|k| occupied(k % w, k / w)).collect(),
        y_down,
    }
}
