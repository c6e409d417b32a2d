//! A disc robot on a map: the inflation and the cells a robot can stand in against brute
//! force on seeded random maps, plans that keep the radius from every true occupied cell
//! (exact segment-to-square distances, segment by segment), and the refusals (a start closer
//! than the radius, naming its clearance; a saved graph of another radius; a bad radius).

use homospline_geom::{Point, Real};
use homospline_maps::{MapError, OccupancyMap, PreparedMap, plan_map_for_robot};
use homospline_testkit::{SplitMix, track_clearance};

fn random_map(seed: u64, w: usize, h: usize, density: f64, cell: Real) -> OccupancyMap {
    let mut rng = SplitMix(seed);
    OccupancyMap {
        name: format!("random-{seed}"),
        width: w,
        height: h,
        cell,
        origin: Point::new(-2.0, 3.0),
        occupied: (0..w * h).map(|_| rng.next_unit() < density).collect(),
        y_down: false,
    }
}

/// Distance from cell `(i, j)`'s closed square to the nearest occupied square or the edge,
/// by brute force over every cell.
fn square_clearance(m: &OccupancyMap, i: usize, j: usize) -> Real {
    let edge = [i, j, m.width - 1 - i, m.height - 1 - j]
        .into_iter()
        .min()
        .unwrap_or(0) as Real;
    let mut best = edge * m.cell;
    for b in 0..m.height {
        for a in 0..m.width {
            if m.occupied[b * m.width + a] {
                let dx = (i.abs_diff(a) as Real - 1.0).max(0.0);
                let dy = (j.abs_diff(b) as Real - 1.0).max(0.0);
                best = best.min(dx.hypot(dy) * m.cell);
            }
        }
    }
    best
}

fn centre(m: &OccupancyMap, i: usize, j: usize) -> Point {
    Point::new(
        m.origin.x + (i as Real + 0.5) * m.cell,
        m.origin.y + (j as Real + 0.5) * m.cell,
    )
}

/// Distance from a point to the nearest occupied square or the edge, by brute force.
fn point_clearance(m: &OccupancyMap, p: Point) -> Real {
    let b = m.bounds();
    let mut best = (p.x - b.min.x)
        .min(b.max.x - p.x)
        .min(p.y - b.min.y)
        .min(b.max.y - p.y);
    for j in 0..m.height {
        for i in 0..m.width {
            if m.occupied[j * m.width + i] {
                best = best.min(m.distance_to_cell(&p, (i, j)));
            }
        }
    }
    best
}

#[test]
fn the_inflation_blocks_exactly_the_cells_whose_square_comes_closer_than_the_radius() {
    for seed in 0..12 {
        let cell = if seed % 2 == 0 { 1.0 } else { 0.05 };
        let m = random_map(seed, 17, 13, 0.08, cell);
        for r in [0.3, 0.5, 1.0, 1.5, 2.2, 3.7] {
            let radius = r * cell;
            let inflated = m.inflated(radius).unwrap();
            for j in 0..m.height {
                for i in 0..m.width {
                    let k = j * m.width + i;
                    let blocked = m.occupied[k] || square_clearance(&m, i, j) < radius - 1e-12;
                    assert_eq!(
                        inflated.occupied[k], blocked,
                        "seed {seed} radius {radius} cell ({i}, {j})"
                    );
                }
            }
        }
    }
}

#[test]
fn a_robot_stands_in_the_cells_whose_centre_keeps_its_radius() {
    for seed in 20..28 {
        let cell = if seed % 2 == 0 { 1.0 } else { 0.05 };
        let m = random_map(seed, 19, 15, 0.07, cell);
        for r in [0.4, 0.5, 1.0, 1.3, 2.0] {
            let radius = r * cell;
            let prepared = PreparedMap::for_robot(&m, radius).unwrap();
            let free = prepared.map();
            for j in 0..m.height {
                for i in 0..m.width {
                    let k = j * m.width + i;
                    let c = point_clearance(&m, centre(&m, i, j));
                    // A centre at the radius to rounding (half a cell from a wall at
                    // radius 0.5 cell) may go either way.
                    if (c - radius).abs() <= 1e-9 * cell {
                        continue;
                    }
                    let stands = !m.occupied[k] && c >= radius;
                    assert_eq!(
                        !free.occupied[k], stands,
                        "seed {seed} radius {radius} cell ({i}, {j})"
                    );
                }
            }
        }
    }
}

/// A 60 x 40 room with pillars and a wall with two doors of 5 cells.
fn room() -> OccupancyMap {
    let (w, h) = (60, 40);
    let mut occupied = vec![false; w * h];
    for j in 0..h {
        if !(6..11).contains(&j) && !(27..32).contains(&j) {
            occupied[j * w + 30] = true;
        }
    }
    for (i, j) in [(10, 10), (11, 10), (15, 25), (45, 12), (46, 13), (50, 30)] {
        occupied[j * w + i] = true;
    }
    OccupancyMap {
        name: "room".into(),
        width: w,
        height: h,
        cell: 1.0,
        origin: Point::origin(),
        occupied,
        y_down: false,
    }
}

#[test]
fn plans_keep_the_radius_from_every_true_cell_segment_by_segment() {
    let m = room();
    let cfg = homospline_maps::map_config();
    for radius in [0.0, 0.7, 1.0, 1.8] {
        let (plan, _) = plan_map_for_robot(
            &m,
            radius,
            Point::new(4.5, 20.5),
            Point::new(55.5, 20.5),
            &cfg,
        )
        .unwrap();
        let free: Vec<_> = plan.classes.iter().filter(|c| c.collision_free).collect();
        assert!(!free.is_empty(), "radius {radius}: no collision-free class");
        for c in free {
            assert!(c.certified_clearance > 0.0 && c.min_clearance > 0.0);
            let d = track_clearance(&m, &c.path, radius + 2.0);
            assert!(
                d >= radius + c.min_clearance - 1e-9,
                "radius {radius} class {}: the path comes {d} from a true wall, its reported \
                 body clearance is {}",
                c.signature,
                c.min_clearance
            );
        }
    }
}

#[test]
fn a_start_closer_than_the_radius_is_refused_with_its_clearance() {
    let m = room();
    let cfg = homospline_maps::map_config();
    let e = plan_map_for_robot(
        &m,
        1.0,
        Point::new(29.5, 20.5),
        Point::new(55.5, 20.5),
        &cfg,
    )
    .map(|_| ())
    .unwrap_err();
    assert!(
        matches!(&e, MapError::Endpoint { what: "start", .. })
            && e.to_string()
                .contains("has clearance 0.5000, less than the robot radius 1"),
        "{e}"
    );
    let prepared = PreparedMap::for_robot(&m, 1.0).unwrap();
    let e = prepared
        .plan(Point::new(4.5, 20.5), Point::new(55.5, 0.6), &cfg)
        .map(|_| ())
        .unwrap_err();
    assert!(
        e.to_string().contains("goal") && e.to_string().contains("has clearance 0.6000"),
        "{e}"
    );
    // A radius that no cell keeps leaves no free space: refused, not a graph without edges.
    assert!(matches!(
        PreparedMap::for_robot(&m, 1e6).map(|_| ()),
        Err(MapError::Radius(_))
    ));
    for bad in [-1.0, Real::NAN, Real::INFINITY] {
        assert!(matches!(
            PreparedMap::for_robot(&m, bad).map(|_| ()),
            Err(MapError::Radius(_))
        ));
    }
}

#[test]
fn a_saved_graph_serves_only_its_own_radius() {
    let m = room();
    let g = PreparedMap::for_robot(&m, 1.0).unwrap().graph.graph.clone();
    assert!(PreparedMap::with_graph(&m, g.clone(), 1.0).is_ok());
    let e = PreparedMap::with_graph(&m, g, 0.0).map(|_| ()).unwrap_err();
    assert!(e.to_string().contains("robot radius"), "{e}");
}
