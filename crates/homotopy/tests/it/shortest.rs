//! Property tests of the shortest path of a class: no feasible route of a class is shorter
//! than its class's optimum, the optimum of any class is the overall shortest path, and the
//! path found has the word it was asked for.

use homospline_geom::math::distance_point_segment;
use homospline_geom::shortest::TangentGraph;
use homospline_geom::{Circle, Point, Real};
use homospline_homotopy::{Rays, shortest_in_class};
use proptest::prelude::*;

fn circles() -> impl Strategy<Value = Vec<Circle>> {
    prop::collection::vec(
        (-15.0..15.0, -15.0..15.0, 0.5..4.0).prop_map(|(x, y, r)| Circle::new(x, y, r)),
        1..6,
    )
}

fn point() -> impl Strategy<Value = Point> {
    (-25.0..25.0, -25.0..25.0).prop_map(|(x, y)| Point::new(x, y))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// A detour `S -> P -> Q -> T` that keeps the clearance is a route of its class, so the
    /// class's optimum exists within its length and has its word; the optimum of any class
    /// is the overall shortest path.
    #[test]
    fn no_route_of_a_class_is_shorter_than_its_optimum(
        cs in circles(), s in point(), t in point(), p in point(), q in point(), c in 0.0..1.5f64,
    ) {
        let Some(g) = TangentGraph::build(&s, &t, &cs, c).unwrap() else { return Ok(()) };
        let rays = Rays::new(cs.iter().map(|k| k.center).collect());
        if let Some(best) = g.shortest() {
            let any = shortest_in_class(&g, &rays, |_| true, Real::INFINITY).unwrap().unwrap();
            prop_assert!((any.length - best.length).abs() <= 1e-9 * (1.0 + best.length));
        }
        let route = [s, p, q, t];
        let keeps = route.windows(2).all(|w| {
            cs.iter().all(|k| distance_point_segment(&k.center, &w[0], &w[1]) >= k.radius + c)
        });
        if !keeps {
            return Ok(());
        }
        let len: Real = route.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        let class = rays.signature(&route);
        let opt = shortest_in_class(&g, &rays, |w| *w == class, len * (1.0 + 1e-9) + 1e-9).unwrap();
        prop_assert!(opt.is_some(), "no route of class {class} within the detour's length {len}");
        let opt = opt.unwrap();
        prop_assert!(opt.length <= len * (1.0 + 1e-9) + 1e-9);
        let pts: Vec<Point> = opt
            .pieces
            .iter()
            .flat_map(|piece| (0..=256).map(move |k| piece.point(k as Real / 256.0)))
            .collect();
        prop_assert_eq!(rays.signature(&pts), class);
    }
}
