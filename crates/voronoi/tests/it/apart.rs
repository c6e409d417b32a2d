//! Start and goal apart on a scene's grid, against an exact oracle: the tangent graph of
//! the circles (`homospline_geom::shortest`), which joins start and goal exactly when a
//! path keeps out of every disc.

use homospline_geom::shortest::TangentGraph;
use homospline_geom::{Bounds, Circle, Obstacle, Point, Scene};
use homospline_voronoi::{BuildError, GraphError};
use proptest::prelude::*;

/// A ring of `n` overlapping circles of ring radius 6 around the start (bounds 0 to 50,
/// goal outside at (3, 3)); with `door`, circle 0 shrinks so that it leaves a gap of
/// `width` to each neighbour.
fn ring(n: usize, door: Option<f64>) -> Scene {
    let (cx, cy, big_r) = (25.0, 25.0, 6.0);
    let chord = 2.0 * big_r * (std::f64::consts::PI / n as f64).sin();
    // Neighbours overlap by 0.8.
    let rho = chord / 2.0 + 0.4;
    let obstacles = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            let r = match door {
                Some(width) if i == 0 => rho - 0.8 - width,
                _ => rho,
            };
            Obstacle {
                name: format!("c{i}"),
                circles: vec![Circle::new(cx + big_r * a.cos(), cy + big_r * a.sin(), r)],
            }
        })
        .collect();
    Scene {
        name: "ring".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(50.0, 50.0),
        },
        start: Point::new(cx, cy),
        goal: Point::new(3.0, 3.0),
        robot_radius: 0.0,
        obstacles,
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    }
}

/// Whether a path from start to goal keeps out of every circle (bounds far from all).
fn oracle(scene: &Scene) -> bool {
    TangentGraph::build(&scene.start, &scene.goal, &scene.circles(), 0.0)
        .unwrap()
        .and_then(|g| g.shortest())
        .is_some()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// The graph joins start and goal exactly when the circles let a path through: a door
    /// of half a unit or more, narrower than a cell or not, is found (on a finer grid when
    /// needed), and a closed ring is reported walled, naming its circles, never as a gap
    /// the grid could not see.
    #[test]
    fn apart_on_the_grid_is_judged_from_the_circles(
        n in 5usize..10,
        door in prop::option::of(0.5f64..1.5),
        resolution in prop::sample::select(vec![1.0, 2.0, 5.12]),
    ) {
        let scene = ring(n, door);
        let through = oracle(&scene);
        prop_assert_eq!(through, door.is_some(), "the oracle disagrees with the ring's make");
        match homospline_voronoi::build(&scene, resolution) {
            Ok((_, _, g)) => {
                prop_assert!(through, "a graph through a closed ring");
                prop_assert!(g.connected(g.start.unwrap(), g.goal.unwrap()));
            }
            Err(BuildError::Graph(e @ GraphError::Walled { .. })) => {
                prop_assert!(!through, "walled, but a path exists: {}", e);
                prop_assert!(e.is_no_route());
                prop_assert!(e.to_string().contains("'c0', 'c1'"), "{}", e);
            }
            Err(e) => prop_assert!(false, "{}", e),
        }
    }
}

/// Two discs meeting the bounds' lower and upper sides wall the left half off: named,
/// and the other obstacles (a free disc) are not.
#[test]
fn a_wall_across_the_bounds_is_named() {
    let scene = Scene {
        name: "across".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(60.0, 60.0),
        },
        start: Point::new(5.0, 30.0),
        goal: Point::new(55.0, 30.0),
        robot_radius: 3.0,
        obstacles: vec![
            Obstacle {
                name: "top".into(),
                circles: vec![Circle::new(30.0, 45.0, 12.0)],
            },
            Obstacle {
                name: "rock".into(),
                circles: vec![Circle::new(50.0, 52.0, 1.0)],
            },
            Obstacle {
                name: "bot".into(),
                circles: vec![Circle::new(30.0, 15.0, 12.0)],
            },
        ],
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    };
    let e = homospline_voronoi::build(&scene, 4.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "no route: start and goal are walled apart by 'top', 'bot': their circles (grown by the robot's radius) touch one another or the bounds, and no gap between them lets a path through"
    );
    // Without the robot's radius they leave a gap of 6: planned.
    let open = Scene {
        robot_radius: 0.0,
        ..scene
    };
    assert!(homospline_voronoi::build(&open, 4.0).is_ok());
}

#[test]
fn an_end_closer_to_a_circle_than_a_cell_gets_a_finer_grid() {
    let scene = |start_x: f64| Scene {
        name: "near".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(60.0, 60.0),
        },
        start: Point::new(start_x, 30.0),
        goal: Point::new(55.0, 30.0),
        robot_radius: 0.0,
        obstacles: vec![Obstacle {
            name: "rock".into(),
            circles: vec![Circle::new(20.2, 30.0, 10.0)],
        }],
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    };
    // At 2 cells per unit the cell [10, 10.5] holding (10.05, 30), 0.15 from the rock, has
    // its centre in it (it was refused: "falls in an occupied cell"); a grid of cells no
    // wider than the clearance holds it in a free cell, joined to the graph.
    for x in [10.05, 10.1] {
        let clearance = 20.2 - 10.0 - x;
        let (grid, _, g) = homospline_voronoi::build(&scene(x), 2.0).unwrap();
        assert!(grid.cell() <= clearance, "{x}: {}", grid.cell());
        assert!(g.connected(g.start.unwrap(), g.goal.unwrap()), "{x}");
    }
    // A start the default grid holds is built on it, as before.
    let (grid, _, _) = homospline_voronoi::build(&scene(5.0), 2.0).unwrap();
    assert_eq!(grid.cell(), 0.5);
    // Too close for any grid within the limit: refused, naming the end and the obstacle.
    let e = homospline_voronoi::build(&scene(10.2 - 1e-6), 2.0).unwrap_err();
    assert!(
        matches!(e, BuildError::Graph(GraphError::TooClose { .. }))
            && e.to_string().starts_with(
                "the start [10.199999, 30] is 0.000001 from obstacle 'rock', closer than a grid of 2 cells per unit can tell"
            ),
        "{e}"
    );
}

/// A gap narrower than the grid that would resolve it for certain, within the cell limit:
/// the finest grid within the limit opens it all the same, and the graph joins start and
/// goal through it (a review's case, where the plan was refused as bad input while
/// `--resolution 50` planned it); and where that grid joins them only along its border
/// cells, outside the bounds, no verdict is claimed, as before.
#[test]
fn a_gap_finer_than_the_limit_allows_is_tried_on_the_finest_grid_within_it() {
    let wall = |gap: f64| Scene {
        name: "wall".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(20.0, 20.0),
        },
        start: Point::new(3.0, 10.0),
        goal: Point::new(17.0, 10.0),
        robot_radius: 0.0,
        obstacles: vec![
            Obstacle {
                name: "low".into(),
                circles: vec![Circle::new(10.0, 5.0, 5.0)],
            },
            Obstacle {
                name: "high".into(),
                circles: vec![Circle::new(10.0, 15.0 + gap, 5.0)],
            },
        ],
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    };
    // A gap of 0.05, which the refinement would resolve at about 120 cells per unit (some
    // 6 M cells): within a million cells (51 per unit, cells under 0.02) the grid opens it.
    let (grid, _, graph) = homospline_voronoi::build_within(&wall(0.05), 1.0, 1 << 20).unwrap();
    assert!(grid.resolution() > 40.0, "{}", grid.resolution());
    assert!(graph.connected(graph.start.unwrap(), graph.goal.unwrap()));
    // The high circle overhangs the top bound by a hair (its top at 20.0005): a coarse
    // grid's border cells there are free, but that way round is outside the bounds.
    let e = homospline_voronoi::build_within(&wall(0.0005), 1.0, 1 << 20)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no plan is claimed"), "{e}");
}
