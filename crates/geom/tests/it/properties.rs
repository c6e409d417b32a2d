//! Property tests for the geometry: set queries against brute force, both backends,
//! inflation, scene round trips and the polygon cover.

use homospline_geom::math::distance_point_segment;
use homospline_geom::query::{cast_ray_circle, distance_segment_circle};
use homospline_geom::{
    Bounds, Circle, CircleSet, Obstacle, Placement, Point, Polygon, QueryBackend, Scene, Vector,
    cover_polygon, topological_obstacles,
};
use proptest::prelude::*;

fn circle() -> impl Strategy<Value = Circle> {
    (-50.0..50.0, -50.0..50.0, 0.1..8.0).prop_map(|(x, y, r)| Circle::new(x, y, r))
}

fn circles(max: usize) -> impl Strategy<Value = Vec<Circle>> {
    prop::collection::vec(circle(), 1..max)
}

fn point() -> impl Strategy<Value = Point> {
    (-60.0..60.0, -60.0..60.0).prop_map(|(x, y)| Point::new(x, y))
}

fn both(cs: &[Circle]) -> [CircleSet; 2] {
    [
        CircleSet::with_backend(cs.to_vec(), QueryBackend::Linear),
        CircleSet::with_backend(cs.to_vec(), QueryBackend::Bvh),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn a_disc_is_placed_against_the_bounds_as_dense_sampling_finds_it(c in circle()) {
        let b = Bounds { min: Point::new(-20.0, -10.0), max: Point::new(25.0, 30.0) };
        // The disc's boundary sampled densely, and the rectangle's corners and the centre:
        // inside if every boundary sample is strictly within; apart if no sample of either
        // shape lies in the other.
        const N: usize = 3600;
        let ring: Vec<Point> = (0..N)
            .map(|k| {
                let t = k as f64 / N as f64 * std::f64::consts::TAU;
                c.center + Vector::new(t.cos(), t.sin()) * c.radius
            })
            .collect();
        let corners = [b.min, b.max, Point::new(b.min.x, b.max.y), Point::new(b.max.x, b.min.y)];
        let within = |p: &Point| b.wall_clearance(p);
        let least = ring.iter().map(within).fold(f64::INFINITY, f64::min);
        let most = ring.iter().chain([c.center].iter()).map(within).fold(f64::NEG_INFINITY, f64::max);
        let corner_in = corners.iter().map(|q| c.signed_distance(q)).fold(f64::INFINITY, f64::min);
        // Skip draws within sampling error of a tie (a disc grazing a wall).
        let tie = 1e-3 * (1.0 + c.radius);
        prop_assume!(least.abs() > tie && most.abs() > tie && corner_in.abs() > tie);
        let expected = if least > 0.0 {
            Placement::Inside
        } else if most < 0.0 && corner_in > 0.0 {
            Placement::Outside
        } else {
            Placement::OnWall
        };
        prop_assert_eq!(b.place_disc(&c), expected);
        // A group of one is placed as its disc, and a group mixing places meets a wall.
        prop_assert_eq!(b.place_discs([&c]), expected);
        let inner = Circle::new(0.0, 0.0, 1.0);
        if expected != Placement::Inside {
            prop_assert_eq!(b.place_discs([&inner, &c]), Placement::OnWall);
        }
    }

    #[test]
    fn clearance_is_the_minimum_over_circles(cs in circles(60), p in point()) {
        let brute = cs.iter().map(|c| (p - c.center).norm() - c.radius).fold(f64::INFINITY, f64::min);
        for set in both(&cs) {
            let c = set.clearance(&p).unwrap();
            prop_assert!((c.distance - brute).abs() <= 1e-12 * (1.0 + brute.abs()), "{:?}: {} vs {}", set.backend(), c.distance, brute);
            prop_assert!((cs[c.nearest].signed_distance(&p) - brute).abs() <= 1e-12 * (1.0 + brute.abs()));
            // The gradient is the finite-difference slope of the clearance.
            let h = 1e-6;
            let fd = (set.clearance(&(p + Vector::new(h, 0.0))).unwrap().distance
                - set.clearance(&(p - Vector::new(h, 0.0))).unwrap().distance) / (2.0 * h);
            let tie = cs.iter().filter(|k| (k.signed_distance(&p) - brute).abs() < 1e-4).count() > 1;
            if !tie && (p - cs[c.nearest].center).norm() > 1e-3 {
                prop_assert!((fd - c.gradient.x).abs() < 1e-4, "fd {} grad {}", fd, c.gradient.x);
            }
        }
    }

    #[test]
    fn segment_distance_agrees_with_dense_sampling(cs in circles(40), a in point(), b in point()) {
        const N: usize = 4000;
        let len = (b - a).norm();
        let mut sampled = f64::INFINITY;
        for k in 0..=N {
            let q = a + (b - a) * (k as f64 / N as f64);
            for c in &cs { sampled = sampled.min(c.signed_distance(&q)); }
        }
        for set in both(&cs) {
            let (exact, i) = set.distance_to_segment(&a, &b).unwrap();
            // Sampling can only overestimate, by at most half the spacing (1-Lipschitz).
            prop_assert!(exact <= sampled + 1e-9, "{:?}: exact {} > sampled {}", set.backend(), exact, sampled);
            prop_assert!(sampled - exact <= len / N as f64 / 2.0 + 1e-9, "exact {} sampled {}", exact, sampled);
            prop_assert!((distance_segment_circle(&a, &b, &cs[i]) - exact).abs() < 1e-12);
        }
    }

    #[test]
    fn line_of_sight_agrees_with_segment_intersection(cs in circles(40), a in point(), b in point()) {
        let blocked = cs.iter().any(|c| distance_point_segment(&c.center, &a, &b) <= c.radius);
        for set in both(&cs) {
            prop_assert_eq!(set.intersects_segment(&a, &b), blocked);
            prop_assert_eq!(set.line_of_sight(&a, &b), !blocked);
            prop_assert_eq!(set.line_of_sight(&b, &a), !blocked);
        }
    }

    #[test]
    fn inflating_lowers_every_clearance_by_exactly_r(cs in circles(30), p in point(), r in 0.0..5.0) {
        for set in both(&cs) {
            let before = set.clearance(&p).unwrap().distance;
            let after = set.inflated(r).clearance(&p).unwrap().distance;
            prop_assert!((before - r - after).abs() <= 1e-12 * (1.0 + before.abs()), "{} - {} != {}", before, r, after);
        }
    }

    #[test]
    fn ray_cast_hits_the_first_circle(cs in circles(40), o in point(), angle in 0.0..std::f64::consts::TAU) {
        let dir = Vector::new(angle.cos(), angle.sin());
        let brute = cs.iter().enumerate()
            .filter_map(|(i, c)| cast_ray_circle(&o, &dir, c, 200.0).map(|t| (t, i)))
            .fold(None, |best: Option<(f64, usize)>, x| match best { Some(b) if b.0 <= x.0 => Some(b), _ => Some(x) });
        for set in both(&cs) {
            let hit = set.cast_ray(&o, &dir, 200.0);
            prop_assert_eq!(hit.is_some(), brute.is_some());
            if let (Some(h), Some((t, _))) = (hit, brute) {
                prop_assert!((h.toi - t).abs() < 1e-9);
                // The hit point is on (or, for a start inside, within) the circle hit.
                prop_assert!(cs[h.circle].signed_distance(&h.point) <= 1e-9);
                // Nothing blocks the ray before the hit: the open segment up to it is clear.
                if h.toi > 1e-6 {
                    let just_before = o + dir * (h.toi * (1.0 - 1e-9));
                    prop_assert!(!set.intersects_segment(&o, &just_before));
                }
            }
        }
    }

    #[test]
    fn topological_obstacles_are_the_components_of_touching(cs in circles(40)) {
        let groups = topological_obstacles(&cs);
        let mut group_of = vec![usize::MAX; cs.len()];
        for (g, t) in groups.iter().enumerate() {
            for &i in &t.circles { group_of[i] = g; }
            // The representative is strictly inside the group.
            prop_assert!(t.circles.iter().any(|&i| cs[i].signed_distance(&t.representative) < 0.0));
        }
        prop_assert!(group_of.iter().all(|&g| g != usize::MAX));
        for i in 0..cs.len() {
            for j in 0..cs.len() {
                if cs[i].touches(&cs[j]) { prop_assert_eq!(group_of[i], group_of[j]); }
            }
        }
        // No group splits into two parts that do not touch each other.
        for t in &groups {
            let mut seen = vec![t.circles[0]];
            let mut k = 0;
            while k < seen.len() {
                let i = seen[k];
                for &j in &t.circles {
                    if !seen.contains(&j) && cs[i].touches(&cs[j]) { seen.push(j); }
                }
                k += 1;
            }
            prop_assert_eq!(seen.len(), t.circles.len());
        }
    }

    #[test]
    fn polygon_cover_contains_the_polygon_and_stays_close(
        radii in prop::collection::vec(2.0..12.0, 3..9),
        tol in 0.3..2.0,
        samples in prop::collection::vec((0.0..1.0, 0.0..1.0), 64),
    ) {
        // A star-shaped polygon around the origin: simple by construction.
        let n = radii.len();
        let poly = Polygon::new((0..n).map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            Point::new(radii[i] * a.cos(), radii[i] * a.sin())
        }).collect());
        let cover = cover_polygon(&poly, tol, 200_000).unwrap();
        for (u, v) in samples {
            let (u, v): (f64, f64) = (u, v);
            // A point of the polygon: in a triangle fan from the origin.
            let i = ((u * n as f64) as usize).min(n - 1);
            let (a, b) = (poly.vertices[i], poly.vertices[(i + 1) % n]);
            let w = u * n as f64 - i as f64;
            let (s, t) = if v + w > 1.0 { (1.0 - v, 1.0 - w) } else { (v, w) };
            let p = Point::origin() + a.coords * s + b.coords * t;
            prop_assert!(cover.iter().any(|c| c.signed_distance(&p) <= 1e-9), "{:?} not covered", p);
            // Points on the boundary are covered too.
            let q = a + (b - a) * v;
            prop_assert!(cover.iter().any(|c| c.signed_distance(&q) <= 1e-9), "{:?} not covered", q);
        }
        for c in &cover {
            for k in 0..8 {
                let ang = std::f64::consts::TAU * k as f64 / 8.0;
                let p = c.center + Vector::new(ang.cos(), ang.sin()) * c.radius;
                prop_assert!(poly.signed_distance(&p) <= tol + 1e-9);
            }
        }
    }

    #[test]
    fn scene_yaml_and_json_round_trip(
        cs in circles(12),
        start in (1.0..9.0, 1.0..9.0),
        rr in 0.0..0.01,
        dp in prop::collection::vec(((-50.0..50.0, -50.0..50.0), 0.1..20.0), 0..3),
        hz in prop::collection::vec((-50.0..50.0, -50.0..50.0), 0..3),
    ) {
        // Obstacles live in [-58, 58]; the free corner [0, 10]^2 below x = -60 holds no
        // circle, so start and goal are shifted there.
        let shift = Vector::new(-200.0, -200.0);
        let scene = Scene {
            name: "random".to_owned(),
            bounds: Bounds { min: Point::new(-210.0, -210.0), max: Point::new(70.0, 70.0) },
            start: Point::new(start.0, start.1) + shift,
            goal: Point::new(start.1, start.0) + shift,
            robot_radius: rr,
            obstacles: cs.chunks(3).enumerate().map(|(i, c)| Obstacle { name: format!("o{i}"), circles: c.to_vec() }).collect(),
            danger_points: dp.iter().map(|&((x, y), d)| homospline_geom::DangerPoint { at: Point::new(x, y), min_distance: d }).collect(),
            critical_points: dp.iter().map(|&((x, y), d)| homospline_geom::CriticalPoint { at: Point::new(y, x), max_distance: d }).collect(),
            hazards: hz.iter().map(|&(x, y)| Point::new(x, y)).collect(),
        };
        prop_assert!(scene.validate("generated").is_ok());
        let yaml = scene.to_yaml();
        prop_assert_eq!(&Scene::from_str(&yaml, "x.yaml").unwrap(), &scene, "{}", yaml);
        let json = scene.to_json();
        prop_assert_eq!(&Scene::from_str(&json, "x.json").unwrap(), &scene, "{}", json);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Malformed input of any kind is an error, never a panic.
    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = Scene::from_bytes(&bytes, "fuzz.yaml");
    }

    /// Every fixture cut short, or with one byte changed, is read or rejected, never a panic.
    #[test]
    fn mutated_fixtures_never_panic(which in 0usize..5, cut in 0.0..1.0f64, at in 0.0..1.0f64, byte in any::<u8>()) {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
        let mut files: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
        let text = std::fs::read(&files[which % files.len()]).unwrap();
        let truncated = &text[..(text.len() as f64 * cut) as usize];
        let _ = Scene::from_bytes(truncated, "cut.yaml");
        let mut changed = text.clone();
        let i = ((changed.len() - 1) as f64 * at) as usize;
        changed[i] = byte;
        if let Ok(s) = Scene::from_bytes(&changed, "changed.yaml") {
            // What is accepted is valid.
            prop_assert!(s.validate("changed.yaml").is_ok());
        }
    }
}
