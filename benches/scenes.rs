//! Seeded random scenes shared by the benches.

use homospline_geom::{Bounds, Circle, Obstacle, Point, Scene};

/// A small deterministic generator (SplitMix64), so every run sees the same scene.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in `[0, 1)`.
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` compound obstacles (3 to 6 overlapping circles each) in a `size x size` square, kept
/// off the start (left middle) and goal (right middle).
pub fn compound_scene(size: f64, n: usize, seed: u64) -> Scene {
    let mut rng = Rng(seed);
    let start = Point::new(size * 0.02, size * 0.5);
    let goal = Point::new(size * 0.98, size * 0.5);
    let mut obstacles = Vec::new();
    while obstacles.len() < n {
        let c = Point::new(
            size * (0.08 + 0.84 * rng.next()),
            size * (0.05 + 0.9 * rng.next()),
        );
        let r = size * (0.008 + 0.012 * rng.next());
        let k = 3 + (rng.next() * 4.0) as usize;
        let circles: Vec<Circle> = (0..k)
            .map(|_| {
                let a = rng.next() * std::f64::consts::TAU;
                Circle::new(
                    c.x + a.cos() * r,
                    c.y + a.sin() * r,
                    r * (0.6 + 0.5 * rng.next()),
                )
            })
            .collect();
        if circles.iter().any(|ci| {
            ci.signed_distance(&start) < size * 0.02 || ci.signed_distance(&goal) < size * 0.02
        }) {
            continue;
        }
        obstacles.push(Obstacle {
            name: format!("o{}", obstacles.len()),
            circles,
        });
    }
    Scene {
        name: format!("compound-{n}"),
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
