//! Property tests of the complete graph on generated maps (cellular-automaton caves, room grids
//! with one-cell doors, mazes, random fields): (a) start and goal are joined by the graph
//! exactly when free cells join them; (b) one independent cycle per obstacle hole; (c) every
//! polyline point lies in a free cell.

use homospline_geom::Point;
use homospline_voronoi::{DistanceField, GraphError, Grid, MapGraph, VoronoiGraph};
use proptest::prelude::*;

/// A SplitMix64 step: the generators' randomness, from one seed.
fn next(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn chance(state: &mut u64, p: f64) -> bool {
    (next(state) >> 11) as f64 / (1u64 << 53) as f64 <= p
}

/// Occupancy `w x h` with a wall ring, the inside from `inside(i, j)`.
fn with_ring(w: usize, h: usize, inside: impl Fn(usize, usize) -> bool) -> Grid {
    let occ = (0..w * h)
        .map(|k| {
            let (i, j) = (k % w, k / w);
            i == 0 || j == 0 || i + 1 == w || j + 1 == h || inside(i, j)
        })
        .collect();
    Grid::from_occupancy(w, h, Point::origin(), 1.0, occ).unwrap()
}

/// A cave: random fill, then four rounds of the 4-5 cellular-automaton rule.
fn cave(w: usize, h: usize, seed: u64) -> Grid {
    let mut s = seed;
    let mut occ: Vec<bool> = (0..w * h).map(|_| chance(&mut s, 0.45)).collect();
    for _ in 0..4 {
        let prev = occ.clone();
        for j in 0..h {
            for i in 0..w {
                let mut n = 0;
                for dj in -1i64..=1 {
                    for di in -1i64..=1 {
                        let (a, b) = (i as i64 + di, j as i64 + dj);
                        let outside = a < 0 || b < 0 || a >= w as i64 || b >= h as i64;
                        if outside || prev[b as usize * w + a as usize] {
                            n += 1;
                        }
                    }
                }
                occ[j * w + i] = n >= 5;
            }
        }
    }
    with_ring(w, h, |i, j| occ[j * w + i])
}

/// Rooms of `r x r` cells behind one-cell walls, each wall with a one-cell door at a random
/// place, some doors shut; a few pillars inside rooms.
fn rooms(w: usize, h: usize, r: usize, seed: u64) -> Grid {
    let mut s = seed;
    let mut occ = vec![false; w * h];
    for j in 0..h {
        for i in 0..w {
            occ[j * w + i] = i % (r + 1) == 0 || j % (r + 1) == 0;
        }
    }
    for j in 0..h {
        for i in 0..w {
            let (wall_x, wall_y) = (i % (r + 1) == 0, j % (r + 1) == 0);
            // Door cells: in a vertical wall at a room's middle row, or a horizontal one.
            if wall_x != wall_y {
                let along = if wall_x { j % (r + 1) } else { i % (r + 1) };
                let door_at = 1 + (next(&mut s) as usize % r);
                if along == door_at && chance(&mut s, 0.8) {
                    occ[j * w + i] = false;
                }
            }
            if !wall_x && !wall_y && chance(&mut s, 0.02) {
                occ[j * w + i] = true;
            }
        }
    }
    with_ring(w, h, |i, j| occ[j * w + i])
}

/// A maze by randomised depth-first search on a lattice of `c`-cell corridors, with a few
/// walls knocked out to make loops.
fn maze(w: usize, h: usize, c: usize, seed: u64) -> Grid {
    let mut s = seed;
    let (cw, ch) = ((w - 1) / (c + 1), (h - 1) / (c + 1));
    let mut occ = vec![true; w * h];
    let carve = |occ: &mut Vec<bool>, i0: usize, j0: usize, wdt: usize, hgt: usize| {
        for j in j0..(j0 + hgt).min(h) {
            for i in i0..(i0 + wdt).min(w) {
                occ[j * w + i] = false;
            }
        }
    };
    let origin = |x: usize, y: usize| (1 + x * (c + 1), 1 + y * (c + 1));
    let mut seen = vec![false; cw * ch];
    let mut stack = vec![(0usize, 0usize)];
    seen[0] = true;
    let (i0, j0) = origin(0, 0);
    carve(&mut occ, i0, j0, c, c);
    while let Some(&(x, y)) = stack.last() {
        let mut options = Vec::new();
        if x + 1 < cw && !seen[y * cw + x + 1] {
            options.push((x + 1, y));
        }
        if y + 1 < ch && !seen[(y + 1) * cw + x] {
            options.push((x, y + 1));
        }
        if x > 0 && !seen[y * cw + x - 1] {
            options.push((x - 1, y));
        }
        if y > 0 && !seen[(y - 1) * cw + x] {
            options.push((x, y - 1));
        }
        if options.is_empty() {
            stack.pop();
            continue;
        }
        let (nx, ny) = options[next(&mut s) as usize % options.len()];
        seen[ny * cw + nx] = true;
        let (a, b) = origin(x.min(nx), y.min(ny));
        if nx != x {
            carve(&mut occ, a, b, 2 * c + 1, c);
        } else {
            carve(&mut occ, a, b, c, 2 * c + 1);
        }
        stack.push((nx, ny));
    }
    for (k, o) in occ.iter_mut().enumerate() {
        let (i, j) = (k % w, k / w);
        if *o && i > 1 && j > 1 && i + 2 < w && j + 2 < h && chance(&mut s, 0.03) {
            *o = false;
        }
    }
    with_ring(w, h, |i, j| occ[j * w + i])
}

fn field_map(w: usize, h: usize, p: f64, seed: u64) -> Grid {
    let mut s = seed;
    let occ: Vec<bool> = (0..w * h).map(|_| chance(&mut s, p)).collect();
    with_ring(w, h, |i, j| occ[j * w + i])
}

/// 4-connected free components (the MovingAI rule: 8-connected moves without corner cutting
/// join the same cells).
fn free_components(grid: &Grid) -> Vec<usize> {
    let (w, h) = (grid.width(), grid.height());
    let mut label = vec![usize::MAX; w * h];
    let mut n = 0;
    for s in 0..w * h {
        if grid.occupancy()[s] || label[s] != usize::MAX {
            continue;
        }
        label[s] = n;
        let mut stack = vec![s];
        while let Some(c) = stack.pop() {
            for d in [1isize, -1, w as isize, -(w as isize)] {
                let m = (c as isize + d) as usize;
                if !grid.occupancy()[m] && label[m] == usize::MAX {
                    label[m] = n;
                    stack.push(m);
                }
            }
        }
        n += 1;
    }
    label
}

/// Every polyline point of every edge, sampled every 0.05 cell, lies in a free cell.
fn polylines_in_free_space(grid: &Grid, g: &VoronoiGraph) -> Result<(), String> {
    for (k, e) in g.edges.iter().enumerate() {
        for s in e.polyline.windows(2) {
            let (a, b) = (Point::new(s[0][0], s[0][1]), Point::new(s[1][0], s[1][1]));
            let n = ((b - a).norm() / 0.05).ceil().max(1.0) as usize;
            for t in 0..=n {
                let p = a + (b - a) * (t as f64 / n as f64);
                match grid.cell_of(&p) {
                    Some((i, j)) if !grid.occupied(i, j) => {}
                    _ => return Err(format!("edge {k}: point {p:?} is not in a free cell")),
                }
            }
        }
    }
    Ok(())
}

fn check(grid: &Grid, picks: &[(u64, u64)]) -> Result<(), TestCaseError> {
    let field = DistanceField::build(grid);
    let holes = field.obstacles().filter(|&k| k != field.wall_key()).count();
    let prepared = MapGraph::build(grid, &field);
    prop_assert_eq!(prepared.graph.cycle_rank(), holes, "(b) on the whole map");
    polylines_in_free_space(grid, &prepared.graph).map_err(TestCaseError::fail)?;
    let free: Vec<usize> = (0..grid.width() * grid.height())
        .filter(|&k| !grid.occupancy()[k])
        .collect();
    if free.is_empty() {
        return Ok(());
    }
    let comp = free_components(grid);
    let w = grid.width();
    for &(a, b) in picks {
        let (s, t) = (free[a as usize % free.len()], free[b as usize % free.len()]);
        let ps = grid.center(s % w, s / w) + homospline_geom::Vector::new(0.2, -0.1);
        let pt = grid.center(t % w, t / w) + homospline_geom::Vector::new(-0.3, 0.25);
        match prepared.with_endpoints(grid, &field, ps, pt) {
            Ok(g) => {
                prop_assert_eq!(comp[s], comp[t], "(a) a graph path where no free path is");
                prop_assert!(g.connected(g.start.unwrap(), g.goal.unwrap()));
                prop_assert_eq!(g.cycle_rank(), holes, "(b) on the query graph");
                polylines_in_free_space(grid, &g).map_err(TestCaseError::fail)?;
                // The query without a copy is the same graph where the search walks it (the
                // start's component), numbered in the same order.
                let q = prepared
                    .query(grid, &field, ps, pt)
                    .map_err(|e| TestCaseError::fail(e.to_string()))?;
                prop_assert_eq!(
                    start_component(&q.to_graph()),
                    start_component(&g),
                    "(c) the query graph"
                );
            }
            Err(GraphError::DifferentRegions) => {
                prop_assert_ne!(
                    comp[s],
                    comp[t],
                    "(a) free cells join them, the graph does not"
                );
            }
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        }
    }
    Ok(())
}

/// The part of `g` joined to its start, renumbered in order.
fn start_component(g: &VoronoiGraph) -> VoronoiGraph {
    let start = g.start.unwrap();
    let mut parent: Vec<usize> = (0..g.nodes.len()).collect();
    fn root(p: &mut [usize], mut k: usize) -> usize {
        while p[k] != k {
            p[k] = p[p[k]];
            k = p[k];
        }
        k
    }
    for e in &g.edges {
        let (a, b) = (root(&mut parent, e.from), root(&mut parent, e.to));
        parent[a] = b;
    }
    let r = root(&mut parent, start);
    let keep: Vec<bool> = (0..g.nodes.len())
        .map(|k| root(&mut parent, k) == r)
        .collect();
    let mut map = vec![usize::MAX; g.nodes.len()];
    let mut nodes = Vec::new();
    for (k, n) in g.nodes.iter().enumerate() {
        if keep[k] {
            map[k] = nodes.len();
            nodes.push(homospline_voronoi::Node {
                id: nodes.len(),
                ..n.clone()
            });
        }
    }
    VoronoiGraph {
        nodes,
        edges: g
            .edges
            .iter()
            .filter(|e| keep[e.from])
            .map(|e| homospline_voronoi::Edge {
                from: map[e.from],
                to: map[e.to],
                ..e.clone()
            })
            .collect(),
        start: Some(map[start]),
        goal: g.goal.map(|k| map[k]),
        ..g.clone()
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn caves(w in 12usize..48, h in 12usize..48, seed: u64, picks in prop::collection::vec((any::<u64>(), any::<u64>()), 6)) {
        check(&cave(w, h, seed), &picks)?;
    }

    #[test]
    fn rooms_with_one_cell_doors(rw in 2usize..6, rh in 2usize..6, r in 3usize..8, seed: u64, picks in prop::collection::vec((any::<u64>(), any::<u64>()), 6)) {
        check(&rooms(rw * (r + 1) + 1, rh * (r + 1) + 1, r, seed), &picks)?;
    }

    #[test]
    fn mazes(w in 12usize..48, h in 12usize..48, c in 1usize..4, seed: u64, picks in prop::collection::vec((any::<u64>(), any::<u64>()), 6)) {
        check(&maze(w, h, c, seed), &picks)?;
    }

    #[test]
    fn random_fields(w in 6usize..40, h in 6usize..40, p in 0.05f64..0.45, seed: u64, picks in prop::collection::vec((any::<u64>(), any::<u64>()), 6)) {
        check(&field_map(w, h, p, seed), &picks)?;
    }
}

#[test]
fn a_corridor_bounded_by_one_wall_has_a_graph() {
    // A U-shaped corridor whose walls are all one obstacle (the wall ring): the crack graph has
    // nothing here; the complete graph runs down the corridor.
    let grid = with_ring(12, 9, |i, j| (3..9).contains(&i) && (1..6).contains(&j));
    let field = DistanceField::build(&grid);
    let prepared = MapGraph::build(&grid, &field);
    let g = prepared
        .with_endpoints(&grid, &field, Point::new(1.5, 1.5), Point::new(10.5, 1.5))
        .unwrap();
    assert!(g.connected(g.start.unwrap(), g.goal.unwrap()));
    assert_eq!(g.cycle_rank(), 0);
    let length: f64 = g.edges.iter().map(|e| e.length).sum();
    // Up the left arm, across the top, down the right arm: about 6 + 9 + 6 cells.
    assert!(length > 15.0 && length < 30.0, "length {length}");
}
