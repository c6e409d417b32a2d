//! The `homospline` command: validate scenes, plan paths, build Voronoi graphs.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};
use homospline_cli::{EXAMPLE_SCENE, picture, report};
use homospline_geom::{Point, Scene};
use homospline_maps::OccupancyMap;
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
    Plan(PlanArgs),
    /// Plan every scenario of a MovingAI `.scen` file (its map sits beside it) and report the
    /// success rate, time per plan and path length over the scenario's octile optimum.
    BenchScen {
        /// The `.scen` file.
        scen: PathBuf,
        /// Plan only the first N scenarios.
        #[arg(long)]
        limit: Option<usize>,
        /// Homotopy classes per plan.
        #[arg(long, default_value_t = 5)]
        classes: usize,
        /// Write one line per scenario here.
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
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
        Command::Plan(args) => plan(args),
        Command::BenchScen {
            scen,
            limit,
            classes,
            csv,
        } => bench_scen(&scen, limit, classes, csv),
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
            picture::graph_svg(
                &picture::Background::Scene(&scene, CostConfig::default().alpha),
                &g,
            )
            .as_bytes(),
        )?;
    }
    Ok(0)
}

/// The options of `plan`.
#[derive(Args, Debug)]
struct PlanArgs {
    /// Scene file (YAML or JSON), MovingAI `.map` or ROS map YAML; without it, the
    /// built-in example (the paper's Fig. 5).
    scene: Option<PathBuf>,
    /// Start in map coordinates, `X,Y` (required for maps; overrides a scene's).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    start: Option<String>,
    /// Goal in map coordinates, `X,Y` (required for maps; overrides a scene's).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    goal: Option<String>,
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
    /// Local optimiser (default nelder-mead for scenes, as in the paper; lbfgs for maps,
    /// whose paths need up to 64 dimensions).
    #[arg(long, value_enum)]
    optimizer: Option<OptimizerArg>,
    /// Worker threads (the result does not depend on it).
    #[arg(long)]
    threads: Option<usize>,
    /// Most via-points a spline may have (default 10 for scenes, 32 for maps, whose
    /// one-cell doors need more).
    #[arg(long)]
    max_via: Option<usize>,
    /// Write the plan result (formats.md) here.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write a picture of the plan here.
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
}

/// What `plan` plans on.
enum Input {
    Scene(Scene),
    Map(OccupancyMap),
}

fn parse_point(opt: &str, text: &str) -> anyhow::Result<Point> {
    let (x, y) = text
        .split_once(',')
        .ok_or_else(|| bad(format!("{opt} {text}: expected X,Y")))?;
    let p = |v: &str| v.trim().parse::<f64>().ok().filter(|f| f.is_finite());
    match (p(x), p(y)) {
        (Some(x), Some(y)) => Ok(Point::new(x, y)),
        _ => Err(bad(format!(
            "{opt} {text}: expected two finite numbers X,Y"
        ))),
    }
}

/// Reads a scene, a MovingAI map or a ROS map YAML (with its image), by content and name.
fn load_input(path: &Path) -> anyhow::Result<Input> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| bad(format!("{name}: cannot read: {e}")))?;
    let is_map = path.extension().is_some_and(|e| e == "map");
    let text = std::str::from_utf8(&bytes).ok();
    let is_ros = !is_map
        && path.extension().is_some_and(|e| e == "yaml" || e == "yml")
        && text.is_some_and(|t| t.lines().any(|l| l.trim_start().starts_with("image:")));
    if is_map {
        let text = text.ok_or_else(|| bad(format!("{name}: not a text file")))?;
        return Ok(Input::Map(
            homospline_maps::movingai::read_map(text, &name).map_err(|e| bad(e.to_string()))?,
        ));
    }
    if is_ros {
        let yaml = homospline_maps::ros::read_yaml(text.unwrap_or_default(), &name)
            .map_err(|e| bad(e.to_string()))?;
        let image = path.parent().unwrap_or(Path::new(".")).join(&yaml.image);
        let img = std::fs::read(&image).map_err(|e| {
            bad(format!(
                "{name}: image {}: cannot read: {e}",
                image.display()
            ))
        })?;
        let map = homospline_maps::ros::read_map(&yaml, &name, &img, &image.display().to_string())
            .map_err(|e| bad(e.to_string()))?;
        return Ok(Input::Map(map));
    }
    Scene::from_bytes(&bytes, &name)
        .map(Input::Scene)
        .map_err(|e| bad(e.to_string()))
}

fn plan(a: PlanArgs) -> anyhow::Result<u8> {
    let input = match &a.scene {
        Some(p) => load_input(p)?,
        None => Input::Scene(
            Scene::from_str(EXAMPLE_SCENE, "narrow-pass.yaml (built-in example)")
                .map_err(|e| bad(e.to_string()))?,
        ),
    };
    let start = a
        .start
        .as_deref()
        .map(|t| parse_point("--start", t))
        .transpose()?;
    let goal = a
        .goal
        .as_deref()
        .map(|t| parse_point("--goal", t))
        .transpose()?;
    let input = match input {
        Input::Scene(mut scene) => {
            if let Some(s) = start {
                scene.start = s;
            }
            if let Some(g) = goal {
                scene.goal = g;
            }
            scene
                .validate(&scene.name.clone())
                .map_err(|e| bad(format!("--start/--goal: {e}")))?;
            Input::Scene(scene)
        }
        Input::Map(map) => {
            if a.resolution.is_some() || a.graph.is_some() {
                return Err(bad(
                    "--resolution and --graph apply to scenes; a map's grid is its cells",
                ));
            }
            Input::Map(map)
        }
    };
    let scene_points = match &input {
        Input::Scene(s) => Some(s),
        Input::Map(_) => None,
    };
    let mut cost = CostConfig::preset(&a.preset).ok_or_else(|| {
        bad(format!(
            "--preset: unknown preset '{}' (paper-voronoi, paper-original)",
            a.preset
        ))
    })?;
    if let Some(s) = scene_points {
        cost = cost.with_scene_points(s);
    }
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
    let base = if matches!(input, Input::Map(_)) {
        homospline_maps::map_config()
    } else {
        PlanConfig::default()
    };
    let max_via = a.max_via.unwrap_or(base.growth.max_via_points);
    if !(1..=200).contains(&max_via) {
        return Err(bad(format!(
            "--max-via {max_via}: must be between 1 and 200"
        )));
    }
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
                Some(OptimizerArg::NelderMead) => Optimizer::NelderMead,
                Some(OptimizerArg::Lbfgs) => Optimizer::Lbfgs,
                None => base.growth.optimizer,
            },
            max_via_points: max_via,
            ..base.growth.clone()
        },
        threads: a.threads,
        ..base
    };
    let alpha = cfg.growth.cost.alpha;
    let (result, picture) = match &input {
        Input::Scene(scene) => {
            let saved = match &a.graph {
                Some(p) => Some(load_graph(p, scene)?),
                None => None,
            };
            let result = plan_with_graph(scene, saved, &cfg)
                .map_err(|e| bad(format!("{}: {e}", scene.name)))?;
            let pic = a
                .svg
                .as_ref()
                .map(|_| picture::plan_svg(&picture::Background::Scene(scene, alpha), &result));
            (result, pic)
        }
        Input::Map(map) => {
            let (s, g) = match (start, goal) {
                (Some(s), Some(g)) => (s, g),
                _ => {
                    return Err(bad(format!(
                        "{}: a map needs --start X,Y and --goal X,Y",
                        map.name
                    )));
                }
            };
            let (result, _) =
                homospline_maps::plan_map(map, s, g, &cfg).map_err(|e| bad(e.to_string()))?;
            let pic = a
                .svg
                .as_ref()
                .map(|_| picture::plan_svg(&picture::Background::Map(map), &result));
            (result, pic)
        }
    };
    print!("{}", report::plan_table(&result));
    if let Some(p) = &a.json {
        write(p, "plan JSON", report::plan_json(&result).as_bytes())?;
    }
    if let (Some(p), Some(pic)) = (&a.svg, picture) {
        write(p, "picture", pic.as_bytes())?;
        println!("picture: {}", p.display());
    }
    Ok(if result.best.is_some() {
        0
    } else {
        EXIT_NO_PLAN
    })
}

fn load_graph(p: &Path, scene: &Scene) -> anyhow::Result<VoronoiGraph> {
    let bytes = std::fs::read(p).map_err(|e| bad(format!("{}: cannot read: {e}", p.display())))?;
    let g = VoronoiGraph::from_msgpack(&bytes).map_err(|e| bad(format!("{}: {e}", p.display())))?;
    let at = |n: Option<usize>| n.and_then(|i| g.nodes.get(i)).map(|n| n.at);
    if at(g.start) != Some([scene.start.x, scene.start.y])
        || at(g.goal) != Some([scene.goal.x, scene.goal.y])
    {
        bail!(bad(format!(
            "{}: the graph was built for another start or goal than this scene's",
            p.display()
        )));
    }
    Ok(g)
}

fn bench_scen(
    scen: &Path,
    limit: Option<usize>,
    classes: usize,
    csv: Option<PathBuf>,
) -> anyhow::Result<u8> {
    use std::fmt::Write as _;
    let name = scen.display().to_string();
    let text =
        std::fs::read_to_string(scen).map_err(|e| bad(format!("{name}: cannot read: {e}")))?;
    let scenarios =
        homospline_maps::movingai::read_scen(&text, &name).map_err(|e| bad(e.to_string()))?;
    let first = &scenarios[0].map;
    let map_file = Path::new(first)
        .file_name()
        .map(PathBuf::from)
        .unwrap_or_default();
    let map_path = scen.parent().unwrap_or(Path::new(".")).join(&map_file);
    let map_text = std::fs::read_to_string(&map_path).map_err(|e| {
        bad(format!(
            "{name}: its map {}: cannot read: {e}",
            map_path.display()
        ))
    })?;
    let map = homospline_maps::movingai::read_map(&map_text, &map_path.display().to_string())
        .map_err(|e| bad(e.to_string()))?;
    if classes == 0 || classes > 64 {
        return Err(bad(format!(
            "--classes {classes}: must be between 1 and 64"
        )));
    }
    let n = limit.unwrap_or(scenarios.len()).min(scenarios.len());
    // The same defaults as `plan MAP`.
    let cfg = PlanConfig {
        classes,
        ..homospline_maps::map_config()
    };
    let bar = indicatif::ProgressBar::new(n as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} scenarios {elapsed_precise} eta {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut rows = String::from(
        "index,bucket,start_x,start_y,goal_x,goal_y,optimal,length,ratio,clearance,classes,success,time_ms\n",
    );
    let (mut ok, mut times, mut ratios) = (0usize, Vec::new(), Vec::new());
    for (k, s) in scenarios.iter().take(n).enumerate() {
        let t = std::time::Instant::now();
        let outcome = homospline_maps::plan_map(&map, s.start, s.goal, &cfg);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        times.push(ms);
        let (length, clearance, found, success) = match &outcome {
            Ok((p, _)) => match p.best {
                Some(b) => {
                    let c = &p.classes[b - 1];
                    (c.length, c.min_clearance, p.classes.len(), true)
                }
                None => (f64::NAN, f64::NAN, p.classes.len(), false),
            },
            Err(_) => (f64::NAN, f64::NAN, 0, false),
        };
        let ratio = if s.optimal_length > 0.0 {
            length / s.optimal_length
        } else {
            f64::NAN
        };
        if success {
            ok += 1;
            if ratio.is_finite() {
                ratios.push(ratio);
            }
        }
        let _ = writeln!(
            rows,
            "{k},{},{},{},{},{},{},{length:.4},{ratio:.4},{clearance:.4},{found},{success},{ms:.3}",
            s.bucket, s.start.x, s.start.y, s.goal.x, s.goal.y, s.optimal_length
        );
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mean = |v: &[f64]| {
        if v.is_empty() {
            f64::NAN
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        }
    };
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        if v.is_empty() {
            f64::NAN
        } else {
            v[v.len() / 2]
        }
    };
    let mut t2 = times.clone();
    let mut r2 = ratios.clone();
    println!(
        "{}: {} scenarios on {} ({} x {})",
        name, n, map.name, map.width, map.height
    );
    println!(
        "success      {ok}/{n} ({:.1} %)",
        100.0 * ok as f64 / n.max(1) as f64
    );
    println!(
        "time / plan  mean {:.2} ms, median {:.2} ms, max {:.2} ms",
        mean(&times),
        median(&mut t2),
        times.iter().copied().fold(0.0, f64::max)
    );
    println!(
        "length / octile optimum  mean {:.4}, median {:.4}, min {:.4}, max {:.4} (an any-angle smooth path can be shorter: below 1 is expected)",
        mean(&ratios),
        median(&mut r2),
        ratios.iter().copied().fold(f64::INFINITY, f64::min),
        ratios.iter().copied().fold(0.0, f64::max)
    );
    if let Some(p) = csv {
        write(&p, "CSV", rows.as_bytes())?;
    }
    Ok(0)
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    #[test]
    fn the_command_line_definition_is_consistent() {
        super::Cli::command().debug_assert();
    }
}
