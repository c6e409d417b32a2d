//! `homospline check` end to end: exit codes and messages on the shipped fixtures.

use crate::common::*;

#[test]
fn valid_scenes_exit_0_with_a_summary() {
    let out = homospline()
        .args(["check", "fixtures/scenes/narrow-pass.yaml"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("scene      narrow-pass"), "{text}");
    assert!(text.contains("2 topological"), "{text}");
}

#[test]
fn maps_and_worlds_are_checked_as_plan_and_simulate_read_them() {
    for (file, lines) in [
        (
            "fixtures/maps/movingai/room-32-32-4.map",
            &[
                "map        room-32-32-4",
                "cells      32 x 32, 1 map unit each (MovingAI: row 0 at the top)",
                "free       682 of 1024 cells (66.6 %)",
            ][..],
        ),
        (
            "fixtures/maps/ros/nav2/tb3_sandbox.yaml",
            &[
                "cells      384 x 384, 0.05 m each (ROS: y up from the origin)",
                "extent     [-10, -10] .. [9.2, 9.2]",
            ][..],
        ),
        (
            "fixtures/worlds/field-blocked.yaml",
            &[
                "world      field-blocked (a scene world)",
                "truth      1 obstacle hidden, 0 cleared",
                "scouts     2",
            ][..],
        ),
        (
            "fixtures/worlds/maps/16room-blocked.yaml",
            &[
                "world      16room-blocked (a map world)",
                "truth      map 16room_000-truth: 1 cell differing from the prior",
            ][..],
        ),
    ] {
        let out = homospline().args(["check", file]).output().unwrap();
        assert_ok(&out);
        let text = String::from_utf8(out.stdout).unwrap();
        for l in lines {
            assert!(text.contains(l), "{file}: {l}\n{text}");
        }
    }
    // A world is read as `simulate` reads it: the scene it names must be there, and its
    // mission must fit in the steps `simulate` allows.
    let dir = tmp("check-world");
    std::fs::create_dir_all(&dir).unwrap();
    let w = dir.join("w.yaml");
    std::fs::write(&w, "scene: nowhere.yaml\n").unwrap();
    let err = refused(&["check", w.to_str().unwrap()]);
    assert!(err.contains("scene: cannot read"), "{err}");
    let scene = root().join("fixtures/scenes/field.yaml");
    std::fs::write(
        &w,
        format!(
            "scene: {}\nteam:\n  ugv: {{speed: 1e-9, sensor_range: 4}}\n",
            scene.display()
        ),
    )
    .unwrap();
    let err = refused(&["check", w.to_str().unwrap()]);
    assert!(err.contains("the mission would take"), "{err}");
    // What check does not take is named.
    for (file, what) in [
        (
            "fixtures/maps/movingai/room-32-32-4-random-1.scen",
            "a MovingAI scenario file",
        ),
        ("fixtures/maps/ros/nav2/tb3_sandbox.pgm", "an image"),
    ] {
        let err = refused(&["check", file]);
        assert!(err.contains(&format!("{file}: {what}")), "{err}");
    }
}

#[test]
fn every_invalid_fixture_exits_2_with_its_message_on_stderr() {
    let dir = root().join("fixtures/invalid");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "expected") {
            continue;
        }
        let rel = format!(
            "fixtures/invalid/{}",
            path.file_name().unwrap().to_str().unwrap()
        );
        let stderr = refused(&["check", &rel]);
        let expected = std::fs::read_to_string(path.with_extension("expected")).unwrap();
        assert_eq!(
            stderr.trim(),
            format!("error: {}", expected.trim()),
            "{rel}"
        );
        n += 1;
    }
    assert!(n >= 20);
}

#[test]
fn a_missing_file_and_bad_usage_exit_2() {
    assert_refused(
        &["check", "no/such/scene.yaml"],
        "no/such/scene.yaml: cannot read",
    );
    refused(&["frobnicate"]);
}

#[test]
fn the_cli_definition_is_consistent() {
    let out = homospline().arg("--help").output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8(out.stdout).unwrap().contains("check"));
}

#[test]
fn obstacles_meeting_or_beyond_the_bounds_are_not_counted_as_holes() {
    // One disc in the middle (a hole), one crossing the lower wall, one apart from the
    // bounds; with robot_radius 1 a fourth, 0.5 from the right wall, meets it once inflated.
    let scene = tmp("edge.yaml");
    std::fs::write(
        &scene,
        "version: 1\nname: edge\nbounds: {min: [0, 0], max: [40, 30]}\nstart: [3, 15]\n\
         goal: [30, 15]\nrobot_radius: 1\nobstacles:\n  - name: middle\n    circles: [[20, 15, 3]]\n\
         \x20 - name: bump\n    circles: [[20, 0, 4]]\n  - name: far\n    circles: [[60, 60, 2]]\n\
         \x20 - name: near-wall\n    circles: [[37, 25, 2.5]]\n",
    )
    .unwrap();
    let out = homospline()
        .args(["check", scene.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("4 topological: 1 hole in free space, 2 meeting the bounds, 1 beyond them"),
        "{text}"
    );
    assert!(
        text.contains("  hole 0: 1 circle from middle; representative [20.000, 15.000]\n"),
        "{text}"
    );
    assert!(
        text.contains(
            "  group 1: 1 circle from bump; representative [20.000, 0.000]; meets the bounds"
        ),
        "{text}"
    );
    assert!(
        text.contains(
            "  group 2: 1 circle from far; representative [60.000, 60.000]; beyond the bounds"
        ),
        "{text}"
    );
    assert!(
        text.contains(
            "  group 3: 1 circle from near-wall; representative [37.000, 25.000]; meets the bounds"
        ),
        "{text}"
    );
}

#[test]
fn a_file_of_another_command_is_named_with_that_command() {
    // A review's case: `plan WORLD` answered the parser's "unknown field `scene`", `simulate
    // SCENE` "unknown field `bounds`" and `plan SCEN` "expected mapping start".
    for (args, needle) in [
        (
            &["plan", "fixtures/worlds/field-blocked.yaml"][..],
            "a world file: `homospline simulate fixtures/worlds/field-blocked.yaml` runs its mission",
        ),
        (
            &["graph", "fixtures/worlds/field-blocked.yaml"][..],
            "this command takes a scene or a map",
        ),
        (
            &["plan", "fixtures/maps/movingai/Boston_0_256.map.scen"][..],
            "a MovingAI scenario file: `homospline bench-scen",
        ),
        (
            &["simulate", "fixtures/scenes/field.yaml"][..],
            "a scene: `homospline plan fixtures/scenes/field.yaml` plans on it; simulate takes a world file",
        ),
        (
            &["simulate", "fixtures/maps/movingai/room-32-32-4.map"][..],
            "a MovingAI map: `homospline plan fixtures/maps/movingai/room-32-32-4.map --start X,Y --goal X,Y`",
        ),
    ] {
        assert_refused(args, needle);
    }
    // A scene with a mistake keeps its parser's message under plan.
    assert_refused(
        &["plan", "fixtures/invalid/wrong-type.yaml"],
        "start: expected a number",
    );
}
