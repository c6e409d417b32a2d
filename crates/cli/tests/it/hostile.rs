//! Hostile input and output: a saved graph that lies, an input that is not a regular file,
//! outputs that would overwrite an input or each other, stderr that cannot be written, a
//! world that lists a cleared obstacle twice. Each is refused with exit 2 (or fails with
//! exit 3) and a message; none panics or hangs.

use crate::common::*;
use homospline_voronoi::VoronoiGraph;
use std::process::Stdio;

/// A saved map graph of room-32-32-4, changed by `edit`, written to `name`.
fn lying_graph(name: &str, edit: impl Fn(&mut VoronoiGraph)) -> std::path::PathBuf {
    let good = tmp(&format!("{name}.good.msgpack"));
    assert_ok(
        &homospline()
            .args(["graph", "fixtures/maps/movingai/room-32-32-4.map", "--out"])
            .arg(&good)
            .output()
            .unwrap(),
    );
    let mut g = VoronoiGraph::from_msgpack(&std::fs::read(&good).unwrap()).unwrap();
    edit(&mut g);
    let p = tmp(&format!("{name}.msgpack"));
    std::fs::write(&p, g.to_msgpack()).unwrap();
    p
}

#[test]
fn saved_graphs_that_lie_are_refused_before_planning() {
    type Edit = fn(&mut VoronoiGraph);
    let cases: [(&str, Edit, &str); 6] = [
        ("index", |g| g.edges[0].to = 9_999, "joins nodes"),
        ("negative", |g| g.edges[1].length = -3.0, "length -3"),
        (
            "nan",
            |g| g.edges[2].min_clearance = f64::NAN,
            "min_clearance NaN",
        ),
        ("no-edges", |g| g.edges.clear(), "no edge"),
        ("ids", |g| g.nodes[1].id = 7, "numbered in order"),
        // Far off the map: its index's sampling had looped for ever.
        (
            "far",
            |g| {
                let mut p = g.edges[0].polyline.to_vec();
                p[0] = [1e300, -1e300];
                g.edges[0].polyline = p.into();
            },
            "not in a free cell",
        ),
    ];
    for (name, edit, needle) in cases {
        let g = lying_graph(name, edit);
        assert_refused(
            &[
                "plan",
                "fixtures/maps/movingai/room-32-32-4.map",
                "--start",
                "1.5,1.5",
                "--goal",
                "30.5,30.5",
                "--graph",
                g.to_str().unwrap(),
            ],
            needle,
        );
    }
}

#[test]
fn an_input_that_is_not_a_regular_file_is_refused_without_blocking() {
    let fifo = tmp("scene.fifo");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    assert_refused(&["check", fifo.to_str().unwrap()], "not a regular file");
    assert_refused(&["plan", fifo.to_str().unwrap()], "not a regular file");
    let dir = tmp("a-directory");
    std::fs::create_dir_all(&dir).unwrap();
    assert_refused(&["check", dir.to_str().unwrap()], "not a regular file");
}

#[test]
fn outputs_never_overwrite_an_input_or_each_other_and_are_checked_first() {
    let scene = tmp("scene-copy.yaml");
    std::fs::copy(root().join("fixtures/scenes/convex.yaml"), &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    let s = scene.to_str().unwrap();
    assert_refused(&["plan", s, "--json", s], "is the input");
    assert_eq!(
        std::fs::read(&scene).unwrap(),
        before,
        "the scene was overwritten"
    );
    let x = tmp("same.out");
    let x = x.to_str().unwrap();
    assert_refused(
        &["plan", s, "--json", x, "--svg", x],
        "is also the --json output",
    );
    // Two spellings of one file that does not exist yet.
    assert_refused(
        &[
            "plan",
            s,
            "--json",
            "same-out.json",
            "--svg",
            "./same-out.json",
        ],
        "is also the --json output",
    );
    // A missing directory is found before the work too, and fails like a write (exit 3).
    let out = homospline()
        .args(["plan", s, "--json", "no/such/dir/plan.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    assert!(out.stdout.is_empty(), "checked before the work");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("the directory no/such/dir does not exist"),
        "{err}"
    );
}

#[test]
fn a_written_output_replaces_the_old_one_whole_and_leaves_no_temporary_file() {
    let dir = tmp("outputs");
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("plan.json");
    std::fs::write(&json, "old").unwrap();
    assert_ok(
        &homospline()
            .args(["plan", "fixtures/scenes/convex.yaml", "--json"])
            .arg(&json)
            .output()
            .unwrap(),
    );
    assert!(read_json(&json)["classes"].is_array());
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["plan.json"]);
}

#[test]
fn a_full_stderr_does_not_panic() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = homospline()
        .args(["check", "fixtures/invalid/nan-coordinate.yaml"])
        .stderr(Stdio::from(full))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_cleared_obstacle_listed_twice_is_refused() {
    let world = tmp("twice.yaml");
    std::fs::write(
        &world,
        format!(
            "version: 1\nscene: {}\ncleared_obstacles: [a, a]\n",
            root().join("fixtures/scenes/convex.yaml").display()
        ),
    )
    .unwrap();
    let err = refused(&["simulate", world.to_str().unwrap()]);
    assert!(
        err.contains("cleared_obstacles[1]") && err.contains("'a' is listed twice"),
        "{err}"
    );
}

/// A file an input names (a ROS map's image, a world's map) is an input too: an output
/// there is refused before the work, and the file is left as it was.
#[test]
fn an_output_onto_a_file_an_input_names_is_refused() {
    let dir = tmp("named-inputs");
    std::fs::create_dir_all(&dir).unwrap();
    let ros = root().join("fixtures/maps/ros/turtlebot3_world");
    for f in ["map.yaml", "map.pgm"] {
        std::fs::copy(ros.join(f), dir.join(f)).unwrap();
    }
    let image = dir.join("map.pgm");
    let before = std::fs::read(&image).unwrap();
    let yaml = dir.join("map.yaml");
    let (y, i) = (yaml.to_str().unwrap(), image.to_str().unwrap());
    let plan = ["plan", y, "--start", "0,0", "--goal", "1,1", "--svg", i];
    let err = assert_refused_with(&plan, "is the input");
    assert!(err.contains("map.pgm"), "{err}");
    assert_refused(&["graph", y, "--json", i], "is the input");
    assert_eq!(
        std::fs::read(&image).unwrap(),
        before,
        "the image was overwritten"
    );
    // A map world names its prior and its true map.
    let world = root().join("fixtures/worlds/maps/room-blocked.yaml");
    let truth = root().join("fixtures/worlds/maps/room-32-32-4-truth.map");
    let before = std::fs::read(&truth).unwrap();
    assert_refused(
        &[
            "simulate",
            world.to_str().unwrap(),
            "--json",
            truth.to_str().unwrap(),
        ],
        "is the input",
    );
    assert_eq!(std::fs::read(&truth).unwrap(), before);
}

/// [`refused`] holding `needle`; its stderr.
fn assert_refused_with(args: &[&str], needle: &str) -> String {
    let err = refused(args);
    assert!(err.contains(needle), "{args:?}: {err}");
    err
}

/// An output path that is a symbolic link: the file it names is replaced, the link stays.
#[cfg(unix)]
#[test]
fn an_output_through_a_link_replaces_the_file_it_names() {
    let dir = tmp("links");
    std::fs::create_dir_all(&dir).unwrap();
    let target = dir.join("target.json");
    let link = dir.join("link.json");
    std::fs::write(&target, "old").unwrap();
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink("target.json", &link).unwrap();
    let out = homospline()
        .args(["plan", "--json", link.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    assert!(
        link.symlink_metadata().unwrap().file_type().is_symlink(),
        "the link was replaced by a file"
    );
    let json = read_json(&target);
    assert!(json["classes"].is_array(), "the linked file holds the plan");
    // A chain of links to a file not there yet: the file is made, both links stay.
    let (first, second, file) = (dir.join("a.json"), dir.join("b.json"), dir.join("c.json"));
    for p in [&first, &second, &file] {
        let _ = std::fs::remove_file(p);
    }
    std::os::unix::fs::symlink("b.json", &first).unwrap();
    std::os::unix::fs::symlink("c.json", &second).unwrap();
    let out = homospline()
        .args(["plan", "--json", first.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    assert!(second.symlink_metadata().unwrap().file_type().is_symlink());
    assert!(read_json(&file)["classes"].is_array());
    // A link into a directory that does not exist fails before the work (exit 3).
    let into = dir.join("into-nowhere.json");
    let _ = std::fs::remove_file(&into);
    std::os::unix::fs::symlink("no/such/dir/plan.json", &into).unwrap();
    let out = homospline()
        .args(["plan", "--json", into.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    assert!(out.stdout.is_empty(), "checked before the work");
}

/// 20,000 hidden obstacles far from every robot: sensing scans the pending ones by index
/// (a name lookup in a list made 2,000 take 11 s and 20,000 run past 600 s). A bound on
/// the whole run, generous for a debug build on a loaded machine, catches a return of the
/// quadratic scan; it measures nothing.
#[test]
fn a_world_of_20000_hidden_obstacles_is_simulated_in_seconds() {
    let mut obstacles = Vec::new();
    for i in 0..200 {
        for j in 0..100 {
            let (x, y) = (88.03 + 0.06 * f64::from(i), -7.95 + 0.1 * f64::from(j));
            obstacles.push(serde_json::json!({
                "name": format!("h{}", i * 100 + j),
                "circles": [[x, y, 0.02]],
            }));
        }
    }
    let world = serde_json::json!({
        "version": 1,
        "name": "hidden-20000",
        "scene": root().join("fixtures/scenes/narrow-pass.yaml"),
        "hidden_obstacles": obstacles,
        "team": {"ugv": {"speed": 1.0, "sensor_range": 6.0}, "uavs": []},
    });
    let path = tmp("hidden-20000.json");
    std::fs::write(&path, world.to_string()).unwrap();
    let mut child = homospline()
        .args(["simulate", path.to_str().unwrap(), "--policy", "none"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let status = wait_bounded(&mut child, 120, "simulate with 20,000 hidden obstacles");
    assert_eq!(status.code(), Some(0), "the goal is reached");
}

/// A start a hair (1e-7) from an occupied cell: its certified clearance is positive, so
/// the plan is collision-free (it once had every class "not collision-free", exit 1).
#[test]
fn a_start_a_hair_from_a_wall_plans() {
    let map = root().join("fixtures/maps/movingai/random-32-32-10.map");
    let text = std::fs::read_to_string(&map).unwrap();
    let m = homospline_maps::movingai::read_map(&text, "random-32-32-10.map").unwrap();
    // A free cell (i, j) whose left neighbour is occupied, far enough from the goal.
    let free = |i: usize, j: usize| !m.occupied[j * m.width + i];
    let (i, j) = (1..m.width)
        .flat_map(|i| (1..m.height).map(move |j| (i, j)))
        .find(|&(i, j)| free(i, j) && !free(i - 1, j) && free(i + 1, j) && i < 16)
        .expect("a free cell beside a wall");
    // Cell (i, j) covers [i, i + 1] x [j, j + 1] in map coordinates (y down).
    let start = format!("{},{}", i as f64 + 1e-7, j as f64 + 0.5);
    let out = homospline()
        .args([
            "plan",
            map.to_str().unwrap(),
            "--start",
            &start,
            "--goal",
            "30.5,2.5",
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("chosen: rank"), "{text}");
}

/// A scene resolution whose grid passes the cell limit is refused before anything of its
/// size is allocated, with the finest resolution that fits (it once said only "lower the
/// resolution").
#[test]
fn a_scene_grid_too_fine_is_refused_with_the_resolution_that_fits() {
    let err = assert_refused_with(
        &[
            "plan",
            "fixtures/scenes/convex.yaml",
            "--resolution",
            "1000",
        ],
        "a resolution of at most 96.5 cells per unit fits",
    );
    assert!(err.contains("3600000000 cells"), "{err}");
    // What it advises fits.
    let out = homospline()
        .args([
            "graph",
            "fixtures/scenes/convex.yaml",
            "--resolution",
            "96.5",
        ])
        .output()
        .unwrap();
    assert_ok(&out);
}

/// Extreme numbers are named short in messages: `1e308`, not 309 digits.
#[test]
fn extreme_numbers_are_named_short() {
    let map = "fixtures/maps/movingai/random-32-32-10.map";
    for (args, needle) in [
        (
            ["--start", "1e308,1", "--goal", "30.5,2.5"],
            "start [1e308, 1] is outside the map [0, 32] x [0, 32]",
        ),
        (
            ["--start", "1.5,27.5", "--robot-radius", "1e300"],
            "less than the robot radius 1e300",
        ),
    ] {
        let mut all = vec!["plan", map];
        all.extend(args);
        if !all.contains(&"--goal") {
            all.extend(["--goal", "30.5,2.5"]);
        }
        let err = assert_refused_with(&all, needle);
        assert!(err.len() < 300, "{err}");
    }
    for (args, needle) in [
        (
            vec!["plan", "--diverse", "1e300"],
            "--diverse 1e300: must be",
        ),
        (
            vec!["plan", "--weight", "omega=-1e300"],
            "--weight omega=-1e300: parameter omega must be finite and > 0, got -1e300",
        ),
        (
            vec![
                "simulate",
                "fixtures/worlds/narrow-pass-blocked.yaml",
                "--dt",
                "1e-300",
            ],
            "--dt 1e-300: must be between",
        ),
        // The mission's settings are checked once, by the library, and spelled as flags.
        (
            vec![
                "simulate",
                "fixtures/worlds/narrow-pass-blocked.yaml",
                "--switch-margin",
                "1",
            ],
            "--switch-margin 1: must be in [0, 1)",
        ),
        (
            vec![
                "simulate",
                "fixtures/worlds/narrow-pass-blocked.yaml",
                "--scouts",
                "65",
            ],
            "--scouts 65: must be at most 64",
        ),
        (
            vec![
                "simulate",
                "fixtures/worlds/narrow-pass-blocked.yaml",
                "--classes",
                "0",
            ],
            "--classes 0: must be between 1 and 64",
        ),
    ] {
        let err = assert_refused_with(&args, needle);
        assert!(err.len() < 300, "{err}");
    }
}

/// A robot just under half a one-cell corridor's width: the curve runs at a nearly constant
/// clearance just above the margin, which the certification once subdivided almost without
/// end (warehouse-10-20-10-2-1 at radius 0.49 ran past 100 s). Killed after 120 s, the
/// command fails the test instead of hanging it.
#[test]
fn a_radius_just_under_half_a_corridor_plans_without_hanging() {
    let scen = "fixtures/maps/movingai/warehouse-10-20-10-2-1-random-1.scen";
    let mut child = homospline()
        .args([
            "bench-scen",
            scen,
            "--sample",
            "6",
            "--robot-radius",
            "0.49",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status = wait_bounded(&mut child, 120, "bench-scen at radius 0.49");
    let mut out = String::new();
    std::io::Read::read_to_string(&mut child.stdout.take().unwrap(), &mut out).unwrap();
    assert!(status.success(), "{out}");
    assert!(out.contains("success      6/6"), "{out}");
}

/// Light clutter: 10,000 discs of radius 0.05 in a 100 x 100 scene (0.8 % of its area) gave
/// no plan at every setting, and nothing said why. Where the discs are smaller than the
/// graph's cells (the default resolution) its paths pass within a hair of them and no curve
/// comes out clear: the answer is exit 1, naming what blocks and what to change.
#[test]
fn light_clutter_without_a_plan_says_what_blocks_and_what_to_change() {
    let scene = clutter_scene(
        "clutter.yaml",
        10_000,
        3,
        Placement::InsideMargin,
        100.0,
        |_| 0.05,
    );
    let out = homospline().arg("plan").arg(&scene).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("obstacles (one every")
            && err.contains("a dense pass along each class's graph path")
            && err.contains("A finer --resolution gives the graph their gaps")
            && err.contains("merge nearby small obstacles"),
        "{err}"
    );
}

/// Clutter the graph sees: 2,000 discs of radius 0.2 to 0.6 in 100 x 100 (10 % of its area)
/// gave no plan: every class's graph path was clear, but no spline through up to 96
/// via-points spread along a path of 1,139 grid points kept to it. The dense pass now pulls
/// the path taut first (about 20 corners) and plans, collision-free.
#[test]
fn clutter_the_graph_sees_is_planned_collision_free() {
    let scene = clutter_scene(
        "clutter-2000.yaml",
        2_000,
        5,
        Placement::InsideMargin,
        100.0,
        |u| 0.2 + 0.4 * u,
    );
    let json = tmp("clutter-2000.json");
    let out = homospline()
        .arg("plan")
        .arg(&scene)
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let best = &v["classes"][v["best"].as_u64().unwrap() as usize - 1];
    assert_eq!(best["collision_free"], true, "{best}");
    assert!(
        best["certified_clearance"].as_f64().unwrap() > 0.0,
        "{best}"
    );
}

/// `--optimum` on 10,000 circles in 141 x 141 with a free margin (`--classes 2`,
/// `--resolution 4`): the classes run along the margin, so the ellipse that bounds the
/// routes as short as a class's curve holds nearly every circle, and testing the tangents of
/// every pair of them took 48 s beyond the plan's 0.8 s (release, 2026-12-06). Only the
/// pairs that a free tangent ray of one can reach are tested now: 2.0 s. Bounded at 30 s,
/// with the any-class optimum reported.
#[test]
fn the_optimum_of_10000_circles_along_a_margin_ends_within_30_s() {
    let scene = clutter_scene(
        "optimum-10000.yaml",
        10_000,
        11,
        Placement::InsideMargin,
        141.42,
        |u| 0.2 + 0.4 * u,
    );
    let json = tmp("optimum-10000.json");
    let mut child = homospline()
        .arg("plan")
        .arg(&scene)
        .args(["--classes", "2", "--resolution", "4", "--optimum", "--json"])
        .arg(&json)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status = wait_bounded(&mut child, 30, "plan --optimum on 10,000 circles");
    assert_eq!(status.code(), Some(0));
    let v = read_json(&json);
    let best = &v["classes"][v["best"].as_u64().unwrap() as usize - 1];
    let any = best["optimum_length_any_class"].as_f64().unwrap();
    let straight = 139.42 * std::f64::consts::SQRT_2;
    assert!(
        any >= straight && any <= best["length"].as_f64().unwrap(),
        "{best}"
    );
}

/// Where [`clutter_scene`] puts the discs' centres.
#[derive(Clone, Copy, PartialEq)]
enum Placement {
    /// In `[2, side - 2]^2`: a free margin all round, which the classes may run along.
    InsideMargin,
    /// Anywhere in the square but 3 units off the start and the goal, as
    /// `scripts/random_discs.py` places them.
    OffTheEnds,
}

/// A scene of `n` discs in a square of side `side` from seed `seed`, each of radius
/// `radius(u)` for a uniform `u`, placed as `placement` says, from the start (1, 1) to the
/// goal (side - 1, side - 1).
fn clutter_scene(
    name: &str,
    n: usize,
    seed: u64,
    placement: Placement,
    side: f64,
    radius: impl Fn(f64) -> f64,
) -> std::path::PathBuf {
    let mut rng = homospline_testkit::SplitMix(seed);
    let goal = side - 1.0;
    let mut text = format!(
        "name: clutter\nbounds: {{min: [0, 0], max: [{side}, {side}]}}\nstart: [1, 1]\ngoal: [{goal}, {goal}]\nobstacles:\n",
    );
    let (lo, span) = match placement {
        Placement::InsideMargin => (2.0, side - 4.0),
        Placement::OffTheEnds => (0.0, side),
    };
    let mut k = 0;
    while k < n {
        let (x, y) = (lo + span * rng.next_unit(), lo + span * rng.next_unit());
        let r = radius(rng.next_unit());
        let near_an_end = [(1.0, 1.0), (goal, goal)]
            .iter()
            .any(|&(px, py): &(f64, f64)| (x - px).hypot(y - py) < 3.0);
        if placement == Placement::OffTheEnds && near_an_end {
            continue;
        }
        text.push_str(&format!("  - {{name: p{k}, circles: [[{x}, {y}, {r}]]}}\n"));
        k += 1;
    }
    let scene = tmp(name);
    std::fs::write(&scene, text).unwrap();
    scene
}
