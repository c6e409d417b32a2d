//! Test support shared by the crates' tests, the benches and `xtask`: the fixture scenes and
//! the seeded generator of random scenes.
//!
//! Tests, benches and tooling only (it reads files and panics on a broken fixture); no
//! library crate depends on it.

use std::path::PathBuf;

use homospline_geom::{Bounds, Obstacle, Point, Scene};

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

/// SplitMix64, a small seeded generator: the seeded scenes of the benches and of
/// `cargo xtask gen-scenes` are the same on every run and machine.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// Uniform in `[0, 1)`.
    pub fn next_unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A scene in the square `[0, size]^2` with these obstacles, no robot radius and no danger
/// points, critical points or hazards.
pub fn square_scene(
    name: String,
    size: f64,
    start: Point,
    goal: Point,
    obstacles: Vec<Obstacle>,
) -> Scene {
    Scene {
        name,
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(size, size),
        },
        start,
        goal,
        robot_radius: 0.0,
        obstacles,
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    }
}
