//! Missions on the paper-like worlds (`fixtures/worlds/`) and on generated worlds: the goal
//! is reached whenever the true world has a path, runs are deterministic, scouts find the
//! blockage before the UGV would, re-plans keep the UGV's heading, the hysteresis keeps two
//! nearly equal classes from oscillating, and world files are validated with clear errors.

use homospline_geom::{Bounds, Circle, Obstacle, Point, Scene};
use homospline_mission::{
    EventKind, MissionConfig, MissionResult, MissionWorld, Policy, Robot, WorldFile, replan_scene,
    should_switch, simulate,
};
use homospline_testkit::{fixture_worlds, random_world};

/// The mission on `world` with `policy` and the default settings (shared by the modules).
pub(crate) fn run(world: &MissionWorld, policy: Policy) -> MissionResult {
    simulate(
        world,
        &MissionConfig {
            policy,
            ..MissionConfig::default()
        },
    )
    .unwrap()
}

#[test]
fn every_policy_reaches_the_goal_on_the_paper_worlds_and_runs_are_deterministic() {
    let worlds = fixture_worlds();
    assert_eq!(worlds.len(), 5);
    for w in &worlds {
        for &policy in Policy::all() {
            let r = run(w, policy);
            assert!(
                r.truth_plan_length.is_some(),
                "{}: the truth has a path",
                w.name
            );
            assert!(
                r.reached,
                "{} {}: not reached: {:?}",
                w.name,
                policy.name(),
                r.events.last()
            );
            // The distance driven is at least the track's chords and the straight line. (Not
            // the truth plan's length: that plan is the cheapest by the cost, and the UGV
            // may drive a shorter, costlier class.)
            let track: Vec<_> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
            let chords: f64 = track.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
            let straight = (w.truth.goal - w.truth.start).norm();
            assert!(
                r.ugv_distance >= chords - 1e-9 && chords >= straight - 1e-9,
                "{} {}: driven {}, chords {chords}, straight line {straight}",
                w.name,
                policy.name(),
                r.ugv_distance
            );
            // The UGV's track never enters a true obstacle.
            let truth = homospline_spline::CircleModel::new(w.truth.circles());
            use homospline_spline::ClearanceModel;
            assert!(
                truth.polyline_clearance(&track) > 0.0,
                "{} {}: collides",
                w.name,
                policy.name()
            );
            assert_eq!(
                r.outcome(),
                run(w, policy).outcome(),
                "{}: not deterministic",
                w.name
            );
        }
    }
}

#[test]
fn a_scout_ahead_finds_the_blockage_before_the_ugv_would() {
    let w = fixture_worlds()
        .into_iter()
        .find(|w| w.name == "narrow-pass-blocked")
        .unwrap();
    let found = |r: &MissionResult| {
        r.events
            .iter()
            .find_map(|e| match e.kind {
                EventKind::Discovered {
                    hidden: true, by, ..
                } => Some((e.t, by)),
                _ => None,
            })
            .unwrap()
    };
    let alone = run(&w, Policy::NONE);
    let ahead = run(&w, Policy::AHEAD);
    let (t_alone, by_alone) = found(&alone);
    let (t_ahead, by_ahead) = found(&ahead);
    assert_eq!(by_alone, Robot::Ugv);
    assert!(matches!(by_ahead, Robot::Uav(_)));
    assert!(t_ahead < t_alone, "{t_ahead} vs {t_alone}");
    assert!(ahead.ugv_distance < alone.ugv_distance);
    assert!(ahead.abandoned_distance < alone.abandoned_distance);
}

#[test]
fn a_re_plan_on_the_move_keeps_the_heading_unless_it_turns_around() {
    for w in fixture_worlds() {
        let r = run(&w, Policy::NONE);
        for e in r
            .events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::Replanned { forced: true, .. }))
        {
            let turned = r
                .events
                .iter()
                .any(|x| x.t == e.t && matches!(x.kind, EventKind::TurnedAround));
            // The plan adopted at the re-plan, and the one before it (at 0 s both: a blockage
            // in sensor range of the start is seen before the UGV moves).
            let ia = r.adopted.iter().rposition(|a| a.t == e.t).unwrap();
            let (before, after) = (&r.adopted[ia - 1], &r.adopted[ia]);
            // Heading before: the old path at the re-plan point; after: the new path's start.
            let k = before
                .path
                .iter()
                .position(|p| (p - e.at).norm() < 0.6)
                .unwrap_or(0)
                .min(before.path.len() - 2);
            let h0 = (before.path[k + 1] - before.path[k]).normalize();
            let h1 = (after.path[1] - after.path[0]).normalize();
            if !turned {
                assert!(
                    h0.dot(&h1) > 0.9,
                    "{}: the new curve leaves at {:.1} degrees from the heading",
                    w.name,
                    h0.dot(&h1).clamp(-1.0, 1.0).acos().to_degrees()
                );
            }
        }
    }
}

/// Two classes of nearly equal cost whose costs cross at every re-plan (noise of 3 %, as
/// when scouts keep reporting small changes): with the default hysteresis (10 % margin,
/// 10 s between switches) the UGV switches at most once; with none it flips at nearly every
/// re-plan, which is what the hysteresis is for.
#[test]
fn the_hysteresis_keeps_two_nearly_equal_classes_from_oscillating() {
    let switches = |cfg: &MissionConfig| {
        let mut current = 0usize;
        let mut last = f64::NEG_INFINITY;
        let mut n = 0;
        for step in 0..100 {
            let t = step as f64; // a re-plan every second
            let wobble = if step % 2 == 0 { 0.03 } else { -0.03 };
            let cost = [100.0 * (1.0 + wobble), 100.0 * (1.0 - wobble)];
            let other = 1 - current;
            if should_switch(cost[current], cost[other], t - last, cfg) {
                current = other;
                last = t;
                n += 1;
            }
        }
        n
    };
    let default = MissionConfig::default();
    assert!(switches(&default) <= 1);
    let none = MissionConfig {
        switch_margin: 0.0,
        min_switch_interval: 0.0,
        ..MissionConfig::default()
    };
    assert!(switches(&none) >= 50, "{}", switches(&none));
    // A clearly better class is still taken.
    assert!(should_switch(100.0, 80.0, 11.0, &default));
    assert!(!should_switch(100.0, 80.0, 5.0, &default));
}

#[test]
fn generated_worlds_are_reached_whenever_the_truth_has_a_path() {
    let mut tried = 0;
    for seed in 0..12 {
        let Some(w) = random_world(seed, 2) else {
            continue;
        };
        tried += 1;
        for &policy in Policy::all() {
            let r = run(&w, policy);
            if r.truth_plan_length.is_some() {
                assert!(
                    r.reached,
                    "{} {}: {:?}",
                    w.name,
                    policy.name(),
                    r.events.last()
                );
            }
        }
    }
    assert!(tried >= 6, "only {tried} worlds generated");
}

fn world_error(text: &str) -> String {
    let scene = homospline_testkit::fixture_scenes().remove(3); // narrow-pass
    match WorldFile::from_str(text, "w.yaml").and_then(|f| MissionWorld::from_file(f, scene)) {
        Ok(_) => panic!("accepted: {text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn world_files_are_checked_with_file_line_field_and_problem() {
    assert_eq!(
        world_error("scene: s.yaml\nhidden_obstacles:\n  - circles: [[50, 30, -1]]\n"),
        // A hidden obstacle is checked as a scene's obstacle is, in the same words.
        "w.yaml:3: hidden_obstacles[0].circles[0]: radius must be > 0, got -1 (obstacle 'hidden-0')"
    );
    assert_eq!(
        world_error("scene: s.yaml\nhidden_obstacles:\n  - circles: [[50, .nan, 1]]\n"),
        "w.yaml:3: hidden_obstacles[0].circles[0]: y is NaN"
    );
    assert_eq!(
        world_error("scene: s.yaml\nhidden_obstacles:\n  - name: x\n    circles: []\n"),
        "w.yaml:3: hidden_obstacles[0].circles: obstacle 'x' has no circles"
    );
    assert_eq!(
        world_error("scene: s.yaml\ncleared_obstacles: [nothing]\n"),
        "w.yaml:2: cleared_obstacles[0]: no obstacle named 'nothing' in the scene"
    );
    assert_eq!(
        world_error("scene: s.yaml\nhidden_obstacles:\n  - circles: [[5, 47, 2]]\n"),
        "w.yaml:3: hidden_obstacles[0]: covers the start (5, 47): the mission cannot be run"
    );
    assert_eq!(
        world_error("scene: s.yaml\nteam:\n  ugv: {speed: -1, sensor_range: 5}\n"),
        "w.yaml:3: team.ugv.speed: -1 must be finite, > 0 and at most 1e9"
    );
    assert_eq!(
        world_error("version: 2\nscene: s.yaml\n"),
        "w.yaml:1: version: version 2 is not supported (this build reads version 1)"
    );
    assert!(world_error("scene: s.yaml\nhiden_obstacles: []\n").starts_with("w.yaml:2"));
    assert!(world_error("hidden_obstacles: []\n").contains("scene"));
    assert_eq!(
        world_error(""),
        "w.yaml: the file is empty (expected a world)"
    );
}

/// A short-sighted UGV (sensor range 1) finds a wide hidden obstacle across its path a unit
/// ahead: every way round starts backwards from there, so the re-plan's curves are not held
/// to the heading, and the UGV turns on the spot and goes round. (When the heading holds and
/// no curve along it clears what was found, the UGV plans again from a standstill: generated
/// world 41 did that until blockages were seen before moving and narrow passages got dense
/// seeds; no world we generate does now.)
#[test]
fn a_blockage_found_a_unit_ahead_is_left_by_turning_around() {
    let scene = |obstacles: Vec<Obstacle>| Scene {
        name: "short-sighted".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(60.0, 60.0),
        },
        start: Point::new(5.0, 30.0),
        goal: Point::new(55.0, 30.0),
        robot_radius: 0.0,
        obstacles,
        danger_points: Vec::new(),
        critical_points: Vec::new(),
        hazards: Vec::new(),
    };
    let island = Obstacle {
        name: "island".into(),
        circles: vec![Circle::new(40.0, 45.0, 5.0)],
    };
    let wall = Obstacle {
        name: "wall".into(),
        circles: vec![Circle::new(19.2, 25.8, 6.0)],
    };
    let mut team = homospline_mission::Team::default();
    team.ugv.sensor_range = 1.0;
    let w = MissionWorld::new(
        "short-sighted",
        scene(vec![island]),
        vec![wall],
        Vec::new(),
        team,
    )
    .unwrap();
    let r = run(&w, Policy::NONE);
    assert!(r.reached, "{:#?}", r.events);
    let blocked = r
        .events
        .iter()
        .position(|e| matches!(e.kind, EventKind::Blocked { .. }))
        .expect("the path is blocked");
    assert!(
        (r.events[blocked].at.x - 14.0).abs() < 0.5,
        "{:?}",
        r.events[blocked]
    );
    assert!(
        r.events[blocked..]
            .iter()
            .any(|e| matches!(e.kind, EventKind::TurnedAround)),
        "{:#?}",
        r.events
    );
}

/// Generated world 139 with re-plans on the full graph and three classes: the second
/// blockage leaves one class, through a winding passage about a unit wide that no spline
/// through ten via-points keeps out of the obstacles; L-BFGS cannot start from a colliding
/// seed, and the UGV was stuck. The via-points now follow the graph's path, as many as it
/// takes, and the goal is reached.
#[test]
fn a_winding_passage_too_narrow_for_ten_via_points_is_still_planned() {
    let w = random_world(139, 2).unwrap();
    let cfg = MissionConfig {
        policy: Policy::NONE,
        replan_classes: 3,
        replan_coarsening: 1.0,
        ..MissionConfig::default()
    };
    let r = simulate(&w, &cfg).unwrap();
    assert!(r.truth_plan_length.is_some(), "the truth has a path");
    assert!(r.reached, "{:#?}", r.events);
}

/// A wall across the scene with one gap a unit wide. The re-plans' graph has half the
/// cells across of the offline plan's; a graph too coarse to see the gap (10 cells across:
/// its one class collides; 5: no path at all) makes the re-plan fall back to the full graph,
/// which finds the gap.
#[test]
fn a_re_plan_falls_back_to_the_full_graph_when_the_coarse_one_has_no_clear_class() {
    let mut circles = Vec::new();
    let mut y = -1.0;
    while y <= 44.0 {
        circles.push(Circle::new(50.0, y, 1.0));
        y += 1.5;
    }
    let mut y = 47.0;
    while y <= 101.5 {
        circles.push(Circle::new(50.0, y, 1.0));
        y += 1.5;
    }
    let scene = Scene {
        name: "gap".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(100.0, 100.0),
        },
        start: Point::new(10.0, 50.0),
        goal: Point::new(90.0, 50.0),
        robot_radius: 0.0,
        obstacles: vec![Obstacle {
            name: "wall".into(),
            circles,
        }],
        danger_points: Vec::new(),
        critical_points: Vec::new(),
        hazards: Vec::new(),
    };
    let cfg = MissionConfig::default();
    assert_eq!(cfg.replan_resolution(&scene), Some(2.56 / 2.0));
    for coarse in [0.1, 0.05] {
        let quick = homospline_optim::PlanConfig {
            resolution: Some(coarse),
            ..cfg.plan.clone()
        };
        let alone = homospline_optim::plan(&scene, &quick);
        assert!(
            alone.is_err() || !alone.unwrap().classes.iter().any(|c| c.collision_free),
            "{coarse}: the coarse graph offers the gap"
        );
        let p = replan_scene(&scene, &cfg.plan, Some(coarse)).expect("a plan");
        let best = p.best.expect("a collision-free class");
        assert!(p.classes[best - 1].collision_free);
    }
}

/// Generated world 359: the second blockage stops the UGV where every way on is narrower than
/// one cell of the graph's grid, which the class search did not offer, and the UGV was stuck.
/// With no other way, those ways are offered (each curve's certification decides), and the
/// goal is reached.
#[test]
fn a_tight_spot_whose_every_way_is_narrower_than_a_cell_is_left() {
    let w = random_world(359, 2).unwrap();
    let r = run(&w, Policy::NONE);
    assert!(r.truth_plan_length.is_some(), "the truth has a path");
    assert!(r.reached, "{:#?}", r.events);
}

#[test]
fn a_bad_re_plan_tolerance_is_refused() {
    let w = &fixture_worlds()[0];
    for bad in [f64::NAN, -1e-5, f64::INFINITY] {
        let cfg = MissionConfig {
            replan_value_tolerance: bad,
            ..MissionConfig::default()
        };
        let e = simulate(w, &cfg).expect_err("refused").to_string();
        assert!(e.starts_with("replan_value_tolerance "), "{e}");
        let cfg = MissionConfig {
            replan_coarsening: if bad < 0.0 { 0.5 } else { bad },
            ..MissionConfig::default()
        };
        let e = simulate(w, &cfg).expect_err("refused").to_string();
        assert!(e.starts_with("replan_coarsening "), "{e}");
        let cfg = MissionConfig {
            max_time: Some(if bad < 0.0 { -1.0 } else { bad }),
            ..MissionConfig::default()
        };
        let e = simulate(w, &cfg).expect_err("refused").to_string();
        assert!(e.starts_with("max_time "), "{e}");
    }
}

#[test]
fn a_fast_ugv_with_a_coarse_step_never_drives_through_what_it_has_not_seen() {
    // At 5 units/s and --dt 10 the UGV would move 50 units between two looks, far past its
    // sensor range (6): it drove through narrow-pass-blocked's hidden blockage and reported
    // the goal reached. The step is now refined to half the range over the speed.
    use homospline_spline::ClearanceModel;
    for mut w in fixture_worlds() {
        w.team.ugv.speed = 5.0;
        let cfg = MissionConfig {
            policy: Policy::NONE,
            dt: 10.0,
            ..MissionConfig::default()
        };
        let r = simulate(&w, &cfg).unwrap();
        let limit = homospline_mission::time_step(10.0, &w.team.ugv, []);
        assert!(
            (r.dt - limit).abs() < 1e-12 && r.dt <= 0.5 * w.team.ugv.sensor_range / 5.0,
            "{}: step {} (limit {limit})",
            w.name,
            r.dt
        );
        let track: Vec<_> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
        let truth = homospline_spline::CircleModel::new(w.truth.circles());
        assert!(
            truth.polyline_clearance(&track) > 0.0,
            "{}: the UGV's track enters a true obstacle",
            w.name
        );
        // What a fine step sees, the coarse one sees too.
        let seen = |r: &MissionResult| {
            r.events
                .iter()
                .any(|e| matches!(e.kind, EventKind::Discovered { hidden: true, .. }))
        };
        let fine = simulate(&w, &MissionConfig { dt: 0.1, ..cfg }).unwrap();
        assert!(
            !seen(&fine) || seen(&r),
            "{}: the hidden obstacle seen at a fine step was never seen",
            w.name
        );
        assert!(r.reached, "{}: not reached", w.name);
    }
}

#[test]
fn a_mission_whose_goal_is_its_start_is_reached_at_once() {
    // It drove a step of nothing and read time over the optimum as 166463 (the optimum's
    // length a rounding error).
    let mut w = fixture_worlds().into_iter().next().unwrap();
    w.truth.goal = w.truth.start;
    w.prior.goal = w.prior.start;
    let r = run(&w, Policy::AHEAD);
    assert!(r.reached);
    assert_eq!(r.time, 0.0);
    assert_eq!(r.ugv_distance, 0.0);
    assert_eq!(r.truth_plan_length, Some(0.0));
    assert_eq!(r.distance_ratio(), None);
    assert_eq!(r.time_ratio(w.team.ugv.speed), None);
}

#[test]
fn every_timed_re_plan_is_a_counted_one_even_when_the_mission_ends_stuck() {
    // A hidden wall across the whole scene: the UGV finds it, re-plans from its heading,
    // then from a standstill, and is stuck. Both tries were timed apart (2 times, 1 re-plan).
    let mut w = fixture_worlds()
        .into_iter()
        .find(|w| w.name == "narrow-pass-blocked")
        .unwrap();
    let wall = Obstacle {
        name: "wall".into(),
        circles: (0..12)
            .map(|k| Circle::new(50.0, -8.0 + 7.0 * k as f64, 5.0))
            .collect(),
    };
    w.truth.obstacles.push(wall);
    w.hidden.push("wall".into());
    let mut runs = 0;
    for world in [&w].into_iter().chain(fixture_worlds().iter()) {
        for &policy in Policy::all() {
            let r = run(world, policy);
            assert_eq!(
                r.replan_ms.len(),
                r.replans,
                "{} {}: {:?}",
                world.name,
                policy.name(),
                r.events.last()
            );
            runs += 1;
        }
    }
    let stuck = run(&w, Policy::NONE);
    assert!(!stuck.reached, "the wall has no way through");
    assert!(runs > 3);
}

#[test]
fn a_step_refined_past_the_limit_says_which_robot_setting_to_change() {
    // A scout at 1000 units/s seeing 0.01 sets a step of 5e-6 s: "raise --dt or the UGV's
    // speed" helped neither.
    let mut w = fixture_worlds().into_iter().next().unwrap();
    for u in &mut w.team.uavs {
        u.speed = 1000.0;
        u.sensor_range = 0.01;
    }
    let cfg = MissionConfig {
        policy: Policy::AHEAD,
        ..MissionConfig::default()
    };
    let e = match simulate(&w, &cfg) {
        Err(e) => e.to_string(),
        Ok(r) => panic!("ran at a step of {} s", r.dt),
    };
    assert!(
        e.contains("the step is refined from --dt 0.25")
            && e.contains("sensor ranges that suit their speeds"),
        "{e}"
    );
}
