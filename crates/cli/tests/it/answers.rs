//! `homospline plan`'s answers a robot acts on, end to end: a time limit, a start next to an
//! obstacle, no route written to the JSON, huge bounds round a small obstacle, and why there
//! is no plan.

use crate::common::*;
use crate::plan::{chosen_class, plan_json};

/// `v` without its times (`timing_ms`, each class's `time_ms`), which differ run to run.
fn without_times(mut v: serde_json::Value) -> serde_json::Value {
    v.as_object_mut().unwrap().remove("timing_ms");
    for c in v["classes"].as_array_mut().unwrap() {
        c.as_object_mut().unwrap().remove("time_ms");
    }
    v
}

#[test]
fn a_time_limit_withholds_a_late_plan_and_never_changes_one() {
    // A millisecond for plans of 64 classes and 100 rounds, which take a tenth of a second
    // and more (so that a watchdog woken late still stops them), on a scene or a map:
    // exit 4, the limit named, nothing written.
    for (input, extra, name) in [
        ("fixtures/scenes/field.yaml", &[][..], "field"),
        (
            "fixtures/maps/movingai/room-32-32-4.map",
            &["--start", "2.5,2.5", "--goal", "30.5,30.5"][..],
            "room-32-32-4",
        ),
    ] {
        let json = tmp(&format!("late-{name}.json"));
        let out = homospline()
            .args(["plan", input, "--time-limit", "1", "--json"])
            .arg(&json)
            .args(["--classes", "64", "--rounds", "100"])
            .args(extra)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(4), "{input}: {err}");
        assert!(
            err.contains(&format!("{name}: no plan within --time-limit 1 ms")),
            "{err}"
        );
        assert!(!json.exists(), "{input}: a withheld plan writes nothing");
    }
    // A limit the plan meets: the plan without one, class for class.
    let scene = "fixtures/scenes/concave-cup.yaml";
    let free = plan_json(scene, &[], "limit-none.json");
    let limited = plan_json(scene, &["--time-limit", "600000"], "limit-long.json");
    assert_eq!(without_times(free), without_times(limited));
    for v in ["0", "-1", "nan", "inf"] {
        assert_refused(
            &["plan", scene, &format!("--time-limit={v}")],
            "must be a positive number of ms",
        );
    }
}

#[test]
fn a_start_next_to_an_obstacle_plans_on_a_finer_grid() {
    // 0.1 from obstacle o2 (centre (35, 30), radius 4): the default grid's cell holding it
    // has its centre in o2. It was refused (exit 2, "falls in an occupied cell"); a robot
    // stopped next to a rock must re-plan from where it stands.
    let v = plan_json(
        "fixtures/scenes/field.yaml",
        &["--start", "30.9,30"],
        "near-rock.json",
    );
    let c = chosen_class(&v);
    let (clear, proven) = (
        c["min_clearance"].as_f64().unwrap(),
        c["certified_clearance"].as_f64().unwrap(),
    );
    assert_eq!(c["collision_free"], true);
    // It leaves from the start's clearance, 0.1.
    assert!(
        proven > 0.0 && (clear - 0.1).abs() < 1e-3,
        "{clear} {proven}"
    );
    // Closer than any grid within the limit can tell: refused, naming the end and what it
    // is near.
    assert_refused(
        &[
            "plan",
            "fixtures/scenes/field.yaml",
            "--start",
            "30.99999999,30",
        ],
        "the start [30.99999999, 30] is 1e-8 from obstacle 'o2', closer than a grid of",
    );
}

#[test]
fn no_route_writes_a_json_without_a_plan_over_an_older_one() {
    // A pipeline that reads the file, not the exit code, must not drive an older plan.
    let json = tmp("no-route.json");
    let map = [
        "plan",
        "fixtures/maps/movingai/room-32-32-4.map",
        "--start",
        "2.5,2.5",
        "--goal",
        "30.5,30.5",
        "--json",
        json.to_str().unwrap(),
    ];
    assert_ok(
        &homospline()
            .args(map)
            .args(["--robot-radius", "0.3"])
            .output()
            .unwrap(),
    );
    assert_eq!(read_json(&json)["best"], 1);
    let out = homospline()
        .args(map)
        .args(["--robot-radius", "1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v = read_json(&json);
    assert!(
        v["best"].is_null() && v["classes"].as_array().unwrap().is_empty(),
        "{v}"
    );
    assert!(
        v["no_route"]
            .as_str()
            .unwrap()
            .starts_with("no route for a robot of radius 1: the widest route"),
        "{v}"
    );
}

#[test]
fn huge_bounds_round_a_small_rock_plan_both_classes() {
    // Bounds of 2e9 round a rock of radius 1: a grid over the bounds put the rock inside one
    // cell, one class was found, and the plan went 252 units round it (the optimum is 21.8).
    // The grid covers the scene's working area instead: both classes, each near the optimum.
    let scene = tmp("huge.yaml");
    std::fs::write(
        &scene,
        "name: huge\nbounds: {min: [-1e9, -1e9], max: [1e9, 1e9]}\nstart: [-10, 0]\ngoal: [10, 0]\n\
         obstacles:\n  - name: rock\n    circles: [[0, 0, 1]]\n",
    )
    .unwrap();
    let v = plan_json(scene.to_str().unwrap(), &[], "huge.json");
    let classes = v["classes"].as_array().unwrap();
    assert_eq!(classes.len(), 2, "{}", v["classes"]);
    for c in classes {
        assert_eq!(c["collision_free"], true);
        let length = c["length"].as_f64().unwrap();
        assert!(length < 22.5, "{length}");
    }
}

#[test]
fn the_straight_seed_in_the_cup_finds_no_plan_and_exits_1() {
    // `--classes 1` is the straight seed's one class, so it is accepted (any other count is
    // refused: see the bad-options table).
    for extra in [&[][..], &["--classes", "1"][..]] {
        let out = homospline()
            .args([
                "plan",
                "fixtures/scenes/concave-cup.yaml",
                "--seed",
                "straight",
            ])
            .args(extra)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{extra:?}");
        let stdout = String::from_utf8(out.stdout).unwrap();
        assert!(
            stdout.contains(
                "no collision-free curve in the 1 class found (the closest, class A (id -1), \
                 comes 0.976 into an obstacle): the straight seed tries one class"
            ),
            "{stdout}"
        );
        assert!(stdout.contains("seed straight  1 classes"), "{stdout}");
    }
    // A floor no class meets: the clearest class is named, with its clearance (its letter,
    // a rank, follows the costs of classes that climbed towards the floor).
    let out = homospline()
        .args([
            "plan",
            "fixtures/scenes/field.yaml",
            "--clearance-floor",
            "12",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout
            .contains("no collision-free class meets the clearance floor 12 (the clearest, class ")
            && stdout.contains("(id -1-3-4-6), is certified"),
        "{stdout}"
    );
    // A radius that leaves a door a two-thousandth of a cell: the map's classes are found
    // (a route exists), but no curve keeps clear; the line says so, not "no route".
    let out = homospline()
        .args([
            "plan",
            "fixtures/maps/movingai/room-32-32-4.map",
            "--start",
            "2.5,2.5",
            "--goal",
            "30.5,30.5",
            "--robot-radius",
            "0.4995",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout.contains("no collision-free curve in the 5 classes found")
            && stdout
                .contains("the graph joins start and goal, but no smooth curve found keeps clear"),
        "{stdout}"
    );
}

#[test]
fn a_change_that_makes_the_scene_invalid_is_named_by_its_option() {
    for (args, msg) in [
        // Each change that makes the scene invalid is named by its option.
        (
            vec!["plan", "--block", "60,60,1", "--block", "5,47,3"],
            "--block 5,47,3: narrow-pass: start: [5, 47] is inside obstacle 'blocked-1'",
        ),
        (
            vec!["plan", "--block", "40,30,1e10"],
            "--block 40,30,1e10: narrow-pass: radius = 1e10 is too large",
        ),
        (
            vec!["plan", "--start", "200,20"],
            "--start 200,20: narrow-pass: [200, 20] is outside the bounds",
        ),
        (
            vec!["plan", "--robot-radius", "45"],
            "--robot-radius 45: narrow-pass: start: [5, 47] is inside obstacle",
        ),
        // On a map too: the block over the start, whose cell the map has free, is named
        // (it read "start [1.5, 1.5] is in an occupied cell").
        (
            vec![
                "plan",
                "fixtures/maps/movingai/room-32-32-4.map",
                "--start",
                "1.5,1.5",
                "--goal",
                "30.5,30.5",
                "--block",
                "20,20,1",
                "--block",
                "0,0,3",
            ],
            "--block 0,0,3: room-32-32-4: the start [1.5, 1.5] is inside the blocked disc",
        ),
    ] {
        assert_refused(&args, msg);
    }
}

#[test]
fn a_clearance_floor_above_dm_is_climbed_to() {
    // The floor only stopped the clearance falling: narrow-pass's class -1-2, which keeps 6
    // when asked to climb, answered "no plan" at --clearance-floor 6 (a review's case).
    let v = plan_json(
        "fixtures/scenes/narrow-pass.yaml",
        &["--clearance-floor", "6"],
        "floor-6.json",
    );
    let best = chosen_class(&v);
    assert!(
        best["certified_clearance"].as_f64().unwrap() >= 6.0,
        "{}",
        best["certified_clearance"]
    );
    assert_eq!(best["collision_free"], true);
}

#[test]
fn a_start_and_goal_on_the_walls_of_an_empty_room_plan_the_straight_line() {
    // No hole: the only class's graph path runs along the walls, and every spline through
    // it bulged out at the corner; "no plan" where the straight line is 10 units clear (a
    // review's case). The class path pulled taut gives the straight line.
    let scene = tmp("walls.yaml");
    std::fs::write(
        &scene,
        "bounds: {min: [0, 0], max: [10, 10]}\nstart: [5, 10]\ngoal: [10, 5]\nobstacles:\n  - circles: [[0, 0, 1]]\n",
    )
    .unwrap();
    let v = plan_json(scene.to_str().unwrap(), &[], "walls.json");
    let best = chosen_class(&v);
    let length = best["length"].as_f64().unwrap();
    assert!((length - 50f64.sqrt()).abs() < 1e-3, "{length}");
    assert_eq!(best["collision_free"], true);
}

#[test]
fn a_curve_not_proven_clear_is_not_said_to_leave_the_bounds() {
    // A start 1e-12 from a disc: the classes' curves are clear where sampled but their
    // certificates stop at about -2e-10; the line said "leaves the bounds" (a review's case).
    let scene = tmp("touch.yaml");
    std::fs::write(
        &scene,
        "bounds: {min: [0, 0], max: [60, 60]}\nstart: [13.999999999999, 28]\ngoal: [55, 30]\nobstacles:\n  - name: a\n    circles: [[20, 28, 6], [35, 35, 4]]\n",
    )
    .unwrap();
    let out = homospline().args(["plan"]).arg(&scene).output().unwrap();
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(!stdout.contains("leaves the bounds"), "{stdout}");
    assert!(
        stdout.contains("is not proven clear of the obstacles (its certificate: -"),
        "{stdout}"
    );
}

#[test]
fn a_goal_on_a_wall_is_reached_straight_when_the_line_is_clear() {
    // The class path ran right to the wall, then down it to the goal; no spline could be
    // pulled off the wall (every candidate across it is out of bounds), and the plan was an
    // L along the walls, 85.8 long, where the straight line, 62.2 long and 17 units clear of
    // the disc, is in the class (a review's case). A seed along the bounds is now the
    // class's taut path.
    let scene = tmp("room60.yaml");
    std::fs::write(
        &scene,
        "bounds: {min: [0, 0], max: [60, 60]}\nstart: [10, 40]\ngoal: [60, 3]\nobstacles:\n  - circles: [[30, 0, 3]]\n",
    )
    .unwrap();
    let v = plan_json(scene.to_str().unwrap(), &[], "room60.json");
    let best = chosen_class(&v);
    let length = best["length"].as_f64().unwrap();
    let straight = (50f64 * 50.0 + 37.0 * 37.0).sqrt();
    assert!(length < straight * 1.001, "{length} against {straight}");
    assert_eq!(best["collision_free"], true);
    assert!(best["certified_clearance"].as_f64().unwrap() > 17.0);
}

#[test]
fn a_class_whose_straight_segment_is_better_reports_the_segment() {
    // The optimiser, started from a class path that dips far below the segment S-T, ended
    // on a curve 26.00 long and 4.58 clear; the segment, in the same class, is 21.26 long
    // and 6.48 clear (a review's case). And a start on a wall with a goal 2.69 from a disc:
    // an L along the wall, 6.70, where the segment keeps the same 2.69.
    let cases = [
        (
            "bounds: {min: [0, 0], max: [20, 60]}\nstart: [20, 42.09]\ngoal: [0, 49.3]\n\
             obstacles:\n  - circles: [[13.97, 57.04, 2.19]]\n  - circles: [[17.03, 32.28, 3.77]]\n\
             \x20 - circles: [[17.79, 56.06, 3.94]]\n  - circles: [[11.4, 14.33, 1.2]]\n",
            [20.0f64, 42.09],
            [0.0f64, 49.3],
        ),
        (
            "bounds: {min: [0, 0], max: [10, 6]}\nstart: [0.919, 0]\ngoal: [5.44, 2.36]\n\
             obstacles:\n  - circles: [[1.164, 5.575, 1.164]]\n  - circles: [[6.70, 5.741, 0.916]]\n\
             \x20 - circles: [[8.383, 4.432, 0.841]]\n",
            [0.919f64, 0.0],
            [5.44f64, 2.36],
        ),
    ];
    for (k, (text, s, t)) in cases.iter().enumerate() {
        let scene = tmp(&format!("straight{k}.yaml"));
        std::fs::write(&scene, text).unwrap();
        let v = plan_json(scene.to_str().unwrap(), &[], &format!("straight{k}.json"));
        let best = chosen_class(&v);
        let length = best["length"].as_f64().unwrap();
        let straight = ((t[0] - s[0]) * (t[0] - s[0]) + (t[1] - s[1]) * (t[1] - s[1])).sqrt();
        assert!(
            (length - straight).abs() < 1e-9 * straight,
            "{k}: {length} against {straight}"
        );
        assert_eq!(best["via_points"].as_array().unwrap().len(), 2, "{k}");
        assert_eq!(best["collision_free"], true);
    }
}

/// The plan (JSON) of a 100 x 60 room split by a wall of discs of radius 5 at x = 50, from
/// (10, 30) to (90, 30), its top disc centred at `top`: the gap under the top side is
/// `55 - top` wide. Written to `NAME.yaml`, planned to `NAME.json`.
fn plan_wall_with_gap(top: f64, name: &str) -> serde_json::Value {
    let scene = tmp(&format!("{name}.yaml"));
    std::fs::write(
        &scene,
        format!(
            "bounds: {{min: [0, 0], max: [100, 60]}}\nstart: [10, 30]\ngoal: [90, 30]\nobstacles:\n\
             \x20 - circles: [[50, 0, 5], [50, 8, 5], [50, 16, 5], [50, 24, 5], [50, 32, 5], [50, 40, 5], [50, 48, 5], [50, {top}, 5]]\n"
        ),
    )
    .unwrap();
    plan_json(scene.to_str().unwrap(), &[], &format!("{name}.json"))
}

#[test]
fn a_gap_between_a_disc_and_a_side_finer_than_the_grid_is_planned_through() {
    // A wall of discs across the room leaves 0.1 between its top disc and the top side:
    // the only way through (the bounds are not obstacles). The graph joins start and goal
    // on the finest grid within the limit, but its path runs along border cells outside
    // the bounds, and every curve came 0.6 into a disc: "no plan" (a review's case). The
    // dense pass now starts from the class's exact taut path inside the bounds.
    let v = plan_wall_with_gap(54.9, "gap-at-side");
    let best = chosen_class(&v);
    assert_eq!(best["collision_free"], true);
    let clear = best["certified_clearance"].as_f64().unwrap();
    assert!(clear > 0.0 && clear < 0.1, "{clear}");
    // Through the gap: every point of the path inside the bounds, one of them above the
    // top disc.
    let path = best["path"].as_array().unwrap();
    assert!(path.iter().any(|p| p[1].as_f64().unwrap() > 59.9));
    assert!(path.iter().all(|p| p[1].as_f64().unwrap() <= 60.0));
    let length = best["length"].as_f64().unwrap();
    assert!(length < 101.0, "{length}");
}

#[test]
fn a_gap_of_one_between_a_disc_and_a_side_is_passed_without_following_the_side() {
    // The same wall with 1 left under the top side. The class path runs along the side from
    // the gap on, and the curve through it did too, then down a second side to the goal:
    // 116.67 long (cost 1,247.8). At `dm` the class has no taut path (the gap is narrower),
    // so none was offered; at the class's own clearance target it has, and the plan from it
    // is 102.59 long (cost 636.6), and clearer.
    let v = plan_wall_with_gap(54.0, "gap-of-one");
    let best = chosen_class(&v);
    assert_eq!(best["collision_free"], true);
    let length = best["length"].as_f64().unwrap();
    assert!(length < 105.0, "{length}");
    assert!(best["certified_clearance"].as_f64().unwrap() > 0.9);
    // Near the top side (within a unit of it) only about the gap, not on to the goal's side.
    let path = best["path"].as_array().unwrap();
    let xs: Vec<f64> = path
        .iter()
        .filter(|p| p[1].as_f64().unwrap() > 59.0)
        .map(|p| p[0].as_f64().unwrap())
        .collect();
    let span =
        xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
    assert!(span < 20.0, "{span}");
}
