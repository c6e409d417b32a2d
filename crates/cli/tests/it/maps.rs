//! `homospline plan` on maps and `homospline bench-scen`, end to end.

use crate::common::*;

#[test]
fn plans_on_a_movingai_map_with_json_and_a_picture() {
    let (json, svg) = (tmp("m.json"), tmp("m.svg"));
    let out = homospline()
        .args(MAP_PLAN)
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
        "3 of 3 scenarios picked from 461 (the first of each file: the shortest paths only), on random-32-32-10",
        "success",
        "time / plan",
        "length / octile optimum",
    ] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    let rows = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(rows.lines().count(), 4);
    assert!(rows.starts_with("file,index,line,bucket,start_x"));
}

#[test]
fn bench_scen_samples_every_bucket_and_summarises_per_bucket() {
    let csv = tmp("s.csv");
    let out = homospline()
        .args([
            "bench-scen",
            "fixtures/maps/movingai/maze-32-32-2-random-1.scen",
            "--sample",
            "4",
            "--classes",
            "1",
            "--time-limit",
            "60000",
        ])
        .args(["--csv", csv.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("(sampled evenly over every bucket)"),
        "{text}"
    );
    assert!(text.contains("timeouts 0"), "{text}");
    assert!(text.contains("buckets   optimal length"), "{text}");
    let rows = std::fs::read_to_string(&csv).unwrap();
    // The first and the last (longest) scenarios of the file are among the four.
    let index: Vec<&str> = rows
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    let total = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/maps/movingai/maze-32-32-2-random-1.scen"
    ))
    .unwrap()
    .lines()
    .skip(1)
    .count();
    assert_eq!(index.len(), 4);
    assert_eq!(index[0], "0");
    assert_eq!(index[3], (total - 1).to_string());
}

#[test]
fn a_map_graph_saved_once_serves_plans() {
    let g = tmp("maze.msgpack");
    let out = homospline()
        .args(["graph", "fixtures/maps/movingai/maze-32-32-2.map", "--out"])
        .arg(&g)
        .output()
        .unwrap();
    assert_ok(&out);
    let args = [
        "--start",
        "7.5,20.5",
        "--goal",
        "22.5,25.5",
        "--classes",
        "2",
    ];
    let with = homospline()
        .args(["plan", "fixtures/maps/movingai/maze-32-32-2.map", "--graph"])
        .arg(&g)
        .args(args)
        .output()
        .unwrap();
    let without = homospline()
        .args(["plan", "fixtures/maps/movingai/maze-32-32-2.map"])
        .args(args)
        .output()
        .unwrap();
    assert_eq!(with.status.code(), without.status.code());
    // The same classes, lengths and clearances (timings differ).
    let table = |o: &std::process::Output| -> Vec<String> {
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .filter(|l| l.trim_start().starts_with(char::is_numeric))
            .map(|l| l.split_whitespace().take(5).collect::<Vec<_>>().join(" "))
            .collect()
    };
    assert_eq!(table(&with), table(&without));
    assert!(!table(&with).is_empty());
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
        // On the side or corner of an occupied cell (cells are closed squares), or on the
        // map's edge: clearance 0. Each was accepted and planned with every class colliding.
        (
            vec![
                "plan",
                "fixtures/maps/movingai/room-32-32-4.map",
                "--start",
                "1,1",
                "--goal",
                "30.5,30.5",
            ],
            "start [1, 1] lies on the side or corner of an occupied cell",
        ),
        (
            vec![
                "plan",
                "fixtures/maps/movingai/room-32-32-4.map",
                "--start",
                "1.5,1.5",
                "--goal",
                "1.5,1",
            ],
            "goal [1.5, 1] lies on the side or corner of an occupied cell",
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
        assert_refused(&args, needle);
    }
}

/// Runs `bench-scen` with `extra` arguments and returns its CSV without the times.
fn bench_rows(extra: &[&str], name: &str) -> Vec<String> {
    let csv = tmp(name);
    let out = homospline()
        .args([
            "bench-scen",
            "fixtures/maps/movingai/maze-32-32-2-random-1.scen",
            "fixtures/maps/movingai/room-32-32-4-random-1.scen",
            "--sample",
            "5",
            "--classes",
            "2",
            "--csv",
            csv.to_str().unwrap(),
        ])
        .args(extra)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .output()
        .unwrap();
    assert_ok(&out);
    std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            // Everything but time_ms (column 15).
            [&f[..14], &f[15..]].concat().join(",")
        })
        .collect()
}

#[test]
fn the_union_of_the_shards_is_the_whole_run_and_merges_into_its_summary() {
    let whole = bench_rows(&[], "whole.csv");
    assert_eq!(whole.len(), 11);
    let mut union: Vec<String> = Vec::new();
    let mut csvs = Vec::new();
    for k in 1..=3 {
        let name = format!("shard{k}.csv");
        let rows = bench_rows(&["--shard", &format!("{k}/3")], &name);
        assert!(rows.len() >= 4 && rows.len() <= 5, "{rows:?}");
        union.extend(rows.into_iter().skip(1));
        csvs.push(tmp(&name));
    }
    let mut expected: Vec<String> = whole[1..].to_vec();
    union.sort();
    expected.sort();
    assert_eq!(union, expected);
    // Merged, the shards give the whole run's summary (times aside) and its rows.
    let merged = tmp("merged.csv");
    let out = homospline()
        .arg("bench-merge")
        .args(&csvs)
        .args(["--out", merged.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("10 scenarios from 3 CSV files"), "{text}");
    assert!(text.contains("success      10/10"), "{text}");
    let strip = |p: &std::path::Path| -> Vec<String> {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                [&f[..14], &f[15..]].concat().join(",")
            })
            .collect()
    };
    let mut merged_rows = strip(&merged);
    let mut whole_sorted = whole.clone();
    merged_rows[1..].sort();
    whole_sorted[1..].sort();
    assert_eq!(merged_rows, whole_sorted);
    // The same shard twice is refused.
    let shard = csvs[0].to_str().unwrap();
    assert_refused(&["bench-merge", shard, shard], "overlapping shards");
    // A Slurm array task picks its shard from the environment (task 2 of 1..3 is 2/3).
    let csv = tmp("slurm.csv");
    let out = homospline()
        .args([
            "bench-scen",
            "fixtures/maps/movingai/maze-32-32-2-random-1.scen",
            "fixtures/maps/movingai/room-32-32-4-random-1.scen",
            "--sample",
            "5",
            "--classes",
            "2",
            "--csv",
            csv.to_str().unwrap(),
        ])
        .env("SLURM_ARRAY_TASK_ID", "2")
        .env("SLURM_ARRAY_TASK_MIN", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .output()
        .unwrap();
    assert_ok(&out);
    assert!(String::from_utf8(out.stdout).unwrap().contains("shard 2/3"));
}

#[test]
fn graphs_of_many_maps_go_to_a_directory_and_a_failed_write_is_not_bad_input() {
    let dir = tmp("graphs");
    let out = homospline()
        .args([
            "graph",
            "fixtures/maps/movingai/maze-32-32-2.map",
            "fixtures/maps/movingai/room-32-32-4.map",
            "--out-dir",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert_ok(&out);
    for stem in ["maze-32-32-2", "room-32-32-4"] {
        assert!(dir.join(format!("{stem}.msgpack")).is_file(), "{stem}");
    }
    // Two inputs without --out-dir: usage.
    refused(&[
        "graph",
        "fixtures/maps/movingai/maze-32-32-2.map",
        "fixtures/maps/movingai/room-32-32-4.map",
    ]);
    // An output that cannot be written: exit 3, not 2.
    let out = homospline()
        .args(["plan", "--json", "/nonexistent-dir/plan.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("cannot write the plan JSON")
    );
}

#[test]
fn a_robot_radius_plans_clear_of_walls_and_refuses_a_start_too_near() {
    let room = "fixtures/maps/movingai/room-32-32-4.map";
    let json = tmp("radius.json");
    let out = homospline()
        .args(["plan", room, "--start", "1.5,1.5", "--goal", "30.5,30.5"])
        .args(["--robot-radius", "0.3", "--json", json.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&json);
    let best = v["best"].as_u64().unwrap() as usize;
    // Clearances are the robot body's: positive means at least 0.3 from every wall.
    assert!(
        v["classes"][best - 1]["certified_clearance"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    let out = homospline()
        .args(["plan", room, "--start", "1.5,1.5", "--goal", "30.5,30.5"])
        .args(["--robot-radius", "0.7"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("start [1.5, 1.5] has clearance 0.5000, less than the robot radius 0.7"),
        "{err}"
    );
    for bad in ["-1", "nan"] {
        let out = homospline()
            .args(["plan", room, "--start", "1.5,1.5", "--goal", "30.5,30.5"])
            .args([&format!("--robot-radius={bad}")])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(
            String::from_utf8(out.stderr)
                .unwrap()
                .contains("robot radius"),
            "{bad}"
        );
    }
}

#[test]
fn a_saved_map_graph_is_reused_only_at_its_robot_radius() {
    let room = "fixtures/maps/movingai/room-32-32-4.map";
    let graph = |radius: &str| {
        let g = tmp(&format!("room-r{radius}.msgpack"));
        let out = homospline()
            .args([
                "graph",
                room,
                "--robot-radius",
                radius,
                "--out",
                g.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert_ok(&out);
        g
    };
    let plan = |g: &std::path::Path, radius: &str| {
        homospline()
            .args(["plan", room, "--start", "1.5,1.5", "--goal", "30.5,30.5"])
            .args(["--graph", g.to_str().unwrap(), "--robot-radius", radius])
            .output()
            .unwrap()
    };
    // A robot's free space is the half-cell lattice's points that keep its radius: at 0.3
    // and 0.35 the same points (every lattice point is 0, 0.5, 0.707 or more from a wall),
    // so one graph serves both.
    let g = graph("0.3");
    assert_ok(&plan(&g, "0.3"));
    assert_ok(&plan(&g, "0.35"));
    // A point robot's free space is the map's cells: another grid, another graph.
    let out = plan(&g, "0");
    assert_eq!(out.status.code(), Some(2));
    // At 0.6 the side midpoints next to walls are closed: another free space.
    let g = graph("0.6");
    let out = plan(&g, "0.3");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("not built for map") && err.contains("robot radius"),
        "{err}"
    );
}

/// A map's classes print as letters by rank (A, B, C), and with `--class-names id` beside
/// short ids (a signature of up to 12 characters, else `#` and eight hex digits), told
/// apart; `--avoid` takes the id as printed; the JSON has the letter, the id and the whole
/// signature.
#[test]
fn map_classes_print_as_letters_and_short_distinct_ids_that_avoid_takes() {
    let args = [
        "plan",
        "fixtures/maps/movingai/room-32-32-4.map",
        "--start",
        "1.5,1.5",
        "--goal",
        "30.5,30.5",
    ];
    let json = tmp("ids.json");
    let column = |table: &str, k: usize| -> Vec<String> {
        table
            .lines()
            .skip(2)
            .take_while(|l| !l.starts_with("chosen"))
            .map(|l| l.split_whitespace().nth(k).unwrap().to_owned())
            .collect()
    };
    let out = homospline().args(args).output().unwrap();
    assert_ok(&out);
    let plain = String::from_utf8(out.stdout).unwrap();
    let out = homospline()
        .args(args)
        .args(["--json", json.to_str().unwrap(), "--class-names", "id"])
        .output()
        .unwrap();
    assert_ok(&out);
    let table = String::from_utf8(out.stdout).unwrap();
    let (letters, ids) = (column(&table, 1), column(&table, 2));
    assert!(ids.len() >= 3, "{table}");
    assert_eq!(column(&plain, 1), letters, "{plain}");
    assert_eq!(&letters[..3], ["A", "B", "C"], "{table}");
    let v = read_json(&json);
    let chosen = v["best"].as_u64().unwrap() as usize;
    assert!(
        plain.contains(&format!(
            "class {} (id {})",
            letters[chosen - 1],
            ids[chosen - 1]
        )),
        "{plain}"
    );
    for ((id, letter), class) in ids
        .iter()
        .zip(&letters)
        .zip(v["classes"].as_array().unwrap())
    {
        assert_eq!(class["letter"], letter.as_str());
        assert_eq!(class["id"], id.as_str());
        let signature = class["signature"].as_str().unwrap();
        assert!(id.len() <= 12, "{id}");
        if signature.len() > 12 {
            assert!(id.starts_with('#') && id.len() == 9, "{id} for {signature}");
        } else {
            assert_eq!(id, signature);
        }
    }
    let mut unique = ids.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), ids.len(), "ids told apart: {ids:?}");
    let out = homospline()
        .args(args)
        .args(["--avoid", &ids[0]])
        .output()
        .unwrap();
    assert_ok(&out);
    let again = String::from_utf8(out.stdout).unwrap();
    assert!(
        !again.contains(&ids[0]),
        "{} still planned:\n{again}",
        ids[0]
    );
    assert!(again.contains(&ids[1]), "{again}");
}

#[test]
fn no_route_for_the_robot_is_no_plan_naming_the_widest_route() {
    // room-32-32-4's doors are one cell wide: a disc of radius 1 passes none of them.
    let out = homospline()
        .args(["plan", "fixtures/maps/movingai/room-32-32-4.map"])
        .args([
            "--start",
            "2.5,2.5",
            "--goal",
            "30.5,30.5",
            "--robot-radius",
            "1",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "no route for a robot of radius 1: the widest route between start and goal keeps 0.5 at"
        ),
        "{err}"
    );
    // A door a disc of 0.5 fits through (its sides' midpoints keep exactly 0.5): a plan,
    // certified, and `safe` judged by the map's own dm.
    let json = tmp("room-r049.json");
    let out = homospline()
        .args(["plan", "fixtures/maps/movingai/room-32-32-4.map"])
        .args([
            "--start",
            "2.5,2.5",
            "--goal",
            "30.5,30.5",
            "--robot-radius",
            "0.49",
        ])
        .args(["--json", json.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&json);
    assert_eq!(v["dm"], 0.25);
    assert!(v["dm_why"].as_str().unwrap().contains("map default"), "{v}");
}
