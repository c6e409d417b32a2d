//! Property tests of the exact shortest path that keeps a clearance from circles: the path
//! it gives is whole and keeps the clearance, no route through a dense sample of the grown
//! circles' boundaries is shorter, and more clearance never makes it shorter.

use homospline_geom::math::distance_point_segment;
use homospline_geom::shortest::{Piece, shortest_path};
use homospline_geom::{Circle, Point, Real};
use proptest::prelude::*;

/// Scattered circles, or circles crowded into compound obstacles (overlapping, as the scenes'
/// cups and brackets are).
fn circles() -> impl Strategy<Value = Vec<Circle>> {
    (
        prop::bool::ANY,
        prop::collection::vec((-1.0..1.0, -1.0..1.0, 0.5..6.0), 1..7),
    )
        .prop_map(|(crowded, cs)| {
            let spread = if crowded { 8.0 } else { 20.0 };
            cs.into_iter()
                .map(|(x, y, r)| Circle::new(x * spread, y * spread, r))
                .collect()
        })
}

fn end() -> impl Strategy<Value = Point> {
    (-30.0..30.0, -30.0..30.0).prop_map(|(x, y)| Point::new(x, y))
}

/// The shortest route through the vertices of polygons circumscribed about the grown circles
/// (`n` vertices each, every polygon edge tangent to its circle), each of its segments
/// checked exactly: a path that keeps the clearance, so never shorter than the optimum.
fn sampled_route(
    s: &Point,
    t: &Point,
    circles: &[Circle],
    clearance: Real,
    n: usize,
) -> Option<Real> {
    let grown: Vec<Circle> = circles.iter().map(|c| c.inflated(clearance)).collect();
    let clear = |p: &Point| grown.iter().all(|d| (p - d.center).norm() >= d.radius);
    let free = |a: &Point, b: &Point| {
        grown
            .iter()
            .all(|d| distance_point_segment(&d.center, a, b) >= d.radius)
    };
    let mut nodes = vec![*s, *t];
    let stretch = 1.0 / (std::f64::consts::PI / n as Real).cos() * (1.0 + 1e-12);
    for d in &grown {
        for k in 0..n {
            let a = std::f64::consts::TAU * k as Real / n as Real;
            let p = d.center + nalgebra::Vector2::new(a.cos(), a.sin()) * d.radius * stretch;
            if clear(&p) {
                nodes.push(p);
            }
        }
    }
    // Dijkstra on the complete graph, edges checked when relaxed.
    let m = nodes.len();
    let mut dist = vec![Real::INFINITY; m];
    let mut done = vec![false; m];
    dist[0] = 0.0;
    loop {
        let u = (0..m)
            .filter(|&i| !done[i])
            .min_by(|&a, &b| dist[a].total_cmp(&dist[b]))?;
        if !dist[u].is_finite() {
            return None;
        }
        if u == 1 {
            return Some(dist[1]);
        }
        done[u] = true;
        for v in 0..m {
            let dv = dist[u] + (nodes[v] - nodes[u]).norm();
            if !done[v] && dv < dist[v] && free(&nodes[u], &nodes[v]) {
                dist[v] = dv;
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// The path runs from the start to the goal without a gap, its pieces add up to its
    /// length, it is at least the straight distance, and every piece keeps the clearance
    /// (segments exactly, arcs at 512 points each).
    #[test]
    fn the_path_is_whole_and_keeps_its_clearance(cs in circles(), s in end(), t in end(), c in 0.0..2.0f64) {
        let Some(p) = shortest_path(&s, &t, &cs, c).unwrap() else { return Ok(()) };
        let tol = 1e-7;
        prop_assert!(!p.pieces.is_empty());
        prop_assert!((p.pieces[0].point(0.0) - s).norm() < tol);
        prop_assert!((p.pieces.last().unwrap().point(1.0) - t).norm() < tol);
        for w in p.pieces.windows(2) {
            prop_assert!((w[0].point(1.0) - w[1].point(0.0)).norm() < tol, "gap between {:?} and {:?}", w[0], w[1]);
        }
        let sum: Real = p.pieces.iter().map(Piece::length).sum();
        prop_assert!((sum - p.length).abs() <= 1e-9 * (1.0 + p.length));
        prop_assert!(p.length >= (t - s).norm() - 1e-9);
        for piece in &p.pieces {
            match *piece {
                Piece::Segment { from, to } => {
                    for k in &cs {
                        prop_assert!(distance_point_segment(&k.center, &from, &to) - k.radius >= c - tol);
                    }
                }
                Piece::Arc { .. } => {
                    for i in 0..=512 {
                        let q = piece.point(i as Real / 512.0);
                        for k in &cs {
                            prop_assert!((q - k.center).norm() - k.radius >= c - tol);
                        }
                    }
                }
            }
        }
    }

    /// No route through 96 points round each grown circle is shorter, and where one exists
    /// the optimum exists too and is within 1 % of it.
    #[test]
    fn no_sampled_route_is_shorter(cs in circles(), s in end(), t in end(), c in 0.0..2.0f64) {
        let exact = shortest_path(&s, &t, &cs, c).unwrap().map(|p| p.length);
        if let Some(route) = sampled_route(&s, &t, &cs, c, 96) {
            let exact = exact.expect("a route exists, so an optimum does");
            prop_assert!(exact <= route + 1e-9, "optimum {exact} above a route {route}");
            prop_assert!(route <= exact * 1.01 + 1e-9, "route {route} far above the optimum {exact}");
        }
    }

    /// More clearance never gives a shorter path, nor a path where there was none.
    #[test]
    fn more_clearance_never_shortens(cs in circles(), s in end(), t in end(), c in 0.0..2.0f64, more in 0.0..1.0f64) {
        let a = shortest_path(&s, &t, &cs, c).unwrap().map_or(Real::INFINITY, |p| p.length);
        let b = shortest_path(&s, &t, &cs, c + more).unwrap().map_or(Real::INFINITY, |p| p.length);
        prop_assert!(a <= b + 1e-9, "{a} at {c}, {b} at {}", c + more);
    }
}
