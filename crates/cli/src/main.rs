//! The `homospline` command: validate scenes, plan paths, build Voronoi graphs, run MovingAI
//! benchmarks (sharded and merged) and missions.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};
use homospline_cli::options::{PlanOptions, plan_config};
use homospline_cli::{EXAMPLE_SCENE, mission, picture, report};
use homospline_geom::{Point, Scene};
use homospline_maps::input::Input;
use homospline_mission::{AnyWorld, MissionConfig, Policy};
use homospline_optim::{PlanConfig, default_resolution, plan_with_graph};
use homospline_spline::{ClearanceSearch, CostConfig, RoughnessForm};
use homospline_voronoi::VoronoiGraph;

/// Exit code when no plan could be found.
const EXIT_NO_PLAN: u8 = 1;

/// Exit code for bad input or usage.
const EXIT_BAD_INPUT: u8 = 2;
/// Exit code of a run that failed for another reason (an output that cannot be written).
const EXIT_FAILURE: u8 = 3;

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

#[derive(Clone, Copy, Debug, ValueEnum)]
enum RoughnessArg {
    /// integral |q''| dt: the paper's (4).
    Paper,
    /// integral |q''|^2 dt: the bending energy.
    Energy,
    /// sqrt(integral |q''|^2 dt): the authors' code.
    Authors,
}

/// Where the optimiser's `m(C)` is searched between the quadrature nodes.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum ClearanceSearchArg {
    /// Around the worst node only (default): a class whose curve ends below its target
    /// there and could rank first runs one more round with every-stretch.
    WorstNode,
    /// Between every two nodes, in every evaluation: every class is optimised against the
    /// clearance it has (1.6 times an evaluation's cost).
    /// On maps too: the exact clearance to squares has the bound of a disc of radius 0.
    EveryStretch,
}

impl From<ClearanceSearchArg> for ClearanceSearch {
    fn from(a: ClearanceSearchArg) -> Self {
        match a {
            ClearanceSearchArg::WorstNode => ClearanceSearch::WorstNode,
            ClearanceSearchArg::EveryStretch => ClearanceSearch::EveryStretch,
        }
    }
}

impl From<RoughnessArg> for RoughnessForm {
    fn from(a: RoughnessArg) -> Self {
        match a {
            RoughnessArg::Paper => RoughnessForm::Paper,
            RoughnessArg::Energy => RoughnessForm::Energy,
            RoughnessArg::Authors => RoughnessForm::Authors,
        }
    }
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Plan paths: a table of classes and the chosen one; exit 0 with a collision-free plan,
    /// 1 when no collision-free class meets the clearance floor, 2 on bad input.
    Plan(Box<PlanArgs>),
    /// Plan every scenario of a MovingAI `.scen` file (its map sits beside it) and report the
    /// success rate, time per plan and path length over the scenario's octile optimum.
    BenchScen(BenchArgs),
    /// Build the Voronoi graph of a scene (start and goal attached) or of a whole map (the
    /// complete graph, for `plan MAP --graph`) and save it.
    Graph {
        /// Scene files, MovingAI `.map` files or ROS map YAMLs (several, or a directory of
        /// `.map` files, only with `--out-dir`).
        #[arg(required = true)]
        scene: Vec<PathBuf>,
        /// Grid cells per map unit (default: 256 cells along the longer side).
        #[arg(long)]
        resolution: Option<f64>,
        /// The robot's radius in map units (metres on a ROS map): the graph of the free space
        /// it can occupy. On a scene it replaces the file's `robot_radius`.
        #[arg(long, value_name = "R")]
        robot_radius: Option<f64>,
        /// Save the graph as MessagePack, to reuse with `plan --graph`.
        #[arg(long, value_name = "FILE.msgpack")]
        out: Option<PathBuf>,
        /// Save each input's graph here as `STEM.msgpack` (many maps, e.g. on a cluster).
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
        /// With `--out-dir`: build only slice K of N interleaved slices of the inputs
        /// (default: from a Slurm job array's environment, as `bench-scen`).
        #[arg(long, value_name = "K/N")]
        shard: Option<String>,
        /// Write the graph as JSON (formats.md).
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// Write a picture of the graph.
        #[arg(long, value_name = "FILE")]
        svg: Option<PathBuf>,
    },
    /// Combine the CSVs of `bench-scen` shards into the summary one run gives.
    BenchMerge {
        /// The shards' CSV files.
        #[arg(required = true)]
        csv: Vec<PathBuf>,
        /// Write the merged rows here, sorted by file and scenario.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Run the team's mission in a world file: the UGV drives its plan, scouts fly, hidden
    /// blockages are discovered and the UGV re-plans; prints the events and the figures.
    /// Exit 0 when the goal is reached, 1 when not, 2 on bad input.
    Simulate(SimulateArgs),
    /// Validate a scene file (YAML or JSON) and summarise it.
    Check {
        /// The scene file.
        scene: PathBuf,
    },
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum PolicyArg {
    /// No scouts fly (the baseline).
    None,
    /// Scouts inspect the far half of the UGV's route.
    Ahead,
    /// Scouts verify the next best classes.
    Alternatives,
}

/// Options of `simulate`.
#[derive(Args, Debug)]
struct SimulateArgs {
    /// The world file (YAML or JSON): a prior scene, hidden and cleared obstacles, the team.
    world: PathBuf,
    /// Scouts to fly (default: every UAV of the world; more are added at the start).
    #[arg(long)]
    scouts: Option<usize>,
    /// How the scouts are used.
    #[arg(long, value_enum, default_value = "ahead")]
    policy: PolicyArg,
    /// Homotopy classes per plan.
    #[arg(long, default_value_t = 5)]
    classes: usize,
    /// Limited overlap between the classes (see `plan --diverse`).
    #[arg(long, value_name = "F")]
    diverse: Option<f64>,
    /// Time step, seconds.
    #[arg(long, default_value_t = 0.25)]
    dt: f64,
    /// Hysteresis: relative cost margin a class must win by to replace a valid plan.
    #[arg(long, default_value_t = 0.1)]
    switch_margin: f64,
    /// Hysteresis: seconds between voluntary class switches.
    #[arg(long, default_value_t = 10.0)]
    min_switch_interval: f64,
    /// Write the mission (timeline and every trajectory) as JSON.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write an animated picture of the mission.
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
}

/// Options of `bench-scen`.
#[derive(Args, Debug)]
struct BenchArgs {
    /// `.scen` files, or directories of them (their map sits beside each).
    #[arg(required = true)]
    scen: Vec<PathBuf>,
    /// Plan only the first N scenarios of each file (a `.scen` is sorted by length: the
    /// shortest only).
    #[arg(long)]
    limit: Option<usize>,
    /// Plan N scenarios of each file, spread evenly over the whole file (every bucket).
    #[arg(long)]
    sample: Option<usize>,
    /// Plan only slice K of N interleaved slices of all the scenarios picked (default: from a
    /// Slurm job array's SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_COUNT
    /// when they are set). `bench-merge` combines the slices' CSVs.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// A plan that takes longer than this many milliseconds counts as a timeout (it is not
    /// interrupted).
    #[arg(long, value_name = "MS")]
    time_limit: Option<f64>,
    /// Homotopy classes per plan.
    #[arg(long, default_value_t = 5)]
    classes: usize,
    /// Set a weight or parameter of the cost over the map defaults, e.g. --weight dm=1
    /// (repeatable).
    #[arg(long = "weight", value_name = "NAME=VALUE")]
    weights: Vec<String>,
    /// The robot's radius in map units: plans keep it from every obstacle; a scenario whose
    /// start or goal is closer to one is an error row that names its clearance.
    #[arg(long, value_name = "R")]
    robot_radius: Option<f64>,
    /// Write one line per scenario here.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
}

/// Writes a line to stdout. A closed pipe (`homospline plan | head`) drops the output
/// and the command goes on to its files and its exit code; any other write error fails.
macro_rules! say {
    ($($arg:tt)*) => {
        stdout_write(&format!("{}\n", format_args!($($arg)*)))?
    };
}

/// [`say!`] without the line end.
macro_rules! say_raw {
    ($($arg:tt)*) => {
        stdout_write(&format!($($arg)*))?
    };
}

fn stdout_write(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::anyhow!("cannot write to stdout: {e}"))
        }
        _ => Ok(()),
    }
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
            robot_radius,
            out,
            out_dir,
            shard,
            json,
            svg,
        } => match out_dir {
            Some(dir) => graph_dir(
                &scene,
                (resolution, robot_radius),
                &dir,
                shard.as_deref(),
                (out, json, svg),
            ),
            None if scene.len() == 1 && shard.is_none() => {
                graph(&scene[0], (resolution, robot_radius), out, json, svg)
            }
            None => Err(bad(
                "several inputs (or --shard) need --out-dir: each graph is saved as DIR/STEM.msgpack",
            )),
        },
        Command::Plan(args) => plan(*args),
        Command::BenchScen(args) => bench_scen(args),
        Command::Simulate(args) => simulate(args),
        Command::BenchMerge { csv, out } => bench_merge(&csv, out.as_deref()),
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            // A failed write to stderr (full, closed) must not panic: the exit code says it.
            let _ = writeln!(std::io::stderr().lock(), "error: {e:#}");
            // The user's input is to blame (2); anything else, such as an output that cannot
            // be written, is the run's failure (3).
            ExitCode::from(if e.downcast_ref::<BadInput>().is_some() {
                EXIT_BAD_INPUT
            } else {
                EXIT_FAILURE
            })
        }
    }
}

fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    let bytes = homospline_cli::read_regular(path)
        .map_err(|e| bad(format!("{}: cannot read: {e}", path.display())))?;
    Scene::from_bytes(&bytes, &path.display().to_string()).map_err(|e| bad(e.to_string()))
}

fn simulate(a: SimulateArgs) -> anyhow::Result<u8> {
    check_outputs(
        &[&a.world],
        &[
            ("--json", "mission JSON", a.json.as_deref()),
            ("--svg", "picture", a.svg.as_deref()),
        ],
    )?;
    let world =
        homospline_mission::world::load_any(&a.world, homospline_cli::read_regular).map_err(bad)?;
    if a.classes == 0 || a.classes > 64 {
        return Err(bad(format!(
            "--classes {}: must be between 1 and 64",
            a.classes
        )));
    }
    if let Some(f) = a.diverse
        && !(f.is_finite() && (0.0..=1.0).contains(&f))
    {
        return Err(bad(format!("--diverse {f}: must be a fraction in [0, 1]")));
    }
    if !(a.switch_margin.is_finite() && (0.0..1.0).contains(&a.switch_margin)) {
        return Err(bad(format!(
            "--switch-margin {}: must be in [0, 1)",
            a.switch_margin
        )));
    }
    if !(a.min_switch_interval.is_finite() && a.min_switch_interval >= 0.0) {
        return Err(bad(format!(
            "--min-switch-interval {}: must be >= 0 seconds",
            a.min_switch_interval
        )));
    }
    let base = MissionConfig::default();
    let cfg = MissionConfig {
        plan: PlanConfig {
            classes: a.classes,
            diverse: a.diverse,
            ..base.plan.clone()
        },
        policy: match a.policy {
            PolicyArg::None => Policy::None,
            PolicyArg::Ahead => Policy::Ahead,
            PolicyArg::Alternatives => Policy::Alternatives,
        },
        scouts: a.scouts,
        dt: a.dt,
        switch_margin: a.switch_margin,
        min_switch_interval: a.min_switch_interval,
        ..base
    };
    let failed = |e: homospline_mission::MissionError| bad(format!("{}: {e}", a.world.display()));
    let (result, text, json, svg) = match &world {
        AnyWorld::Scene(w) => {
            let r = homospline_mission::simulate(w, &cfg).map_err(failed)?;
            let (t, j) = (mission::mission_text(w, &r), mission::mission_json(w, &r));
            let svg = a.svg.as_ref().map(|_| mission::mission_svg(w, &r));
            (r, t, j, svg)
        }
        AnyWorld::Map(w) => {
            let r = homospline_mission::simulate_map(w, &cfg).map_err(failed)?;
            let (t, j) = (
                mission::map_mission_text(w, &r),
                mission::map_mission_json(w, &r),
            );
            let svg = a.svg.as_ref().map(|_| mission::map_mission_svg(w, &r));
            (r, t, j, svg)
        }
    };
    if result.dt < cfg.dt {
        say!(
            "time step {} s: --dt {} refined so that no robot travels more than half its sensor range between two looks",
            result.dt,
            cfg.dt
        );
    }
    say_raw!("{text}");
    if let Some(p) = &a.json {
        write(p, "mission JSON", json.as_bytes())?;
    }
    if let (Some(p), Some(svg)) = (&a.svg, svg) {
        write(p, "picture", svg.as_bytes())?;
        say!("picture: {}", p.display());
    }
    Ok(if result.reached { 0 } else { 1 })
}

/// Writes `bytes` to `path` whole or not at all: into a temporary file beside it, then
/// renamed over it. A full disk or a failed write leaves any file already at `path` as it
/// was (no truncated output, no good file destroyed), and the temporary file is removed.
fn write(path: &Path, what: &str, bytes: &[u8]) -> anyhow::Result<()> {
    let context = || match path
        .parent()
        .filter(|d| !d.as_os_str().is_empty() && !d.exists())
    {
        Some(d) => format!(
            "{}: cannot write the {what}: the directory {} does not exist",
            path.display(),
            d.display()
        ),
        None => format!("{}: cannot write the {what}", path.display()),
    };
    let name = path
        .file_name()
        .map_or_else(|| "output".to_owned(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        use std::io::Write;
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(context)
}

/// Refuses, before any work, an output path that is one of the inputs or another output,
/// or whose directory does not exist: a plan of minutes ended on a typo, and `--json`
/// equal to the scene overwrote it.
fn check_outputs(inputs: &[&Path], outputs: &[(&str, &str, Option<&Path>)]) -> anyhow::Result<()> {
    // Outputs need not exist yet: their directory is resolved, and their name joined.
    let resolve = |p: &Path| {
        p.canonicalize().ok().or_else(|| {
            let dir = match p.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            Some(dir.canonicalize().ok()?.join(p.file_name()?))
        })
    };
    let same = |a: &Path, b: &Path| match (resolve(a), resolve(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    };
    let given: Vec<(&str, &str, &Path)> = outputs
        .iter()
        .filter_map(|&(flag, what, p)| p.map(|p| (flag, what, p)))
        .collect();
    for (k, &(flag, what, p)) in given.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|i| same(i, p)) {
            return Err(bad(format!(
                "{flag} {}: is the input {}; write the output elsewhere",
                p.display(),
                input.display()
            )));
        }
        if let Some((other, _, _)) = given[..k].iter().find(|(_, _, q)| same(q, p)) {
            return Err(bad(format!(
                "{flag} {}: is also the {other} output; give each output its own file",
                p.display()
            )));
        }
        // Not the input's fault: like a write that fails, exit 3.
        if let Some(d) = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty() && !d.is_dir())
        {
            return Err(anyhow::anyhow!(
                "{}: cannot write the {what}: the directory {} does not exist",
                p.display(),
                d.display()
            ));
        }
    }
    Ok(())
}

fn check(path: &Path) -> anyhow::Result<u8> {
    let scene = load_scene(path)?;
    say_raw!("{}", homospline_cli::summary(&scene));
    Ok(0)
}

/// The input of `graph`, read and checked against its options (`--resolution` is a
/// scene's): what `graph --out-dir` checks of every input before it builds any graph.
fn graph_input(
    path: &Path,
    (resolution, robot_radius): (Option<f64>, Option<f64>),
) -> anyhow::Result<Input> {
    if let Some(r) = robot_radius
        && !(r.is_finite() && r >= 0.0)
    {
        return Err(bad(format!(
            "--robot-radius {r}: must be a finite number >= 0"
        )));
    }
    let input = load_input(path)?;
    match input {
        Input::Map(_) if resolution.is_some() => Err(bad(format!(
            "{}: --resolution applies to scenes; a map's grid is its cells",
            path.display()
        ))),
        Input::Scene(mut scene) if robot_radius.is_some() => {
            scene.robot_radius = robot_radius.unwrap_or(0.0);
            scene
                .validate(&path.display().to_string())
                .map_err(|e| bad(format!("--robot-radius: {e}")))?;
            Ok(Input::Scene(scene))
        }
        input => Ok(input),
    }
}

fn graph(
    path: &Path,
    (resolution, robot_radius): (Option<f64>, Option<f64>),
    out: Option<PathBuf>,
    json: Option<PathBuf>,
    svg: Option<PathBuf>,
) -> anyhow::Result<u8> {
    check_outputs(
        &[path],
        &[
            ("--out", "graph", out.as_deref()),
            ("--json", "graph JSON", json.as_deref()),
            ("--svg", "picture", svg.as_deref()),
        ],
    )?;
    let input = graph_input(path, (resolution, robot_radius))?;
    let t = std::time::Instant::now();
    let (g, cells, res, name) = match &input {
        Input::Scene(scene) => {
            let res = resolution.unwrap_or_else(|| default_resolution(scene));
            let (grid, _, g) = homospline_voronoi::build(scene, res)
                .map_err(|e| bad(format!("{}: {e}", path.display())))?;
            (g, (grid.width(), grid.height()), res, scene.name.clone())
        }
        Input::Map(map) => {
            // The complete graph of the whole map, without start or goal: `plan MAP --graph`
            // attaches each query's start and goal to it.
            let prepared =
                homospline_maps::PreparedMap::for_robot(map, robot_radius.unwrap_or(0.0))
                    .map_err(|e| bad(format!("{}: {e}", path.display())))?;
            let res = prepared.grid.resolution();
            // Moved out, not cloned: a 4096 x 4096 map's graph is half a gigabyte.
            (
                prepared.graph.graph,
                (map.width, map.height),
                res,
                map.name.clone(),
            )
        }
    };
    say!(
        "graph of {}: {} x {} cells at {:.3} cells per unit, {} nodes, {} edges, {} cycles, {:.1} ms",
        name,
        cells.0,
        cells.1,
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
        let bg = match &input {
            Input::Scene(scene) => picture::Background::Scene(scene, CostConfig::default().alpha),
            Input::Map(map) => picture::Background::Map(map),
        };
        write(&p, "picture", picture::graph_svg(&bg, &g).as_bytes())?;
    }
    Ok(0)
}

/// `graph --out-dir`: every input's graph (or this shard's slice of them) saved as
/// `DIR/STEM.msgpack`.
fn graph_dir(
    inputs: &[PathBuf],
    grid: (Option<f64>, Option<f64>),
    dir: &Path,
    shard: Option<&str>,
    single: (Option<PathBuf>, Option<PathBuf>, Option<PathBuf>),
) -> anyhow::Result<u8> {
    if single.0.is_some() || single.1.is_some() || single.2.is_some() {
        return Err(bad(
            "--out-dir writes one file per input: drop --out, --json and --svg",
        ));
    }
    let shard = shard_of(shard)?;
    let mut files = Vec::new();
    for p in inputs {
        if p.is_dir() {
            files.extend(homospline_cli::bench::files_in(p, "map").map_err(bad)?);
        } else {
            files.push(p.clone());
        }
    }
    if files.is_empty() {
        return Err(bad(format!(
            "{}: no input to build a graph of (a directory gives its .map files)",
            inputs
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    // Every name is checked before anything is written: a clash found halfway left the
    // first inputs' graphs behind.
    let mut stems = std::collections::BTreeMap::new();
    for f in &files {
        let stem = f
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("graph")
            .to_owned();
        if let Some(first) = stems.insert(stem.clone(), f) {
            return Err(bad(format!(
                "{} and {} would both be saved as {stem}.msgpack",
                first.display(),
                f.display()
            )));
        }
    }
    // Every input of this shard is read, and dropped, before any graph is built: an
    // unreadable map found halfway left the first maps' graphs behind. Reading is a small
    // part of a graph's cost; a graph that cannot be built still stops the run where it is.
    for (i, f) in files.iter().enumerate() {
        if shard.takes(i) {
            graph_input(f, grid)?;
        }
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
    for (i, f) in files.iter().enumerate() {
        if !shard.takes(i) {
            continue;
        }
        let stem = f.file_stem().and_then(|s| s.to_str()).unwrap_or("graph");
        graph(
            f,
            grid,
            Some(dir.join(format!("{stem}.msgpack"))),
            None,
            None,
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
    /// Homotopy classes to optimise, 1 to 64 [default: 5] (--seed straight plans one).
    #[arg(long)]
    classes: Option<usize>,
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
    /// The robot's radius in map units (metres on a ROS map): plans keep it from every
    /// obstacle. On a scene it replaces the file's `robot_radius`.
    #[arg(long, value_name = "R")]
    robot_radius: Option<f64>,
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
    /// Rounds of the growth loop (the paper's iteration limit; default 3).
    #[arg(long)]
    rounds: Option<usize>,
    /// A passage found blocked: the disc at X,Y of radius R becomes an obstacle (on a map:
    /// its cells become occupied) and the plan goes around it (repeatable).
    #[arg(long = "block", value_name = "X,Y,R", allow_hyphen_values = true)]
    block: Vec<String>,
    /// Leave this class out, by its signature as printed (repeatable).
    #[arg(long = "avoid", value_name = "CLASS", allow_hyphen_values = true)]
    avoid: Vec<String>,
    /// Limited overlap: a class is taken only if at most this fraction of its graph path's
    /// length is shared with every class taken before it (k shortest paths with limited
    /// overlap); each class's overlap with the chosen one is in the JSON.
    #[arg(long, value_name = "F")]
    diverse: Option<f64>,
    /// Form of roughness (4): paper = integral |q''| dt (default), energy = integral
    /// |q''|^2 dt, authors = sqrt(integral |q''|^2 dt).
    #[arg(long, value_enum)]
    roughness: Option<RoughnessArg>,
    /// Where the optimiser looks for a curve's least clearance m(C) between its quadrature
    /// nodes (docs/method.md, *Dips between nodes*)
    #[arg(long, value_enum)]
    clearance_search: Option<ClearanceSearchArg>,
    /// Hard margin, map units: candidates less clear than this are rejected, and the chosen
    /// class must be certified at least this clear (default 0: only collisions).
    #[arg(long, value_name = "X", default_value_t = 0.0)]
    clearance_floor: f64,
    /// Let `dm` act only through the safety penalty D, as in the paper's cost alone. By
    /// default on scenes each class's curve first climbs to dm (0.9 of its graph path's
    /// clearance in a narrower passage) and keeps it while the cost falls (the dm rule; maps
    /// never apply it)
    #[arg(long)]
    soft_dm: bool,
    /// Successive halving of the classes (scenes): after every class's first round, a class
    /// whose cost exceeds RATIO times that of the best class keeping dm runs no further
    /// rounds (marked `pruned`); `off` runs every class to its end (default 1.5)
    #[arg(long, value_name = "RATIO|off")]
    prune: Option<String>,
    /// Rounds of polish for the chosen class (scenes, 0 to 10): after ranking, it runs up to
    /// N more rounds at its via-points, each from a fresh simplex and ending with an
    /// interior-point finish (L-BFGS on the cost with a barrier on the clearance; the
    /// table's `rounds` counts the rounds), kept only if the class stays collision-free,
    /// safe if it was, at the floor and no dearer. Default 0
    #[arg(long, value_name = "N", default_value_t = 0)]
    polish: usize,
    /// A work budget for the chosen class's interior-point finish (scenes): if the plan has
    /// spent fewer cost evaluations than N when its classes are ranked, the chosen class gets
    /// the finish (L-BFGS on the cost with a barrier on the clearance, from its curve at its
    /// via-points; half a round's budget, at most what is left of N), kept only as a polish
    /// round is. Evaluations, not time, so plans stay the same on any machine; `off` never
    /// (default 1500, which keeps the paper scenes' plans under 5 ms; `--polish` replaces it)
    #[arg(long, value_name = "N|off")]
    finish_within: Option<String>,
    /// Also give each collision-free class's optima (scenes): the lengths of the shortest
    /// paths that keep its certified clearance from every circle, in its class and of any
    /// class (exact, the bounds left out; no curve of that clearance is shorter), in the
    /// table and as `optimum_length` and `optimum_length_any_class` in the JSON
    #[arg(long)]
    optimum: bool,
    /// Write the plan result (formats.md) here.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write a picture of the plan here.
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
}

/// `--weight NAME=VALUE` options as names and numbers (the names are checked later, by
/// the cost).
fn parse_weights(weights: &[String]) -> anyhow::Result<Vec<(String, f64)>> {
    weights
        .iter()
        .map(|w| {
            let (name, value) = w
                .split_once('=')
                .ok_or_else(|| bad(format!("--weight {w}: expected NAME=VALUE")))?;
            let v: f64 = value
                .trim()
                .parse()
                .map_err(|_| bad(format!("--weight {w}: '{value}' is not a number")))?;
            Ok((name.trim().to_owned(), v))
        })
        .collect()
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
    homospline_maps::input::load(path, homospline_cli::read_regular).map_err(bad)
}

fn plan(a: PlanArgs) -> anyhow::Result<u8> {
    let inputs: Vec<&Path> = a
        .scene
        .iter()
        .chain(&a.graph)
        .map(PathBuf::as_path)
        .collect();
    check_outputs(
        &inputs,
        &[
            ("--json", "plan JSON", a.json.as_deref()),
            ("--svg", "picture", a.svg.as_deref()),
        ],
    )?;
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
    let mut blocks = Vec::new();
    for b in &a.block {
        let v: Vec<f64> = b
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad(format!("--block {b}: expected X,Y,R (three numbers)")))?;
        match v[..] {
            [x, y, r] if x.is_finite() && y.is_finite() && r.is_finite() && r > 0.0 => {
                blocks.push((Point::new(x, y), r))
            }
            _ => {
                return Err(bad(format!(
                    "--block {b}: expected X,Y,R with finite numbers and R > 0"
                )));
            }
        }
    }
    if let Some(f) = a.diverse
        && !(f.is_finite() && (0.0..=1.0).contains(&f))
    {
        return Err(bad(format!("--diverse {f}: must be a fraction in [0, 1]")));
    }
    let input = match input {
        Input::Scene(mut scene) => {
            if let Some(r) = a.robot_radius {
                scene.robot_radius = r;
            }
            if let Some(s) = start {
                scene.start = s;
            }
            if let Some(g) = goal {
                scene.goal = g;
            }
            for (i, (c, r)) in blocks.iter().enumerate() {
                scene.obstacles.push(homospline_geom::Obstacle {
                    name: format!("blocked-{i}"),
                    circles: vec![homospline_geom::Circle::new(c.x, c.y, *r)],
                });
            }
            scene
                .validate(&scene.name.clone())
                .map_err(|e| bad(format!("--start/--goal/--block/--robot-radius: {e}")))?;
            Input::Scene(scene)
        }
        Input::Map(mut map) => {
            if a.resolution.is_some() {
                return Err(bad(
                    "--resolution applies to scenes; a map's grid is its cells",
                ));
            }
            if !blocks.is_empty() && a.graph.is_some() {
                return Err(bad(
                    "--block changes the map: it cannot reuse a saved --graph",
                ));
            }
            for (c, r) in &blocks {
                map.block_disc(c, *r);
            }
            Input::Map(map)
        }
    };
    let weights = parse_weights(&a.weights)?;
    let options = PlanOptions {
        seed: match a.seed {
            SeedArg::Voronoi => "voronoi".into(),
            SeedArg::Straight => "straight".into(),
        },
        classes: a.classes,
        preset: a.preset.clone(),
        weights,
        optimizer: a.optimizer.map(|o| {
            match o {
                OptimizerArg::NelderMead => "nelder-mead",
                OptimizerArg::Lbfgs => "lbfgs",
            }
            .to_owned()
        }),
        roughness: a
            .roughness
            .map(|r| RoughnessForm::from(r).name().to_owned()),
        clearance_search: a
            .clearance_search
            .map(|c| ClearanceSearch::from(c).name().to_owned()),
        resolution: a.resolution,
        threads: a.threads,
        max_via: a.max_via,
        rounds: a.rounds,
        clearance_floor: a.clearance_floor,
        soft_dm: a.soft_dm,
        avoid: a.avoid.clone(),
        diverse: a.diverse,
        prune: a.prune.clone(),
        polish: a.polish,
        finish_within: a.finish_within.clone(),
        graph: a.graph.is_some(),
    };
    let scene_of = match &input {
        Input::Scene(s) => Some(s),
        Input::Map(_) => None,
    };
    if a.optimum && scene_of.is_none() {
        bail!(bad(
            "--optimum needs a scene of circles: a map's walls are cells".to_owned()
        ));
    }
    let cfg = plan_config(&options, scene_of).map_err(bad)?;
    let alpha = cfg.growth.cost.alpha;
    let (result, picture) = match &input {
        Input::Scene(scene) => {
            let saved = match &a.graph {
                Some(p) => Some(load_graph(p, scene, &cfg)?),
                None => None,
            };
            if cfg.seed == homospline_optim::Seed::Voronoi {
                let resolution = saved.as_ref().map_or_else(
                    || cfg.resolution.unwrap_or_else(|| default_resolution(scene)),
                    |g| g.resolution,
                );
                if let Some(n) = homospline_cli::unseen_obstacles(scene, resolution) {
                    let _ = writeln!(std::io::stderr().lock(), "{n}");
                }
            }
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
            let radius = a.robot_radius.unwrap_or(0.0);
            let prepared = match &a.graph {
                Some(p) => {
                    let bytes = homospline_cli::read_regular(p)
                        .map_err(|e| bad(format!("{}: cannot read: {e}", p.display())))?;
                    let g = VoronoiGraph::from_msgpack(&bytes)
                        .map_err(|e| bad(format!("{}: {e}", p.display())))?;
                    homospline_maps::PreparedMap::with_graph(map, g, radius)
                        .map_err(|e| bad(format!("{}: {e}", p.display())))?
                }
                None => homospline_maps::PreparedMap::for_robot(map, radius)
                    .map_err(|e| bad(e.to_string()))?,
            };
            let result = prepared.plan(s, g, &cfg).map_err(|e| bad(e.to_string()))?;
            let pic = a
                .svg
                .as_ref()
                .map(|_| picture::plan_svg(&picture::Background::Map(map), &result));
            (result, pic)
        }
    };
    say_raw!("{}", report::plan_table(&result));
    let optima = match scene_of {
        Some(scene) if a.optimum => report::optima(scene, &result),
        _ => Vec::new(),
    };
    if a.optimum {
        say_raw!("{}", report::optimum_table(&result, &optima));
    }
    if let Some(p) = &a.json {
        write(
            p,
            "plan JSON",
            report::plan_json_with(&result, &optima).as_bytes(),
        )?;
    }
    if let (Some(p), Some(pic)) = (&a.svg, picture) {
        write(p, "picture", pic.as_bytes())?;
        say!("picture: {}", p.display());
    }
    Ok(if result.best.is_some() {
        0
    } else {
        EXIT_NO_PLAN
    })
}

fn load_graph(p: &Path, scene: &Scene, cfg: &PlanConfig) -> anyhow::Result<VoronoiGraph> {
    let bytes = homospline_cli::read_regular(p)
        .map_err(|e| bad(format!("{}: cannot read: {e}", p.display())))?;
    let g = VoronoiGraph::from_msgpack(&bytes).map_err(|e| bad(format!("{}: {e}", p.display())))?;
    if let Some(why) = homospline_optim::graph_misfit(&g, scene, cfg) {
        bail!(bad(format!("{}: {why}", p.display())));
    }
    Ok(g)
}

/// This run's slice: `--shard K/N`, else a Slurm job array's, else the whole.
fn shard_of(opt: Option<&str>) -> anyhow::Result<homospline_maps::bench::Shard> {
    use homospline_maps::bench::Shard;
    match opt {
        Some(t) => Shard::parse(t).map_err(|e| bad(format!("--shard {e}"))),
        None => match Shard::from_slurm(|k| std::env::var(k).ok()) {
            Some(r) => r.map_err(|e| bad(format!("Slurm job array: {e}"))),
            None => Ok(Shard::ALL),
        },
    }
}

/// `bench-scen`: plans this run's shard of the scenarios and prints the summary.
fn bench_scen(a: BenchArgs) -> anyhow::Result<u8> {
    use homospline_cli::bench::{BenchJob, csv_text, run_files};
    use homospline_maps::bench;
    let inputs: Vec<&Path> = a.scen.iter().map(PathBuf::as_path).collect();
    check_outputs(&inputs, &[("--csv", "CSV", a.csv.as_deref())])?;
    let shard = shard_of(a.shard.as_deref())?;
    let job = BenchJob {
        files: a.scen.clone(),
        sample: a.sample,
        limit: a.limit,
        shard,
        classes: a.classes,
        time_limit: a.time_limit,
        weights: parse_weights(&a.weights)?,
        robot_radius: a.robot_radius.unwrap_or(0.0),
    };
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} scenarios {elapsed_precise} eta {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let (rows, info) = run_files(&job, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .map_err(bad)?;
    bar.finish_and_clear();
    say!(
        "{}: {} of {} scenarios picked{}{}{}, on {}; maps prepared once in {:.1} ms",
        info.files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", "),
        rows.len(),
        info.picked,
        if a.limit.is_some() || a.sample.is_some() {
            format!(" from {}", info.total)
        } else {
            String::new()
        },
        match (a.limit, a.sample) {
            (Some(_), _) => " (the first of each file: the shortest paths only)",
            (_, Some(_)) => " (sampled evenly over every bucket)",
            _ => "",
        },
        if shard.n > 1 {
            format!(", shard {}/{}", shard.k, shard.n)
        } else {
            String::new()
        },
        info.maps.join(", "),
        info.prepare_ms
    );
    say_raw!("{}", bench::summary(&rows));
    if let Some(p) = &a.csv {
        write(p, "CSV", csv_text(&rows).as_bytes())?;
    }
    Ok(0)
}

fn bench_merge(csvs: &[PathBuf], out: Option<&Path>) -> anyhow::Result<u8> {
    let inputs: Vec<&Path> = csvs.iter().map(PathBuf::as_path).collect();
    check_outputs(&inputs, &[("--out", "CSV", out)])?;
    let mut texts = Vec::new();
    for p in csvs {
        let name = p.display().to_string();
        let text = homospline_cli::read_regular_string(p)
            .map_err(|e| bad(format!("{name}: cannot read: {e}")))?;
        texts.push((name, text));
    }
    let rows = homospline_cli::bench::rows_of_named(&texts).map_err(bad)?;
    say!("{} scenarios from {} CSV files", rows.len(), csvs.len());
    say_raw!("{}", homospline_maps::bench::summary(&rows));
    if let Some(p) = out {
        write(p, "CSV", homospline_cli::bench::csv_text(&rows).as_bytes())?;
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
