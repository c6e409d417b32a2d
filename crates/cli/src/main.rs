//! The `homospline` command: validate scenes, plan paths, build Voronoi graphs.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Parser, Subcommand};
use homospline_geom::Scene;

/// Exit code for bad input or usage.
const EXIT_BAD_INPUT: u8 = 2;

/// Homotopy-seeded spline path planning for ground robots.
#[derive(Parser, Debug)]
#[command(name = "homospline", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Validate a scene file (YAML or JSON) and summarise it.
    Check {
        /// The scene file.
        scene: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { EXIT_BAD_INPUT } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = match cli.command {
        Command::Check { scene } => check(&scene),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

fn load_scene(path: &std::path::Path) -> anyhow::Result<Scene> {
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    Ok(Scene::from_bytes(&bytes, &path.display().to_string())?)
}

fn check(path: &std::path::Path) -> anyhow::Result<()> {
    let scene = load_scene(path)?;
    print!("{}", homospline_cli::summary(&scene));
    Ok(())
}
