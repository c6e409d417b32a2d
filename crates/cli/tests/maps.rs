//! `homospline plan` on maps and `homospline bench-scen`, end to end.

mod common;

use common::*;

#[test]
fn plans_on_a_movingai_map_with_json_and_a_picture() {
    let (json, svg) = (tmp("m.json"), tmp("m.svg"));
    let out = homospline()
        .args([
            "plan",
            "fixtures/maps/movingai/random-32-32-10.map",
            "--start",
            "1.5,27.5",
            "--goal",
            "30.5,2.5",
        ])
        .args([
            "--json",
            json.to_str().unwrap(),
            "--svg",
            svg.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&json);
    assert_eq!(v["scene"], "random-32-32-10");
    let best = v["best"].as_u64().unwrap() as usize;
    let c = &v["classes"][best - 1];
    assert_eq!(c["collision_free"], true);
    assert_eq!(c["path"][0], serde_json::json!([1.5, 27.5]));
    assert_svg_layers(
        &svg,
        &["obstacles", "voronoi", "best", "legend", "scale-bar"],
    );
}

#[test]
fn plans_on_a_ros_map() {
    let out = homospline()
        .args([
            "plan",
            "fixtures/maps/ros/turtlebot3_world/map.yaml",
            "--start=-2,-0.5",
            "--goal=1.5,0.5",
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    assert!(
        String::from_utf8(out.stdout)
            .unwrap()
            .contains("chosen: rank 1")
    );
}

#[test]
fn bench_scen_reports_success_time_and_length_ratio() {
    let csv = tmp("b.csv");
    let out = homospline()
        .args([
            "bench-scen",
            "fixtures/maps/movingai/random-32-32-10-random-1.scen",
            "--limit",
            "3",
            "--classes",
            "2",
        ])
        .args(["--csv", csv.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    for needle in [
        "3 scenarios on random-32-32-10",
        "success",
        "time / plan",
        "length / octile optimum",
    ] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    let rows = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(rows.lines().count(), 4);
    assert!(rows.starts_with("index,bucket,start_x"));
}

#[test]
fn bad_map_input_exits_2_with_the_file_named() {
    for (args, needle) in [
        (
            vec![
                "plan",
                "fixtures/maps/invalid/short-row.map",
                "--start",
                "0.5,0.5",
                "--goal",
                "1.5,0.5",
            ],
            "short-row.map:6: row 1 has 3 cells",
        ),
        (
            vec!["plan", "fixtures/maps/movingai/room-32-32-4.map"],
            "a map needs --start X,Y and --goal X,Y",
        ),
        (
            vec![
                "plan",
                "fixtures/maps/movingai/room-32-32-4.map",
                "--start",
                "0.5,0.5",
                "--goal",
                "9.5,0.5",
            ],
            "start [0.5, 0.5] is in an occupied cell",
        ),
        (
            vec![
                "plan",
                "fixtures/maps/movingai/room-32-32-4.map",
                "--start",
                "99,1",
                "--goal",
                "9.5,0.5",
            ],
            "start [99, 1] is outside the map",
        ),
        (
            vec![
                "plan",
                "fixtures/maps/movingai/room-32-32-4.map",
                "--start",
                "x,1",
                "--goal",
                "9.5,0.5",
            ],
            "--start x,1: expected two finite numbers",
        ),
        (
            vec![
                "plan",
                "fixtures/maps/invalid/missing-image.yaml",
                "--start",
                "0,0",
                "--goal",
                "1,1",
            ],
            "missing.pgm: cannot read",
        ),
        (
            vec![
                "plan",
                "fixtures/maps/ros/nav2/testmap.yaml",
                "--start",
                "0,0",
                "--goal",
                "1,1",
            ],
            "yaw 1 is not supported",
        ),
        (
            vec!["bench-scen", "fixtures/maps/invalid/bad-number.map.scen"],
            "bad-number.map.scen:2:",
        ),
    ] {
        let out = homospline().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}
