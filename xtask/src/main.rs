//! Project automation.
//!
//! - `cargo xtask regress [--bless]` checks every fixture against its golden.
//! - `cargo xtask gen-scenes` rewrites `fixtures/random/` from a seeded generator.
//! - `cargo xtask gen-worlds` rewrites `fixtures/worlds/`: each paper-like scene with its best
//!   class blocked, for `homospline simulate`.
//! - `cargo xtask missions [--worlds N] [--show WORLD] [--policy NAME]... [--csv FILE]` runs
//!   every scout policy (or the named ones beside `none`) on N generated worlds (default 50)
//!   and prints the mission figures, and the share of single blockages that leave another
//!   class open with and without `--diverse`; `--csv` writes each policy's distance ratio
//!   world by world, to compare two revisions.
//! - `cargo xtask map-memory [N] [--plan]` prepares a seeded random N x N map (20 % occupied, default
//!   4096) in a release build of the benches' `map-memory` binary and prints the time and
//!   the peak resident memory (`VmHWM`), in all and per cell: issue 43's 1.5 GB and 5 s;
//!   `--plan` then times a corner-to-corner plan on it.
//! - `cargo xtask map-clearance [--sample N] [--robot-radius R] [--least-only] SCEN...` plans
//!   scenarios sampled over every bucket and prints the success rate at the robot radius and
//!   the chosen paths' clearance away from their ends ([`map_clearance`]).
//! - `cargo xtask bench-against REV [--runs N] [FILTER]` runs the plan bench of revision REV
//!   and of this checkout in turns (N rounds, default 3; criterion filter, default
//!   `nelder-mead$`) and prints each bench's milliseconds and their ratio: how to read a time
//!   target on a machine that is not the one it was set on ([`bench_against`]).
//!
//! Fixtures and their goldens:
//! - `fixtures/scenes/NAME.yaml` -> `fixtures/golden/check/NAME.txt`: the summary that
//!   `homospline check` prints.
//! - `fixtures/scenes/NAME.yaml` -> `fixtures/golden/plan/NAME.voronoi.txt` and
//!   `NAME.straight.txt`: the plan with each seed, one line per class (signature, length,
//!   clearance, every cost term, collision-free, in class, rounds), never timings.
//! - `fixtures/random/NAME.yaml` -> `fixtures/golden/plan/NAME.voronoi.txt`.
//! - `fixtures/maps/movingai/NAME.map` with its scenario file -> `fixtures/golden/maps/NAME.txt`:
//!   the plans of 4 scenarios spread evenly over the file, at the map defaults.
//! - `fixtures/invalid/NAME.*` -> `fixtures/invalid/NAME.expected`: the exact error line.
//!
//! Tolerances are the rounding of the printed numbers: lengths and clearances to 1e-3 map
//! units, cost terms to 6 significant digits. The planner is deterministic for a build (the
//! same on any thread count), so on one platform goldens match exactly; the rounding absorbs
//! last-bit differences of the maths library between platforms. A change of the optimiser or
//! the cost moves paths by far more than that and must show up as a reviewed golden change.
//!
//! A mismatch prints a line diff and exits 1; `--bless` rewrites the goldens (review the diff
//! with `git diff fixtures/` before committing).

mod bench_against;
mod map_clearance;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use homospline_geom::Scene;
use homospline_optim::{Plan, PlanConfig, Seed};
use homospline_testkit::random_fixture_scenes;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("gen-scenes") if args.len() == 1 => gen_scenes().map(|_| true),
        Some("gen-worlds") if args.len() == 1 => gen_worlds().map(|_| true),
        Some("missions") => {
            let usage = "usage: cargo xtask missions [--worlds N] [--show WORLD] [--policy NAME]... [--csv FILE]";
            let (mut worlds, mut show, mut only, mut csv) = (50, None, Vec::new(), None);
            let mut rest = args[1..].iter();
            while let Some(flag) = rest.next() {
                match (flag.as_str(), rest.next()) {
                    ("--worlds", Some(n)) => match n.parse::<usize>() {
                        Ok(n) if n > 0 => worlds = n,
                        _ => {
                            eprintln!(
                                "cargo xtask missions --worlds N: N must be a positive number, got {n}"
                            );
                            return ExitCode::from(2);
                        }
                    },
                    ("--show", Some(name)) => show = Some(name.clone()),
                    ("--csv", Some(path)) => csv = Some(PathBuf::from(path)),
                    ("--policy", Some(name)) => match homospline_mission::Policy::named(name) {
                        Some(p) => only.push(p),
                        None => {
                            let names: Vec<&str> = homospline_mission::Policy::all()
                                .iter()
                                .map(|p| p.name())
                                .collect();
                            eprintln!(
                                "cargo xtask missions --policy: no policy named {name:?}; the policies are {}",
                                names.join(", ")
                            );
                            return ExitCode::from(2);
                        }
                    },
                    _ => {
                        eprintln!("{usage}  (unexpected {flag:?})");
                        return ExitCode::from(2);
                    }
                }
            }
            missions(worlds, show.as_deref(), &only, csv.as_deref()).map(|_| true)
        }
        Some("bench-against") => {
            let usage = "usage: cargo xtask bench-against REV [--runs N] [FILTER]";
            let (mut runs, mut positional) = (3usize, Vec::new());
            let mut rest = args[1..].iter();
            while let Some(a) = rest.next() {
                match a.as_str() {
                    "--runs" => match rest.next().map(|n| n.parse::<usize>()) {
                        Some(Ok(n)) if n > 0 => runs = n,
                        _ => {
                            eprintln!("{usage}: --runs needs a positive number");
                            return ExitCode::from(2);
                        }
                    },
                    flag if flag.starts_with('-') => {
                        eprintln!("{usage}  (unknown option {flag:?})");
                        return ExitCode::from(2);
                    }
                    _ => positional.push(a.as_str()),
                }
            }
            let (rev, filter) = match positional.as_slice() {
                [rev] => (*rev, "nelder-mead$"),
                [rev, filter] => (*rev, *filter),
                [] => {
                    eprintln!("{usage}");
                    return ExitCode::from(2);
                }
                [_, _, extra, ..] => {
                    eprintln!("{usage}  (unexpected {extra:?})");
                    return ExitCode::from(2);
                }
            };
            bench_against::run(&root(), rev, runs, filter).map(|_| true)
        }
        Some("map-memory") => {
            let usage = "usage: cargo xtask map-memory [N] [--plan]";
            let mut n = 4096;
            let mut plan = false;
            for a in &args[1..] {
                match a.as_str() {
                    "--plan" => plan = true,
                    v => match v.parse::<usize>() {
                        Ok(v) if v >= 2 => n = v,
                        _ => {
                            eprintln!("{usage}  (N >= 2, got {v:?})");
                            return ExitCode::from(2);
                        }
                    },
                }
            }
            map_memory(n, plan)
        }
        Some("map-clearance") => map_clearance::parse(&args[1..])
            .and_then(|o| map_clearance::run(&o))
            .map(|_| true),
        Some("regress") => {
            let bless = match &args[1..] {
                [] => false,
                [flag] if flag == "--bless" => true,
                other => {
                    eprintln!("usage: cargo xtask regress [--bless]  (unexpected {other:?})");
                    return ExitCode::from(2);
                }
            };
            regress(bless)
        }
        _ => {
            eprintln!(
                "usage: cargo xtask regress [--bless] | gen-scenes | gen-worlds | missions [--worlds N] [--show WORLD] [--policy NAME]... [--csv FILE] | bench-against REV [--runs N] [FILTER] | map-memory [N] [--plan] | map-clearance [--sample N] [--robot-radius R] [--least-only] SCEN..."
            );
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!(
                "\nregress: mismatches above. If the change is intended, review it and run\n    cargo xtask regress --bless\nthen inspect `git diff fixtures/` before committing."
            );
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!(
                "{}: error: {e:#}",
                args.first().map_or("xtask", String::as_str)
            );
            ExitCode::from(2)
        }
    }
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn files(dir: &Path, keep: impl Fn(&Path) -> bool) -> Result<Vec<PathBuf>> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && keep(p))
        .collect();
    v.sort();
    Ok(v)
}

/// Compares `actual` with the golden at `golden`; prints a diff; rewrites when blessing.
fn compare(name: &str, golden: &Path, actual: &str, bless: bool) -> Result<bool> {
    let expected = std::fs::read_to_string(golden).unwrap_or_default();
    if expected == actual {
        return Ok(true);
    }
    if bless {
        if let Some(dir) = golden.parent() {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(golden, actual).with_context(|| format!("writing {}", golden.display()))?;
        println!("blessed {name}");
        return Ok(true);
    }
    println!("MISMATCH {name} ({})", golden.display());
    let (e, a): (Vec<&str>, Vec<&str>) = (expected.lines().collect(), actual.lines().collect());
    for i in 0..e.len().max(a.len()) {
        match (e.get(i), a.get(i)) {
            (Some(x), Some(y)) if x == y => {}
            (x, y) => {
                if let Some(x) = x {
                    println!("  -{:>4} {x}", i + 1);
                }
                if let Some(y) = y {
                    println!("  +{:>4} {y}", i + 1);
                }
            }
        }
    }
    Ok(false)
}

/// `map-memory N`: builds and runs the benches' `map-memory` binary in release mode (in its
/// own process, so that its peak resident memory is the preparation's alone); `plan`: then a
/// corner-to-corner plan on the prepared map, its stage times and the peak after it.
fn map_memory(n: usize, plan: bool) -> Result<bool> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let status = std::process::Command::new(cargo)
        .current_dir(root())
        .args([
            "run",
            "--release",
            "--quiet",
            "-p",
            "homospline-benches",
            "--bin",
            "map-memory",
            "--",
            &n.to_string(),
        ])
        .args(plan.then_some("--plan"))
        .status()
        .context("running the map-memory binary")?;
    Ok(status.success())
}

fn regress(bless: bool) -> Result<bool> {
    let root = root();
    let mut ok = true;
    let mut count = 0;
    let scenes = files(&root.join("fixtures/scenes"), |p| {
        p.extension().is_some_and(|e| e == "yaml" || e == "json")
    })?;
    for path in &scenes {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
        let bytes = std::fs::read(path)?;
        let scene = Scene::from_bytes(&bytes, &format!("fixtures/scenes/{stem}"))?;
        let golden = root
            .join("fixtures/golden/check")
            .join(format!("{stem}.txt"));
        ok &= compare(
            &format!("check {stem}"),
            &golden,
            &homospline_front::summary(&scene),
            bless,
        )?;
        count += 1;
    }
    let random = files(&root.join("fixtures/random"), |p| {
        p.extension().is_some_and(|e| e == "yaml")
    })?;
    let plan_cases: Vec<(&PathBuf, Seed)> = scenes
        .iter()
        .flat_map(|p| [(p, Seed::Voronoi), (p, Seed::Straight)])
        .chain(random.iter().map(|p| (p, Seed::Voronoi)))
        .collect();
    for (path, seed) in plan_cases {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
        let bytes = std::fs::read(path)?;
        let scene = Scene::from_bytes(&bytes, &path.display().to_string())?;
        let plan = homospline_optim::plan(
            &scene,
            &PlanConfig {
                seed,
                ..PlanConfig::default()
            },
        )
        .with_context(|| format!("planning {}", path.display()))?;
        let golden = root
            .join("fixtures/golden/plan")
            .join(format!("{stem}.{}.txt", seed.name()));
        ok &= compare(
            &format!("plan {stem} --seed {}", seed.name()),
            &golden,
            &plan_golden(&plan),
            bless,
        )?;
        count += 1;
    }
    let (map_ok, map_count) = regress_maps(&root, bless)?;
    ok &= map_ok;
    count += map_count;
    let invalid = files(&root.join("fixtures/invalid"), |p| {
        p.extension().is_none_or(|e| e != "expected")
    })?;
    for path in &invalid {
        let name = path.file_name().and_then(|s| s.to_str()).unwrap_or("?");
        let rel = format!("fixtures/invalid/{name}");
        let bytes = std::fs::read(path)?;
        let actual = match Scene::from_bytes(&bytes, &rel) {
            Ok(_) => bail!("{rel} was accepted: an invalid fixture must be rejected"),
            Err(e) => format!("{e}\n"),
        };
        ok &= compare(
            &format!("invalid {name}"),
            &path.with_extension("expected"),
            &actual,
            bless,
        )?;
        count += 1;
    }
    println!(
        "regress: {count} fixtures, {}",
        if ok { "all match" } else { "MISMATCHES" }
    );
    Ok(ok)
}

/// Scenarios planned per fixture map, spread evenly over its `.scen` file (first and last
/// included): every length the file covers, not only its short end.
const MAP_SCENARIOS: usize = 4;

/// The scenario file beside a fixture map: `NAME.map.scen` or `NAME-random-1.scen`.
fn scenarios_of(map: &Path) -> Option<PathBuf> {
    let name = map.file_name()?.to_str()?;
    let stem = map.file_stem()?.to_str()?;
    [format!("{name}.scen"), format!("{stem}-random-1.scen")]
        .into_iter()
        .map(|f| map.with_file_name(f))
        .find(|p| p.is_file())
}

/// Plans `MAP_SCENARIOS` scenarios of every fixture map with a scenario file, the map
/// prepared once, at the map defaults, against `fixtures/golden/maps/NAME.txt`.
fn regress_maps(root: &Path, bless: bool) -> Result<(bool, usize)> {
    let maps = files(&root.join("fixtures/maps/movingai"), |p| {
        p.extension().is_some_and(|e| e == "map")
    })?;
    let (mut ok, mut count) = (true, 0);
    for path in &maps {
        let Some(scen_path) = scenarios_of(path) else {
            continue;
        };
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("map");
        let text = std::fs::read_to_string(path)?;
        let map = homospline_maps::movingai::read_map(&text, &path.display().to_string())?;
        let scen_text = std::fs::read_to_string(&scen_path)?;
        let scen =
            homospline_maps::movingai::read_scen(&scen_text, &scen_path.display().to_string())?;
        let prepared = homospline_maps::PreparedMap::new(&map)?;
        let cfg = PlanConfig::maps();
        let mut actual = String::new();
        for k in 0..MAP_SCENARIOS.min(scen.len()) {
            let i = if MAP_SCENARIOS > 1 {
                k * (scen.len() - 1) / (MAP_SCENARIOS - 1)
            } else {
                0
            };
            let s = &scen[i];
            let plan = prepared
                .plan(s.start, s.goal, &cfg)
                .with_context(|| format!("planning scenario {i} of {}", scen_path.display()))?;
            actual += &format!(
                "scenario {i} bucket {} octile {:.3}\n{}",
                s.bucket,
                s.optimal_length,
                plan_golden(&plan)
            );
        }
        ok &= compare(
            &format!("maps {stem}"),
            &root
                .join("fixtures/golden/maps")
                .join(format!("{stem}.txt")),
            &actual,
            bless,
        )?;
        count += 1;
    }
    Ok((ok, count))
}

/// Six significant digits.
fn sig6(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = 5 - x.abs().log10().floor() as i32;
    if digits >= 0 {
        format!("{:.*}", digits as usize, x)
    } else {
        format!("{:.0}", x)
    }
}

/// What a plan golden records: classes, never timings.
fn plan_golden(plan: &Plan) -> String {
    let mut s = format!(
        "plan {} seed={} classes={} best={}\n",
        plan.scene,
        plan.seed.name(),
        plan.classes.len(),
        plan.best.map_or("none".to_owned(), |b| b.to_string())
    );
    for c in &plan.classes {
        // Every term of the cost by its name, in the order of the total (`TERMS`: a new
        // term joins the goldens without a change here).
        let terms: Vec<String> = homospline_spline::cost::TERMS
            .iter()
            .map(|term| format!("{}={}", term.name, sig6((term.value)(&c.cost))))
            .collect();
        s += &format!(
            "#{} {} length={:.3} clearance={:.3} free={} safe={} in_class={} rounds={} via={}{}\n   cost total={} {}\n",
            c.rank,
            c.signature,
            c.length,
            c.min_clearance,
            c.collision_free,
            c.safe,
            c.in_class,
            c.iterations,
            c.via_points.len().saturating_sub(2),
            if c.pruned { " pruned" } else { "" },
            sig6(c.cost.total),
            terms.join(" "),
        );
    }
    s
}

/// A random scene: `n` circles (grouped in compound obstacles of 1 to `group` circles) in a
/// `size x size` square, none within `keep` of the start or goal.
/// Writes `fixtures/random/`: 10 small scenes and 5 with hundreds of circles.
fn gen_scenes() -> Result<()> {
    let dir = root().join("fixtures/random");
    std::fs::create_dir_all(&dir)?;
    let scenes = random_fixture_scenes();
    for s in &scenes {
        s.validate(&s.name)
            .with_context(|| format!("generated scene {}", s.name))?;
        let text = format!(
            "# Generated by `cargo xtask gen-scenes` (seeded); do not edit by hand.\n{}",
            s.to_yaml()
        );
        std::fs::write(dir.join(format!("{}.yaml", s.name)), text)?;
    }
    println!("wrote {} scenes to {}", scenes.len(), dir.display());
    Ok(())
}

/// Writes `fixtures/worlds/`: each paper-like scene with its best class blocked in its
/// narrowest passage, two scouts.
fn gen_worlds() -> Result<()> {
    let dir = root().join("fixtures/worlds");
    std::fs::create_dir_all(&dir)?;
    let mut n = 0;
    for scene in homospline_testkit::fixture_scenes() {
        let Some(world) = homospline_testkit::blocked_world(&scene, 2, false) else {
            println!("{}: no blockable class, skipped", scene.name);
            continue;
        };
        let text = format!(
            "# Generated by `cargo xtask gen-worlds`: the scene's best class blocked in its narrowest\n# passage; do not edit by hand.\n{}",
            world.to_yaml(&format!("../scenes/{}.yaml", scene.name))
        );
        std::fs::write(dir.join(format!("{}.yaml", world.name)), text)?;
        n += 1;
    }
    println!("wrote {n} worlds to {}", dir.display());
    Ok(())
}

fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Every scout policy (or those of `only`, with `none` as the baseline) on `count` generated
/// worlds, and the limited-overlap measurement.
fn missions(
    count: usize,
    show: Option<&str>,
    only: &[homospline_mission::Policy],
    csv: Option<&Path>,
) -> Result<()> {
    let (worlds, seeds) = generated_worlds(count);
    let maps = homospline_testkit::map_worlds(count.div_ceil(4));
    println!(
        "{} scene worlds (seeds 0..{seeds}: hidden blockages in the best class, in the two best, late on the route, and pebbles that block nothing) and {} map worlds (doors blocked, dead ends, pebbles); 2 scouts; a world counts as worse than none when its distance / truth plan is more than 1 % above none's (or none reaches the goal and the policy does not)",
        worlds.len(),
        maps.len()
    );
    println!(
        "{:<13} {:>8} {:>9} {:>9} {:>9} {:>8} {:>9} {:>9} {:>16}",
        "policy",
        "reached",
        "dist/opt",
        "worst",
        "time/opt",
        "replans",
        "switches",
        "UAV dist",
        "worse than none"
    );
    let mut clearance = TrackClearance {
        least: f64::INFINITY,
        missions: 0,
    };
    let mut rows = Vec::new();
    for &policy in homospline_mission::Policy::all() {
        if !only.is_empty() && policy != homospline_mission::Policy::NONE && !only.contains(&policy)
        {
            continue;
        }
        let mut figures = policy_figures(&worlds, policy, &mut clearance, show)?;
        map_policy_figures(&maps, policy, &mut figures, &mut clearance, show)?;
        rows.push((policy, figures));
    }
    let none = rows
        .iter()
        .find(|(p, _)| *p == homospline_mission::Policy::NONE)
        .map(|(_, f)| f.per_world.clone())
        .unwrap_or_default();
    for (policy, f) in &rows {
        print_policy_row(*policy, f, &none);
    }
    if let Some(path) = csv {
        // One row per policy and world: its distance over the truth plan's (inf: goal not
        // reached; NaN: the truth plan has none), to compare two revisions world by world.
        let mut text = String::from("policy,world,distance_ratio\n");
        for (policy, f) in &rows {
            for (name, d) in f.names.iter().zip(&f.per_world) {
                text += &format!("{},{name},{d:.6}\n", policy.name());
            }
        }
        std::fs::write(path, text).with_context(|| format!("{}: cannot write", path.display()))?;
    }
    for (policy, f) in &rows {
        let worse = worse_than(f, &none);
        if !worse.is_empty() {
            let list: Vec<String> = worse
                .iter()
                .take(30)
                .map(|&(k, a, b)| format!("{} {a:.3} (none {b:.3})", f.names[k]))
                .collect();
            println!(
                "  {} worse than none: {}{}",
                policy.name(),
                list.join(", "),
                if worse.len() > 30 { ", ..." } else { "" }
            );
        }
    }
    println!(
        "UGV tracks: least clearance to the true obstacles, robot radius included, segment by segment: {:.4} over {} missions{}",
        clearance.least,
        clearance.missions,
        if clearance.least > 0.0 {
            ""
        } else {
            "  TRACK ENTERS AN OBSTACLE"
        }
    );
    // Limited overlap: single random blockages on the chosen path (policy-independent, so
    // left out of a run narrowed with --policy).
    if !only.is_empty() {
        return Ok(());
    }
    for diverse in [None, Some(0.8), Some(0.5)] {
        print_single_blockages(&worlds, diverse);
    }
    Ok(())
}

/// The first `count` worlds of the seeded generator (2 scouts each) within `20 * count`
/// seeds, and the end of the seeds tried.
fn generated_worlds(count: usize) -> (Vec<homospline_mission::MissionWorld>, u64) {
    let mut worlds = Vec::new();
    let mut seed = 0;
    while worlds.len() < count && seed < 20 * count as u64 {
        if let Some(w) = homospline_testkit::suite_world(seed, 2) {
            worlds.push(w);
        }
        seed += 1;
    }
    (worlds, seed)
}

/// The least clearance of any UGV track, segment by segment, to the true obstacles
/// (inflated by the robot radius: a track keeps the radius where it is positive), over the
/// missions run.
struct TrackClearance {
    least: f64,
    missions: usize,
}

/// One policy's figures over the generated worlds.
#[derive(Default)]
struct PolicyFigures {
    /// Worlds whose goal was reached, of those the truth plan reaches.
    reached: usize,
    solvable: usize,
    /// Distance and time over the truth plan's, where both exist.
    dist: Vec<f64>,
    time: Vec<f64>,
    replans: Vec<f64>,
    switches: Vec<f64>,
    uav: Vec<f64>,
    /// Per world (scene worlds, then map worlds): its name and distance over the truth
    /// plan's (infinite where the goal was not reached, NaN where the truth plan has none).
    names: Vec<String>,
    per_world: Vec<f64>,
}

impl PolicyFigures {
    /// Adds one mission's result.
    fn add(&mut self, r: &homospline_mission::MissionResult, speed: f64) {
        if r.truth_plan_length.is_some() {
            self.solvable += 1;
            self.reached += usize::from(r.reached);
        }
        if let (Some(d), Some(t)) = (r.distance_ratio(), r.time_ratio(speed)) {
            self.dist.push(d);
            self.time.push(t);
        }
        self.names.push(r.world.clone());
        self.per_world.push(match r.truth_plan_length {
            None => f64::NAN,
            Some(_) => r.distance_ratio().unwrap_or(f64::INFINITY),
        });
        self.replans.push(r.replans as f64);
        self.switches.push(r.switches as f64);
        self.uav.push(r.uav_distance);
    }
}

/// Runs `policy` on every scene world; each UGV track's clearance goes to `clearance`.
fn policy_figures(
    worlds: &[homospline_mission::MissionWorld],
    policy: homospline_mission::Policy,
    clearance: &mut TrackClearance,
    show: Option<&str>,
) -> Result<PolicyFigures> {
    use homospline_mission::{MissionConfig, simulate};
    use homospline_spline::{CircleModel, ClearanceModel};
    use rayon::prelude::*;
    let cfg = MissionConfig {
        policy,
        ..MissionConfig::default()
    };
    let mut f = PolicyFigures::default();
    // The missions in parallel (each is deterministic), read in the worlds' order.
    let results: Vec<_> = worlds.par_iter().map(|w| simulate(w, &cfg)).collect();
    for (w, r) in worlds.iter().zip(results) {
        let r = r?;
        print_events(&r, show);
        let track: Vec<homospline_geom::Point> = r.ugv.samples.iter().map(|s| s.1).collect();
        let truth = CircleModel::new(w.truth.circles());
        clearance.least = clearance.least.min(truth.polyline_clearance(&track));
        clearance.missions += 1;
        f.add(&r, w.team.ugv.speed);
    }
    Ok(f)
}

/// Runs `policy` on every map world into `f`; each UGV track's clearance to the true map's
/// occupied cells, less the robot's radius, goes to `clearance`.
fn map_policy_figures(
    worlds: &[homospline_mission::MapWorld],
    policy: homospline_mission::Policy,
    f: &mut PolicyFigures,
    clearance: &mut TrackClearance,
    show: Option<&str>,
) -> Result<()> {
    use homospline_mission::{MissionConfig, simulate_map};
    use rayon::prelude::*;
    let cfg = MissionConfig {
        policy,
        ..MissionConfig::for_maps()
    };
    let results: Vec<_> = worlds.par_iter().map(|w| simulate_map(w, &cfg)).collect();
    for (w, r) in worlds.iter().zip(results) {
        let r = r?;
        print_events(&r, show);
        let track: Vec<homospline_geom::Point> = r.ugv.samples.iter().map(|s| s.1).collect();
        clearance.least = clearance.least.min(
            homospline_testkit::track_clearance(
                &w.truth,
                &track,
                w.team.ugv.radius + 2.0 * w.truth.cell,
            ) - w.team.ugv.radius,
        );
        clearance.missions += 1;
        f.add(&r, w.team.ugv.speed);
    }
    Ok(())
}

/// With `--show WORLD`, the mission's events on that world, to standard error.
fn print_events(r: &homospline_mission::MissionResult, show: Option<&str>) {
    if show != Some(r.world.as_str()) {
        return;
    }
    eprintln!(
        "{} {}: drove {:.2}, truth plan {:.2}",
        r.world,
        r.policy,
        r.ugv_distance,
        r.truth_plan_length.unwrap_or(f64::NAN)
    );
    for e in &r.events {
        eprintln!(
            "  {:8.2} s  ({:.2}, {:.2})  {:?}",
            e.t, e.at.x, e.at.y, e.kind
        );
    }
}

/// The worlds where `f` drove more than 1 % farther over the truth plan than `none` (or
/// did not reach a goal `none` reached): `(index, ratio, none's ratio)`.
fn worse_than(f: &PolicyFigures, none: &[f64]) -> Vec<(usize, f64, f64)> {
    f.per_world
        .iter()
        .zip(none)
        .enumerate()
        .filter(|&(_, (&a, &b))| b.is_finite() && (a.is_nan() || a > 1.01 * b))
        .map(|(k, (&a, &b))| (k, a, b))
        .collect()
}

/// Prints `policy`'s row: means, the worst distance over the truth plan, and in how many
/// worlds it drove more than 1 % farther than `none`.
fn print_policy_row(policy: homospline_mission::Policy, f: &PolicyFigures, none: &[f64]) {
    let worse = if policy == homospline_mission::Policy::NONE {
        "-".to_owned()
    } else {
        format!("{}/{}", worse_than(f, none).len(), f.per_world.len())
    };
    // The three worst worlds, worst first (ties by name).
    let mut ranked: Vec<(f64, &str)> = f
        .per_world
        .iter()
        .zip(&f.names)
        .filter(|(r, _)| !r.is_nan())
        .map(|(&r, n)| (r, n.as_str()))
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(b.1)));
    let worst = ranked.first().map_or(0.0, |w| w.0);
    let worst_worlds: Vec<String> = ranked
        .iter()
        .take(3)
        .map(|(r, n)| format!("{n} {r:.3}"))
        .collect();
    let worst_worlds = worst_worlds.join(", ");
    println!(
        "{:<13} {:>8} {:>9.3} {:>9.3} {:>9.3} {:>8.2} {:>9.2} {:>9.1} {:>16}  worst: {worst_worlds}",
        policy.name(),
        format!("{}/{}", f.reached, f.solvable),
        mean(&f.dist),
        worst,
        mean(&f.time),
        mean(&f.replans),
        mean(&f.switches),
        mean(&f.uav),
        worse
    );
}

/// Prints how often a single random blockage on the chosen path (10 per world, at the same
/// places for every variant) leaves another collision-free class open, planning with
/// `diverse`.
fn print_single_blockages(worlds: &[homospline_mission::MissionWorld], diverse: Option<f64>) {
    use homospline_mission::MissionConfig;
    use homospline_optim::plan;
    use homospline_spline::{CircleModel, ClearanceModel};
    // The same blockage positions (as fractions of the chosen path) for every variant.
    let mut rng = homospline_testkit::SplitMix(42);
    let (mut open, mut trials, mut classes, mut plans) = (0, 0, 0, 0);
    for w in worlds {
        let cfg = PlanConfig {
            diverse,
            ..MissionConfig::default().plan
        };
        let Ok(p) = plan(&w.prior, &cfg) else {
            continue;
        };
        let Some(b) = p.best else { continue };
        let chosen = &p.classes[b - 1];
        plans += 1;
        classes += p.classes.iter().filter(|c| c.collision_free).count();
        let model = CircleModel::new(w.prior.circles());
        for _ in 0..10 {
            let i = 1 + (rng.next_unit() * (chosen.path.len() - 2) as f64) as usize;
            let at = chosen.path[i];
            let r = model.clearance(&at).0 + 0.5;
            let blocked = CircleModel::new(vec![homospline_geom::Circle::new(at.x, at.y, r)]);
            trials += 1;
            let other_open = p.classes.iter().any(|c| {
                c.rank != chosen.rank
                    && c.collision_free
                    && blocked.polyline_clearance(&c.path) > 0.0
            });
            open += usize::from(other_open);
        }
    }
    println!(
        "single blockage on the chosen path, {}: another class open in {open}/{trials} ({:.1} %), {:.2} collision-free classes per plan",
        match diverse {
            None => "k best classes".to_owned(),
            Some(f) => format!("--diverse {f}"),
        },
        100.0 * open as f64 / trials.max(1) as f64,
        classes as f64 / plans.max(1) as f64
    );
}
