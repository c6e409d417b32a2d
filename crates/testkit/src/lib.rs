//! Test support shared by the crates' tests, the benches and `xtask`: the fixture scenes and
//! the seeded generator of random scenes (always), occupancy-map helpers (feature `maps`) and
//! the generator of mission worlds (feature `mission`).
//!
//! Tests, benches and tooling only (it reads files and panics on a broken fixture); no
//! library crate depends on it. Without features it depends on `geom` alone, so the low
//! floors (`voronoi`, `homotopy`, `optim`) test without compiling the crates above them.

use std::path::PathBuf;

use homospline_geom::{Bounds, Circle, Obstacle, Point, Real, Scene};

#[cfg(feature = "maps")]
mod maps;
#[cfg(feature = "maps")]
pub use maps::*;
#[cfg(feature = "mission")]
mod worlds;
#[cfg(feature = "mission")]
pub use worlds::*;

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

/// A random `n x n` occupancy grid, row-major (`true` = occupied): every cell occupied with
/// probability `density`, seeded (like MovingAI's random512-20-0 at `density = 0.2`: the
/// map with the most cycles of its size). The maps of the preparation bench and of
/// `cargo xtask map-memory`.
pub fn random_occupancy(n: usize, density: f64, seed: u64) -> Vec<bool> {
    let mut rng = SplitMix(seed);
    (0..n * n).map(|_| rng.next_unit() < density).collect()
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

/// A seeded random scene in `[0, size]^2`: `n` circles in clusters of up to `group`, start
/// and goal at mid-height near the left and right sides and kept clear (`cargo xtask
/// gen-scenes` and the mission worlds).
pub fn random_scene(name: &str, seed: u64, size: f64, n: usize, group: usize) -> Scene {
    let mut rng = SplitMix(seed);
    let start = Point::new((size * 0.04 * 1000.0).round() / 1000.0, size * 0.5);
    let goal = Point::new((size * 0.96 * 1000.0).round() / 1000.0, size * 0.5);
    let keep = size * 0.03;
    let mut obstacles = Vec::new();
    let mut placed = 0;
    while placed < n {
        let k = (1 + (rng.next_unit() * group as f64) as usize).min(n - placed);
        let c = Point::new(
            size * (0.1 + 0.8 * rng.next_unit()),
            size * (0.05 + 0.9 * rng.next_unit()),
        );
        let r = size * (0.01 + 0.03 * rng.next_unit());
        let circles: Vec<Circle> = (0..k)
            .map(|_| {
                let a = rng.next_unit() * std::f64::consts::TAU;
                let d = r * 1.2 * rng.next_unit();
                let rr = (r * (0.5 + 0.5 * rng.next_unit()) * 1000.0).round() / 1000.0;
                Circle::new(
                    ((c.x + a.cos() * d) * 1000.0).round() / 1000.0,
                    ((c.y + a.sin() * d) * 1000.0).round() / 1000.0,
                    rr,
                )
            })
            .collect();
        if circles
            .iter()
            .any(|ci| ci.signed_distance(&start) < keep || ci.signed_distance(&goal) < keep)
        {
            continue;
        }
        placed += k;
        obstacles.push(Obstacle {
            name: format!("o{}", obstacles.len()),
            circles,
        });
    }
    square_scene(name.to_owned(), size, start, goal, obstacles)
}

/// The seeded random scenes of `fixtures/random`, as `cargo xtask gen-scenes` writes them:
/// 10 small scenes (60 x 60, 4 to 12 circles) and 5 with hundreds of circles (240 x 240).
pub fn random_fixture_scenes() -> Vec<Scene> {
    let small = (0..10u64).map(|i| {
        let n = 4 + (i as usize * 3) % 9;
        random_scene(&format!("random-small-{i:02}"), 1000 + i, 60.0, n, 3)
    });
    let large = (0..5u64).map(|i| {
        let n = 200 + 50 * i as usize;
        random_scene(&format!("random-large-{i:02}"), 2000 + i, 240.0, n, 6)
    });
    small.chain(large).collect()
}

/// The scenes of the ignored scan tests: the fixture scenes, the seeded random fixtures and
/// `SCAN_SCENES` generated worlds ([`world_scene`] 0, 1, ...; `default` when unset).
pub fn scan_scenes(default: u64) -> Vec<Scene> {
    let n: u64 = std::env::var("SCAN_SCENES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default);
    let mut all = fixture_scenes();
    all.extend(random_fixture_scenes());
    all.extend((0..n).map(world_scene));
    all
}

/// The prior scene of `random_world(seed, _)` (feature `mission`): a random 60 x 60 scene of 5 to 12 circles.
pub fn world_scene(seed: u64) -> Scene {
    let mut rng = SplitMix(seed ^ 0x5EED);
    let n = 5 + (rng.next_unit() * 8.0) as usize;
    random_scene(&format!("world-{seed:03}"), 7000 + seed, 60.0, n, 3)
}

/// Distance from segment `ab` to the closed square `[x0, x0 + s] x [y0, y0 + s]` (0 when
/// they meet).
pub fn segment_square(a: Point, b: Point, x0: Real, y0: Real, s: Real) -> Real {
    let inside = |p: Point| p.x >= x0 && p.x <= x0 + s && p.y >= y0 && p.y <= y0 + s;
    let corners = [
        Point::new(x0, y0),
        Point::new(x0 + s, y0),
        Point::new(x0 + s, y0 + s),
        Point::new(x0, y0 + s),
    ];
    if inside(a) || inside(b) {
        return 0.0;
    }
    // The segment crosses a side: parameters of the crossings with each side's line.
    let cross = |p: Point, q: Point, c: Point, d: Point| {
        let r = q - p;
        let e = d - c;
        let den = r.x * e.y - r.y * e.x;
        if den == 0.0 {
            return false;
        }
        let t = ((c - p).x * e.y - (c - p).y * e.x) / den;
        let u = ((c - p).x * r.y - (c - p).y * r.x) / den;
        (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)
    };
    for k in 0..4 {
        if cross(a, b, corners[k], corners[(k + 1) % 4]) {
            return 0.0;
        }
    }
    let point_square = |p: Point| {
        let dx = (x0 - p.x).max(p.x - x0 - s).max(0.0);
        let dy = (y0 - p.y).max(p.y - y0 - s).max(0.0);
        dx.hypot(dy)
    };
    let point_segment = |c: Point| {
        let d = b - a;
        let t = if d.norm_squared() > 0.0 {
            ((c - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a + d * t - c).norm()
    };
    corners
        .iter()
        .map(|&c| point_segment(c))
        .chain([point_square(a), point_square(b)])
        .fold(Real::INFINITY, Real::min)
}
