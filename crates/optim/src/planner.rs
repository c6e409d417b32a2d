//! The planner: one entry point from a scene to ranked, optimised, checked paths.
//!
//! [`plan`] builds the Voronoi graph (or takes a saved one), finds the k best homotopy
//! classes, seeds a spline from each class path, runs the growth loop on every class in
//! parallel (each class is independent and deterministic, so the result does not depend on
//! the thread count), checks every curve for collisions, ranks the classes by the user's
//! weights and reports the Pareto set over (length, roughness, minimum clearance).
//!
//! [`plan_world`] is the pipeline; its stages live in the submodules:
//!
//! - `config`: [`PlanConfig`], [`Seed`], their defaults and checks, [`PlanError`].
//! - `world`: [`World`], what the planner plans in, and the dm rule's exact check
//!   ([`keeps_dm`]).
//! - `seed`: the seeds (straight, or the Voronoi graph's classes), made from class paths
//!   (with `clearance`, `pull` for a map's taut seeds and `via` for the via-points).
//! - `class`: one class's optimisation, a round at a time.
//! - `optimise` and `board`: every class of a scene run with successive halving, on a
//!   shared board of jobs.
//! - `finish`: the repair of classes that could rank first, and the chosen class's polish
//!   or finish.
//! - `rank`: the rank order, the chosen class, the pruning's decision, diversity, overlaps
//!   and the Pareto set.
//! - `report`: the plan's result types and a class's report.

use std::time::Instant;

use homospline_geom::{Point, Real, Scene};
use homospline_homotopy::Rays;
use homospline_spline::CircleModel;
use homospline_voronoi::{BuildError, VoronoiGraph};

mod board;
mod class;
mod clearance;
mod config;
mod finish;
mod optimise;
mod pool;
pub mod profile;
mod pull;
mod rank;
mod report;
mod seed;
mod via;
mod world;

pub use class::DENSE_SEED_SHARE;
pub use config::{
    ConfigError, DEFAULT_FINISH_WITHIN, DEFAULT_PRUNE, DIVERSE_CANDIDATES, DM_RULE_SHARE, Deadline,
    Detour, Interrupt, MAX_CLASSES, MAX_POLISH, MAX_ROUNDS, MAX_THREADS, MAX_VIA_POINTS_CAP,
    PlanConfig, PlanError, Seed, Setting, check_classes, check_diverse,
};
pub use report::{ClassPlan, Plan, Timing};
pub use seed::PlanGraph;
pub use via::SEED_MAX_GAP;
pub use world::{
    ExactCircles, KEEPS_DM_CIRCLES, KEEPS_DM_LENGTH, KEEPS_DM_STATES, World, keeps_dm,
    taut_in_class,
};

use report::ms;

/// The default grid resolution for a scene: about 256 cells along the longer side of its
/// working area ([`Scene::working_area`]: the bounds, unless they are more than three times
/// the box of its obstacles and ends).
pub fn default_resolution(scene: &Scene) -> Real {
    let e = scene.working_area().extent();
    256.0 / e.x.max(e.y)
}

/// Plans `scene`: the Voronoi graph of its free space, the k best homotopy classes on it,
/// each class's spline optimised over its via-points, the classes ranked and the best
/// collision-free one chosen ([`Plan::best`]).
///
/// Every class reported `collision_free` is certified on its whole curve, segment by
/// segment, against the exact clearance. Errors when the graph cannot be built (start and
/// goal in different regions, a grid too large) or a setting is out of range.
///
/// # Examples
///
/// ```
/// use homospline_geom::Scene;
/// use homospline_optim::{PlanConfig, plan};
///
/// let scene = Scene::from_str(
///     r#"
/// name: two-discs
/// bounds: {min: [0, 0], max: [40, 20]}
/// start: [2, 10]
/// goal: [38, 10]
/// obstacles:
///   - name: a
///     circles: [[14, 10, 3]]
///   - name: b
///     circles: [[26, 10, 3]]
/// "#,
///     "two-discs.yaml",
/// )?;
/// let plan = plan(&scene, &PlanConfig::default())?;
/// let best = plan.chosen().expect("a collision-free class");
/// assert!(best.collision_free && best.length < 45.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// See also [`PlanConfig`], [`plan_world`] (the same on any graph and clearance model, as
/// maps use it).
pub fn plan(scene: &Scene, cfg: &PlanConfig) -> Result<Plan, PlanError> {
    plan_with_graph(scene, None, cfg)
}

/// Why `graph` cannot be reused for `scene` under `cfg`, if it cannot: it was built for
/// another start or goal, or from other geometry (bounds, circles or robot radius: a graph
/// records them, [`homospline_voronoi::BuiltFor`]; one saved before they were recorded is
/// checked by its start and goal only), or at another resolution than `cfg.resolution` asks.
pub fn graph_misfit(graph: &VoronoiGraph, scene: &Scene, cfg: &PlanConfig) -> Option<String> {
    let at = |n: Option<usize>| n.and_then(|i| graph.nodes.get(i)).map(|n| n.at);
    if graph.start.is_none() && graph.goal.is_none() && graph.built_for.is_none() {
        return Some(
            "the graph is a map's complete graph (no start or goal; saved by `homospline graph MAP`): it serves plans on that map (`plan MAP --graph`), not on a scene"
                .into(),
        );
    }
    if at(graph.start) != Some([scene.start.x, scene.start.y])
        || at(graph.goal) != Some([scene.goal.x, scene.goal.y])
    {
        return Some("the graph was built for another start or goal than this scene's".into());
    }
    if graph
        .built_for
        .as_ref()
        .is_some_and(|b| *b != homospline_voronoi::BuiltFor::of(scene))
    {
        return Some(
            "the graph was built for another scene: its bounds, obstacles or robot radius differ from this scene's"
                .into(),
        );
    }
    match cfg.resolution {
        Some(r) if r != graph.resolution => Some(format!(
            "the graph was built at {} cells per unit, not at the {r} asked for: leave --resolution out to reuse it",
            graph.resolution
        )),
        _ => None,
    }
}

/// Plans `scene`, reusing `graph` when given (built offline for this scene: refused, with
/// [`graph_misfit`]'s reason, if it was built for another scene, start or goal, or at
/// another resolution than `cfg` asks).
pub fn plan_with_graph(
    scene: &Scene,
    graph: Option<VoronoiGraph>,
    cfg: &PlanConfig,
) -> Result<Plan, PlanError> {
    if let Some(why) = graph.as_ref().and_then(|g| graph_misfit(g, scene, cfg)) {
        return Err(ConfigError::given(Setting::Graph, why).into());
    }
    let circles = ExactCircles::new(scene.circles());
    let model = CircleModel::new(scene.circles());
    let world = World {
        name: scene.name.clone(),
        bounds: scene.bounds,
        start: scene.start,
        goal: scene.goal,
        model: &model,
        rays: std::borrow::Cow::Owned(Rays::for_scene(scene)),
        grid_is_exact: false,
        circles: Some(&circles),
    };
    let resolution = cfg.resolution.unwrap_or_else(|| default_resolution(scene));
    plan_world(
        &world,
        || match graph {
            Some(g) => Ok(PlanGraph::Whole(g)),
            None => Ok(PlanGraph::Whole(
                homospline_voronoi::build_within(scene, resolution, cfg.max_refined_cells)?.2,
            )),
        },
        cfg,
    )
}

/// Plans in `world`; `graph` gives the Voronoi graph (with start and goal attached) when the
/// Voronoi seed asks for it: a graph of its own, which the plan keeps ([`Plan::graph`]), or a
/// query on a prepared map ([`PlanGraph::Query`]), which it does not.
pub fn plan_world<'g>(
    world: &World<'_>,
    graph: impl FnOnce() -> Result<PlanGraph<'g>, BuildError>,
    cfg: &PlanConfig,
) -> Result<Plan, PlanError> {
    config::validate(cfg, world.rays.len())?;
    if world.start == world.goal {
        return Ok(report::plan_to_stay(world, cfg));
    }
    let t0 = Instant::now();
    let mut timing = Timing::default();
    let pool = pool::build(cfg)?;
    let seeded = seed::seed_classes(world, graph, cfg, pool.as_ref(), &mut timing)?;
    let graph_cell = seeded.cell;
    let to = Instant::now();
    let seed_signatures = seeded.signatures();
    let (done, optimise_ms) = match seeded.streamed {
        Some((done, after_search)) => (done, Some(after_search)),
        None => {
            let (seeds, raw) = (&seeded.seeds, seeded.raw);
            let done =
                optimise::optimise_classes(world, cfg, pool.as_ref(), seeds, raw, graph_cell);
            (done, None)
        }
    };
    // With the classes optimised during the search, the optimisation's own time is what
    // came after the search ended (the stages overlap).
    timing.optimize = optimise_ms.unwrap_or_else(|| ms(to));
    if cfg.interrupt.is_raised() {
        return Err(PlanError::Interrupted);
    }
    let (mut classes, best) = rank::rank(done, cfg);
    // Overlap with the chosen class, by graph edges.
    rank::set_overlaps(&mut classes, best, &seed_signatures, &seeded.edges);
    let pareto = rank::pareto(&classes);
    timing.total = ms(t0);
    Ok(Plan {
        scene: world.name.clone(),
        start: world.start,
        goal: world.goal,
        seed: cfg.seed,
        dm: cfg.growth.cost.dm,
        dm_why: None,
        clearance_floor: cfg.clearance_floor,
        classes,
        best,
        pareto,
        timing,
        graph: seeded.graph,
        avoided: seeded.avoided,
    })
}

/// The length of the polyline `poly` (the sum of its segments').
fn polyline_length(poly: &[Point]) -> Real {
    poly.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

#[cfg(test)]
mod tests;
