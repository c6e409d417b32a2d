//! The command line's arguments: one struct per command, options under help headings
//! (Input, Classes, Cost, Output, Advanced), values parsed into the planner's own types.

use std::path::PathBuf;

use clap::Args;
use homospline_front::OrOff;
use homospline_front::report::ClassNames;
use homospline_mission::{MissionConfig, Policy};
use homospline_optim::{Optimizer, PlanConfig, Seed};
use homospline_spline::{Choice, ClearanceSearch, Preset, RoughnessForm};

/// The help heading of the options that say what is planned on.
const INPUT: &str = "Input";
/// ... which classes are optimised.
const CLASSES: &str = "Classes";
/// ... what a path costs.
const COST: &str = "Cost";
/// ... what is written.
const OUTPUT: &str = "Output";
/// ... how the optimiser works.
const ADVANCED: &str = "Advanced";
/// `simulate`: the scouts and how they are used.
const TEAM: &str = "Team";

/// An option whose values are a library type's [`Choice`]s: each value with its help and
/// aliases, read back to the type (no mirror enum here to keep in step).
fn choice<T: Choice + Send + Sync>() -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new(T::ALL.iter().map(|c| {
        PossibleValue::new(c.name())
            .help(c.help())
            .aliases(c.aliases().iter().copied())
    }))
    .map(|name| T::choose(&name).unwrap_or(T::ALL[0]))
}

/// The registered scout policies as `--policy`'s values, each with its summary.
fn policy_arg() -> impl clap::builder::TypedValueParser<Value = Policy> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new(
        Policy::all()
            .iter()
            .map(|p| PossibleValue::new(p.name()).help(p.summary())),
    )
    .map(|name| Policy::named(&name).unwrap_or_default())
}

/// `--prune RATIO|off`.
fn prune_arg(s: &str) -> Result<OrOff<f64>, String> {
    s.parse()
        .map_err(|_| "expected off or a ratio of at least 1".to_owned())
}

/// `--finish-within N|off`.
fn finish_arg(s: &str) -> Result<OrOff<usize>, String> {
    s.parse()
        .map_err(|_| "expected off or a number of evaluations".to_owned())
}

/// The options of `plan`.
#[derive(Args, Debug)]
pub struct PlanArgs {
    /// Scene file (YAML or JSON), MovingAI `.map` or ROS map YAML [default: the built-in
    /// example, the paper's Fig. 5].
    pub scene: Option<PathBuf>,
    /// Start `X,Y` in map coordinates (required for maps; overrides a scene's).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true, help_heading = INPUT)]
    pub start: Option<String>,
    /// Goal `X,Y` in map coordinates (required for maps; overrides a scene's).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true, help_heading = INPUT)]
    pub goal: Option<String>,
    /// The robot's radius in map units (metres on a ROS map); replaces a scene's.
    ///
    /// Plans keep it from every obstacle; a start or goal closer than it is refused.
    #[arg(long, allow_negative_numbers = true, value_name = "R", help_heading = INPUT)]
    pub robot_radius: Option<f64>,
    /// A passage found blocked: the disc X,Y,R becomes an obstacle (repeatable).
    ///
    /// On a map its cells become occupied; the plan goes around it.
    #[arg(long = "block", value_name = "X,Y,R", allow_hyphen_values = true, help_heading = INPUT)]
    pub block: Vec<String>,
    /// Reuse a graph saved by `homospline graph --out`.
    #[arg(long, value_name = "FILE.msgpack", help_heading = INPUT)]
    pub graph: Option<PathBuf>,
    /// Grid cells per unit for a scene's Voronoi graph [default: 256 along the longer side of its working area].
    #[arg(long, allow_negative_numbers = true, help_heading = INPUT)]
    pub resolution: Option<f64>,
    /// How the splines are seeded.
    #[arg(long, value_parser = choice::<Seed>(), default_value = "voronoi", help_heading = CLASSES)]
    pub seed: Seed,
    /// Homotopy classes to optimise, 1 to 64; --seed straight plans one [default: 5].
    #[arg(long, allow_negative_numbers = true, help_heading = CLASSES)]
    pub classes: Option<usize>,
    /// Leave this class out, by its id or signature as printed (repeatable).
    #[arg(long = "avoid", value_name = "CLASS", allow_hyphen_values = true, help_heading = CLASSES)]
    pub avoid: Vec<String>,
    /// Limited overlap: a class shares at most this fraction of its graph path's length.
    ///
    /// A class is taken only if at most this fraction of its graph path's length is shared
    /// with every class taken before it (k shortest paths with limited overlap); each
    /// class's overlap with the chosen one is in the JSON.
    #[arg(long, allow_negative_numbers = true, value_name = "F", help_heading = CLASSES)]
    pub diverse: Option<f64>,
    /// Successive halving of a scene's classes after their first round [default: 1.5].
    ///
    /// A class whose cost exceeds RATIO times that of the best class keeping dm runs no
    /// further rounds (marked `pruned`); `off` runs every class to its end.
    #[arg(long, allow_negative_numbers = true, value_name = "RATIO|off", value_parser = prune_arg, help_heading = CLASSES)]
    pub prune: Option<OrOff<f64>>,
    /// Cost preset.
    #[arg(long, value_parser = choice::<Preset>(), default_value = "paper-voronoi", help_heading = COST)]
    pub preset: Preset,
    /// Set a weight or parameter, e.g. --weight safety=2 --weight dm=4 (repeatable).
    #[arg(long = "weight", value_name = "NAME=VALUE", help_heading = COST)]
    pub weights: Vec<String>,
    /// Form of roughness (4) [default: paper].
    #[arg(long, value_parser = choice::<RoughnessForm>(), help_heading = COST)]
    pub roughness: Option<RoughnessForm>,
    /// Hard margin, map units: the chosen class must be certified at least this clear.
    ///
    /// Candidates less clear than this are rejected; 0 rejects only collisions.
    #[arg(long, allow_negative_numbers = true, value_name = "X", default_value_t = PlanConfig::default().clearance_floor, help_heading = COST)]
    pub clearance_floor: f64,
    /// Let dm act only through the safety penalty D, as in the paper's cost alone.
    ///
    /// By default on scenes each class's curve first climbs to dm (0.9 of its graph path's
    /// clearance in a narrower passage) and keeps it while the cost falls (the dm rule;
    /// maps never apply it).
    #[arg(long, help_heading = COST)]
    pub soft_dm: bool,
    /// Write the plan result (docs/formats.md) here.
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub json: Option<PathBuf>,
    /// Write a picture of the plan here.
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub svg: Option<PathBuf>,
    /// Write the picture as a PNG here, at twice the SVG's size (rendered by resvg).
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub png: Option<PathBuf>,
    /// Also give each collision-free class's optimal lengths (scenes).
    ///
    /// The lengths of the shortest paths that keep its certified clearance from every
    /// circle, in its class and of any class (exact, the bounds left out), in the table and
    /// as `optimum_length` and `optimum_length_any_class` in the JSON.
    #[arg(long, help_heading = OUTPUT)]
    pub optimum: bool,
    /// How the table and the picture name classes: `letter` (A, B, C... by rank) or `id`
    /// (the letter and the id `--avoid` takes). The JSON has both, and the signature.
    #[arg(long, value_parser = choice::<ClassNames>(), default_value = "letter", help_heading = OUTPUT)]
    pub class_names: ClassNames,
    /// Local optimiser [default: nelder-mead for scenes, lbfgs for maps].
    #[arg(long, value_parser = choice::<Optimizer>(), help_heading = ADVANCED)]
    pub optimizer: Option<Optimizer>,
    /// Worker threads (the result does not depend on it).
    #[arg(long, allow_negative_numbers = true, help_heading = ADVANCED)]
    pub threads: Option<usize>,
    /// Most via-points a spline may have [default: 10 for scenes, 32 for maps].
    #[arg(long, allow_negative_numbers = true, help_heading = ADVANCED)]
    pub max_via: Option<usize>,
    /// Rounds of the growth loop, the paper's iteration limit [default: 3].
    #[arg(long, allow_negative_numbers = true, help_heading = ADVANCED)]
    pub rounds: Option<usize>,
    /// Where m(C) is searched between quadrature nodes [default: worst-node].
    ///
    /// See docs/method.md, *Dips between nodes*.
    #[arg(long, value_parser = choice::<ClearanceSearch>(), help_heading = ADVANCED)]
    pub clearance_search: Option<ClearanceSearch>,
    /// Rounds of polish for a scene's chosen class, 0 to 10.
    ///
    /// After ranking, it runs up to N more rounds at its via-points, each from a fresh
    /// simplex and ending with an interior-point finish (L-BFGS with a barrier on the
    /// clearance), kept only if the class stays collision-free, safe if it was, at the
    /// floor and no dearer.
    #[arg(long, allow_negative_numbers = true, value_name = "N", default_value_t = PlanConfig::default().polish, help_heading = ADVANCED)]
    pub polish: usize,
    /// Work budget in evaluations for a scene's chosen-class finish [default: 1500].
    ///
    /// If the plan has spent fewer cost evaluations than N when its classes are ranked,
    /// the chosen class gets an interior-point finish (half a round's budget, at most what
    /// is left of N), kept only as a polish round is. Evaluations, not time, so plans stay
    /// the same on any machine; `off` never; `--polish` replaces it.
    #[arg(long, allow_negative_numbers = true, value_name = "N|off", value_parser = finish_arg, help_heading = ADVANCED)]
    pub finish_within: Option<OrOff<usize>>,
    /// Stop planning after this many milliseconds: no plan, exit 4.
    ///
    /// Counted from when planning starts (the input read and checked). The plan stops at
    /// its next growth round or class seed once the limit has passed; building the graph
    /// and preparing a map run to their end. A plan done within the limit is the plan
    /// without one.
    #[arg(long, allow_negative_numbers = true, value_name = "MS", help_heading = ADVANCED)]
    pub time_limit: Option<f64>,
}

/// The options of `graph`.
#[derive(Args, Debug)]
pub struct GraphArgs {
    /// Scene files, MovingAI `.map` files or ROS map YAMLs (several, or a directory of
    /// `.map` files, only with `--out-dir`).
    #[arg(required = true)]
    pub scene: Vec<PathBuf>,
    /// Grid cells per unit for a scene [default: 256 along the longer side of its working area].
    #[arg(long, allow_negative_numbers = true, help_heading = INPUT)]
    pub resolution: Option<f64>,
    /// The robot's radius in map units: the graph of the free space it can occupy.
    ///
    /// Metres on a ROS map. On a scene it replaces the file's `robot_radius`.
    #[arg(long, allow_negative_numbers = true, value_name = "R", help_heading = INPUT)]
    pub robot_radius: Option<f64>,
    /// Save the graph as MessagePack, to reuse with `plan --graph`.
    #[arg(long, value_name = "FILE.msgpack", help_heading = OUTPUT)]
    pub out: Option<PathBuf>,
    /// Save each input's graph here as `STEM.msgpack` (many maps, e.g. on a cluster).
    #[arg(long, value_name = "DIR", help_heading = OUTPUT)]
    pub out_dir: Option<PathBuf>,
    /// With `--out-dir`: build only slice K of N interleaved slices of the inputs.
    ///
    /// Default: from a Slurm job array's environment, as `bench-scen`.
    #[arg(long, value_name = "K/N", help_heading = INPUT)]
    pub shard: Option<String>,
    /// Write the graph as JSON (docs/formats.md).
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub json: Option<PathBuf>,
    /// Write a picture of the graph.
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub svg: Option<PathBuf>,
    /// Write the picture as a PNG here, at twice the SVG's size (rendered by resvg).
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub png: Option<PathBuf>,
}

/// The options of `simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    /// The world file (YAML or JSON): a prior scene or map, what it hides (obstacles or a true
    /// map), what it no longer has, and the team.
    pub world: PathBuf,
    /// Scouts to fly [default: every UAV of the world; more are added at the start].
    #[arg(long, allow_negative_numbers = true, help_heading = TEAM)]
    pub scouts: Option<usize>,
    /// How the scouts are used [default: the library's, `Policy::default()`].
    #[arg(long, value_parser = policy_arg(), help_heading = TEAM)]
    pub policy: Option<Policy>,
    /// Homotopy classes per plan, 1 to 64.
    #[arg(long, allow_negative_numbers = true, default_value_t = MissionConfig::default().plan.classes, help_heading = CLASSES)]
    pub classes: usize,
    /// Limited overlap between the classes (see `plan --diverse`).
    #[arg(long, allow_negative_numbers = true, value_name = "F", help_heading = CLASSES)]
    pub diverse: Option<f64>,
    /// Time step, seconds, 0.001 to 10.
    #[arg(long, allow_negative_numbers = true, default_value_t = MissionConfig::default().dt, help_heading = ADVANCED)]
    pub dt: f64,
    /// Hysteresis: relative cost margin a class must win by to replace a valid plan.
    #[arg(long, allow_negative_numbers = true, default_value_t = MissionConfig::default().switch_margin, help_heading = ADVANCED)]
    pub switch_margin: f64,
    /// Hysteresis: seconds between voluntary class switches.
    #[arg(long, allow_negative_numbers = true, default_value_t = MissionConfig::default().min_switch_interval, help_heading = ADVANCED)]
    pub min_switch_interval: f64,
    /// Blockage prior P, 0 to 10: a class costs 1 + P x (the share of its route no robot
    /// has seen) times its plan's cost when the UGV re-plans; 0 plans as if the unseen were
    /// clear.
    #[arg(long, allow_negative_numbers = true, value_name = "P", default_value_t = MissionConfig::default().blockage_prior, help_heading = TEAM)]
    pub blockage_prior: f64,
    /// Write the mission (timeline and every trajectory) as JSON.
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub json: Option<PathBuf>,
    /// Write an animated picture of the mission.
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub svg: Option<PathBuf>,
    /// Make the pictures a still of the mission at T seconds: tracks and plans up to then,
    /// the robots where they were, what had been found drawn as found.
    #[arg(long, allow_negative_numbers = true, value_name = "T", help_heading = OUTPUT)]
    pub svg_at: Option<f64>,
    /// Write a still of the mission as a PNG here, at twice the SVG's size (at `--svg-at`,
    /// else at the end of the mission).
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub png: Option<PathBuf>,
    /// How the events and the picture name classes: `letter` (A, B, C... in the order the
    /// mission first plans them) or `id` (the letter and the id `plan --avoid` takes).
    #[arg(long, value_parser = choice::<ClassNames>(), default_value = "letter", help_heading = OUTPUT)]
    pub class_names: ClassNames,
}

/// The options of `bench-scen`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// `.scen` files, or directories of them (their map sits beside each).
    #[arg(required = true)]
    pub scen: Vec<PathBuf>,
    /// Plan N scenarios of each file, spread evenly over the whole file (every bucket).
    #[arg(long, allow_negative_numbers = true, help_heading = INPUT)]
    pub sample: Option<usize>,
    /// Plan only the first N scenarios of each file (the shortest only: a `.scen` is sorted).
    #[arg(long, allow_negative_numbers = true, help_heading = INPUT)]
    pub limit: Option<usize>,
    /// Plan only slice K of N interleaved slices of the scenarios picked.
    ///
    /// Default: from a Slurm job array's SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_MIN and
    /// SLURM_ARRAY_TASK_COUNT when they are set. `bench-merge` combines the slices' CSVs.
    #[arg(long, value_name = "K/N", help_heading = INPUT)]
    pub shard: Option<String>,
    /// The robot's radius in map units: plans keep it from every obstacle.
    ///
    /// A scenario whose start or goal is closer to one is an error row that names its
    /// clearance.
    #[arg(long, allow_negative_numbers = true, value_name = "R", help_heading = INPUT)]
    pub robot_radius: Option<f64>,
    /// Homotopy classes per plan, 1 to 64.
    #[arg(long, allow_negative_numbers = true, default_value_t = PlanConfig::maps().classes, help_heading = CLASSES)]
    pub classes: usize,
    /// Set a weight or parameter over the map defaults, e.g. --weight dm=1 (repeatable).
    #[arg(long = "weight", value_name = "NAME=VALUE", help_heading = COST)]
    pub weights: Vec<String>,
    /// A plan still running after this many milliseconds is stopped and counts as a timeout.
    #[arg(long, allow_negative_numbers = true, value_name = "MS", help_heading = ADVANCED)]
    pub time_limit: Option<f64>,
    /// Write one line per scenario here.
    #[arg(long, value_name = "FILE", help_heading = OUTPUT)]
    pub csv: Option<PathBuf>,
}

/// The options of `serve`.
#[derive(Args, Debug)]
pub struct ServeArgs {
    /// The folder whose scenes, maps and worlds the page opens (nothing outside it).
    #[arg(default_value = ".")]
    pub dir: PathBuf,
    /// The address to listen on (only this machine by default).
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: String,
    /// The port (0: any free one, printed at the start).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// The server's memory limit in MB (its `ulimit -v`): a map or scene too large for it
    /// gets the command line's out-of-memory message instead of the allocator's abort.
    #[arg(long, allow_negative_numbers = true, value_name = "MB")]
    pub memory_limit: Option<u64>,
}
