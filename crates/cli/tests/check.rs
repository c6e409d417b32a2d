//! `homospline check` end to end: exit codes and messages on the shipped fixtures.

mod common;

use common::*;

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
