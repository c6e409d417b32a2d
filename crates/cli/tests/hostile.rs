//! Hostile input and output: a saved graph that lies, an input that is not a regular file,
//! outputs that would overwrite an input or each other, stderr that cannot be written, a
//! world that lists a cleared obstacle twice. Each is refused with exit 2 (or fails with
//! exit 3) and a message; none panics or hangs.

mod common;

use common::*;
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
            |g| g.edges[0].polyline[0] = [1e300, -1e300],
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
