//! The `homospline` command: validate scenes, plan paths, build Voronoi graphs.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::{Parser, Subcommand, ValueEnum};
use homospline_cli::{EXAMPLE_SCENE, picture, report};
use homospline_geom::Scene;
use homospline_optim::{
    GrowthConfig, Optimizer, PlanConfig, Seed, default_resolution, plan_with_graph,
};
use homospline_spline::CostConfig;
use homospline_voronoi::VoronoiGraph;

/// Exit code when no plan could be found.
const EXIT_NO_PLAN: u8 = 1;
/// Exit code for bad input or usage.
const EXIT_BAD_INPUT: u8 = 2;

/// Homotopy-seeded spline path planning for ground robots.
#[derive(Parser, Debug)]
#[command(name = "homospline", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SeedArg {
    /// One seed per homotopy class of the Voronoi graph (the paper's planner).
    Voronoi,
    /// The straight line S-T (the original planner; one class).
    Straight,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum OptimizerArg {
    /// Nelder-Mead, the paper's method.
    NelderMead,
    /// L-BFGS on the analytic gradient.
    Lbfgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Plan paths: a table of classes and the chosen one; exit 0 with a collision-free plan,
    /// 1 when there is none, 2 on bad input.
    Plan {
        /// Scene file (YAML or JSON); without it, the built-in example (the paper's Fig. 5).
        scene: Option<PathBuf>,
        /// How the splines are seeded.
        #[arg(long, value_enum, default_value = "voronoi")]
        seed: SeedArg,
        /// Homotopy classes to optimise.
        #[arg(long, default_value_t = 5)]
        classes: usize,
        /// Cost preset: paper-voronoi (cost 10) or paper-original (cost 9).
        #[arg(long, default_value = "paper-voronoi")]
        preset: String,
        /// Set a weight or parameter, e.g. --weight safety=2 --weight dm=4 (repeatable).
        #[arg(long = "weight", value_name = "NAME=VALUE")]
        weights: Vec<String>,
        /// Grid cells per map unit for the Voronoi graph (default: 256 cells along the longer side).
        #[arg(long)]
        resolution: Option<f64>,
        /// Reuse a graph saved by `homospline graph --out`.
        #[arg(long, value_name = "FILE.msgpack")]
        graph: Option<PathBuf>,
        /// Local optimiser.
        #[arg(long, value_enum, default_value = "nelder-mead")]
        optimizer: OptimizerArg,
        /// Worker threads (the result does not depend on it).
        #[arg(long)]
        threads: Option<usize>,
        /// Write the plan result (formats.md) here.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// Write a picture of the plan here.
        #[arg(long, value_name = "FILE")]
        svg: Option<PathBuf>,
    },
    /// Build the Voronoi graph of a scene and save it.
    Graph {
        /// Scene file.
        scene: PathBuf,
        /// Grid cells per map unit (default: 256 cells along the longer side).
        #[arg(long)]
        resolution: Option<f64>,
        /// Save the graph as MessagePack, to reuse with `plan --graph`.
        #[arg(long, value_name = "FILE.msgpack")]
        out: Option<PathBuf>,
        /// Write the graph as JSON (formats.md).
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// Write a picture of the graph.
        #[arg(long, value_name = "FILE")]
        svg: Option<PathBuf>,
    },
    /// Validate a scene file (YAML or JSON) and summarise it.
    Check {
        /// The scene file.
        scene: PathBuf,
    },
}

/// An error that is the user's input: exit 2.
#[derive(Debug)]
struct BadInput(String);

impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

fn bad(msg: impl Into<String>) -> anyhow::Error {
    BadInput(msg.into()).into()
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
        Command::Graph {
            scene,
            resolution,
            out,
            json,
            svg,
        } => graph(&scene, resolution, out, json, svg),
        Command::Plan {
            scene,
            seed,
            classes,
            preset,
            weights,
            resolution,
            graph,
            optimizer,
            threads,
            json,
            svg,
        } => plan(PlanArgs {
            scene,
            seed,
            classes,
            preset,
            weights,
            resolution,
            graph,
            optimizer,
            threads,
            json,
            svg,
        }),
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    let bytes =
        std::fs::read(path).map_err(|e| bad(format!("{}: cannot read: {e}", path.display())))?;
    Scene::from_bytes(&bytes, &path.display().to_string()).map_err(|e| bad(e.to_string()))
}

fn write(path: &Path, what: &str, bytes: &[u8]) -> anyhow::Result<()> {
    std::fs::write(path, bytes)
        .with_context(|| format!("{}: cannot write the {what}", path.display()))
}

fn check(path: &Path) -> anyhow::Result<u8> {
    let scene = load_scene(path)?;
    print!("{}", homospline_cli::summary(&scene));
    Ok(0)
}

fn graph(
    path: &Path,
    resolution: Option<f64>,
    out: Option<PathBuf>,
    json: Option<PathBuf>,
    svg: Option<PathBuf>,
) -> anyhow::Result<u8> {
    let scene = load_scene(path)?;
    let res = resolution.unwrap_or_else(|| default_resolution(&scene));
    let t = std::time::Instant::now();
    let (grid, _, g) = homospline_voronoi::build(&scene, res)
        .map_err(|e| bad(format!("{}: {e}", path.display())))?;
    println!(
        "graph of {}: {} x {} cells at {:.3} cells per unit, {} nodes, {} edges, {} cycles, {:.1} ms",
        scene.name,
        grid.width(),
        grid.height(),
        res,
        g.nodes.len(),
        g.edges.len(),
        g.cycle_rank(),
        t.elapsed().as_secs_f64() * 1e3
    );
    if let Some(p) = out {
        write(&p, "graph", &g.to_msgpack())?;
    }
    if let Some(p) = json {
        write(&p, "graph JSON", g.to_json().as_bytes())?;
    }
    if let Some(p) = svg {
        write(
            &p,
            "picture",
            picture::graph_svg(&scene, &g, CostConfig::default().alpha).as_bytes(),
        )?;
    }
    Ok(0)
}

struct PlanArgs {
    scene: Option<PathBuf>,
    seed: SeedArg,
    classes: usize,
    preset: String,
    weights: Vec<String>,
    resolution: Option<f64>,
    graph: Option<PathBuf>,
    optimizer: OptimizerArg,
    threads: Option<usize>,
    json: Option<PathBuf>,
    svg: Option<PathBuf>,
}

fn plan(a: PlanArgs) -> anyhow::Result<u8> {
    let scene = match &a.scene {
        Some(p) => load_scene(p)?,
        None => Scene::from_str(EXAMPLE_SCENE, "narrow-pass.yaml (built-in example)")
            .map_err(|e| bad(e.to_string()))?,
    };
    let mut cost = CostConfig::preset(&a.preset)
        .ok_or_else(|| {
            bad(format!(
                "--preset: unknown preset '{}' (paper-voronoi, paper-original)",
                a.preset
            ))
        })?
        .with_scene_points(&scene);
    for w in &a.weights {
        let (name, value) = w
            .split_once('=')
            .ok_or_else(|| bad(format!("--weight {w}: expected NAME=VALUE")))?;
        let v: f64 = value
            .trim()
            .parse()
            .map_err(|_| bad(format!("--weight {w}: '{value}' is not a number")))?;
        cost.set(name.trim(), v)
            .map_err(|e| bad(format!("--weight {w}: {e}")))?;
    }
    if a.classes == 0 || a.classes > 64 {
        return Err(bad(format!(
            "--classes {}: must be between 1 and 64",
            a.classes
        )));
    }
    if let Some(r) = a.resolution
        && !(r.is_finite() && r > 0.0)
    {
        return Err(bad(format!("--resolution {r}: must be positive")));
    }
    if a.threads == Some(0) {
        return Err(bad("--threads 0: must be at least 1"));
    }
    let saved = match &a.graph {
        Some(p) => {
            let bytes =
                std::fs::read(p).map_err(|e| bad(format!("{}: cannot read: {e}", p.display())))?;
            let g = VoronoiGraph::from_msgpack(&bytes)
                .map_err(|e| bad(format!("{}: {e}", p.display())))?;
            let at = |n: Option<usize>| n.and_then(|i| g.nodes.get(i)).map(|n| n.at);
            if at(g.start) != Some([scene.start.x, scene.start.y])
                || at(g.goal) != Some([scene.goal.x, scene.goal.y])
            {
                bail!(bad(format!(
                    "{}: the graph was built for another start or goal than this scene's",
                    p.display()
                )));
            }
            Some(g)
        }
        None => None,
    };
    let cfg = PlanConfig {
        seed: match a.seed {
            SeedArg::Voronoi => Seed::Voronoi,
            SeedArg::Straight => Seed::Straight,
        },
        classes: a.classes,
        resolution: a.resolution,
        growth: GrowthConfig {
            cost,
            optimizer: match a.optimizer {
                OptimizerArg::NelderMead => Optimizer::NelderMead,
                OptimizerArg::Lbfgs => Optimizer::Lbfgs,
            },
            ..GrowthConfig::default()
        },
        threads: a.threads,
        ..PlanConfig::default()
    };
    let result =
        plan_with_graph(&scene, saved, &cfg).map_err(|e| bad(format!("{}: {e}", scene.name)))?;
    print!("{}", report::plan_table(&result));
    if let Some(p) = &a.json {
        write(p, "plan JSON", report::plan_json(&result).as_bytes())?;
    }
    if let Some(p) = &a.svg {
        write(
            p,
            "picture",
            picture::plan_svg(&scene, &result, cfg.growth.cost.alpha).as_bytes(),
        )?;
        println!("picture: {}", p.display());
    }
    Ok(if result.best.is_some() {
        0
    } else {
        EXIT_NO_PLAN
    })
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    #[test]
    fn the_command_line_definition_is_consistent() {
        super::Cli::command().debug_assert();
    }
}
