//! Data-driven test: every file in `fixtures/invalid/` is rejected with the message in its
//! `.expected` sibling (the whole line, so a change in wording is a reviewed change).

use std::path::Path;

use homospline_geom::Scene;

#[test]
fn every_invalid_fixture_is_rejected_with_its_message() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = root.join("fixtures/invalid");
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .expect("fixtures/invalid exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e != "expected"))
        .collect();
    entries.sort();
    assert!(
        entries.len() >= 20,
        "expected at least 20 invalid fixtures, found {}",
        entries.len()
    );
    let mut failures = Vec::new();
    for path in &entries {
        let rel = path
            .strip_prefix(&root)
            .unwrap()
            .to_str()
            .unwrap()
            .replace('\\', "/");
        let expected_path = path.with_extension("expected");
        let expected = std::fs::read_to_string(&expected_path)
            .unwrap_or_else(|_| panic!("{rel}: missing {}", expected_path.display()));
        let bytes = std::fs::read(path).unwrap();
        match Scene::from_bytes(&bytes, &rel) {
            Ok(_) => failures.push(format!(
                "{rel}: accepted, expected error: {}",
                expected.trim()
            )),
            Err(e) if e.to_string() != expected.trim() => failures.push(format!(
                "{rel}:\n  expected: {}\n  actual:   {e}",
                expected.trim()
            )),
            Err(_) => {}
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_shipped_scene_is_valid() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let path = e.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        let scene = Scene::from_bytes(&bytes, &path.display().to_string())
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(!scene.obstacles.is_empty());
        n += 1;
    }
    assert!(n >= 5);
}

#[test]
fn the_name_defaults_to_the_file_stem() {
    let s = Scene::from_str(
        "bounds: {min: [0, 0], max: [1, 1]}\nstart: [0.1, 0.1]\ngoal: [0.9, 0.9]\n",
        "dir/my-room.yaml",
    )
    .unwrap();
    assert_eq!(s.name, "my-room");
}
