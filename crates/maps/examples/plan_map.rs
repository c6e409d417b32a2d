//! Plans on a MovingAI map for a disc robot: prepares the map once for the robot's radius
//! (its free space, Voronoi graph and clearance model), then answers several queries on it,
//! and says "no route" where the robot does not fit (room-32-32-4's doors are one cell
//! wide: a radius of 0.3 passes them, 0.5 does not).
//! `cargo run --release -p homospline-maps --example plan_map [RADIUS]`

use homospline_geom::Point;
use homospline_maps::{PreparedMap, movingai};
use homospline_optim::PlanConfig;

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let radius: f64 = std::env::args().nth(1).map_or(Ok(0.3), |r| r.parse())?;
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/maps/movingai/room-32-32-4.map"
    );
    let map = movingai::read_map(&std::fs::read_to_string(path)?, path)?;
    // Preparing costs the most; each query after it reuses the prepared map.
    let prepared = PreparedMap::for_robot(&map, radius)?;
    let cfg = PlanConfig::maps();
    // Room centres 1.5 cells from every wall: corner to corner, and across.
    for (s, g) in [
        ((2.5, 2.5), (30.5, 30.5)),
        ((2.5, 30.5), (30.5, 2.5)),
        ((6.5, 2.5), (2.5, 6.5)),
    ] {
        let (s, g) = (Point::new(s.0, s.1), Point::new(g.0, g.1));
        match prepared.plan(s, g, &cfg) {
            Ok(plan) => match plan.best {
                Some(b) => {
                    let c = &plan.classes[b - 1];
                    println!(
                        "{s} -> {g}: length {:.2}, the robot keeps {:.3} beyond its radius {radius}",
                        c.length, c.min_clearance
                    );
                }
                None => println!("{s} -> {g}: no collision-free class"),
            },
            // A start or goal too near a wall, or no route wide enough: the message says which.
            Err(e) => println!("{s} -> {g}: {e}"),
        }
    }
    Ok(())
}
