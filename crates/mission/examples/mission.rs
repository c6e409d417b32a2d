//! Runs a mission: a ground robot crosses a world whose map is out of date (a passage the
//! map shows open is blocked) with aerial scouts ahead of it, re-planning in another class
//! when a scout or its own sensor finds the blockage; prints what happened.
//! `cargo run --release -p homospline-mission --example mission [WORLD.yaml]`

use homospline_mission::{AnyWorld, MissionConfig, Policy, simulate, simulate_map};

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
    let path = std::env::args().nth(1).unwrap_or_else(|| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/worlds/convex-blocked.yaml"
        )
        .into()
    });
    let world =
        homospline_mission::world::load_any(std::path::Path::new(&path), |p| std::fs::read(p))?;
    // The default scout policy, `survey` (`simulate --policy survey`); `Policy::all()` lists
    // the others. A map world takes the map profile, `MissionConfig::for_maps()`.
    let result = match &world {
        AnyWorld::Scene(w) => simulate(
            w,
            &MissionConfig {
                policy: Policy::SURVEY,
                ..MissionConfig::default()
            },
        )?,
        AnyWorld::Map(w) => simulate_map(
            w,
            &MissionConfig {
                policy: Policy::SURVEY,
                ..MissionConfig::for_maps()
            },
        )?,
    };
    println!(
        "{}: goal reached {} after {:.1} s; the UGV drove {:.1} (the plan on the true world: {}), \
         {} re-plans, {} class switches; the scouts flew {:.1}",
        result.world,
        result.reached,
        result.time,
        result.ugv_distance,
        result
            .truth_plan_length
            .map_or("none".to_owned(), |l| format!("{l:.1}")),
        result.replans,
        result.switches,
        result.uav_distance
    );
    for e in result.events.iter().take(8) {
        println!(
            "  t = {:5.1} s at ({:.1}, {:.1}): {:?}",
            e.t, e.at[0], e.at[1], e.kind
        );
    }
    Ok(())
}
