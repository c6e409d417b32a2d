//! Test support shared by the crates' tests and the benches: the fixture scenes.
//!
//! Tests and benches only (it reads files and panics on a broken fixture); no library crate
//! depends on it.

use std::path::PathBuf;

use homospline_geom::Scene;

/// `fixtures/scenes` of the workspace.
pub fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes")
}

/// The paper-like fixture scenes, in file-name order.
pub fn fixture_scenes() -> Vec<Scene> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenes_dir())
        .expect("fixtures/scenes is readable")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let bytes = std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            Scene::from_bytes(&bytes, &p.display().to_string()).unwrap_or_else(|e| panic!("{e}"))
        })
        .collect()
}
