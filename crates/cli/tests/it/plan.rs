//! `homospline plan` and `homospline graph` end to end: exit codes, the plan JSON of
//! formats.md, well-formed SVG with every layer, saved graphs reused.

use crate::common::*;
use std::path::Path;

#[test]
fn the_built_in_example_plans_with_json_and_a_picture() {
    let (json, svg) = (tmp("plan.json"), tmp("plan.svg"));
    let out = homospline()
        .args([
            "plan",
            "--json",
            json.to_str().unwrap(),
            "--svg",
            svg.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(table.contains("chosen: rank 1"), "{table}");
    let v = read_json(&json);
    assert_eq!(v["scene"], "narrow-pass");
    assert_eq!(v["seed"], "voronoi");
    assert_eq!(v["best"], 1);
    let classes = v["classes"].as_array().unwrap();
    assert!(!classes.is_empty());
    for (i, c) in classes.iter().enumerate() {
        assert_eq!(c["rank"], i as u64 + 1);
        for key in [
            "signature",
            "seed_path",
            "via_points",
            "path",
            "cost",
            "length",
            "min_clearance",
            "collision_free",
            "iterations",
            "evaluations",
            "time_ms",
        ] {
            assert!(!c[key].is_null(), "class field {key}");
        }
        for key in ["total", "topology", "roughness", "length", "safety"] {
            assert!(c["cost"][key].is_number(), "cost field {key}");
        }
        let path = c["path"].as_array().unwrap();
        assert_eq!(path[0], serde_json::json!([5.0, 47.0]));
        assert_eq!(path[path.len() - 1], serde_json::json!([95.0, 47.0]));
    }
    for key in ["voronoi", "classes", "optimize", "total"] {
        assert!(v["timing_ms"][key].is_number());
    }
    assert_svg_layers(
        &svg,
        &[
            "heatmap",
            "obstacles",
            "voronoi",
            "seeds",
            "paths",
            "best",
            "endpoints",
            "legend",
            "scale-bar",
        ],
    );
}

#[test]
fn a_saved_graph_gives_the_same_plan() {
    let (g, j1, j2, gj, gs) = (
        tmp("g.msgpack"),
        tmp("a.json"),
        tmp("b.json"),
        tmp("g.json"),
        tmp("g.svg"),
    );
    let scene = "fixtures/scenes/two-homotopies.yaml";
    let out = homospline()
        .args([
            "graph",
            scene,
            "--resolution",
            "3",
            "--out",
            g.to_str().unwrap(),
            "--json",
            gj.to_str().unwrap(),
            "--svg",
            gs.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let gv: serde_json::Value = read_json(&gj);
    assert!(gv["nodes"].as_array().unwrap().len() > 2 && gv["start"].is_number());
    assert_svg_layers(&gs, &["voronoi"]);
    let run = |extra: &[&str], json: &Path| {
        let mut args = vec![
            "plan",
            scene,
            "--threads",
            "1",
            "--json",
            json.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = homospline().args(&args).output().unwrap();
        assert_ok(&out);
        let mut v = read_json(json);
        v.as_object_mut().unwrap().remove("timing_ms");
        for c in v["classes"].as_array_mut().unwrap() {
            c.as_object_mut().unwrap().remove("time_ms");
        }
        v
    };
    assert_eq!(
        run(&["--resolution", "3"], &j1),
        run(&["--graph", g.to_str().unwrap()], &j2)
    );
    // A graph of another scene is refused.
    assert_refused(
        &[
            "plan",
            "fixtures/scenes/convex.yaml",
            "--graph",
            g.to_str().unwrap(),
        ],
        "another start or goal",
    );
    // A map's complete graph said "built for another start or goal": it has none.
    let map_graph = tmp("map-graph-for-a-scene.json");
    assert_ok(
        &homospline()
            .args([
                "graph",
                "fixtures/maps/movingai/random-32-32-10.map",
                "--out",
                map_graph.to_str().unwrap(),
            ])
            .output()
            .unwrap(),
    );
    assert_refused(
        &[
            "plan",
            "fixtures/scenes/convex.yaml",
            "--graph",
            map_graph.to_str().unwrap(),
        ],
        "the graph is a map's complete graph (no start or goal; saved by `homospline graph MAP`): it serves plans on that map (`plan MAP --graph`), not on a scene",
    );
    // So is one of the same start and goal but other obstacles: a wall added across the
    // scene gave "no collision-free class" (every class through the wall), an obstacle
    // taken away a dearer class, both silently.
    let text = std::fs::read_to_string(root().join(scene)).unwrap();
    for (name, changed) in [
        (
            "walled.yaml",
            text.replacen(
                "obstacles:",
                "obstacles:\n  - name: wall\n    circles: [[50, 20, 4], [50, 30, 4]]",
                1,
            ),
        ),
        ("inflated.yaml", format!("{text}\nrobot_radius: 0.5\n")),
    ] {
        assert_ne!(changed, text, "{name}: the scene was not changed");
        let p = tmp(name);
        std::fs::write(&p, changed).unwrap();
        assert_refused(
            &["plan", p.to_str().unwrap(), "--graph", g.to_str().unwrap()],
            "built for another scene",
        );
    }
    // And a resolution other than the graph's.
    assert_refused(
        &[
            "plan",
            scene,
            "--graph",
            g.to_str().unwrap(),
            "--resolution",
            "4",
        ],
        "built at 3 cells per unit, not at the 4",
    );
}

#[test]
fn bad_options_exit_2_with_the_option_named() {
    for (args, needle) in [
        (
            vec!["plan", "--weight", "safety"],
            "--weight safety: expected NAME=VALUE",
        ),
        (
            vec!["plan", "--weight", "safty=1"],
            "unknown weight or parameter 'safty'",
        ),
        (vec!["plan", "--weight", "alpha=-1"], "--weight alpha=-1"),
        (
            vec!["plan", "--preset", "fast"],
            "invalid value 'fast' for '--preset <PRESET>'",
        ),
        (vec!["plan", "--classes", "0"], "--classes 0"),
        (vec!["plan", "--resolution", "0"], "--resolution 0"),
        // A negative value is the option's, not a flag of its own ("unexpected argument
        // '-1'"): the message names the option.
        (
            vec!["plan", "--clearance-floor", "-1"],
            "--clearance-floor -1: must be a finite number >= 0",
        ),
        (
            vec!["plan", "--finish-within", "-1"],
            "invalid value '-1' for '--finish-within <N|off>'",
        ),
        (
            vec![
                "simulate",
                "fixtures/worlds/field-blocked.yaml",
                "--svg-at",
                "-1",
            ],
            "--svg-at -1: must be a time in seconds, >= 0",
        ),
        // A still with no picture to draw it in was silently ignored.
        (
            vec![
                "simulate",
                "fixtures/worlds/field-blocked.yaml",
                "--svg-at",
                "5",
            ],
            "--svg-at 5: draws the picture of --svg or --png, and neither is asked for",
        ),
        // Found by an adversarial run: each of these was accepted.
        (
            vec!["plan", "--threads", "5000"],
            "--threads 5000: must be between 1 and 256",
        ),
        (
            vec!["plan", "--avoid", "abc"],
            "narrow-pass: --avoid 'abc': not a class: e, ray crossings such as -1+2, or an id such as #3f9a01c2",
        ),
        (
            vec!["plan", "--avoid", "-9"],
            "avoid '-9': ray 9: there are",
        ),
        (
            vec!["plan", "--seed", "straight", "--avoid", "e"],
            "the straight seed plans one class",
        ),
        (
            vec!["plan", "--seed", "straight", "--diverse", "0.5"],
            "the straight seed plans one class",
        ),
        (
            vec!["plan", "--seed", "straight", "--graph", "g.msgpack"],
            "--seed straight plans one class",
        ),
        (
            vec!["plan", "--seed", "straight", "--classes", "3"],
            "--classes 3: --seed straight plans one class, from the straight line S-T",
        ),
        (
            vec!["plan", "--seed", "straight", "--classes", "0"],
            "--classes 0: must be between 1 and 64",
        ),
        (
            vec!["plan", "--weight", "dm=-5"],
            "parameter dm must be finite and >= 0, got -5",
        ),
        (
            vec![
                "plan",
                "fixtures/scenes/narrow-pass.yaml",
                "--resolution",
                "0.05",
            ],
            "5 cells along the scene's longer side (at least 16)",
        ),
        (vec!["plan", "no/such.yaml"], "no/such.yaml: cannot read"),
        (
            vec!["plan", "--graph", "no/such.msgpack"],
            "no/such.msgpack: cannot read",
        ),
    ] {
        assert_refused(&args, needle);
    }
    // A file that is not a graph.
    let junk = tmp("junk.msgpack");
    std::fs::write(&junk, b"not a graph").unwrap();
    assert_refused(&["plan", "--graph", junk.to_str().unwrap()], "junk.msgpack");
}

#[test]
fn every_command_has_help() {
    for cmd in [
        vec!["--help"],
        vec!["plan", "--help"],
        vec!["graph", "--help"],
        vec!["check", "--help"],
    ] {
        let out = homospline().args(&cmd).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{cmd:?}");
        assert!(!out.stdout.is_empty());
    }
}

/// The help states the planner's own default pruning ratio (it once said 1.5 when the
/// default had become 2.5).
#[test]
fn the_help_gives_the_default_pruning_ratio() {
    let out = homospline().args(["plan", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let said = format!("[default: {}]", homospline_optim::planner::DEFAULT_PRUNE);
    assert!(help.contains(&said), "plan --help does not say {said}");
    // --classes has no clap default (so that --seed straight can refuse a given count): its
    // help states the library's.
    let said = format!(
        "[default: {}]",
        homospline_optim::PlanConfig::default().classes
    );
    assert!(help.contains(&said), "plan --help does not say {said}");
}

/// `plan -h` gives one line per option under the headings, each default said once.
#[test]
fn the_short_help_is_grouped_with_one_line_per_option() {
    let out = homospline().args(["plan", "-h"]).output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout).into_owned();
    for heading in ["Input:", "Classes:", "Cost:", "Output:", "Advanced:"] {
        assert!(
            help.lines().any(|l| l == heading),
            "no heading {heading}:\n{help}"
        );
    }
    for line in help.lines() {
        assert!(
            line.matches("default").count() <= 1,
            "a default said twice: {line}"
        );
    }
    let options = help
        .lines()
        .filter(|l| l.trim_start().starts_with("--"))
        .count();
    assert!(options >= 25, "{options} options:\n{help}");
    // One line each: an option's help is on its line, or (a long name) on the next one.
    let mut after = 0;
    for line in help.lines() {
        let t = line.trim_start();
        if t.starts_with('-') || t.is_empty() || !line.starts_with(' ') {
            after = 0;
        } else {
            after += 1;
            assert!(after <= 1, "an option's help runs on: {line}\n{help}");
        }
    }
}

#[test]
fn block_avoid_and_diverse_change_the_classes() {
    // The chosen class of the built-in example runs through the pass at about (50, 30).
    let plain = tmp("plain.json");
    assert_ok(
        &homospline()
            .args(["plan", "--json", plain.to_str().unwrap()])
            .output()
            .unwrap(),
    );
    let v = read_json(&plain);
    let best = v["classes"][0]["signature"].as_str().unwrap().to_owned();
    assert_eq!(v["classes"][0]["overlap"], 1.0);
    // Left out, it is not among the classes.
    let avoided = tmp("avoided.json");
    let out = homospline()
        .args([
            "plan",
            "--avoid",
            &best,
            "--json",
            avoided.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&avoided);
    assert!(
        v["classes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|c| c["signature"] != best.as_str())
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A well-formed id of no class found is said to have left nothing out.
    let out = homospline()
        .args(["plan", "--avoid", &best, "--avoid", "#00000000"])
        .output()
        .unwrap();
    assert_ok(&out);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--avoid '#00000000' matched none of the classes the search found")
            && !err.contains(&format!("'{best}'")),
        "{err}"
    );
    // A blocked disc on its path: the chosen path keeps clear of it.
    let path = read_json(&plain)["classes"][0]["path"]
        .as_array()
        .unwrap()
        .clone();
    let mid = &path[path.len() / 2];
    let (x, y) = (mid[0].as_f64().unwrap(), mid[1].as_f64().unwrap());
    let blocked = tmp("blocked.json");
    let out = homospline()
        .args([
            "plan",
            "--block",
            &format!("{x},{y},2"),
            "--json",
            blocked.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&blocked);
    let b = v["best"].as_u64().unwrap() as usize;
    for p in v["classes"][b - 1]["path"].as_array().unwrap() {
        let (px, py) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
        assert!(
            (px - x).hypot(py - y) > 2.0,
            "({px}, {py}) inside the blocked disc"
        );
    }
    // Limited overlap: every class shares at most half its graph path with the chosen one.
    let diverse = tmp("diverse.json");
    let out = homospline()
        .args([
            "plan",
            "fixtures/scenes/field.yaml",
            "--diverse",
            "0.5",
            "--json",
            diverse.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&diverse);
    let b = v["best"].as_u64().unwrap() as usize;
    for (i, c) in v["classes"].as_array().unwrap().iter().enumerate() {
        if i + 1 != b {
            assert!(c["overlap"].as_f64().unwrap() <= 0.5 + 1e-9, "{c}");
        }
    }
    // Bad values are refused with the option named.
    for (args, msg) in [
        (
            vec!["plan", "--block", "1,2"],
            "--block 1,2: expected X,Y,R",
        ),
        (vec!["plan", "--block", "1,2,-3"], "R > 0"),
        (
            vec!["plan", "--diverse", "1.5"],
            "--diverse 1.5: must be a fraction in [0, 1]",
        ),
    ] {
        assert_refused(&args, msg);
    }
}

#[test]
fn a_closed_stdout_does_not_stop_the_plan() {
    // `homospline plan | head -3`: the reader goes away before the table is printed. The
    // plan still writes its JSON and exits with its own code, without a panic.
    let json = tmp("closed-stdout.json");
    let mut child = homospline()
        .args(["plan", "--json"])
        .arg(&json)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert_ok(&out);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    assert!(read_json(&json)["best"].is_u64());
}

/// The chosen class of a plan result.
pub(crate) fn chosen_class(v: &serde_json::Value) -> serde_json::Value {
    v["classes"][v["best"].as_u64().unwrap() as usize - 1].clone()
}

/// `plan SCENE --json FILE` with `extra` options (FILE named `name` in the test's temporary
/// directory): the plan result, after checking that the command succeeded.
pub(crate) fn plan_json(scene: &str, extra: &[&str], name: &str) -> serde_json::Value {
    let json = tmp(name);
    let out = homospline()
        .args(["plan", scene, "--json"])
        .arg(&json)
        .args(extra)
        .output()
        .unwrap();
    assert_ok(&out);
    read_json(&json)
}

#[test]
fn prune_marks_the_stopped_classes_and_off_runs_every_class_to_its_end() {
    // On convex three classes cost more than 1.5 times the best after their first round.
    // The chosen class's finish is off: it depends on the evaluations spent, which the
    // pruning changes (convex: 1,324 evaluations, under `--finish-within`'s default, against
    // 2,707 without pruning).
    let scene = "fixtures/scenes/convex.yaml";
    let p = plan_json(scene, &["--finish-within", "off"], "prune-default.json");
    let f = plan_json(
        scene,
        &["--prune", "off", "--finish-within", "off"],
        "prune-off.json",
    );
    let stopped = |v: &serde_json::Value| {
        v["classes"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["pruned"].as_bool().unwrap())
            .map(|c| c["iterations"].as_u64().unwrap())
            .collect::<Vec<_>>()
    };
    assert_eq!(stopped(&p), vec![1, 1, 1]);
    assert!(stopped(&f).is_empty());
    let chosen = |v: &serde_json::Value| {
        let b = v["best"].as_u64().unwrap() as usize;
        v["classes"][b - 1]["path"].clone()
    };
    assert_eq!(chosen(&p), chosen(&f));
    // A value that is no number is clap's to refuse; a number out of range, the options'.
    for (bad, needle) in [
        ("0.9", "--prune 0.9: expected off or a ratio of at least 1"),
        ("nan", "--prune NaN: expected off or a ratio of at least 1"),
        (
            "none",
            "invalid value 'none' for '--prune <RATIO|off>': expected off or a ratio of at least 1",
        ),
    ] {
        assert_refused(&["plan", "--prune", bad], needle);
    }
}

/// `--optimum` gives each collision-free class the shortest length of its class and of any
/// class at its certified clearance, in that order below the class's own length, in the
/// table and the JSON; the JSON has no such field without it, and a map is refused by name.
#[test]
fn the_optimum_is_reported_and_never_above_a_class_length() {
    let json = tmp("optimum.json");
    let out = homospline()
        .args([
            "plan",
            "fixtures/scenes/concave-cup.yaml",
            "--optimum",
            "--json",
            json.to_str().unwrap(),
        ])
        .current_dir(root())
        .output()
        .unwrap();
    assert_ok(&out);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(table.contains(": its class "), "{table}");
    assert!(!table.contains("CHECK FAILED"), "{table}");
    let v = read_json(&json);
    let mut seen = 0;
    for c in v["classes"].as_array().unwrap() {
        match (
            c["optimum_length"].as_f64(),
            c["optimum_length_any_class"].as_f64(),
        ) {
            (Some(o), Some(any)) => {
                assert_eq!(c["collision_free"], true);
                let len = c["length"].as_f64().unwrap();
                assert!(
                    any > 0.0 && any <= o && o <= len,
                    "optimum {o}, of any class {any}, against length {len}"
                );
                seen += 1;
            }
            (None, None) => assert_eq!(c["collision_free"], false),
            other => panic!("one optimum without the other: {other:?}"),
        }
    }
    assert!(seen > 0);
    let plain = tmp("no-optimum.json");
    assert_ok(
        &homospline()
            .args(["plan", "--json", plain.to_str().unwrap()])
            .output()
            .unwrap(),
    );
    assert!(
        read_json(&plain)["classes"][0]
            .get("optimum_length")
            .is_none()
    );
    assert_refused(
        &[
            "plan",
            "fixtures/maps/movingai/maze-32-32-2.map",
            "--start",
            "5,5",
            "--goal",
            "20,20",
            "--optimum",
        ],
        "--optimum needs a scene of circles",
    );
}

/// `--clearance-search every-stretch` optimises every class against the clearance it has: on
/// convex, class `e` reads 3.011 by the default search of `m(C)` and is certified 2.958 (it
/// cannot rank first, so it is not repaired: `safe: false`); searched between every two
/// nodes it keeps `dm` and is safe. The chosen class is the same. A bad value is refused by
/// name.
#[test]
fn clearance_search_every_stretch_keeps_every_class_at_its_target() {
    let scene = "fixtures/scenes/convex.yaml";
    let d = plan_json(scene, &[], "search-default.json");
    let e = plan_json(
        scene,
        &["--clearance-search", "every-stretch"],
        "search-every.json",
    );
    let class = |v: &serde_json::Value, sig: &str| {
        v["classes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["signature"] == sig)
            .cloned()
            .unwrap()
    };
    let (ed, ee) = (class(&d, "e"), class(&e, "e"));
    // The safety term is omega^(dm - m(C)): at most 1 when the cost's m(C) keeps dm.
    assert!(ed["cost"]["safety"].as_f64().unwrap() <= 1.0, "{ed}");
    assert!(!ed["safe"].as_bool().unwrap(), "{ed}");
    assert!(ee["safe"].as_bool().unwrap(), "{ee}");
    let chosen = |v: &serde_json::Value| chosen_class(v)["signature"].clone();
    assert_eq!(chosen(&d), chosen(&e));
    assert_refused(
        &["plan", "--clearance-search", "exact"],
        "--clearance-search",
    );
}

#[test]
fn polish_lowers_the_chosen_class_and_refuses_bad_counts_and_maps() {
    let scene = "fixtures/scenes/convex.yaml";
    let d = plan_json(scene, &["--finish-within", "off"], "polish-default.json");
    let p = plan_json(scene, &["--polish", "1"], "polish-one.json");
    let (cd, cp) = (chosen_class(&d), chosen_class(&p));
    assert_eq!(cd["signature"], cp["signature"]);
    assert!(cp["safe"].as_bool().unwrap(), "{cp}");
    let cost = |c: &serde_json::Value| c["cost"]["total"].as_f64().unwrap();
    assert!(
        cost(&cp) < 0.95 * cost(&cd),
        "{} against {}",
        cost(&cp),
        cost(&cd)
    );
    assert_eq!(
        cp["iterations"].as_u64().unwrap(),
        cd["iterations"].as_u64().unwrap() + 1
    );
    assert_refused(
        &["plan", scene, "--polish", "11"],
        "--polish 11: must be between 0 and 10",
    );
    assert_refused(
        &[&MAP_PLAN[..], &["--polish", "1"]].concat(),
        "--polish applies to scenes",
    );
}

#[test]
fn the_finish_within_its_budget_lowers_the_chosen_class_and_refuses_bad_budgets_and_maps() {
    // Convex's classes spend 1,324 evaluations: under the default budget (1,500) the chosen
    // class gets the finish, under 1,000 it does not, as with `off`.
    let scene = "fixtures/scenes/convex.yaml";
    let d = plan_json(scene, &[], "finish-default.json");
    let off = plan_json(scene, &["--finish-within", "off"], "finish-off.json");
    let small = plan_json(scene, &["--finish-within", "1000"], "finish-1000.json");
    let (cd, co, cs) = (chosen_class(&d), chosen_class(&off), chosen_class(&small));
    // The table says which rounds came after the ranking.
    let table = |extra: &[&str]| {
        let out = homospline()
            .args(["plan", scene])
            .args(extra)
            .output()
            .unwrap();
        assert_ok(&out);
        String::from_utf8(out.stdout).unwrap()
    };
    assert!(
        table(&[]).contains("; 1 of its 4 rounds after the ranking"),
        "{}",
        table(&[])
    );
    assert!(!table(&["--finish-within", "off"]).contains("after the ranking"));
    assert_eq!(cd["signature"], co["signature"]);
    assert!(cd["safe"].as_bool().unwrap(), "{cd}");
    let cost = |c: &serde_json::Value| c["cost"]["total"].as_f64().unwrap();
    assert!(
        cost(&cd) < 0.95 * cost(&co),
        "{} against {}",
        cost(&cd),
        cost(&co)
    );
    let iterations = |c: &serde_json::Value| c["iterations"].as_u64().unwrap();
    assert_eq!(iterations(&cd), iterations(&co) + 1);
    let evaluations = |c: &serde_json::Value| c["evaluations"].as_u64().unwrap();
    let total = |v: &serde_json::Value| -> u64 {
        v["classes"]
            .as_array()
            .unwrap()
            .iter()
            .map(evaluations)
            .sum()
    };
    // At most half a round's budget (3 via-points: 6 coordinates, 30 each), and the plan
    // within its budget.
    let added = evaluations(&cd) - evaluations(&co);
    assert!(added > 0 && added <= 90, "{added}");
    assert!(total(&d) <= 1500, "{}", total(&d));
    assert_eq!(cs["path"], co["path"]);
    assert_eq!(iterations(&cs), iterations(&co));
    for bad in ["-1", "lots", "1.5"] {
        assert_refused(
            &["plan", scene, &format!("--finish-within={bad}")],
            &format!(
                "invalid value '{bad}' for '--finish-within <N|off>': expected off or a number of \
                 evaluations"
            ),
        );
    }
    assert_refused(
        &[&MAP_PLAN[..], &["--finish-within", "2000"]].concat(),
        "--finish-within applies to scenes",
    );
}

#[test]
fn an_output_into_a_missing_directory_fails_with_exit_3_naming_it() {
    let dir = tmp("no-such-dir");
    let _ = std::fs::remove_dir_all(&dir);
    let target = dir.join("p.json");
    let out = homospline()
        .args(["plan", "--json", target.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains(&format!("the directory {} does not exist", dir.display())),
        "{err}"
    );
    assert!(!dir.exists(), "no directory is made");
}

#[test]
fn graph_out_dir_checks_its_inputs_before_writing_anything() {
    let (out, other, empty) = (tmp("od-out"), tmp("od-other"), tmp("od-empty"));
    for d in [&out, &other, &empty] {
        let _ = std::fs::remove_dir_all(d);
    }
    std::fs::create_dir_all(&other).unwrap();
    std::fs::create_dir_all(&empty).unwrap();
    let map = "fixtures/maps/movingai/room-32-32-4.map";
    let twin = other.join("room-32-32-4.map");
    std::fs::copy(root().join(map), &twin).unwrap();
    // Two inputs of one name: refused before the first was written (it used to be).
    assert_refused(
        &[
            "graph",
            "--out-dir",
            out.to_str().unwrap(),
            map,
            twin.to_str().unwrap(),
        ],
        "would both be saved as room-32-32-4.msgpack",
    );
    assert!(!out.exists(), "nothing written");
    // A good map, then one that cannot be read: refused before the first graph was written
    // (it used to be written); so is --resolution with a map after a scene.
    let broken = other.join("zz-broken.map");
    std::fs::write(&broken, "type octile\nheight 2\nwidth x\nmap\n..\n..\n").unwrap();
    let stderr = refused(&[
        "graph",
        "--out-dir",
        out.to_str().unwrap(),
        map,
        broken.to_str().unwrap(),
    ]);
    assert!(stderr.contains("zz-broken.map"), "{stderr}");
    assert!(!out.exists(), "nothing written");
    assert_refused(
        &[
            "graph",
            "--out-dir",
            out.to_str().unwrap(),
            "--resolution",
            "4",
            "fixtures/scenes/convex.yaml",
            map,
        ],
        "room-32-32-4.map: --resolution applies to scenes",
    );
    assert!(!out.exists(), "nothing written");
    // A directory without maps: refused (it exited 0 having done nothing).
    assert_refused(
        &[
            "graph",
            "--out-dir",
            out.to_str().unwrap(),
            empty.to_str().unwrap(),
        ],
        "no input to build a graph of",
    );
    // A missing input is refused on every shard, not only on the one that reads it (shard
    // 3 of 8 of one input had exited 0 without a word).
    assert_refused(
        &[
            "graph",
            "--out-dir",
            out.to_str().unwrap(),
            "--shard",
            "3/8",
            "no-such-maps/",
        ],
        "no-such-maps/: cannot read",
    );
    // A shard that gets no input says so and writes nothing.
    let run = homospline()
        .args([
            "graph",
            "--out-dir",
            out.to_str().unwrap(),
            "--shard",
            "3/8",
            map,
        ])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0));
    let said = String::from_utf8(run.stdout).unwrap();
    assert!(
        said.contains("shard 3/8 gets none of the 1 inputs"),
        "{said}"
    );
    assert!(!out.exists(), "nothing written");
}

#[test]
fn the_json_says_what_safe_was_judged_by() {
    // An outside tool could not check `safe` or `best` without knowing dm and the floor.
    let json = tmp("judged.json");
    let out = homospline()
        .args(["plan", "--weight", "dm=2.5", "--clearance-floor", "1.5"])
        .args(["--json", json.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&json);
    assert_eq!(v["dm"], 2.5);
    assert_eq!(v["clearance_floor"], 1.5);
    for c in v["classes"].as_array().unwrap() {
        let cert = c["certified_clearance"].as_f64().unwrap();
        assert_eq!(c["safe"].as_bool().unwrap(), cert >= 2.5, "{c}");
    }
}

#[test]
fn an_obstacle_smaller_than_a_cell_gets_a_note() {
    // A block of radius 0.2 in narrow-pass's pass (cells of 0.39 units) left the classes
    // through the pass out, silently.
    let out = homospline()
        .args(["plan", "--block", "50,30,0.2"])
        .output()
        .unwrap();
    assert_ok(&out);
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains(
            "note: 1 obstacle ('blocked-0') is smaller than the graph's cells (0.391 units)"
        ),
        "{err}"
    );
    // None on the paper's scenes, and none once the grid is fine enough.
    for args in [
        vec!["plan"],
        vec!["plan", "--block", "50,30,0.2", "--resolution", "10"],
    ] {
        let out = homospline().args(&args).output().unwrap();
        assert_ok(&out);
        assert!(
            out.stderr.is_empty(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// The class table keeps its columns: `safe`, then `pareto`, then `pruned`, each at its own
/// place whatever the others say (a pruned class that was not Pareto-optimal had its tag
/// under `pareto`), and no row ends in blanks.
#[test]
fn the_class_table_keeps_its_columns() {
    let out = homospline()
        .args(["plan", "fixtures/scenes/field.yaml"])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines().skip(1);
    let safe = lines.next().unwrap().find("safe").unwrap();
    let rows: Vec<&str> = lines.take_while(|l| !l.starts_with("chosen")).collect();
    assert!(rows.iter().any(|r| r.contains("pruned")), "{text}");
    assert!(rows.iter().any(|r| r.contains("pareto")), "{text}");
    for row in rows {
        let tail = &row[safe..];
        assert!(tail.starts_with("yes") || tail.starts_with("no"), "{row}");
        if let Some(at) = row.find("pareto") {
            assert_eq!(at, safe + 6, "{row}");
        }
        if let Some(at) = row.find("pruned") {
            assert_eq!(at, safe + 14, "{row}");
        }
        assert_eq!(row, row.trim_end(), "{row}");
    }
}

#[test]
fn a_scene_walled_apart_is_no_plan_naming_the_wall_and_a_narrow_gap_is_planned() {
    // Two discs that, grown by the robot's radius 3, touch each other and the bounds.
    let closed = tmp("walled-apart.yaml");
    let scene = "bounds: {min: [0, 0], max: [60, 60]}\nstart: [5, 30]\ngoal: [55, 30]\n\
                 robot_radius: 3\nobstacles:\n  - name: top\n    circles: [[30, 45, 12]]\n  \
                 - name: bot\n    circles: [[30, 15, 12]]\n";
    std::fs::write(&closed, scene).unwrap();
    let out = homospline()
        .args(["plan", closed.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("no route: start and goal are walled apart by 'top', 'bot'"),
        "{err}"
    );
    // Without the radius they leave a gap of a tenth of a unit, under a cell of the default
    // grid (4.27 cells per unit): a finer grid is made for it, and the plan goes through.
    let open = tmp("narrow-gap.yaml");
    let narrow = scene
        .replace("robot_radius: 3\n", "")
        .replace("[30, 45, 12]", "[30, 45.05, 15]")
        .replace("[30, 15, 12]", "[30, 14.95, 15]");
    std::fs::write(&open, narrow).unwrap();
    let json = tmp("narrow-gap.json");
    let out = homospline()
        .args(["plan", open.to_str().unwrap(), "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert_ok(&out);
    let v = read_json(&json);
    let best = v["best"].as_u64().unwrap();
    let chosen = v["classes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["rank"].as_u64() == Some(best))
        .unwrap();
    assert_eq!(chosen["collision_free"], true);
    assert!(chosen["length"].as_f64().unwrap() < 50.1, "{chosen}");
}
