//! Plans a scene of circles (the paper's Fig. 5, or the scene file given) with the default
//! configuration and prints each homotopy class: its length, clearance and whether it is
//! collision-free and safe. `cargo run -p homospline-optim --example plan_scene [SCENE.yaml]`

use homospline_geom::Scene;
use homospline_optim::{PlanConfig, plan};

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
    let (text, source) = match std::env::args().nth(1) {
        Some(path) => (std::fs::read_to_string(&path)?, path),
        None => (
            include_str!("../../../fixtures/scenes/narrow-pass.yaml").to_owned(),
            "narrow-pass.yaml".to_owned(),
        ),
    };
    let scene = Scene::from_str(&text, &source)?;
    let plan = plan(&scene, &PlanConfig::default())?;
    for c in &plan.classes {
        println!(
            "class {:>2} {:<12} length {:8.2}  clearance {:6.3}  collision-free {}  safe {}",
            c.rank,
            homospline_homotopy::class_id(&c.signature),
            c.length,
            c.min_clearance,
            c.collision_free,
            c.safe
        );
    }
    match plan.best {
        Some(b) => println!(
            "chosen: class {b}, {} path points",
            plan.classes[b - 1].path.len()
        ),
        None => println!("no collision-free class"),
    }
    Ok(())
}
