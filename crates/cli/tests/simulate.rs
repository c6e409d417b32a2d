//! `homospline simulate` end to end: a paper-like world with a hidden blockage is reached,
//! the JSON holds the timeline and the tracks, the SVG animates the robots, and a bad world
//! file is refused with its file, line and field.

mod common;

use common::*;

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
        "bad-world.yaml:3: team.ugv.speed: 0 must be finite and > 0",
    );
    let missing = tmp("missing-scene.yaml");
    std::fs::write(&missing, "scene: nowhere.yaml\n").unwrap();
    assert_refused(
        &["simulate", missing.to_str().unwrap()],
        "missing-scene.yaml: scene: cannot read",
    );
}
