//! `homospline`, the command line: parses the arguments and hands each command to its module;
//! an error's exit code says whose fault it is (2: the input, 3: the run).

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[macro_use]
mod out;
mod args;
mod bench_scen;
mod graph;
mod input;
mod mission_svg;
mod picture;
mod plan;
mod png;
mod serve;
mod simulate;

use args::{BenchArgs, GraphArgs, PlanArgs, ServeArgs, SimulateArgs};
use out::BadInput;

/// Exit code for bad input or usage.
const EXIT_BAD_INPUT: u8 = 2;

/// Exit code of no plan: no route for the robot (`plan`).
const EXIT_NO_PLAN: u8 = 1;

/// Exit code of a run that failed for another reason (an output that cannot be written).
const EXIT_FAILURE: u8 = 3;

/// Exit code of no plan because `plan --time-limit` passed first.
const EXIT_TIME_LIMIT: u8 = 4;

/// Homotopy-seeded spline path planning for ground robots.
#[derive(Parser, Debug)]
#[command(name = "homospline", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Plan paths: a table of classes and the chosen one; exit 0 with a collision-free plan,
    /// 1 when no collision-free class meets the clearance floor or no route exists, 2 on bad
    /// input, 3 on another failure (an output that cannot be written, too little memory), 4
    /// when --time-limit passes first.
    Plan(Box<PlanArgs>),
    /// Plan every scenario of a MovingAI `.scen` file (its map sits beside it) and report the
    /// success rate, time per plan and path length over the scenario's octile optimum.
    BenchScen(BenchArgs),
    /// Build the Voronoi graph of a scene (start and goal attached) or of a whole map (the
    /// complete graph, for `plan MAP --graph`) and save it.
    Graph(GraphArgs),
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
    /// A local web page to plan on: open a scene, a map or a world of DIR, click the start
    /// and the goal, block passages and watch the re-plan, play a mission. Serves until
    /// Ctrl-C.
    Serve(ServeArgs),
    /// Validate an input and summarise it: a scene (YAML or JSON), a map (MovingAI `.map`
    /// or ROS map YAML) or a world file, read as `plan` and `simulate` read them.
    Check {
        /// The file.
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
    out::remove_temporaries_on_signals();
    let result = check_thread_env().and_then(|()| match cli.command {
        Command::Check { scene } => check(&scene),
        Command::Graph(args) => graph::run(args),
        Command::Plan(args) => plan::plan(*args),
        Command::BenchScen(args) => bench_scen::bench_scen(args),
        Command::Simulate(args) => simulate::simulate(args),
        Command::Serve(args) => serve::serve(&args.dir, &args.bind, args.port, args.memory_limit),
        Command::BenchMerge { csv, out } => bench_scen::bench_merge(&csv, out.as_deref()),
    });
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            // A failed write to stderr (full, closed) must not panic: the exit code says it.
            let _ = writeln!(std::io::stderr().lock(), "error: {e:#}");
            // The user's input is to blame (2); anything else, such as an output that cannot
            // be written, is the run's failure (3).
            ExitCode::from(if e.downcast_ref::<out::NoPlan>().is_some() {
                EXIT_NO_PLAN
            } else if e.downcast_ref::<out::TimedOut>().is_some() {
                EXIT_TIME_LIMIT
            } else if e.downcast_ref::<BadInput>().is_some() {
                EXIT_BAD_INPUT
            } else {
                EXIT_FAILURE
            })
        }
    }
}

/// Refuses a `RAYON_NUM_THREADS` (rayon's default thread count) above the `--threads`
/// limit: 5,000 threads ran a plan of milliseconds past a minute on two cores. A value
/// that is no number, or 0, is rayon's to ignore.
fn check_thread_env() -> anyhow::Result<()> {
    let max = homospline_optim::planner::MAX_THREADS;
    match std::env::var("RAYON_NUM_THREADS").map(|v| v.parse::<u64>()) {
        Ok(Ok(n)) if n > max as u64 => Err(out::bad(format!(
            "the environment's RAYON_NUM_THREADS={n}: at most {max} threads (as --threads)"
        ))),
        _ => Ok(()),
    }
}

/// `check`: the summary of a scene, a map (MovingAI or ROS) or a world file, each read as
/// `plan` and `simulate` read them.
fn check(path: &std::path::Path) -> anyhow::Result<u8> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let not_taken = match ext.as_deref() {
        Some("scen") => Some("a MovingAI scenario file (`bench-scen` plans its scenarios)"),
        Some("pgm" | "png") => Some("an image (a ROS map is checked through its YAML)"),
        _ => None,
    };
    if let Some(what) = not_taken {
        return Err(out::bad(format!(
            "{}: {what}; check takes a scene, a map (.map or ROS map YAML) or a world file",
            path.display()
        )));
    }
    let reads = input::Reads::default();
    let bytes = reads
        .read(path)
        .map_err(|e| out::bad(format!("{}: cannot read: {e}", path.display())))?;
    let world = std::str::from_utf8(&bytes).is_ok_and(homospline_front::check::is_world);
    let summary = if world {
        let w = homospline_mission::world::load_any(path, |p| reads.read(p)).map_err(out::bad)?;
        homospline_front::check::world_fits(&w)
            .map_err(|e| out::bad(format!("{}: {e}", path.display())))?;
        homospline_front::check::world_summary(&w)
    } else {
        match input::load_input(path, &reads)? {
            homospline_maps::input::Input::Scene(scene) => homospline_front::summary(&scene),
            homospline_maps::input::Input::Map(map) => homospline_front::check::map_summary(&map),
        }
    };
    say_raw!("{summary}");
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
