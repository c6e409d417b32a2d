//! `homospline plan`: read the input, apply the command line's changes to it (start, goal,
//! blocks, radius), check the options once, plan, print the table and write the outputs.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::bail;
use homospline_front::{EXAMPLE_SCENE, PlanOptions, report};
use homospline_geom::math::Num;
use homospline_geom::{Circle, Obstacle, Point, Scene};
use homospline_maps::input::Input;
use homospline_maps::{MapError, OccupancyMap, PreparedMap};
use homospline_optim::{Plan, PlanConfig, PlanError, Seed, default_resolution, plan_with_graph};
use homospline_voronoi::VoronoiGraph;

use crate::args::PlanArgs;
use crate::input::{Reads, load_input, parse_point, parse_weights, read_graph};
use crate::out::{NoPlan, TimedOut, bad, check_outputs, map_error, no_plan, write};
use crate::picture;

/// Exit code when no plan could be found.
const EXIT_NO_PLAN: u8 = 1;

/// `plan`: exit 0 with a collision-free plan, 1 without one.
pub fn plan(a: PlanArgs) -> anyhow::Result<u8> {
    let reads = Reads::default();
    let (input, ends) = edited_input(&a, &reads)?;
    // The input, the files it names (a ROS map's image) and the graph: none is overwritten.
    let inputs = reads.paths();
    check_outputs(
        &inputs
            .iter()
            .chain(&a.graph)
            .map(PathBuf::as_path)
            .collect::<Vec<_>>(),
        &[
            ("--json", "plan JSON", a.json.as_deref()),
            ("--svg", "picture", a.svg.as_deref()),
            ("--png", "PNG picture", a.png.as_deref()),
        ],
    )?;
    let wants_picture = a.svg.is_some() || a.png.is_some();
    let name = input_name(&input).to_owned();
    let done = match outcome(&a, input, ends, wants_picture) {
        // No route is an answer: the JSON says so (best null, the reason), so that no older
        // file's plan stands in its place.
        Err(e) if e.downcast_ref::<NoPlan>().is_some() => {
            if let Some(p) = &a.json {
                let seed = a.seed.name();
                write(
                    p,
                    "plan JSON",
                    report::no_route_json(&name, seed, &e.to_string()).as_bytes(),
                )?;
            }
            return Err(e);
        }
        other => other?,
    };
    let scene = match &done.input {
        Input::Scene(s) => Some(s),
        Input::Map(_) => None,
    };
    for n in homospline_front::avoid_notes(&a.avoid, &done.result) {
        let _ = writeln!(std::io::stderr().lock(), "{n}");
    }
    report_plan(&a, scene, &done.result, done.picture)?;
    Ok(if done.result.best.is_some() {
        0
    } else {
        EXIT_NO_PLAN
    })
}

/// What `plan` computes before it prints or writes anything; `homospline serve` answers
/// with it.
pub struct Outcome {
    /// The input as planned (start, goal, blocks and radius applied).
    pub input: Input,
    /// The plan.
    pub result: Plan,
    /// Its picture, when asked for.
    pub picture: Option<String>,
}

/// Checks the options against the edited input (from [`edited_input`]) and plans.
pub fn outcome(
    a: &PlanArgs,
    input: Input,
    ends: Option<(Point, Point)>,
    wants_picture: bool,
) -> anyhow::Result<Outcome> {
    let scene = match &input {
        Input::Scene(s) => Some(s),
        Input::Map(_) => None,
    };
    if a.optimum && scene.is_none() {
        bail!(bad(
            "--optimum needs a scene of circles: a map's walls are cells"
        ));
    }
    let cfg = options(a)?
        .validate(scene)
        .map_err(|e| bad(format!("{}: {e}", input_name(&input))))?;
    let deadline = time_limit(a)?.map(|after| cfg.interrupt.raise_after(after));
    let planned = match &input {
        Input::Scene(scene) => plan_scene(a, scene, &cfg, wants_picture),
        Input::Map(map) => plan_map(a, map, ends, &cfg, wants_picture),
    };
    drop(deadline);
    let (result, picture) = planned?;
    Ok(Outcome {
        input,
        result,
        picture,
    })
}

/// `--time-limit MS` as a duration (a limit past what one holds is none); refused unless
/// a positive number.
fn time_limit(a: &PlanArgs) -> anyhow::Result<Option<std::time::Duration>> {
    let Some(ms) = a.time_limit else {
        return Ok(None);
    };
    if !(ms.is_finite() && ms > 0.0) {
        bail!(bad(format!(
            "--time-limit {}: must be a positive number of ms",
            Num(ms)
        )));
    }
    Ok(std::time::Duration::try_from_secs_f64(ms / 1e3).ok())
}

/// A setting that the input refuses at plan time (an avoided class of rays it has not),
/// on `name`, spelled as its option (`--avoid 'abc': ...`).
fn refused_setting(name: &str, c: homospline_optim::planner::ConfigError) -> String {
    format!(
        "{name}: {}",
        homospline_front::OptionError::from(c).spelled(homospline_front::Spelling::Flag)
    )
}

/// The error of a plan that `--time-limit` stopped (exit 4), naming `name`.
fn timed_out(a: &PlanArgs, name: &str) -> anyhow::Error {
    TimedOut(format!(
        "{name}: no plan within --time-limit {} ms (the plan stopped there; a larger limit, \
         fewer --classes or fewer --rounds let it finish)",
        Num(a.time_limit.unwrap_or(f64::NAN))
    ))
    .into()
}

/// The input's name, as its errors start.
fn input_name(input: &Input) -> &str {
    match input {
        Input::Scene(s) => &s.name,
        Input::Map(m) => &m.name,
    }
}

/// The options as the planner takes them.
fn options(a: &PlanArgs) -> anyhow::Result<PlanOptions> {
    Ok(PlanOptions {
        seed: a.seed,
        classes: a.classes,
        preset: a.preset,
        weights: parse_weights(&a.weights)?,
        optimizer: a.optimizer,
        roughness: a.roughness,
        clearance_search: a.clearance_search,
        resolution: a.resolution,
        threads: a.threads,
        max_via: a.max_via,
        rounds: a.rounds,
        clearance_floor: a.clearance_floor,
        soft_dm: a.soft_dm,
        avoid: a.avoid.clone(),
        diverse: a.diverse,
        prune: a.prune,
        polish: a.polish,
        finish_within: a.finish_within,
        graph: a.graph.is_some(),
    })
}

/// `--block X,Y,R` options as discs.
fn blocks(a: &PlanArgs) -> anyhow::Result<Vec<(Point, f64)>> {
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
    Ok(blocks)
}

/// The input (the built-in example without one) with the command line's start, goal,
/// radius and blocked discs applied (a scene is checked again after them); a map's start
/// and goal, which it needs.
pub fn edited_input(
    a: &PlanArgs,
    reads: &Reads,
) -> anyhow::Result<(Input, Option<(Point, Point)>)> {
    let input = match &a.scene {
        Some(p) => load_input(p, reads)?,
        None => Input::Scene(
            Scene::from_str(EXAMPLE_SCENE, "narrow-pass.yaml (built-in example)")
                .map_err(|e| bad(e.to_string()))?,
        ),
    };
    edit_input(a, input)
}

/// `input` with the command line's start, goal, radius and blocked discs applied (see
/// [`edited_input`]).
pub fn edit_input(a: &PlanArgs, input: Input) -> anyhow::Result<(Input, Option<(Point, Point)>)> {
    let point = |opt, t: &Option<String>| t.as_deref().map(|t| parse_point(opt, t)).transpose();
    let (start, goal) = (point("--start", &a.start)?, point("--goal", &a.goal)?);
    let blocks = blocks(a)?;
    let mut ends = None;
    let input = match input {
        Input::Scene(mut scene) => {
            let listed = scene.obstacles.len();
            if let Some(r) = a.robot_radius {
                scene.robot_radius = r;
            }
            scene.start = start.unwrap_or(scene.start);
            scene.goal = goal.unwrap_or(scene.goal);
            for (i, (c, r)) in blocks.iter().enumerate() {
                scene.obstacles.push(Obstacle {
                    name: format!("blocked-{i}"),
                    circles: vec![Circle::new(c.x, c.y, *r)],
                });
            }
            scene
                .validate(&scene.name.clone())
                .map_err(|e| bad(blame_option(a, &scene, listed, &e)))?;
            Input::Scene(scene)
        }
        Input::Map(mut map) => {
            let (Some(s), Some(g)) = (start, goal) else {
                bail!(bad(format!(
                    "{}: a map needs --start X,Y and --goal X,Y",
                    map.name
                )));
            };
            if !blocks.is_empty() && a.graph.is_some() {
                bail!(bad(
                    "--block changes the map: it cannot reuse a saved --graph"
                ));
            }
            // A block that fills the cell of the start or the goal is named, as on scenes:
            // the map's own check would call that cell occupied.
            for ((c, r), text) in blocks.iter().zip(&a.block) {
                let before = [s, g].map(|p| map.free_at(&p));
                map.block_disc(c, *r);
                for ((p, what), was) in [(s, "start"), (g, "goal")].into_iter().zip(before) {
                    if was == Some(true) && map.free_at(&p) == Some(false) {
                        bail!(bad(format!(
                            "--block {text}: {}: the {what} [{}, {}] is inside the blocked disc",
                            map.name,
                            Num(p.x),
                            Num(p.y)
                        )));
                    }
                }
            }
            ends = Some((s, g));
            Input::Map(map)
        }
    };
    Ok((input, ends))
}

/// The message of a scene that the command line's changes made invalid (`e`, from the
/// scene with `listed` obstacles of its own), blamed on the option at fault: `--block X,Y,R`
/// for a blocked disc's field or one that covers an end, `--start`, `--goal` or
/// `--robot-radius` for theirs.
fn blame_option(
    a: &PlanArgs,
    scene: &Scene,
    listed: usize,
    e: &homospline_geom::SceneError,
) -> String {
    let field = e.field.as_deref().unwrap_or("");
    // The blocked discs are the obstacles after the scene's own: a disc's own field (its
    // radius), or an end inside the obstacle the message names.
    let own = field
        .strip_prefix("obstacles[")
        .and_then(|r| r.split(']').next())
        .and_then(|k| k.parse::<usize>().ok());
    let covers = || {
        let name = e
            .problem
            .split(" inside obstacle '")
            .nth(1)?
            .split('\'')
            .next()?;
        scene.obstacles.iter().rposition(|o| o.name == name)
    };
    let block = |k: Option<usize>| {
        k.and_then(|k| k.checked_sub(listed))
            .and_then(|k| a.block.get(k))
    };
    match (block(own), block(covers())) {
        (Some(b), _) => return format!("--block {b}: {}: {}", e.source_name, e.problem),
        (None, Some(b)) => return format!("--block {b}: {}: {}", e.source_name, with_field(e)),
        (None, None) => {}
    }
    // An end that the radius put inside an obstacle: outside every circle, inside one
    // grown by the radius.
    let end = match field {
        "start" => Some(scene.start),
        "goal" => Some(scene.goal),
        _ => None,
    };
    let bare = |p: Point| {
        scene
            .obstacles
            .iter()
            .flat_map(|o| &o.circles)
            .all(|c| (p - c.center).norm() > c.radius)
    };
    if let (Some(r), Some(p)) = (a.robot_radius, end)
        && e.problem.contains("after inflating by robot_radius")
        && bare(p)
    {
        return format!(
            "--robot-radius {}: {}: {}",
            Num(r),
            e.source_name,
            with_field(e)
        );
    }
    let given = match field {
        "start" => a.start.as_ref().map(|v| ("--start", v.clone())),
        "goal" => a.goal.as_ref().map(|v| ("--goal", v.clone())),
        "robot_radius" => a
            .robot_radius
            .map(|r| ("--robot-radius", Num(r).to_string())),
        _ => None,
    };
    match given {
        Some((opt, v)) => format!("{opt} {v}: {}: {}", e.source_name, e.problem),
        // The scene's own field, made invalid by another change (a radius that swallows
        // its start): the options together, and the field.
        None => format!("--start/--goal/--block/--robot-radius: {e}"),
    }
}

/// `field: problem` of `e`, or the problem alone.
fn with_field(e: &homospline_geom::SceneError) -> String {
    match &e.field {
        Some(f) => format!("{f}: {}", e.problem),
        None => e.problem.clone(),
    }
}

/// A plan on a scene, and its picture when one is asked for.
fn plan_scene(
    a: &PlanArgs,
    scene: &Scene,
    cfg: &PlanConfig,
    wants_picture: bool,
) -> anyhow::Result<(Plan, Option<String>)> {
    let saved = match &a.graph {
        Some(p) => Some(scene_graph(p, scene, cfg)?),
        None => None,
    };
    let resolution = saved.as_ref().map_or_else(
        || cfg.resolution.unwrap_or_else(|| default_resolution(scene)),
        |g| g.resolution,
    );
    homospline_front::memory::check(
        || format!("scene {} at --resolution {resolution}", scene.name),
        homospline_front::memory::scene_cells(scene, resolution),
    )?;
    let result = plan_with_graph(scene, saved, cfg).map_err(|e| {
        let msg = match &e {
            // A setting the scene refuses (an avoided class of rays it has not), as the
            // option spells it.
            PlanError::Config(c) => refused_setting(&scene.name, c.clone()),
            e => format!("{}: {e}", scene.name),
        };
        if matches!(e, PlanError::Interrupted) {
            timed_out(a, &scene.name)
        } else if e.is_no_route() {
            no_plan(msg)
        } else {
            bad(msg)
        }
    })?;
    // Said once the grid is built: a grid refused (too coarse, too fine) is the message.
    if cfg.seed == Seed::Voronoi
        && let Some(n) = homospline_front::unseen_obstacles(scene, resolution)
    {
        let _ = writeln!(std::io::stderr().lock(), "{n}");
    }
    if let Some(n) = homospline_front::clutter_note(scene, &result) {
        let _ = writeln!(std::io::stderr().lock(), "{n}");
    }
    let alpha = cfg.growth.cost.alpha;
    let pic = wants_picture.then(|| {
        picture::plan_svg(
            &picture::Background::Scene(scene, alpha),
            &result,
            a.class_names,
        )
    });
    Ok((result, pic))
}

/// A saved graph for `scene`, refused when it is another scene's or another grid's.
fn scene_graph(p: &Path, scene: &Scene, cfg: &PlanConfig) -> anyhow::Result<VoronoiGraph> {
    let g = read_graph(p)?;
    if let Some(why) = homospline_optim::graph_misfit(&g, scene, cfg) {
        bail!(bad(format!("{}: {why}", p.display())));
    }
    Ok(g)
}

/// A plan on a map (its start and goal given), and its picture when one is asked for.
fn plan_map(
    a: &PlanArgs,
    map: &OccupancyMap,
    ends: Option<(Point, Point)>,
    cfg: &PlanConfig,
    wants_picture: bool,
) -> anyhow::Result<(Plan, Option<String>)> {
    let Some((s, g)) = ends else {
        bail!(bad(format!(
            "{}: a map needs --start X,Y and --goal X,Y",
            map.name
        )));
    };
    let radius = a.robot_radius.unwrap_or(0.0);
    // A start or goal closer than the radius is bad input, whatever the map's free space.
    map.check_endpoints_for(&s, &g, radius)
        .map_err(|e| bad(e.to_string()))?;
    check_map_memory(map, radius)?;
    let prepared = match &a.graph {
        Some(p) => PreparedMap::with_graph(map, read_graph(p)?, radius)
            .map_err(|e| bad(format!("{}: {e}", p.display())))?,
        None => PreparedMap::for_robot(map, radius).map_err(map_error)?,
    };
    let mut result = prepared.plan(s, g, cfg).map_err(|e| match e {
        MapError::Plan(PlanError::Interrupted) => timed_out(a, &map.name),
        MapError::Plan(PlanError::Config(c)) => bad(refused_setting(&map.name, c)),
        e => map_error(e),
    })?;
    // A map's plan does not copy the query's graph out of the map's; the picture draws it.
    if wants_picture {
        result.graph = prepared.query_graph(s, g).ok();
    }
    let pic = wants_picture
        .then(|| picture::plan_svg(&picture::Background::Map(map), &result, a.class_names));
    Ok((result, pic))
}

/// Refuses `map` when preparing it for a robot of `radius` may need more memory than the
/// process may use (exit 3, the run's failure, not the input's).
pub(crate) fn check_map_memory(map: &OccupancyMap, radius: f64) -> anyhow::Result<()> {
    Ok(homospline_front::memory::check_map(&map.name, map, radius)?)
}

/// Prints the table (and the optima, when asked for) and writes the outputs.
fn report_plan(
    a: &PlanArgs,
    scene: Option<&Scene>,
    result: &Plan,
    picture: Option<String>,
) -> anyhow::Result<()> {
    say_raw!("{}", report::plan_table(result, a.class_names));
    let optima = match scene {
        Some(scene) if a.optimum => report::optima(scene, result),
        _ => Vec::new(),
    };
    if a.optimum {
        say_raw!("{}", report::optimum_table(result, &optima, a.class_names));
    }
    if let Some(p) = &a.json {
        let json = report::plan_json_with(result, &optima);
        write(p, "plan JSON", json.as_bytes())?;
    }
    if let (Some(p), Some(pic)) = (&a.svg, &picture) {
        write(p, "picture", pic.as_bytes())?;
        say!("picture: {}", p.display());
    }
    if let (Some(p), Some(pic)) = (&a.png, &picture) {
        crate::png::write_png(p, "PNG picture", pic)?;
    }
    Ok(())
}
