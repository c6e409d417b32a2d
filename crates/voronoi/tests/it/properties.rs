//! Property tests: the brushfire against brute force, the graph's cycles on random scenes,
//! and local updates against full rebuilds.

use homospline_geom::{Bounds, Circle, Obstacle, Point, Scene};
use homospline_voronoi::field::{PARALLEL_CELLS, obstacle_keys};
use homospline_voronoi::{DistanceField, GraphError, Grid, VoronoiGraph};
use proptest::prelude::*;

/// The lexicographic minimum of (squared distance, obstacle key) from cell `(i, j)` over
/// every occupied cell, by brute force.
fn brute_nearest(grid: &Grid, keys: &[u32], i: usize, j: usize) -> (i64, u32) {
    let (w, h) = (grid.width(), grid.height());
    let mut best = (i64::MAX, u32::MAX);
    for b in 0..h {
        for a in 0..w {
            if grid.occupied(a, b) {
                let d = (a as i64 - i as i64).pow(2) + (b as i64 - j as i64).pow(2);
                best = best.min((d, keys[b * w + a]));
            }
        }
    }
    best
}

fn random_grid(w: usize, h: usize, bits: &[bool]) -> Grid {
    Grid::from_occupancy(w, h, Point::origin(), 1.0, bits[..w * h].to_vec()).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Every cell holds the lexicographic minimum of (squared distance, obstacle key) over
    /// all occupied cells: exact, so the worst error against brute force is zero.
    #[test]
    fn brushfire_is_exact(w in 3usize..24, h in 3usize..24, bits in prop::collection::vec(prop::bool::weighted(0.12), 576)) {
        let grid = random_grid(w, h, &bits);
        let field = DistanceField::build(&grid);
        let keys = obstacle_keys(&grid);
        for j in 0..h {
            for i in 0..w {
                let best = brute_nearest(&grid, &keys, i, j);
                prop_assert_eq!((field.d2(i, j), field.nearest(i, j)), best, "cell ({}, {})", i, j);
            }
        }
    }

    /// Grids large enough for the parallel transform: the same field with 1 and 3 threads
    /// (strips of columns and rows split differently), and exact against brute force at
    /// sampled cells.
    #[test]
    fn parallel_brushfire_is_exact_and_the_same_for_any_thread_count(
        w in 130usize..260, h in 127usize..200,
        obstacles in prop::collection::vec((0usize..260, 0usize..200, 0usize..4), 1..40),
        probes in prop::collection::vec((0usize..260, 0usize..200), 64),
    ) {
        let mut bits = vec![false; w * h];
        for &(ci, cj, r) in &obstacles {
            for j in cj.saturating_sub(r)..(cj + r + 1).min(h) {
                for i in ci.saturating_sub(r)..(ci + r + 1).min(w) {
                    bits[j * w + i] = true;
                }
            }
        }
        let grid = random_grid(w, h, &bits);
        prop_assert!(w * h >= PARALLEL_CELLS);
        let in_pool = |n: usize| {
            rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap().install(|| DistanceField::build(&grid))
        };
        let one = in_pool(1);
        prop_assert!(one == in_pool(3), "1 and 3 threads differ");
        prop_assert!(one == DistanceField::build(&grid), "the global pool differs");
        let keys = obstacle_keys(&grid);
        for &(pi, pj) in &probes {
            let (i, j) = (pi % w, pj % h);
            let best = brute_nearest(&grid, &keys, i, j);
            prop_assert_eq!((one.d2(i, j), one.nearest(i, j)), best, "cell ({}, {})", i, j);
        }
    }

    /// Obstacle keys are the 8-connected components, each keyed by its smallest raster index.
    #[test]
    fn obstacle_keys_are_8_connected_components(w in 3usize..30, h in 3usize..30, bits in prop::collection::vec(prop::bool::weighted(0.4), 900)) {
        let grid = random_grid(w, h, &bits);
        let keys = obstacle_keys(&grid);
        let mut expect = vec![u32::MAX; w * h];
        for start in 0..w * h {
            if !grid.occupancy()[start] || expect[start] != u32::MAX {
                continue;
            }
            // Raster order: the first unlabelled cell of a component is its smallest.
            let mut stack = vec![start];
            expect[start] = start as u32;
            while let Some(c) = stack.pop() {
                let (i, j) = ((c % w) as i64, (c / w) as i64);
                for dj in -1..=1 {
                    for di in -1..=1 {
                        let (a, b) = (i + di, j + dj);
                        if a < 0 || b < 0 || a >= w as i64 || b >= h as i64 {
                            continue;
                        }
                        let n = b as usize * w + a as usize;
                        if grid.occupancy()[n] && expect[n] == u32::MAX {
                            expect[n] = start as u32;
                            stack.push(n);
                        }
                    }
                }
            }
        }
        prop_assert_eq!(keys, expect);
    }

    /// Random scenes: one independent cycle per obstacle inside the wall, start and goal
    /// joined whenever their free cells are joined.
    #[test]
    fn one_cycle_per_obstacle_on_random_scenes(
        circles in prop::collection::vec((8.0..92.0, 8.0..62.0, 1.0..6.0), 0..14),
        resolution in prop::sample::select(vec![0.5, 1.0, 2.0]),
    ) {
        let scene = Scene {
            name: "random".into(),
            bounds: Bounds { min: Point::new(0.0, 0.0), max: Point::new(100.0, 70.0) },
            start: Point::new(2.0, 35.0),
            goal: Point::new(98.0, 35.0),
            robot_radius: 0.0,
            obstacles: circles.iter().enumerate().map(|(i, &(x, y, r))| Obstacle { name: format!("o{i}"), circles: vec![Circle::new(x, y, r)] }).collect(),
            danger_points: vec![], critical_points: vec![], hazards: vec![],
        };
        let grid = Grid::from_scene(&scene, resolution).unwrap();
        let field = DistanceField::build(&grid);
        match VoronoiGraph::build(&grid, &field, Some(scene.start), Some(scene.goal)) {
            Ok(g) => {
                prop_assert_eq!(g.cycle_rank(), g.obstacles.len());
                prop_assert!(g.connected(g.start.unwrap(), g.goal.unwrap()));
                for e in &g.edges {
                    prop_assert!(e.length >= 0.0 && e.min_clearance >= 0.0 && e.polyline.len() >= 2);
                    prop_assert!(e.min_clearance <= e.mean_clearance + 1e-12);
                }
            }
            // Obstacles on the wall can cut the free space; then the error is the right one.
            Err(e) => prop_assert!(matches!(e, GraphError::DifferentRegions | GraphError::Occupied(..)), "{}", e),
        }
    }

    /// Random sequences of added and removed obstacles: the locally updated field, and the
    /// graph built from it, equal a full rebuild after every step.
    #[test]
    fn local_updates_equal_full_rebuilds(
        ops in prop::collection::vec((any::<bool>(), 2usize..38, 2usize..28, 1usize..4, any::<prop::sample::Index>()), 1..12),
    ) {
        let (w, h) = (40, 30);
        let mut grid = Grid::new(w, h, Point::origin(), 1.0).unwrap();
        let mut field = DistanceField::build(&grid);
        for (add, ci, cj, r, pick) in ops {
            if add {
                let cells: Vec<(usize, usize)> = (cj.saturating_sub(r)..=(cj + r).min(h - 2))
                    .flat_map(|j| (ci.saturating_sub(r)..=(ci + r).min(w - 2)).map(move |i| (i, j)))
                    .filter(|&(i, j)| i >= 1 && j >= 1 && (i as i64 - ci as i64).pow(2) + (j as i64 - cj as i64).pow(2) <= (r * r) as i64)
                    .collect();
                if field.add_obstacle(&mut grid, &cells).is_err() {
                    continue; // touching: not a local update
                }
            } else {
                let keys: Vec<u32> = field.obstacles().filter(|&k| k != field.wall_key()).collect();
                if keys.is_empty() {
                    continue;
                }
                field.remove_obstacle(&mut grid, keys[pick.index(keys.len())]).unwrap();
            }
            let rebuilt = DistanceField::build(&grid);
            for j in 0..h {
                for i in 0..w {
                    prop_assert_eq!((field.d2(i, j), field.nearest(i, j)), (rebuilt.d2(i, j), rebuilt.nearest(i, j)), "cell ({}, {})", i, j);
                }
            }
            let a = VoronoiGraph::build(&grid, &field, None, None).unwrap();
            let b = VoronoiGraph::build(&grid, &rebuilt, None, None).unwrap();
            prop_assert_eq!(a, b);
        }
    }

    /// Random discs added with `add_cells` (which may join the wall or an obstacle) and
    /// obstacles removed: the field equals a full rebuild after every step, and a refused
    /// addition changes nothing.
    #[test]
    fn added_cells_equal_full_rebuilds(
        ops in prop::collection::vec((0u8..3, 1usize..39, 1usize..29, 0usize..4, any::<prop::sample::Index>()), 1..14),
    ) {
        let (w, h) = (40, 30);
        let mut grid = Grid::new(w, h, Point::origin(), 1.0).unwrap();
        let mut field = DistanceField::build(&grid);
        for (op, ci, cj, r, pick) in ops {
            if op < 2 {
                let cells: Vec<(usize, usize)> = (cj.saturating_sub(r)..=(cj + r).min(h - 2))
                    .flat_map(|j| (ci.saturating_sub(r)..=(ci + r).min(w - 2)).map(move |i| (i, j)))
                    .filter(|&(i, j)| i >= 1 && j >= 1 && (i as i64 - ci as i64).pow(2) + (j as i64 - cj as i64).pow(2) <= (r * r) as i64)
                    .collect();
                let before = (grid.clone(), field.clone());
                if field.add_cells(&mut grid, &cells).is_err() {
                    prop_assert!(grid == before.0 && field == before.1, "a refused addition changed the field");
                    continue;
                }
            } else {
                let keys: Vec<u32> = field.obstacles().filter(|&k| k != field.wall_key()).collect();
                if keys.is_empty() {
                    continue;
                }
                field.remove_obstacle(&mut grid, keys[pick.index(keys.len())]).unwrap();
            }
            let rebuilt = DistanceField::build(&grid);
            for j in 0..h {
                for i in 0..w {
                    prop_assert_eq!((field.d2(i, j), field.nearest(i, j)), (rebuilt.d2(i, j), rebuilt.nearest(i, j)), "cell ({}, {})", i, j);
                }
            }
            let mut keys: Vec<u32> = field.obstacles().collect();
            let mut fresh: Vec<u32> = rebuilt.obstacles().collect();
            keys.sort_unstable();
            fresh.sort_unstable();
            prop_assert_eq!(keys, fresh);
        }
    }
}

#[test]
fn start_and_goal_in_different_regions_are_an_error() {
    // A column of touching circles from the bottom wall to the top wall.
    let scene = Scene {
        name: "split".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(40.0, 20.0),
        },
        start: Point::new(5.0, 10.0),
        goal: Point::new(35.0, 10.0),
        robot_radius: 0.0,
        obstacles: vec![Obstacle {
            name: "wall".into(),
            circles: (0..=10)
                .map(|k| Circle::new(20.0, k as f64 * 2.0, 1.5))
                .collect(),
        }],
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    };
    assert_eq!(
        homospline_voronoi::build(&scene, 1.0)
            .unwrap_err()
            .to_string(),
        "no route: start and goal are walled apart by 'wall': their circles (grown by the robot's radius) touch one another or the bounds, and no gap between them lets a path through"
    );
    // A gap of 0.1 between two circles, a tenth of a cell: closed on the grid at 1 cell
    // per unit, so the graph is built again on a grid fine enough for it (60 cells per
    // unit) and joins start and goal.
    let gap = Scene {
        obstacles: vec![Obstacle {
            name: "wall".into(),
            circles: vec![Circle::new(20.0, 4.95, 5.0), Circle::new(20.0, 15.05, 5.0)],
        }],
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(40.0, 20.0),
        },
        ..scene.clone()
    };
    let (grid, _, graph) = homospline_voronoi::build(&gap, 1.0).unwrap();
    assert!(grid.resolution() >= 59.9, "{}", grid.resolution());
    assert!(graph.connected(graph.start.unwrap(), graph.goal.unwrap()));
    // A gap of 0.001 would need a grid over the limit: no verdict, and the message says
    // between what and how wide.
    let hair = Scene {
        obstacles: vec![Obstacle {
            name: "wall".into(),
            circles: vec![
                Circle::new(20.0, 4.9995, 5.0),
                Circle::new(20.0, 15.0005, 5.0),
            ],
        }],
        ..gap.clone()
    };
    let e = homospline_voronoi::build(&hair, 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("'wall' and 'wall' leave a gap of 0.001") && e.contains("no plan is claimed"),
        "{e}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Invariant (c) on scenes: the graph is built on the raster of the circles, where a
    /// gap narrower than a cell can look free; every segment of every edge's polyline must
    /// still keep out of every circle (exact segment distance), so a seed never starts
    /// inside an obstacle. Pairs of nearly touching circles make such gaps.
    #[test]
    fn scene_graph_polylines_keep_out_of_the_circles(
        pairs in prop::collection::vec((10.0..90.0, 10.0..60.0, 1.5..5.0, 1.5..5.0, 0.0..6.3, 0.0..1.0), 1..7),
        resolution in prop::sample::select(vec![0.5, 1.0, 2.0]),
    ) {
        let mut obstacles = Vec::new();
        for (k, &(x, y, r1, r2, angle, gap)) in pairs.iter().enumerate() {
            let (x, y, r1, r2, angle, gap): (f64, f64, f64, f64, f64, f64) = (x, y, r1, r2, angle, gap);
            // Two circles `gap` cells apart (less than a cell).
            let d = r1 + r2 + gap / resolution;
            let (x2, y2) = (x + d * angle.cos(), y + d * angle.sin());
            obstacles.push(Obstacle { name: format!("a{k}"), circles: vec![Circle::new(x, y, r1)] });
            obstacles.push(Obstacle { name: format!("b{k}"), circles: vec![Circle::new(x2, y2, r2)] });
        }
        let scene = Scene {
            name: "gaps".into(),
            bounds: Bounds { min: Point::new(0.0, 0.0), max: Point::new(100.0, 70.0) },
            start: Point::new(2.0, 35.0),
            goal: Point::new(98.0, 35.0),
            robot_radius: 0.0,
            obstacles,
            danger_points: vec![], critical_points: vec![], hazards: vec![],
        };
        let circles = scene.circle_set();
        prop_assume!([scene.start, scene.goal].iter().all(|p: &Point| circles.clearance(p).is_none_or(|c| c.distance > 0.0)));
        if let Ok((_, _, g)) = homospline_voronoi::build(&scene, resolution) {
            for (i, e) in g.edges.iter().enumerate() {
                // An edge's length is its polyline's (a connector once took in a detour to
                // the grid's corner).
                let along: f64 = e.polyline.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).sum();
                prop_assert!((e.length - along).abs() <= 1e-9 * (1.0 + along), "edge {} has length {} along a polyline of {}", i, e.length, along);
                for w in e.polyline.windows(2) {
                    let (a, b) = (Point::new(w[0][0], w[0][1]), Point::new(w[1][0], w[1][1]));
                    let d = circles.distance_to_segment(&a, &b).map_or(f64::INFINITY, |(d, _)| d);
                    prop_assert!(d >= 0.0, "edge {} ({} -> {}) passes {} inside a circle", i, e.from, e.to, -d);
                }
            }
        }
    }
}
