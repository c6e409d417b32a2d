//! Maps: readers, the grid clearance model against brute force, and plans on real maps
//! checked independently of the planner.

use homospline_geom::Point;
use homospline_maps::{GridModel, OccupancyMap, movingai, plan_map, ros};
use homospline_optim::PlanConfig;
use homospline_voronoi::DistanceField;
use proptest::prelude::*;

fn fixture(rel: &str) -> String {
    format!("{}/../../fixtures/maps/{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn movingai_map(name: &str) -> OccupancyMap {
    let path = fixture(&format!("movingai/{name}.map"));
    movingai::read_map(&std::fs::read_to_string(&path).unwrap(), &path).unwrap()
}

/// Independent check: every point of the path, sampled every 0.01 cell, is in a free cell.
fn path_is_free(map: &OccupancyMap, path: &[Point]) -> bool {
    path.windows(2).all(|w| {
        let n = (((w[1] - w[0]).norm() / (0.01 * map.cell)).ceil() as usize).max(1);
        (0..=n).all(|k| map.free_at(&(w[0] + (w[1] - w[0]) * (k as f64 / n as f64))) == Some(true))
    })
}

#[test]
fn movingai_maps_and_scenarios_read() {
    let map = movingai_map("room-32-32-4");
    assert_eq!((map.width, map.height), (32, 32));
    assert!(map.y_down);
    // Row 0 of the file starts "@@@.": cell (3, 0) is free, (0, 0) blocked.
    assert_eq!(map.free_at(&Point::new(3.5, 0.5)), Some(true));
    assert_eq!(map.free_at(&Point::new(0.5, 0.5)), Some(false));
    let path = fixture("movingai/room-32-32-4-random-1.scen");
    let scen = movingai::read_scen(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    assert!(scen.len() > 10);
    assert_eq!(scen[0].start, Point::new(21.5, 14.5));
    assert_eq!(scen[0].goal, Point::new(9.5, 0.5));
    for s in &scen {
        assert_eq!(map.free_at(&s.start), Some(true));
        assert_eq!(map.free_at(&s.goal), Some(true));
    }
}

#[test]
fn ros_maps_read_with_y_up_from_the_origin() {
    let path = fixture("ros/turtlebot3_world/map.yaml");
    let yaml = ros::read_yaml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let img_path = fixture(&format!("ros/turtlebot3_world/{}", yaml.image));
    let map = ros::read_map(&yaml, &path, &std::fs::read(&img_path).unwrap(), &img_path).unwrap();
    assert_eq!((map.width, map.height, map.cell), (384, 384, 0.05));
    assert_eq!(map.origin, Point::new(-10.0, -10.0));
    assert!(!map.y_down);
    // The world's middle is free, the image's outskirts unknown (so blocked).
    assert_eq!(map.free_at(&Point::new(-0.5, 0.0)), Some(true));
    assert_eq!(map.free_at(&Point::new(-9.9, -9.9)), Some(false));
    // A rotated origin is refused, not ignored.
    let rot = fixture("ros/nav2/testmap.yaml");
    let e = ros::read_yaml(&std::fs::read_to_string(&rot).unwrap(), &rot)
        .unwrap_err()
        .to_string();
    assert!(e.contains("testmap.yaml") && e.contains("yaw 1"), "{e}");
}

#[test]
fn malformed_maps_are_named_errors() {
    for (file, needle) in [
        (
            "invalid/short-row.map",
            "short-row.map:6: row 1 has 3 cells, expected 4",
        ),
        (
            "invalid/unknown-cell.map",
            "unknown-cell.map:5: unknown cell 'x' at column 1",
        ),
        ("invalid/missing-height.map", "missing `height` line"),
        (
            "invalid/too-few-rows.map",
            "expected 3 rows after `map`, found 2",
        ),
        (
            "invalid/not-a-map.map",
            "not-a-map.map:1: expected `type`, `height`, `width` or `map`",
        ),
    ] {
        let path = fixture(file);
        let e = movingai::read_map(&std::fs::read_to_string(&path).unwrap(), &path)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{file}: {e}");
    }
    for (file, needle) in [
        ("invalid/short-record.map.scen", ":2:"),
        ("invalid/bad-number.map.scen", ":2:"),
    ] {
        let path = fixture(file);
        let e = movingai::read_scen(&std::fs::read_to_string(&path).unwrap(), &path)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{file}: {e}");
    }
    for (file, needle) in [
        (
            "invalid/bad-thresholds.yaml",
            "must satisfy 0 <= free < occupied <= 1",
        ),
        ("invalid/unknown-key.yaml", "unknown field `colour`"),
    ] {
        let path = fixture(file);
        let e = ros::read_yaml(&std::fs::read_to_string(&path).unwrap(), &path)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{file}: {e}");
    }
    let path = fixture("invalid/corrupt-image.yaml");
    let yaml = ros::read_yaml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let img = fixture("invalid/corrupt.pgm");
    let e = ros::read_map(&yaml, &path, &std::fs::read(&img).unwrap(), &img)
        .unwrap_err()
        .to_string();
    assert!(e.contains("corrupt.pgm: cannot decode the image"), "{e}");
    // A resolution or origin that puts the map beyond the scenes' coordinate limit (1e9):
    // a resolution of 1e300 hung the planner, 1e9 asked for 104 GB of path samples.
    let path = fixture("ros/turtlebot3_world/map.yaml");
    let text = std::fs::read_to_string(&path).unwrap();
    let img = fixture("ros/turtlebot3_world/map.pgm");
    let bytes = std::fs::read(&img).unwrap();
    for (from, to) in [
        ("resolution: 0.050000", "resolution: 1e300"),
        ("resolution: 0.050000", "resolution: 1e7"),
        ("origin: [-10.000000", "origin: [-2e9"),
    ] {
        let changed = text.replace(from, to);
        assert_ne!(changed, text, "{to}: the YAML was not changed");
        let yaml = ros::read_yaml(&changed, &path).unwrap();
        let e = ros::read_map(&yaml, &path, &bytes, &img)
            .unwrap_err()
            .to_string();
        assert!(e.contains("coordinates must stay within 1e9"), "{to}: {e}");
    }
    let yaml = ros::read_yaml(&text.replace("0.050000", "1e4"), &path).unwrap();
    assert!(
        ros::read_map(&yaml, &path, &bytes, &img).is_ok(),
        "1e4 m per cell reads"
    );
}

#[test]
fn plans_on_movingai_scenarios_are_collision_free_when_reported_so() {
    for name in [
        "random-32-32-10",
        "room-32-32-4",
        "maze-32-32-2",
        "warehouse-10-20-10-2-1",
    ] {
        let map = movingai_map(name);
        let path = fixture(&format!("movingai/{name}-random-1.scen"));
        let scen = movingai::read_scen(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
        let mut found = 0;
        for s in scen.iter().step_by(7).take(4) {
            let cfg = PlanConfig {
                classes: 3,
                ..PlanConfig::default()
            };
            let (plan, _) = plan_map(&map, s.start, s.goal, &cfg).unwrap();
            for c in &plan.classes {
                assert_eq!(c.path[0], s.start);
                assert_eq!(*c.path.last().unwrap(), s.goal);
                if c.collision_free {
                    assert!(
                        path_is_free(&map, &c.path),
                        "{name}: class {} reported free",
                        c.signature
                    );
                }
            }
            found += usize::from(plan.best.is_some());
        }
        // One-cell maze corridors need more via-points than a plan may use: there the
        // planner reports its classes as colliding, which the loop above checks is honest.
        if name != "maze-32-32-2" {
            assert!(found >= 1, "{name}: no scenario planned");
        }
    }
}

#[test]
fn plans_on_a_ros_map() {
    let path = fixture("ros/turtlebot3_world/map.yaml");
    let yaml = ros::read_yaml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let img_path = fixture(&format!("ros/turtlebot3_world/{}", yaml.image));
    let map = ros::read_map(&yaml, &path, &std::fs::read(&img_path).unwrap(), &img_path).unwrap();
    let (s, g) = (Point::new(-2.0, -0.5), Point::new(1.5, 0.5));
    let (plan, prepared) = plan_map(&map, s, g, &PlanConfig::default()).unwrap();
    assert!(prepared.graph.graph.cycle_rank() >= 1);
    let best = &plan.classes[plan.best.expect("a plan on turtlebot3_world") - 1];
    assert!(path_is_free(&map, &best.path));
}

/// A map at a micrometre a cell is certified to a fiftieth of its cell, as any other map:
/// the certificate's tolerance (1e-3 map units) was absolute, a thousand cells at 1e-6 m.
/// (The cost itself is in map units, not cells: on such a map the curve is pushed from the
/// walls far less than on the same map at a metre a cell; docs/guide.md says so.)
#[test]
fn the_certificate_is_as_fine_as_the_cell() {
    let base = movingai_map("room-32-32-4");
    let (s, g) = (Point::new(21.5, 14.5), Point::new(9.5, 0.5));
    let cfg = PlanConfig::maps();
    for cell in [1e-6, 1e-5, 1e-3, 1.0] {
        let map = OccupancyMap {
            cell,
            ..base.clone()
        };
        let scaled = |p: Point| Point::new(p.x * cell, p.y * cell);
        let plan = plan_map(&map, scaled(s), scaled(g), &cfg).unwrap().0;
        for c in &plan.classes {
            // The sampled path's clearance bounds the curve's from above; the certificate
            // is a lower bound within its tolerance of the curve's.
            let gap = c.min_clearance - c.certified_clearance;
            assert!(
                gap <= 0.05 * cell,
                "cell {cell}, class {}: certified {:e} against sampled {:e}",
                c.rank,
                c.certified_clearance,
                c.min_clearance
            );
        }
    }
}

/// The chosen class's finish and polish are for scenes: on a map neither runs, even when
/// a configuration asks for them and takes the planner's path that ranks its classes after
/// the search (`diverse`).
#[test]
fn a_map_plan_gets_no_finish_or_polish_whatever_the_configuration() {
    let map = movingai_map("room-32-32-4");
    let (s, g) = (Point::new(21.5, 14.5), Point::new(9.5, 0.5));
    for (finish_within, polish) in [(Some(1_000_000), 0), (None, 2)] {
        for diverse in [None, Some(0.5)] {
            let cfg = PlanConfig {
                finish_within,
                polish,
                diverse,
                ..PlanConfig::maps()
            };
            let (plan, _) = plan_map(&map, s, g, &cfg).unwrap();
            assert!(plan.best.is_some());
            for c in &plan.classes {
                assert!(
                    c.rounds.iter().all(|r| !r.polish),
                    "{:?} {polish} {diverse:?}: class {}",
                    finish_within,
                    c.signature
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The exact clearance is the distance to the nearest occupied square, by brute force.
    #[test]
    fn exact_clearance_is_the_distance_to_the_nearest_occupied_cell(
        bits in prop::collection::vec(prop::bool::weighted(0.15), 12 * 10),
        points in prop::collection::vec((0.0..12.0, 0.0..10.0), 1..6),
    ) {
        let map = OccupancyMap { name: "t".into(), width: 12, height: 10, cell: 1.0, origin: Point::origin(), occupied: bits, y_down: false };
        let grid = map.to_grid().unwrap();
        let model = GridModel::new(&grid, &DistanceField::build(&grid));
        // Several points: later ones in a cell use the candidate list the first one made.
        for (px, py) in points {
        let p = Point::new(px, py);
        // Brute force over the grid (map plus wall ring), distance to closed squares.
        let mut best = f64::INFINITY;
        for j in 0..grid.height() {
            for i in 0..grid.width() {
                if grid.occupied(i, j) {
                    let c = grid.corner(i, j);
                    let dx = (c.x - p.x).max(p.x - c.x - 1.0).max(0.0);
                    let dy = (c.y - p.y).max(p.y - c.y - 1.0).max(0.0);
                    best = best.min((dx * dx + dy * dy).sqrt());
                }
            }
        }
        let e = model.exact(&p);
        if e >= 0.0 {
            prop_assert!((e - best).abs() < 1e-12, "exact {} brute {}", e, best);
        } else {
            prop_assert_eq!(best, 0.0);
        }
    }
        }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// The segment bound `(d(a) + d(b) - |ab|) / 2` never exceeds the exact clearance at any
    /// of 400 points along the segment (so it is a lower bound wherever it is positive).
    #[test]
    fn the_segment_bound_is_below_the_clearance_along_the_segment(
        bits in prop::collection::vec(prop::bool::weighted(0.15), 12 * 10),
        (ax, ay, bx, by) in (0.0..12.0, 0.0..10.0, 0.0..12.0, 0.0..10.0),
    ) {
        use homospline_spline::ClearanceModel;
        let map = OccupancyMap { name: "t".into(), width: 12, height: 10, cell: 1.0, origin: Point::origin(), occupied: bits, y_down: false };
        let grid = map.to_grid().unwrap();
        let model = GridModel::new(&grid, &DistanceField::build(&grid));
        let (a, b) = (Point::new(ax, ay), Point::new(bx, by));
        let bound = model.segment_clearance(&a, &b);
        let least = (0..=400)
            .map(|k| model.exact(&(a + (b - a) * (k as f64 / 400.0))))
            .fold(f64::INFINITY, f64::min);
        prop_assert!(bound <= least.max(0.0) + 1e-12, "bound {} above the least sampled clearance {}", bound, least);
    }
}

/// Total turning, degrees, of a path over its first `span` units of length.
fn turning(path: &[Point], span: f64) -> f64 {
    let (mut arc, mut total, mut heading) = (0.0, 0.0, None::<f64>);
    for w in path.windows(2) {
        let d = w[1] - w[0];
        if d.norm() == 0.0 {
            continue;
        }
        let h = d.y.atan2(d.x);
        if let Some(prev) = heading {
            let pi = std::f64::consts::PI;
            total += ((h - prev + pi).rem_euclid(2.0 * pi) - pi).abs();
        }
        heading = Some(h);
        arc += d.norm();
        if arc > span {
            break;
        }
    }
    total.to_degrees()
}

/// Distance from `p` to the nearest blocked cell of `map`, by brute force.
fn brute_clearance(map: &OccupancyMap, p: Point) -> f64 {
    let mut best = f64::INFINITY;
    for j in 0..map.height {
        for i in 0..map.width {
            let c = Point::new(i as f64 + 0.5, j as f64 + 0.5);
            if map.free_at(&c) == Some(false) {
                let dx = ((p.x - c.x).abs() - 0.5).max(0.0);
                let dy = ((p.y - c.y).abs() - 0.5).max(0.0);
                best = best.min(dx.hypot(dy));
            }
        }
    }
    best
}

/// Start and goal join the graph along their maximum-clearance route, which can meet the
/// ridge behind them. Before seeds were shortcut at their ends, the chosen curve on these
/// city scenarios ran past its goal and curled back into it, turning by 45 to 140 degrees
/// within 5 cells of an end. Nothing forces a turn within an end's own clearance (the robot
/// can head any way there): the curve turns by at most 30 degrees over the first
/// `min(5, clearance)` cells at each end.
#[test]
fn curves_do_not_curl_at_their_ends() {
    let map = movingai_map("Boston_0_256");
    let prepared = homospline_maps::PreparedMap::new(&map).unwrap();
    let cfg = PlanConfig::maps();
    for (s, g) in [
        ((89, 49), (146, 93)),
        ((182, 252), (9, 53)),
        ((40, 213), (243, 48)),
        ((83, 31), (141, 177)),
        ((206, 241), (241, 111)),
        ((37, 219), (25, 210)),
    ] {
        let at = |(x, y): (i32, i32)| Point::new(x as f64 + 0.5, y as f64 + 0.5);
        let (s, g) = (at(s), at(g));
        let plan = prepared.plan(s, g, &cfg).unwrap();
        let best = &plan.classes[plan.best.expect("a collision-free plan") - 1];
        assert!(path_is_free(&map, &best.path));
        let mut back = best.path.clone();
        back.reverse();
        for (end, path) in [(s, &best.path), (g, &back)] {
            let span = brute_clearance(&map, end).min(5.0);
            let turn = turning(path, span);
            assert!(
                turn <= 30.0,
                "{s:?} -> {g:?}: the curve turns {turn:.1} degrees within {span:.1} of {end:?}"
            );
        }
    }
}

/// random512-20-0, scenario line 1583 (80,475 to 499,93): a random field of one-cell
/// obstacles, where the graph holds thousands of paths of nearly equal length whose sums
/// differ only by rounding. The class search once went breadth first on those differences and
/// ran out of its budget with no class at all (a wrong "no path"); it must find k.
#[test]
fn a_random_field_yields_its_classes() {
    let map = movingai_map("random512-20-0");
    let prepared = homospline_maps::PreparedMap::new(&map).unwrap();
    let graph = prepared
        .query_graph(Point::new(80.5, 475.5), Point::new(499.5, 93.5))
        .unwrap();
    let cfg = PlanConfig::maps();
    let found = homospline_homotopy::k_best_classes(&graph, &prepared.rays, &cfg.search).unwrap();
    assert_eq!(
        found.classes.len(),
        cfg.search.k,
        "expansions {}",
        found.expansions
    );
}

/// A map's classes are optimised while the class search goes on (each as soon as it is
/// found): the plan must not depend on the thread count, nor on which class finished first.
#[test]
fn map_plans_are_the_same_for_any_thread_count() {
    let map = movingai_map("Boston_0_256");
    let prepared = homospline_maps::PreparedMap::new(&map).unwrap();
    let (s, g) = (Point::new(40.5, 213.5), Point::new(243.5, 48.5));
    let strip = |mut p: homospline_optim::Plan| {
        p.timing = Default::default();
        for c in &mut p.classes {
            c.time_ms = 0.0;
        }
        p
    };
    let with = |threads| {
        let cfg = PlanConfig {
            threads: Some(threads),
            ..PlanConfig::maps()
        };
        strip(prepared.plan(s, g, &cfg).unwrap())
    };
    let one = with(1);
    assert!(one.classes.len() >= 3);
    assert_eq!(one, with(2));
    assert_eq!(one, with(4));
}

#[test]
fn start_and_goal_at_one_point_is_a_plan_to_stay() {
    // It was an empty path at clearance -inf, reported as no collision-free class (exit 1),
    // while the same on a scene planned a curve of length 0.
    let map = movingai_map("room-32-32-4");
    let p = Point::new(1.5, 1.5);
    let (plan, _) = plan_map(&map, p, p, &PlanConfig::default()).unwrap();
    let c = plan.chosen().expect("a plan");
    assert_eq!(c.path, vec![p, p]);
    assert_eq!(c.length, 0.0);
    assert!(c.collision_free && c.in_class);
    assert!((c.min_clearance - 0.5).abs() < 1e-9, "{}", c.min_clearance);
}

#[test]
fn a_point_touching_an_occupied_cell_or_the_edge_is_not_a_position() {
    // 3 x 2 cells of 2 units from (10, 20), cell (1, 0) occupied.
    let map = OccupancyMap {
        name: "tiny".into(),
        width: 3,
        height: 2,
        cell: 2.0,
        origin: Point::new(10.0, 20.0),
        occupied: vec![false, true, false, false, false, false],
        y_down: false,
    };
    let at = |x: f64, y: f64| map.touches_obstacle(&Point::new(x, y));
    assert_eq!(at(11.0, 21.0), None);
    assert_eq!(
        at(13.0, 23.0),
        None,
        "a free cell's corner among free cells"
    );
    for (x, y) in [
        (12.0, 21.0),
        (14.0, 21.0),
        (12.0, 22.0),
        (13.0, 22.0),
        (16.0, 22.0),
    ] {
        let why = if x == 16.0 {
            "lies on the map's edge"
        } else {
            "lies on the side or corner of an occupied cell"
        };
        assert_eq!(at(x, y), Some(why), "({x}, {y})");
    }
    for (x, y) in [(10.0, 21.0), (11.0, 20.0), (11.0, 24.0)] {
        assert_eq!(at(x, y), Some("lies on the map's edge"), "({x}, {y})");
    }
}

#[test]
fn a_ros_map_yaml_without_its_image_says_so() {
    // Detected by `image:` alone, it was read as a scene: "unknown field `resolution`".
    let text = "resolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    let e = match homospline_maps::input::load(std::path::Path::new("noimage.yaml"), |_| {
        Ok(text.as_bytes().to_vec())
    }) {
        Err(e) => e,
        Ok(_) => panic!("read"),
    };
    assert_eq!(e, "noimage.yaml:5: missing field `image`");
}

#[test]
fn a_ros_point_on_a_cell_side_in_decimal_coordinates_touches_it() {
    // (0.1 + 10) / 0.05 is 201.99999999999997 cells: the exact side test let this goal
    // through, and its plan ran past 20 s.
    let path = fixture("ros/nav2/tb3_sandbox.yaml");
    let yaml = ros::read_yaml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let img = fixture(&format!("ros/nav2/{}", yaml.image));
    let map = ros::read_map(&yaml, &path, &std::fs::read(&img).unwrap(), &img).unwrap();
    for (x, y) in [(-2.825, 0.1), (-0.15, -1.125)] {
        let p = Point::new(x, y);
        assert!(
            map.free_at(&p) == Some(false) || map.touches_obstacle(&p).is_some(),
            "({x}, {y}) passes for a position"
        );
    }
}

#[test]
fn every_class_on_a_ros_map_ends_at_the_goal_to_the_bit() {
    // A class's seed ended at 1.9999999999999998 for a goal at 2 (the seed's interpolation),
    // and so did its curve and path.
    let path = fixture("ros/turtlebot3_world/map.yaml");
    let yaml = ros::read_yaml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let img = fixture(&format!("ros/turtlebot3_world/{}", yaml.image));
    let map = ros::read_map(&yaml, &path, &std::fs::read(&img).unwrap(), &img).unwrap();
    let (s, t) = (Point::new(-2.0, -0.5), Point::new(2.0, 0.5));
    let (plan, _) = plan_map(&map, s, t, &PlanConfig::default()).unwrap();
    assert!(plan.classes.len() > 1);
    for c in &plan.classes {
        for pts in [&c.via_points, &c.path] {
            assert_eq!(
                (pts[0], pts[pts.len() - 1]),
                (s, t),
                "class {}",
                c.signature
            );
        }
    }
}

/// A map beyond 4096 x 4096 cells is refused up front, with what fits and what to do (not a
/// scene's "lower the resolution"): from a MovingAI header before its rows are read, and by
/// the preparation before the grid is allocated (a map whose cells were never allocated is
/// refused, not indexed).
#[test]
fn maps_beyond_4096_squared_are_refused_before_allocation() {
    let expected = "map big is 5790 x 5790 cells (33524100 cells); at most 16777216 cells (4096 x 4096) fit in the 1.5 GB a map may take: crop or downsample the map";
    // Header only: the refusal comes before the missing rows are noticed.
    let e = movingai::read_map("type octile\nheight 5790\nwidth 5790\nmap\n", "big.map")
        .unwrap_err()
        .to_string();
    assert_eq!(e, expected);
    let huge = OccupancyMap {
        name: "big".into(),
        width: 5790,
        height: 5790,
        cell: 1.0,
        origin: Point::origin(),
        occupied: Vec::new(),
        y_down: true,
    };
    assert_eq!(huge.to_grid().unwrap_err().to_string(), expected);
    let e = homospline_maps::PreparedMap::new(&huge)
        .err()
        .unwrap()
        .to_string();
    assert_eq!(e, expected);
    assert!(!e.contains("resolution"));
    // The largest map that fits passes the check; one more row does not.
    assert!(homospline_maps::check_map_size("m", 4096, 4096).is_ok());
    assert!(homospline_maps::check_map_size("m", 4096, 4097).is_err());
    assert!(homospline_maps::check_map_size("m", usize::MAX, 2).is_err());
}

/// The class search on a query of a prepared map (no copy of its graph) finds the same
/// classes, in the same order, as on the query's graph copied and pruned
/// (`MapGraph::with_endpoints`): the same paths, costs and signatures. Scenario pairs from
/// every bucket of each map's file (short ones cost edges and settle distances as the
/// search asks, long ones all at once: both are compared), and a blocked region (a
/// mission's closed passage).
#[test]
fn a_query_without_a_copy_searches_as_the_copied_graph() {
    use homospline_homotopy::{k_best_classes, k_best_classes_on};
    let cfg = PlanConfig::maps();
    let mut modes = [0, 0];
    for (name, scen) in [
        ("room-32-32-4", "room-32-32-4-random-1.scen"),
        ("maze-32-32-2", "maze-32-32-2-random-1.scen"),
        ("random-32-32-10", "random-32-32-10-random-1.scen"),
        ("Boston_0_256", "Boston_0_256.map.scen"),
    ] {
        let map = movingai_map(name);
        let prepared = homospline_maps::PreparedMap::new(&map).unwrap();
        let path = fixture(&format!("movingai/{scen}"));
        let all = movingai::read_scen(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
        let step = (all.len() / 12).max(1);
        let mut compared = 0;
        for (i, s) in all.iter().step_by(step).enumerate() {
            let (g, q) = (
                prepared.query_graph(s.start, s.goal),
                prepared
                    .graph
                    .query(&prepared.grid, &prepared.field, s.start, s.goal),
            );
            let (Ok(g), Ok(q)) = (g, q) else {
                panic!("{name} #{i}: a query where the other way has none");
            };
            // Both ways of costing edges and settling distances are compared.
            modes[usize::from(q.reach() >= homospline_homotopy::search::EAGER_REACH)] += 1;
            let mut search = cfg.search.clone();
            search.k = 5;
            if i % 3 == 2 {
                // A disc on the first class's way, as a mission closes a blocked passage.
                let first = k_best_classes(&g, &prepared.rays, &search).unwrap();
                let poly = &first.classes[0].polyline;
                search.blocked_regions = vec![(poly[poly.len() / 2], 1.5)];
            }
            let a = k_best_classes(&g, &prepared.rays, &search).unwrap();
            let b = k_best_classes_on(&q, &prepared.rays, &search).unwrap();
            let key = |r: &homospline_homotopy::SearchResult| {
                r.classes
                    .iter()
                    .map(|c| (c.polyline.clone(), c.cost, c.signature.clone()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(key(&a), key(&b), "{name} #{i}");
            assert_eq!(
                (a.complete, a.expansions),
                (b.complete, b.expansions),
                "{name} #{i}"
            );
            compared += 1;
        }
        assert!(compared >= 10, "{name}: {compared} scenarios");
    }
    assert!(
        modes.iter().all(|&m| m >= 5),
        "short and long queries: {modes:?}"
    );
}
