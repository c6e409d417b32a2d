//! The planner's unit tests: the checks of avoided classes, rounds run ahead of the pruning
//! and undone, the clearance march, pulled seeds, and the reported path's clearance.

use super::clearance::clear_at_least;
use super::config::avoid_misfit;
use super::pull::pull_taut;
use super::report::refine_samples;
use super::*;
use homospline_geom::{Circle, Point};
use homospline_homotopy::{Rays, SearchConfig, k_best_classes};
use homospline_spline::{CircleModel, ClearanceModel, EndCondition, Spline};
use proptest::prelude::*;

#[test]
fn an_avoided_class_must_be_written_as_signatures_print() {
    for ok in ["e", "-1", "+3-1+12", "-12", "#3f9a01c2"] {
        assert_eq!(avoid_misfit(ok, 12), None, "{ok}");
    }
    for (bad, why) in [
        ("abc", "not a class"),
        ("", "not a class"),
        ("1-2", "not a class"),
        ("-", "not a class"),
        ("-1+", "not a class"),
        ("+0", "not a class"),
        ("-01", "not a class"),
        ("-1x", "not a class"),
        ("E", "not a class"),
        ("#3f9a01c", "not a class"),
        ("#3f9a01cz", "not a class"),
        ("-13", "ray 13: there are 12 rays here"),
    ] {
        let got = avoid_misfit(bad, 12).unwrap_or_default();
        assert!(got.contains(why), "{bad}: {got}");
    }
}

/// Rounds run ahead of the pruning decision and undone for the classes it stops leave
/// no trace: on one thread, with every class's rounds run ahead before the next class
/// starts, the plans of the scenes with a stopped class are those of the plain order.
#[test]
fn rounds_run_ahead_and_undone_leave_the_plan_as_it_was() {
    use std::sync::atomic::Ordering;
    let one = PlanConfig {
        threads: Some(1),
        ..PlanConfig::default()
    };
    let bare = |mut p: Plan| {
        p.timing = Timing::default();
        for c in &mut p.classes {
            c.time_ms = 0.0;
        }
        p
    };
    let scenes: Vec<Scene> = homospline_testkit::fixture_scenes()
        .into_iter()
        .filter(|s| ["convex", "narrow-pass", "two-homotopies"].contains(&s.name.as_str()))
        .collect();
    assert_eq!(scenes.len(), 3);
    for scene in &scenes {
        board::AHEAD_FIRST.store(false, Ordering::Relaxed);
        let plain = bare(plan(scene, &one).unwrap());
        assert!(
            plain.classes.iter().any(|c| c.pruned),
            "{}: nothing stopped",
            scene.name
        );
        board::AHEAD_FIRST.store(true, Ordering::Relaxed);
        let before = board::UNDONE.load(Ordering::Relaxed);
        let ahead = bare(plan(scene, &one).unwrap());
        let undone = board::UNDONE.load(Ordering::Relaxed) - before;
        board::AHEAD_FIRST.store(false, Ordering::Relaxed);
        assert!(undone > 0, "{}: no round undone", scene.name);
        assert_eq!(plain, ahead, "{}", scene.name);
    }
}

/// The least exact clearance over `n` evenly spaced points of `ab`, ends included.
fn sampled(model: &CircleModel, a: Point, b: Point, n: usize) -> Real {
    (0..=n)
        .map(|k| model.exact_clearance(&(a + (b - a) * (k as Real / n as Real))))
        .fold(Real::INFINITY, Real::min)
}

/// String pulling checks only the farthest chord that keeps its margin: here that chord
/// passes under a small circle that the path goes over, so its loop is not trivial, and the
/// pass searches again with every chord held to the class. The result keeps the class and
/// goes over the circle about as tautly as its margin allows, clear of it.
#[test]
fn a_chord_that_jumps_a_small_obstacle_is_refused_and_the_class_kept() {
    let model = CircleModel::new(vec![Circle::new(5.0, 0.0, 0.05)]);
    let rays = Rays::new(vec![Point::new(5.0, 0.0)]);
    let tent: Vec<Point> = (0..=40)
        .map(|k| {
            let x = k as Real * 0.25;
            Point::new(x, 1.0 - 0.3 * (x - 5.0).abs())
        })
        .collect();
    let sig = rays.signature(&tent);
    // The straight chord between the tent's ends keeps the pull's margin (a quarter cell
    // of 0.25 at most) but passes below the circle: the other class.
    let (a, b) = (tent[0], tent[40]);
    assert!(clear_at_least(&model, a, b, 0.25, 0.25));
    assert_ne!(rays.signature(&[a, b]), sig);
    let pulled = pull_taut(&tent, &model, &rays, 0.25, &sig);
    assert_eq!(rays.signature(&pulled), sig);
    assert_eq!((pulled[0], pulled[pulled.len() - 1]), (a, b));
    let length = |p: &[Point]| -> Real { p.windows(2).map(|w| (w[1] - w[0]).norm()).sum() };
    // Over the circle at the pull's margin (0.25 from its edge): about 10.127.
    let over = 2.0 * (5.0 as Real).hypot(0.5 + 0.05 + 0.25);
    assert!(
        length(&pulled) <= over + 0.01,
        "{} against {over}",
        length(&pulled)
    );
    assert!(model.polyline_clearance(&pulled) > 0.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The march never certifies a segment that a dense sampling finds less clear than
    /// the target, and does certify one whose every point keeps the target with room.
    #[test]
    fn clear_at_least_is_sound(
        circles in prop::collection::vec((0.0..40.0f64, 0.0..40.0f64, 0.3..4.0f64), 1..12),
        ax in 0.0..40.0f64, ay in 0.0..40.0f64, bx in 0.0..40.0f64, by in 0.0..40.0f64,
        target in 0.0..2.0f64,
    ) {
        let model = CircleModel::new(circles.iter().map(|&(x, y, r)| Circle::new(x, y, r)).collect());
        let (a, b) = (Point::new(ax, ay), Point::new(bx, by));
        let dense = sampled(&model, a, b, 4000);
        if clear_at_least(&model, a, b, target, 0.25) {
            prop_assert!(dense >= target - 1e-9, "certified at {target} but {dense}");
        }
        // The circle model's segment distance is exact: a segment clear by a margin
        // is certified.
        if model.segment_clearance(&a, &b) >= target + 1e-6 {
            prop_assert!(clear_at_least(&model, a, b, target, 0.25));
        }
    }

    /// Pulled class paths of random scenes keep their ends and their class, are no
    /// longer than the graph's path, and every chord is clear of the circles.
    #[test]
    fn pulled_seeds_keep_their_class_and_are_clear_and_shorter(seed in 0u64..1_000) {
        let scene = homospline_testkit::random_scene("pull", seed, 60.0, 10, 3);
        let (_, _, graph) = homospline_voronoi::build(&scene, 4.0).unwrap();
        let rays = Rays::for_scene(&scene);
        let model = CircleModel::new(scene.circles());
        let search = SearchConfig { k: 4, ..SearchConfig::default() };
        let length = |p: &[Point]| -> Real { p.windows(2).map(|w| (w[1] - w[0]).norm()).sum() };
        for c in k_best_classes(&graph, &rays, &search).unwrap().classes {
            let mut poly = c.polyline.clone();
            poly[0] = scene.start;
            let last = poly.len() - 1;
            poly[last] = scene.goal;
            // Only paths that are clear to begin with are pulled taut.
            if poly.windows(2).any(|w| sampled(&model, w[0], w[1], 50) <= 0.0) {
                continue;
            }
            let pulled = pull_taut(&poly, &model, &rays, 0.25, &c.signature);
            prop_assert_eq!(pulled[0], scene.start);
            prop_assert_eq!(pulled[pulled.len() - 1], scene.goal);
            prop_assert_eq!(rays.signature(&pulled), c.signature.clone());
            prop_assert!(length(&pulled) <= length(&poly) + 1e-9);
            for w in pulled.windows(2) {
                let d = sampled(&model, w[0], w[1], 400);
                prop_assert!(d > 0.0, "a chord comes {d} from the circles");
            }
        }
    }

    /// The reported path's least clearance comes from the same checks that refine it:
    /// it is the model's polyline clearance of the path, bit for bit.
    #[test]
    fn refined_paths_report_their_polyline_clearance(
        circles in prop::collection::vec((0.0..40.0f64, 0.0..40.0f64, 0.3..4.0f64), 1..12),
        via in prop::collection::vec((0.0..40.0f64, 0.0..40.0f64), 1..5),
        spacing in 0.2..2.0f64,
    ) {
        let model = CircleModel::new(circles.iter().map(|&(x, y, r)| Circle::new(x, y, r)).collect());
        let mut pts = vec![Point::new(-1.0, -1.0)];
        pts.extend(via.iter().map(|&(x, y)| Point::new(x, y)));
        pts.push(Point::new(41.0, 41.0));
        let Ok(sp) = Spline::new(&pts, homospline_spline::Parametrization::Uniform, EndCondition::Natural) else {
            return Ok(());
        };
        let (path, least) = refine_samples(&sp, &model, &sp.sample_by_arc_length(spacing));
        prop_assert_eq!(least.to_bits(), model.polyline_clearance(&path).to_bits());
    }
}

#[test]
fn a_path_along_a_side_of_the_bounds_is_measured_there_only() {
    use super::class::along_bounds;
    use homospline_geom::Bounds;
    let b = Bounds {
        min: Point::new(0.0, 0.0),
        max: Point::new(60.0, 60.0),
    };
    // Up to the top (not counted), along it, then down the right wall within a cell of it:
    // 9.9 + 9.9 + 47.
    let hug = [
        Point::new(10.0, 40.0),
        Point::new(50.0, 59.9),
        Point::new(59.9, 59.9),
        Point::new(59.95, 50.0),
        Point::new(60.0, 3.0),
    ];
    let along = along_bounds(&hug, &b, 0.25);
    assert!((along - (9.9 + 9.9 + 47.0)).abs() < 0.01, "{along}");
    // Across the room: only the last step, within a cell of the right side and the bottom
    // at both ends, counts.
    let across = [
        Point::new(0.0, 30.0),
        Point::new(30.0, 30.0),
        Point::new(59.9, 0.1),
        Point::new(60.0, 0.0),
    ];
    assert!((along_bounds(&across, &b, 0.25) - 0.02f64.sqrt()).abs() < 1e-9);
    assert_eq!(along_bounds(&across[..3], &b, 0.25), 0.0);
}
