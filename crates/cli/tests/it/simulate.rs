//! `homospline simulate` end to end: a paper-like world with a hidden blockage is reached,
//! the JSON holds the timeline and the tracks, the SVG animates the robots, and a bad world
//! file is refused with its file, line and field.

use crate::common::*;

#[test]
fn a_blocked_world_is_reached_with_a_timeline_and_an_animated_picture() {
    let (json, svg) = (tmp("mission.json"), tmp("mission.svg"));
    let out = homospline()
        .args([
            "simulate",
            "fixtures/worlds/narrow-pass-blocked.yaml",
            "--policy",
            "ahead",
            "--json",
            json.to_str().unwrap(),
            "--svg",
            svg.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("goal reached"), "{text}");
    assert!(text.contains("not on the map"), "{text}");
    let v = read_json(&json);
    assert_eq!(v["reached"], true);
    assert_eq!(v["policy"], "ahead");
    let kinds: Vec<&str> = v["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["kind"].as_str().unwrap())
        .collect();
    for k in ["planned", "discovered", "blocked", "replanned", "reached"] {
        assert!(kinds.contains(&k), "{k} in {kinds:?}");
    }
    assert!(v["ugv"]["samples"].as_array().unwrap().len() > 100);
    assert_eq!(v["uavs"].as_array().unwrap().len(), 2);
    assert!(v["adopted"].as_array().unwrap().len() >= 2);
    assert!(v["distance_ratio"].as_f64().unwrap() > 0.9);
    assert_svg_layers(
        &svg,
        &["map", "hidden", "plans", "tracks", "events", "robots"],
    );
    assert!(
        std::fs::read_to_string(&svg)
            .unwrap()
            .contains("<animateMotion")
    );
}

#[test]
fn a_bad_world_file_names_the_file_line_and_field() {
    let bad = tmp("bad-world.yaml");
    std::fs::write(
        &bad,
        "scene: ../scenes/convex.yaml\nteam:\n  ugv: {speed: 0, sensor_range: 5}\n",
    )
    .unwrap();
    assert_refused(
        &["simulate", bad.to_str().unwrap()],
        "bad-world.yaml:3: team.ugv.speed: 0 must be finite, > 0 and at most 1e9",
    );
    let missing = tmp("missing-scene.yaml");
    std::fs::write(&missing, "scene: nowhere.yaml\n").unwrap();
    assert_refused(
        &["simulate", missing.to_str().unwrap()],
        "missing-scene.yaml: scene: cannot read",
    );
}

#[test]
fn a_coarse_step_is_refined_and_said_so() {
    // A UGV at 5 units/s with sensor range 6 and --dt 10 would move 50 units between two
    // looks: it drove through the hidden blockage and reported the goal reached.
    let world = tmp("fast-ugv.yaml");
    let text = std::fs::read_to_string(root().join("fixtures/worlds/narrow-pass-blocked.yaml"))
        .unwrap()
        .replace("speed: 1.0", "speed: 5.0")
        .replace(
            "../scenes/",
            &format!("{}/", root().join("fixtures/scenes").display()),
        );
    assert!(
        text.contains("speed: 5.0"),
        "the world's UGV speed moved: {text}"
    );
    std::fs::write(&world, text).unwrap();
    let json = tmp("fast-ugv.json");
    let out = homospline()
        .args([
            "simulate",
            world.to_str().unwrap(),
            "--policy",
            "none",
            "--dt",
            "10",
        ])
        .args(["--json", json.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout.contains("time step 0.6 s: --dt 10 refined"),
        "{stdout}"
    );
    assert!(stdout.contains("not on the map"), "{stdout}");
    let v = read_json(&json);
    assert_eq!(v["dt"], 0.6);
    assert_eq!(v["reached"], true);
}

#[test]
fn policies_come_from_the_registry_and_an_unknown_one_is_refused_with_the_list() {
    let help = homospline().args(["simulate", "--help"]).output().unwrap();
    assert_ok(&help);
    let text = String::from_utf8(help.stdout).unwrap();
    for p in homospline_mission::Policy::all() {
        assert!(text.contains(p.name()), "{} in --help:\n{text}", p.name());
    }
    let out = homospline()
        .args([
            "simulate",
            "fixtures/worlds/narrow-pass-blocked.yaml",
            "--policy",
            "bogus",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("bogus") && err.contains("guard"), "{err}");
}

/// Mission events name classes by letters in the order the mission first names them (A: the
/// class first driven), with `--class-names id` beside the ids `plan --avoid` takes; the
/// JSON keeps the signatures.
#[test]
fn mission_events_letter_classes_in_order_of_appearance() {
    let world = "fixtures/worlds/convex-blocked.yaml";
    let run = |extra: &[&str]| {
        let out = homospline()
            .args(["simulate", world])
            .args(extra)
            .output()
            .unwrap();
        assert_ok(&out);
        String::from_utf8(out.stdout).unwrap()
    };
    let letters = run(&[]);
    assert!(letters.contains("driving A\n"), "{letters}");
    assert!(letters.contains("switched class A -> "), "{letters}");
    let json = tmp("letters.json");
    let ids = run(&["--class-names", "id", "--json", json.to_str().unwrap()]);
    let v = read_json(&json);
    let first = v["events"][0]["class"].as_str().unwrap();
    assert!(
        ids.contains(&format!(
            "driving A {}\n",
            homospline_homotopy::class_id(first)
        )),
        "{ids}"
    );
    // Every letter names one class: the same letter never stands for two signatures.
    let switched = v["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["kind"] == "switched")
        .unwrap();
    assert_eq!(switched["from"].as_str(), Some(first), "{switched}");
    assert_ne!(switched["to"].as_str(), Some(first));
}
