//! Seeded random scenes shared by the benches.

use homospline_geom::{Circle, Obstacle, Point, Scene};
use homospline_testkit::{SplitMix, square_scene};

/// `n` compound obstacles (3 to 6 overlapping circles each) in a `size x size` square, kept
/// off the start (left middle) and goal (right middle).
pub fn compound_scene(size: f64, n: usize, seed: u64) -> Scene {
    let mut rng = SplitMix(seed);
    let start = Point::new(size * 0.02, size * 0.5);
    let goal = Point::new(size * 0.98, size * 0.5);
    let mut obstacles = Vec::new();
    while obstacles.len() < n {
        let c = Point::new(
            size * (0.08 + 0.84 * rng.next_unit()),
            size * (0.05 + 0.9 * rng.next_unit()),
        );
        let r = size * (0.008 + 0.012 * rng.next_unit());
        let k = 3 + (rng.next_unit() * 4.0) as usize;
        let circles: Vec<Circle> = (0..k)
            .map(|_| {
                let a = rng.next_unit() * std::f64::consts::TAU;
                Circle::new(
                    c.x + a.cos() * r,
                    c.y + a.sin() * r,
                    r * (0.6 + 0.5 * rng.next_unit()),
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
    square_scene(format!("compound-{n}"), size, start, goal, obstacles)
}
