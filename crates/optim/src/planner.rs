//! The planner: one entry point from a scene to ranked, optimised, checked paths.
//!
//! [`plan`] builds the Voronoi graph (or takes a saved one), finds the k best homotopy
//! classes, seeds a spline from each class path, runs the growth loop on every class in
//! parallel (each class is independent and deterministic, so the result does not depend on
//! the thread count), checks every curve for collisions, ranks the classes by the user's
//! weights and reports the Pareto set over (length, roughness, minimum clearance).

use std::borrow::Cow;
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

use homospline_geom::shortest::TangentGraph;
use homospline_geom::{Bounds, Circle, Point, Real, Scene, Vector};
use homospline_homotopy::{
    ClassPath, Rays, SearchConfig, SearchError, Signature, k_best_classes, k_best_classes_each,
    shortest_in_class_within,
};
use homospline_spline::{
    CircleModel, ClearanceModel, CostTerms, EndCondition, Spline, evaluate_weighted,
    is_collision_free, min_clearance,
};
use homospline_voronoi::{BuildError, VoronoiGraph};
use rayon::prelude::*;
use thiserror::Error;

use crate::growth::{Grown, Growth, GrowthConfig, Guard, Round, SHORT_OF_TARGET, grow};

mod board;

/// How the initial spline is made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Seed {
    /// The paper's planner: one seed per class of the Voronoi graph.
    #[default]
    Voronoi,
    /// The original planner: `S`, the midpoint, `T` (one class).
    Straight,
}

impl Seed {
    /// `voronoi` or `straight`, as in the plan result.
    pub fn name(self) -> &'static str {
        match self {
            Seed::Voronoi => "voronoi",
            Seed::Straight => "straight",
        }
    }
}

/// The dm rule's target in a class whose graph path is less clear than `dm` (a passage
/// narrower than `2 dm`), as a share of that path's least clearance: the graph path runs
/// midway between obstacles, the most a path of the class can keep, and a smooth curve
/// through the passage keeps somewhat less.
pub const DM_RULE_SHARE: Real = 0.9;

/// The least clearance of a class's graph path (at its vertices).
fn bottleneck(poly: &[Point], model: &dyn ClearanceModel) -> Real {
    clearances_of(model, poly)
        .into_iter()
        .fold(Real::INFINITY, Real::min)
}

/// The clearance at each of `pts`, without gradients, in one batch
/// ([`ClearanceModel::clearances`]).
fn clearances_of(model: &dyn ClearanceModel, pts: &[Point]) -> Vec<Real> {
    let mut out = vec![0.0; pts.len()];
    model.clearances(pts, &mut out);
    out
}

/// How much longer than its graph path a class's shortest path that keeps `dm` may be for
/// [`keeps_dm`] to look for it. With this bound and [`KEEPS_DM_STATES`] the chosen plans of
/// 320 scenes and all 59 goldens are those of 1.5 and 4,096 (and the chosen plans those of an
/// unlimited search), and a search that finds nothing ends sooner: re-plans during a mission
/// take it too (256 states lost a class of one golden, 128 of four).
pub const KEEPS_DM_LENGTH: Real = 1.25;

/// The most (node, word) states [`keeps_dm`]'s search may hold.
pub const KEEPS_DM_STATES: usize = 1024;

/// Scenes of more circles than this keep the rule's graph-path target: the tangent graph's
/// build is cubic in the circles (400 circles: 100 ms, more than the plan gains).
pub const KEEPS_DM_CIRCLES: usize = 128;

/// Whether a path of the class `signature` keeps `clearance` from every circle and stays in
/// the world's bounds, within [`KEEPS_DM_LENGTH`] times the length of `poly` (its graph
/// path): the class's exact shortest path at that clearance
/// ([`homospline_homotopy::shortest_in_class_within`]). The graph path's clearance (at its
/// vertices, from the grid) does not say what the class can keep: of the 512 classes of 320
/// scenes whose graph path is less clear than `dm / 0.9`, 259 can keep `dm`. The rule aimed
/// those at 0.9 of it, and on two generated worlds a class ended a hair below `dm` while a
/// safe class 31 and 52 % longer was chosen. `false` when the search gives up.
pub fn keeps_dm(
    world: &World<'_>,
    circles: &ExactCircles,
    poly: &[Point],
    signature: &Signature,
    clearance: Real,
) -> bool {
    let Some(graph) = circles.graph(world, clearance) else {
        return false;
    };
    let length: Real = poly.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let Ok(Some(path)) = shortest_in_class_within(
        graph,
        &world.rays,
        |w| w == signature,
        KEEPS_DM_LENGTH * length,
        KEEPS_DM_STATES,
    ) else {
        return false;
    };
    // In bounds: every piece's ends and, on an arc, points a degree apart.
    path.pieces.iter().all(|piece| {
        piece
            .points(0.0175)
            .iter()
            .all(|p| world.bounds.contains(p))
    })
}

/// Settings of [`plan`].
#[derive(Clone, Debug, PartialEq)]
pub struct PlanConfig {
    /// Seeding.
    pub seed: Seed,
    /// Classes to optimise (the paper uses 5 to 7).
    pub classes: usize,
    /// Grid cells per map unit; `None` picks about 256 cells along the longer side.
    pub resolution: Option<Real>,
    /// Class search (its `k` is overridden by `classes`).
    pub search: SearchConfig,
    /// Growth loop and cost.
    pub growth: GrowthConfig,
    /// Worker threads, 1 to [`MAX_THREADS`]; `None` uses rayon's default. The result is the
    /// same for any count.
    pub threads: Option<usize>,
    /// Tolerance of the certified clearance, map units.
    pub certify_tolerance: Real,
    /// A hard margin: the growth loop rejects candidates whose clearance is below it (see
    /// [`Guard::clearance_floor`]), and the chosen class must be certified at least this
    /// clear. 0 (default): only collisions are rejected.
    pub clearance_floor: Real,
    /// The paper's rule that a path must keep `dm` (docs/method.md, *Safety as a rule*), applied
    /// inside the optimiser as a constraint ([`Guard::clearance_target`]): each class's
    /// curve first climbs to `dm` (or, in a passage narrower than `2 dm`, to
    /// [`DM_RULE_SHARE`] of its graph path's clearance), then lowers its cost while keeping
    /// it. Without it `dm` acts only through the penalty `D`, which at the paper's weights
    /// trades clearance for roughness and length (chosen paths at 0.8 to 1.0 dm). On
    /// (default) for scenes; off on maps, whose one-cell doors and corners sit far below
    /// any `dm` (see `homospline_maps::map_config`).
    pub dm_rule: bool,
    /// The robot's heading at the start, when it is moving (a re-plan on the way): curves
    /// leave along it, unless their class path starts backwards (the robot turns on the
    /// spot: it is omni-directional).
    pub start_heading: Option<Vector>,
    /// Classes to leave out, by signature text.
    pub avoid: Vec<String>,
    /// Limited overlap: a class is taken only if it shares at most this fraction of its
    /// graph path's length with every class already taken (k shortest paths with limited
    /// overlap). `None`: the k best classes, however alike.
    pub diverse: Option<Real>,
    /// Successive halving of the classes: after every class's first round, a class whose
    /// cost exceeds this ratio times that of the class ranked first (keeping `dm` itself as
    /// the dm rule's target, certified clear) runs no further rounds, and is reported from its
    /// first round's curve, marked [`ClassPlan::pruned`]. A heuristic: a first round can be a
    /// poor guide (a class's cost fell by 54 % in its second round on one generated scene).
    /// On 1,020 scenes (the fixtures and 1,000 generated ones; the ignored test
    /// `scan_the_ratio` in `tests/prune.rs`, with [`PlanConfig::finish_within`] off), the
    /// default [`DEFAULT_PRUNE`] of 1.5 changes one chosen class against running every
    /// class to its end (world-030: a class whose
    /// first round cost 1.98 times the reference's won, and the plan chosen instead costs
    /// 1.4 % more), as do 1.4 to 1.75, while 1.25 changes three (one of them 45 % dearer)
    /// and 2 to 4 none; 1.5 saves 60 % of the evaluations there (2.5: 53 %), and on the
    /// paper scenes 30 to 47 % of them (2.5: none on three of the five). With either
    /// optimiser (L-BFGS plans take half the evaluations with it, the same chosen cost in 319
    /// of 320 scanned scenes, one 6.8 % dearer). `None`
    /// runs every class to its end (a mission does: its other classes are its alternatives).
    /// Applies where the classes are optimised after the search (scenes), not to a map's
    /// classes, optimised while the search goes on. At the defaults the evaluations it saves
    /// also decide whether the chosen class gets its finish ([`PlanConfig::finish_within`]):
    /// convex's does with pruning (1,324 evaluations) and not without (2,707).
    pub prune: Option<Real>,
    /// Rounds of polish for the class the plan chooses ([`Growth::polish`]): after the
    /// classes are ranked, the first one's loop runs up to this many more rounds at its
    /// via-points, each from a fresh simplex and ending with an interior-point finish
    /// (L-BFGS with a barrier on the clearance), and is reported again. The polish is kept only
    /// if the class stays collision-free, at the floor, safe if it was, and no dearer, so it
    /// stays first; else its curve is put back. 0 (default): none. Scenes only, like the
    /// pruning; a class stopped by the pruning is not polished.
    pub polish: usize,
    /// A work budget, in cost evaluations, for the chosen class's interior-point finish:
    /// after the classes are ranked, if the plan has spent fewer evaluations than this, the
    /// class it chooses gets one finish-only polish round ([`Growth::finish`]: L-BFGS on the
    /// cost with a log barrier on the clearance, from its curve at its via-points) with half
    /// a round's budget, at most what is left of this one (nothing when fewer than
    /// [`crate::growth::MIN_FINISH_EVALUATIONS`] are left). It is kept as a polish is (the
    /// same class, collision-free, at the floor, safe if it was, no dearer), else undone.
    /// A deterministic stand-in for a latency budget: evaluations, not time, so the plan
    /// does not depend on the machine or its load (a value with its gradient counts one,
    /// though it costs about 2.5 times a simplex evaluation). `None` or 0: never. Scenes
    /// only, like [`PlanConfig::polish`], which replaces it when set; on an occupancy map
    /// neither runs.
    pub finish_within: Option<usize>,
}

impl Default for PlanConfig {
    fn default() -> Self {
        Self {
            seed: Seed::Voronoi,
            classes: 5,
            resolution: None,
            search: SearchConfig::default(),
            growth: GrowthConfig::default(),
            threads: None,
            certify_tolerance: 1e-3,
            clearance_floor: 0.0,
            dm_rule: true,
            start_heading: None,
            avoid: Vec::new(),
            diverse: None,
            prune: Some(DEFAULT_PRUNE),
            polish: 0,
            finish_within: Some(DEFAULT_FINISH_WITHIN),
        }
    }
}

/// The default of [`PlanConfig::finish_within`].
pub const DEFAULT_FINISH_WITHIN: usize = 1500;

/// The default of [`PlanConfig::prune`].
pub const DEFAULT_PRUNE: Real = 1.5;

/// Relative slack between a class's cost as the optimiser evaluates it (far circles'
/// potential truncated within `1e-6` of the total) and as it is reported (nothing left out),
/// when the planner checks that a class run to its end came in under the reference cost of
/// a pruning.
const PRUNE_SLACK: Real = 1e-5;

/// Why planning failed before any class was optimised.
#[derive(Debug, Error)]
pub enum PlanError {
    /// Grid or graph.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// Class search.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// Configuration.
    #[error("{0}")]
    Config(String),
    /// Thread pool.
    #[error("cannot start worker threads: {0}")]
    Threads(String),
}

/// One optimised class.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassPlan {
    /// 1 = best by the user's weights (collision-free classes first).
    pub rank: usize,
    /// Homotopy signature (stable text form).
    pub signature: String,
    /// The class path the seed came from (for `straight`: `S`, midpoint, `T`).
    pub seed_path: Vec<Point>,
    /// `S`, optimised via-points, `T`.
    pub via_points: Vec<Point>,
    /// The curve sampled at arc-length spacing of at most `min(0.5, length / 1000)`.
    pub path: Vec<Point>,
    /// Cost terms of the final curve.
    pub cost: CostTerms,
    /// Length of the curve.
    pub length: Real,
    /// Minimum clearance of the sampled path, segment by segment, to the (inflated) circles.
    pub min_clearance: Real,
    /// Certified lower bound of the curve's own minimum clearance.
    pub certified_clearance: Real,
    /// Collision-free: the sampled path and the certified curve both clear every circle,
    /// and the path stays inside the bounds.
    pub collision_free: bool,
    /// Certified to keep the required clearance `dm`: the paper's rule is that a path
    /// breaking it is not used while another keeps it, so safe classes rank first.
    pub safe: bool,
    /// Still in the class of its seed (always true for guarded Voronoi seeds).
    pub in_class: bool,
    /// Rounds of the growth loop.
    pub iterations: usize,
    /// Each round's via-points, cost at its end and evaluations (the curve reported is the
    /// best of them: [`grow`]).
    pub rounds: Vec<Round>,
    /// Cost evaluations.
    pub evaluations: usize,
    /// Time spent on this class, milliseconds.
    pub time_ms: Real,
    /// Graph cost of the class path (Voronoi seeds).
    pub graph_cost: Real,
    /// Share of its graph path's length on edges the chosen class's graph path uses too
    /// (0 when nothing is chosen or for the straight seed; 1 for the chosen class).
    pub overlap: Real,
    /// Stopped after its first round: its cost then was more than [`PlanConfig::prune`]
    /// times that of the reference class, a margin it is taken not to make up in later
    /// rounds (a heuristic: see [`PlanConfig::prune`]). Its curve is its first round's,
    /// certified like every other.
    pub pruned: bool,
}

/// A seed: the polyline, its class (none for the straight seed), its graph cost.
type SeedPath = (Vec<Point>, Option<Signature>, Real);

/// The length of a class path on each graph edge it uses.
type EdgeLengths = Vec<(usize, Real)>;

/// Classes optimised while the search ran (by seed index), their seeds, and the time spent
/// after the search ended, ms.
type Streamed = (Vec<(usize, ClassPlan)>, Vec<SeedPath>, Real);

/// Greedy limited-overlap selection: classes in cost order, each kept if what it shares with
/// every class kept before it is at most `limit` of either's length, until `k` are kept. (The
/// shared length of two graph paths is the length of their common edges: symmetric.)
fn limited_overlap(paths: &[EdgeLengths], lengths: &[Real], limit: Real, k: usize) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::new();
    for i in 0..paths.len() {
        if kept.len() == k {
            break;
        }
        if kept
            .iter()
            .all(|&j| shared_length(&paths[i], &paths[j]) <= limit * lengths[i].min(lengths[j]))
        {
            kept.push(i);
        }
    }
    kept
}

/// The length of `a` on edges that `b` uses too.
fn shared_length(a: &EdgeLengths, b: &EdgeLengths) -> Real {
    a.iter()
        .filter(|(e, _)| b.iter().any(|(f, _)| f == e))
        .map(|(_, l)| l)
        .sum()
}

/// Time per stage, milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// Grid, brushfire and graph.
    pub voronoi: Real,
    /// Class search.
    pub classes: Real,
    /// Seeding and optimisation of all classes.
    pub optimize: Real,
    /// Everything.
    pub total: Real,
}

/// A plan: every class, ranked.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Scene name.
    pub scene: String,
    /// Start.
    pub start: Point,
    /// Goal.
    pub goal: Point,
    /// Seeding used.
    pub seed: Seed,
    /// The minimal distance `dm` the classes' `safe` was judged by.
    pub dm: Real,
    /// The clearance floor the chosen class had to meet ([`PlanConfig::clearance_floor`]).
    pub clearance_floor: Real,
    /// Classes in rank order.
    pub classes: Vec<ClassPlan>,
    /// Rank of the chosen class: the best-ranked collision-free class certified at least
    /// [`PlanConfig::clearance_floor`] clear; `None` if none is.
    pub best: Option<usize>,
    /// Ranks of the Pareto-optimal classes over (length, roughness, minimum clearance).
    pub pareto: Vec<usize>,
    /// Stage timings.
    pub timing: Timing,
    /// The graph (Voronoi seeds).
    pub graph: Option<VoronoiGraph>,
}

impl Plan {
    /// The chosen class (rank [`Plan::best`]), if any.
    pub fn chosen(&self) -> Option<&ClassPlan> {
        self.best.map(|b| &self.classes[b - 1])
    }

    /// Cost evaluations over every class.
    pub fn evaluations(&self) -> usize {
        self.classes.iter().map(|c| c.evaluations).sum()
    }
}

fn ms(t: Instant) -> Real {
    t.elapsed().as_secs_f64() * 1e3
}

/// What the planner plans in: bounds, start, goal, the obstacles as the cost sees them, and
/// the rays that name homotopy classes. A scene of circles and an occupancy map are both one.
pub struct World<'a> {
    /// Name for the plan.
    pub name: String,
    /// The robot stays inside.
    pub bounds: Bounds,
    /// Start.
    pub start: Point,
    /// Goal.
    pub goal: Point,
    /// Obstacles for the cost and the collision checks.
    pub model: &'a dyn ClearanceModel,
    /// One ray per obstacle representative.
    pub rays: Rays,
    /// Whether the Voronoi grid is the world itself (an occupancy map) rather than a
    /// rasterisation of it (circles). Passages narrower than one cell are offered only then.
    pub grid_is_exact: bool,
    /// The obstacles as circles, when they are circles (a scene): the dm rule then asks the
    /// exact geometry whether a class whose graph path is less clear than `dm` can keep it
    /// ([`keeps_dm`]). `None` on a map.
    pub circles: Option<&'a ExactCircles>,
}

/// A scene's circles for the dm rule's exact check ([`keeps_dm`]), with the tangent graph at
/// the rule's clearance built once, by the first class that asks, for all of them.
pub struct ExactCircles {
    circles: Vec<Circle>,
    /// The graph, and the start, goal and clearance it was built for.
    graph: OnceLock<(Point, Point, Real, Option<TangentGraph>)>,
}

impl ExactCircles {
    /// The scene's circles.
    pub fn new(circles: Vec<Circle>) -> Self {
        Self {
            circles,
            graph: OnceLock::new(),
        }
    }

    /// The tangent graph from the world's start to its goal at `clearance` (`None` when an
    /// end is less clear, the input is not valid, or there are more than
    /// [`KEEPS_DM_CIRCLES`] circles).
    fn graph(&self, world: &World<'_>, clearance: Real) -> Option<&TangentGraph> {
        if self.circles.len() > KEEPS_DM_CIRCLES {
            return None;
        }
        let build = || {
            TangentGraph::build(&world.start, &world.goal, &self.circles, clearance)
                .ok()
                .flatten()
        };
        let (start, goal, at, graph) = self
            .graph
            .get_or_init(|| (world.start, world.goal, clearance, build()));
        // Every class of a plan asks for the same; a world that shares these circles with
        // another start, goal or clearance gets no answer rather than a wrong one.
        (*start == world.start && *goal == world.goal && *at == clearance)
            .then_some(graph.as_ref())
            .flatten()
    }
}

/// The default grid resolution for a scene: about 256 cells along the longer side.
pub fn default_resolution(scene: &Scene) -> Real {
    let e = scene.bounds.extent();
    256.0 / e.x.max(e.y)
}

/// Plans `scene`.
pub fn plan(scene: &Scene, cfg: &PlanConfig) -> Result<Plan, PlanError> {
    plan_with_graph(scene, None, cfg)
}

/// Why `graph` cannot be reused for `scene` under `cfg`, if it cannot: it was built for
/// another start or goal, or from other geometry (bounds, circles or robot radius: a graph
/// records them, [`homospline_voronoi::BuiltFor`]; one saved before they were recorded is
/// checked by its start and goal only), or at another resolution than `cfg.resolution` asks.
pub fn graph_misfit(graph: &VoronoiGraph, scene: &Scene, cfg: &PlanConfig) -> Option<String> {
    let at = |n: Option<usize>| n.and_then(|i| graph.nodes.get(i)).map(|n| n.at);
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
        return Err(PlanError::Config(why));
    }
    let circles = ExactCircles::new(scene.circles());
    let model = CircleModel::new(scene.circles());
    let world = World {
        name: scene.name.clone(),
        bounds: scene.bounds,
        start: scene.start,
        goal: scene.goal,
        model: &model,
        rays: Rays::for_scene(scene),
        grid_is_exact: false,
        circles: Some(&circles),
    };
    let resolution = cfg.resolution.unwrap_or_else(|| default_resolution(scene));
    plan_world(
        &world,
        || match graph {
            Some(g) => Ok(g),
            None => Ok(homospline_voronoi::build(scene, resolution)?.2),
        },
        cfg,
    )
}

/// Why `text` names no class of a scene or map with `rays` rays, if it does not: a class is
/// written as its signature prints, `e` or ray crossings such as `-1+12` (rays from 1). A
/// mistyped class was left out of nothing, silently.
fn avoid_misfit(text: &str, rays: usize) -> Option<String> {
    if text == "e" {
        return None;
    }
    let mut rest = text;
    if rest.is_empty() {
        return Some("not a class: e, or ray crossings such as -1+2".into());
    }
    while let Some(sign) = rest.chars().next() {
        if sign != '+' && sign != '-' {
            return Some("not a class: e, or ray crossings such as -1+2".into());
        }
        let digits = rest[1..]
            .find(['+', '-'])
            .map_or(&rest[1..], |end| &rest[1..1 + end]);
        match digits.parse::<usize>() {
            Ok(k) if k >= 1 && k <= rays && !digits.starts_with('0') => {}
            Ok(k) if k >= 1 && !digits.starts_with('0') => {
                return Some(format!("ray {k}: there are {rays} rays here"));
            }
            _ => return Some("not a class: e, or ray crossings such as -1+2".into()),
        }
        rest = &rest[1 + digits.len()..];
    }
    None
}

/// The plan when start and goal are one point: one class, `e`, the path that stays there,
/// with the point's clearance; nothing to optimise, and it costs nothing. (On a scene the
/// seeding panicked where the class path was one node, and elsewhere a curve looped a
/// thousandth of a unit; on a map the path was empty at clearance -inf, exit 1.)
fn plan_to_stay(world: &World<'_>, cfg: &PlanConfig) -> Plan {
    let (s, path) = (world.start, vec![world.start, world.goal]);
    let clear = world.model.polyline_clearance(&path);
    let collision_free = clear > 0.0 && world.bounds.contains(&s);
    let class = ClassPlan {
        rank: 1,
        signature: world.rays.signature(&path).to_string(),
        seed_path: path.clone(),
        via_points: path.clone(),
        path,
        cost: CostTerms::default(),
        length: 0.0,
        min_clearance: clear,
        certified_clearance: clear,
        collision_free,
        safe: clear >= cfg.growth.cost.dm,
        in_class: true,
        iterations: 0,
        rounds: Vec::new(),
        evaluations: 0,
        time_ms: 0.0,
        graph_cost: 0.0,
        overlap: 1.0,
        pruned: false,
    };
    let best = (collision_free && clear >= cfg.clearance_floor).then_some(1);
    Plan {
        scene: world.name.clone(),
        start: world.start,
        goal: world.goal,
        seed: cfg.seed,
        dm: cfg.growth.cost.dm,
        clearance_floor: cfg.clearance_floor,
        classes: vec![class],
        best,
        pareto: vec![1],
        timing: Timing::default(),
        graph: None,
    }
}

/// Most worker threads a plan may ask for ([`PlanConfig::threads`]): far beyond the
/// classes a plan has, and a pool of 5,000 threads took longer to start than 20 s.
pub const MAX_THREADS: usize = 256;

/// Plans in `world`; `graph` gives the Voronoi graph (with start and goal attached) when the
/// Voronoi seed asks for it.
pub fn plan_world(
    world: &World<'_>,
    graph: impl FnOnce() -> Result<VoronoiGraph, BuildError>,
    cfg: &PlanConfig,
) -> Result<Plan, PlanError> {
    if cfg.classes == 0 {
        return Err(PlanError::Config("classes must be at least 1".into()));
    }
    for a in &cfg.avoid {
        avoid_misfit(a, world.rays.len()).map_or(Ok(()), |why| {
            Err(PlanError::Config(format!("avoid '{a}': {why}")))
        })?;
    }
    if cfg.seed == Seed::Straight && (!cfg.avoid.is_empty() || cfg.diverse.is_some()) {
        return Err(PlanError::Config(
            "avoid and diverse choose among the Voronoi seed's classes; the straight seed plans one class"
                .into(),
        ));
    }
    if let Some(n) = cfg.threads
        && !(1..=MAX_THREADS).contains(&n)
    {
        return Err(PlanError::Config(format!(
            "threads must be between 1 and {MAX_THREADS}, got {n}"
        )));
    }
    if !(cfg.clearance_floor.is_finite() && cfg.clearance_floor >= 0.0) {
        return Err(PlanError::Config(format!(
            "clearance floor must be finite and >= 0, got {}",
            cfg.clearance_floor
        )));
    }
    cfg.growth
        .cost
        .validate()
        .map_err(|e| PlanError::Config(e.to_string()))?;
    if let Some(f) = cfg.diverse
        && !(f.is_finite() && (0.0..=1.0).contains(&f))
    {
        return Err(PlanError::Config(format!(
            "diverse must be a fraction in [0, 1], got {f}"
        )));
    }
    if let Some(r) = cfg.prune
        && !(r.is_finite() && r >= 1.0)
    {
        return Err(PlanError::Config(format!(
            "prune must be a ratio of at least 1, got {r}"
        )));
    }
    if world.start == world.goal {
        return Ok(plan_to_stay(world, cfg));
    }
    let t0 = Instant::now();
    let rays = &world.rays;
    let mut timing = Timing::default();
    let pool = match cfg.threads {
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| PlanError::Threads(e.to_string()))?,
        ),
        None => None,
    };
    // Each seed's graph path by edge (for overlaps), in seed order.
    let mut class_edges: Vec<EdgeLengths> = Vec::new();
    // One class: a map's seed pulled taut in its class, then the growth loop.
    let mut streamed: Option<Streamed> = None;
    // Seeds: (seed polyline, class signature, graph cost).
    // `raw`: the seeds are class paths still to be made into seeds ([`class_seed`]), on the
    // graph's cell.
    let (seeds, graph, raw): (Vec<SeedPath>, Option<VoronoiGraph>, Option<Real>) = match cfg.seed {
        Seed::Straight => {
            timing.voronoi = 0.0;
            let mid = Point::from((world.start.coords + world.goal.coords) * 0.5);
            (
                vec![(vec![world.start, mid, world.goal], None, 0.0)],
                None,
                None,
            )
        }
        Seed::Voronoi => {
            let tv = Instant::now();
            let graph = graph()?;
            timing.voronoi = ms(tv);
            let tc = Instant::now();
            let cell = 1.0 / graph.resolution;
            // A passage narrower than one grid cell of a rasterised scene is below what the
            // grid can tell apart from a wall: it is not offered, unless there is no other
            // way (below). On a map the cells are the truth, and a one-cell door is a door.
            let floor = if world.grid_is_exact { 0.0 } else { cell };
            let min_clearance = cfg.search.min_clearance.max(floor);
            // Avoided classes and the limited-overlap selection need more candidates.
            let extra = cfg.avoid.len();
            let k = match cfg.diverse {
                Some(_) => (cfg.classes + extra) * DIVERSE_CANDIDATES,
                None => cfg.classes + extra,
            };
            let search = SearchConfig {
                k,
                min_clearance,
                ..cfg.search.clone()
            };
            let make_seed = |c: &ClassPath| -> SeedPath {
                (
                    class_seed(world, cell, &c.polyline, &c.signature),
                    Some(c.signature.clone()),
                    c.cost,
                )
            };
            let taken = |c: &ClassPath| !cfg.avoid.contains(&c.signature.to_string());
            let result = match cfg.diverse {
                // On a map, without the limited-overlap selection, the classes to optimise
                // are the first found: each is optimised as soon as the search has it, on
                // another thread, while the search goes on (a map's search takes a tenth of
                // a plan). Each class is independent of the others and of when it ran, so
                // this changes no result. A scene's search takes microseconds: there the
                // classes are better run longest first, below.
                None if world.grid_is_exact => {
                    let done = Mutex::new(Vec::new());
                    // The search's result, the seeds it handed out, and when it ended.
                    let (r, made, end) = in_pool(pool.as_ref(), || {
                        rayon::scope(|s| {
                            let mut made = Vec::new();
                            let r = k_best_classes_each(&graph, rays, &search, |c| {
                                if made.len() >= cfg.classes || !taken(c) {
                                    return;
                                }
                                let (i, seed, done) = (made.len(), make_seed(c), &done);
                                made.push(seed.clone());
                                s.spawn(move |_| {
                                    let (poly, sig, gcost) = &seed;
                                    let task = start_class(
                                        world,
                                        cfg,
                                        poly,
                                        sig.as_ref(),
                                        *gcost,
                                        Some(cell),
                                    )
                                    .optimised(world.model);
                                    let (plan, _) = task.report(world, cfg);
                                    done.lock()
                                        .unwrap_or_else(|e| e.into_inner())
                                        .push((i, plan));
                                });
                            });
                            (r, made, Instant::now())
                        })
                    });
                    let optimised = done.into_inner().unwrap_or_else(|e| e.into_inner());
                    streamed = Some((optimised, made, ms(end)));
                    timing.classes = end.duration_since(tc).as_secs_f64() * 1e3;
                    r
                }
                // When every way is narrower than a cell (a robot that has driven into a
                // tight spot), those ways are offered after all: the certification of each
                // curve decides whether it is clear.
                _ => k_best_classes(&graph, rays, &search).and_then(|r| {
                    if r.classes.is_empty() && min_clearance > cfg.search.min_clearance {
                        let below = SearchConfig {
                            min_clearance: cfg.search.min_clearance,
                            ..search.clone()
                        };
                        k_best_classes(&graph, rays, &below)
                    } else {
                        Ok(r)
                    }
                }),
            };
            let mut found = result?.classes;
            found.retain(|c| taken(c));
            let edge_lengths: Vec<EdgeLengths> = found
                .iter()
                .map(|c| {
                    c.edges
                        .iter()
                        .map(|&(e, _)| (e, graph.edges[e].length))
                        .collect()
                })
                .collect();
            let keep = match cfg.diverse {
                Some(limit) => {
                    let lengths: Vec<Real> = found.iter().map(|c| c.length).collect();
                    limited_overlap(&edge_lengths, &lengths, limit, cfg.classes)
                }
                None => (0..found.len().min(cfg.classes)).collect(),
            };
            let kept: Vec<&ClassPath> = found
                .iter()
                .enumerate()
                .filter(|(i, _)| keep.contains(i))
                .map(|(_, c)| c)
                .collect();
            class_edges.extend(
                (0..found.len())
                    .filter(|i| keep.contains(i))
                    .map(|i| edge_lengths[i].clone()),
            );
            // A scene's seeds are the class paths as found: each is made (its ends shortcut,
            // centred: a tenth of a millisecond or two) in its class's first job, while the
            // other classes run ([`class_seed`]).
            let mut seeds: Vec<SeedPath> = kept
                .iter()
                .map(|c| (c.polyline.clone(), Some(c.signature.clone()), c.cost))
                .collect();
            let mut raw = Some(cell);
            if let Some((_, made, _)) = &mut streamed {
                seeds = std::mem::take(made);
                raw = None;
            } else {
                timing.classes = ms(tc);
            }
            (seeds, Some(graph), raw)
        }
    };
    let graph_cell = graph.as_ref().map(|g| 1.0 / g.resolution);
    let to = Instant::now();
    let seed_signatures: Vec<String> = seeds
        .iter()
        .map(|(_, s, _)| s.as_ref().map(|s| s.to_string()).unwrap_or_default())
        .collect();
    let mut optimise_ms = None;
    let mut done: Vec<(usize, ClassPlan)> = match streamed {
        Some((done, _, after_search)) => {
            optimise_ms = Some(after_search);
            done
        }
        None => {
            // Longest first (a scene's class paths, its seeds still to be made): the classes'
            // times differ by up to 3x, and a long class started last would run alone at the
            // end. Each class is independent, so the order changes no result.
            let mut order: Vec<usize> = (0..seeds.len()).collect();
            let seed_length =
                |i: usize| -> Real { seeds[i].0.windows(2).map(|w| (w[1] - w[0]).norm()).sum() };
            order.sort_by(|&a, &b| seed_length(b).total_cmp(&seed_length(a)).then(a.cmp(&b)));
            let model = world.model;
            // Successive halving (`cfg.prune`, with either optimiser: its doc says why): every class runs its first round (and is scored in its own
            // job), then the classes that cannot win stop ([`outclassed`]) and the others run
            // their rounds left. The decision depends on the first rounds only, not on the
            // threads: the board ([`board`]) runs rounds ahead of it only on a core that
            // would otherwise wait, and undoes them for a class it stops. (Without a decision
            // point, the tasks ran to their ends one after the other on each thread, and the
            // decision came after the classes to be stopped had run every round:
            // two-homotopies took 14.6 ms against 10.1 ms.)
            let board::Ran {
                mut tasks,
                mut runs,
                pruning,
            } = in_pool(pool.as_ref(), || {
                board::run_classes(world, cfg, &seeds, raw, graph_cell, &order)
            });
            let run_left = |tasks: &mut Vec<(usize, ClassTask<'_>)>| {
                in_pool(pool.as_ref(), || {
                    tasks
                        .par_iter_mut()
                        .with_max_len(1)
                        .filter(|(_, task)| !task.pruned)
                        .for_each(|(_, task)| task.run(model));
                });
            };
            let report = |tasks: &mut Vec<(usize, ClassTask<'_>)>| -> Vec<(usize, ClassRun)> {
                in_pool(pool.as_ref(), || {
                    tasks
                        .par_iter_mut()
                        .with_max_len(1)
                        .map(|(i, task)| (*i, task.report(world, cfg)))
                        .collect()
                })
            };
            // A class whose loop ended on a curve that its cost's `m(C)` (searched around the
            // worst quadrature node) took to keep its target, but that is not proven to, was
            // optimised against a constraint it did not see ([`Growth::needs_repair`]). If it
            // could rank first (it costs less than every class reported certified safe), it
            // runs one more round searching every stretch between nodes, and is reported
            // again. A class that cannot rank first is reported as it is: its certificate
            // says how clear it is (convex's class `e`: a repair would cost the plan half its
            // time for an alternative).
            repair_contenders(world, cfg, pool.as_ref(), &mut tasks, &mut runs);
            // The stop assumed that a class run to its end would rank first at no more than
            // the reference's first-round cost. If none does (its certification found it
            // less clear than its cost evaluations did), the stopped classes run on after
            // all.
            if let Some(p) = &pruning {
                let bar = p.reference_cost * (1.0 + PRUNE_SLACK);
                let holds = runs.iter().any(|(_, (c, _))| {
                    !c.pruned
                        && c.collision_free
                        && c.safe
                        && c.certified_clearance >= cfg.clearance_floor
                        && c.cost.total <= bar
                });
                if !holds {
                    for (_, task) in tasks.iter_mut() {
                        task.pruned = false;
                    }
                    run_left(&mut tasks);
                    runs = report(&mut tasks);
                    repair_contenders(world, cfg, pool.as_ref(), &mut tasks, &mut runs);
                }
            }
            polish_chosen(world, cfg, &mut tasks, &mut runs);
            // No class came out clear: those that could not start from a clear seed are tried
            // again with dense via-points (a winding passage too narrow for a spline through
            // `max_via_points` via-points may be the only way). Only then: dense seeds cost
            // several times a class's usual time, and re-plans on the move wait for them.
            // The second pass starts from the dense seed; the first pass's curve stands
            // unless the dense one comes out clear. (The straight seed has no class to
            // follow: it is never marked.)
            let again: Vec<usize> = runs
                .iter()
                .filter(|(_, (_, retry))| *retry)
                .map(|(i, _)| *i)
                .collect();
            let mut done: Vec<(usize, ClassPlan)> =
                runs.into_iter().map(|(i, (c, _))| (i, c)).collect();
            if !again.is_empty() && !done.iter().any(|(_, c)| c.collision_free) {
                let firsts = &done;
                let retried: Vec<(usize, ClassPlan)> = in_pool(pool.as_ref(), || {
                    tasks
                        .par_iter_mut()
                        .with_max_len(1)
                        .filter(|(i, _)| again.contains(i))
                        .filter_map(|(i, task)| {
                            let first = &firsts.iter().find(|(j, _)| j == i)?.1;
                            task.dense(world, cfg, graph_cell, first).map(|c| (*i, c))
                        })
                        .collect()
                });
                for (i, c) in retried {
                    if let Some(slot) = done.iter_mut().find(|(j, _)| *j == i) {
                        slot.1 = c;
                    }
                }
            }
            done
        }
    };
    done.sort_by_key(|(i, _)| *i);
    let mut classes: Vec<ClassPlan> = done.into_iter().map(|(_, c)| c).collect();
    // With the classes optimised during the search, the optimisation's own time is what
    // came after the search ended (the stages overlap).
    timing.optimize = optimise_ms.unwrap_or_else(|| ms(to));
    // Rank: collision-free and safe first, then collision-free, then the rest; within each,
    // by cost; ties by signature for determinism.
    classes.sort_by(rank_order);
    for (i, c) in classes.iter_mut().enumerate() {
        c.rank = i + 1;
    }
    let best = classes.iter().find(|c| choosable(c, cfg)).map(|c| c.rank);
    // Overlap with the chosen class, by graph edges.
    let edges_of = |sig: &str| {
        seed_signatures
            .iter()
            .position(|s| s == sig)
            .and_then(|i| class_edges.get(i))
    };
    if let Some(chosen) = best
        .and_then(|b| edges_of(&classes[b - 1].signature))
        .cloned()
    {
        for c in &mut classes {
            if let Some(own) = edges_of(&c.signature) {
                let total: Real = own.iter().map(|(_, l)| l).sum();
                if total > 0.0 {
                    c.overlap = shared_length(own, &chosen) / total;
                }
            }
        }
    }
    let pareto = classes
        .iter()
        .filter(|a| {
            !classes.iter().any(|b| {
                let no_worse = b.length <= a.length
                    && b.cost.roughness <= a.cost.roughness
                    && b.min_clearance >= a.min_clearance;
                let better = b.length < a.length
                    || b.cost.roughness < a.cost.roughness
                    || b.min_clearance > a.min_clearance;
                no_worse && better
            })
        })
        .map(|c| c.rank)
        .collect();
    timing.total = ms(t0);
    Ok(Plan {
        scene: world.name.clone(),
        start: world.start,
        goal: world.goal,
        seed: cfg.seed,
        dm: cfg.growth.cost.dm,
        clearance_floor: cfg.clearance_floor,
        classes,
        best,
        pareto,
        timing,
        graph,
    })
}

/// Start and goal join the graph along their maximum-clearance route, which may meet the
/// ridge behind them: the class path then runs away from its start and turns back (or passes
/// its goal and curls into it), and the curve through it does too. This replaces each end's
/// stretch, up to `4 clearance + 8 cells` of arc length from the start (goal), by the
/// straight segment to the farthest point of it that the segment reaches with at least the
/// stretch's least vertex clearance less half a cell (and at least half of it: a start next
/// to a wall keeps its margin), as long as the class stays the same.
fn shortcut_ends(
    poly: &[Point],
    model: &dyn ClearanceModel,
    cell: Real,
    same_class: impl Fn(&[Point]) -> bool,
) -> Vec<Point> {
    // The indices `k > 1` (within the window) of the points `poly[k]` that `poly[0]` joins.
    let reachable = |poly: &[Point]| -> Vec<usize> {
        let mut stretch = model.clearance_value(&poly[0]);
        let window = 4.0 * stretch.max(cell) + 8.0 * cell;
        let mut arc = 0.0;
        let mut out = Vec::new();
        for k in 1..poly.len() - 1 {
            arc += (poly[k] - poly[k - 1]).norm();
            if arc > window {
                break;
            }
            stretch = stretch.min(model.clearance_value(&poly[k]));
            let target = (stretch - 0.5 * cell).max(0.5 * stretch);
            if k > 1 && clear_at_least(model, poly[0], poly[k], target, cell) {
                out.push(k);
            }
        }
        out
    };
    if poly.len() < 3 {
        return poly.to_vec();
    }
    let mut out = poly.to_vec();
    for pass in 0..2 {
        // The farthest point whose shortcut keeps the class (a few tries: each is a
        // signature of the whole path). The second pass works on the reversed path.
        for &k in reachable(&out).iter().rev().take(SHORTCUT_TRIES) {
            let mut cut = vec![out[0]];
            cut.extend_from_slice(&out[k..]);
            if pass == 1 {
                cut.reverse();
            }
            if same_class(&cut) {
                if pass == 1 {
                    cut.reverse();
                }
                out = cut;
                break;
            }
        }
        out.reverse();
    }
    out
}

/// Runs `f` on `pool`, or on rayon's global pool when there is none.
fn in_pool<R: Send>(pool: Option<&rayon::ThreadPool>, f: impl FnOnce() -> R + Send) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

/// String pulling on a map's class path, which runs along the ridge of free space: through
/// the middle of every room and round every bend at the bend's full clearance, so the curve
/// seeded by it is up to a fifth longer than the octile path, and an optimiser with a budget
/// that follows the path's length does not pull it straight.
///
/// Each point of the ridge gets a margin: its clearance less half a cell, at least half of
/// it (as at the ends) and at most [`PULL_MARGIN`] cells. A pass ([`pull_pass`]) puts a
/// point every cell along the path and replaces it by chords between its points that keep
/// the least margin of the stretch they replace. A chord's corners lie on the path it
/// replaced (the ridge, at first), and once every chord touches its margin no chord can
/// move them; so before each further pass every corner is cut ([`cut_corners`]), and passes
/// go on, the points carrying their chord's margin, until the length falls by less than
/// 0.1 % (at most [`PULL_PASSES`]): the corners move in towards the walls, to the margin.
///
/// The passes run unchecked first and the class is tested once, on the result; if it left
/// the class, they run again with every chord proven to keep it. Failing both, the ridge
/// path is kept. The cost then decides how far from walls the curve ends up. Measured on
/// the MovingAI maps (`bench-scen --sample 20`): the median length over the octile optimum
/// fell from 1.03 to 1.22 to between 0.96 and 1.00.
fn pull_taut(
    poly: &[Point],
    model: &dyn ClearanceModel,
    rays: &Rays,
    cell: Real,
    signature: &Signature,
) -> Vec<Point> {
    if poly.len() < 3 {
        return poly.to_vec();
    }
    let margin = |c: Real| (c - 0.5 * cell).max(0.5 * c).min(PULL_MARGIN * cell);
    let margins: Vec<Real> = clearances_of(model, poly).into_iter().map(margin).collect();
    // A vertex's margin applies to both its segments.
    let path: Vec<(Point, Real)> = poly
        .iter()
        .enumerate()
        .map(|(i, &p)| (p, margins[i].min(margins[i.saturating_sub(1)])))
        .collect();
    let length =
        |p: &[(Point, Real)]| -> Real { p.windows(2).map(|w| (w[1].0 - w[0].0).norm()).sum() };
    // Unchecked first (the class is tested once, at the end); if the result left the class,
    // again with every chord and cut proven to keep it.
    for checked in [false, true] {
        let mut path = path.clone();
        for pass in 0..PULL_PASSES {
            let cut = if pass == 0 {
                path.clone()
            } else {
                cut_corners(&path, model, rays, cell)
            };
            let next = pull_pass(&cut, model, rays, cell, checked);
            let (before, after) = (length(&path), length(&next));
            path = next;
            if after > before * (1.0 - 1e-3) {
                break;
            }
        }
        let pulled: Vec<Point> = path.into_iter().map(|(p, _)| p).collect();
        if rays.signature(&pulled) == *signature {
            return pulled;
        }
    }
    poly.to_vec()
}

/// Cuts each corner `V` of `path` (between `A` and `B`) by the chord between `V + s (A - V)`
/// and `V + s (B - V)`, for the largest `s` of a halving search whose chord keeps the margin
/// of both segments and whose cut triangle holds no obstacle. A chord's corners lie on the
/// path it replaced; cutting moves them in towards the walls, which a pass of chords alone
/// cannot do once every chord touches its margin.
fn cut_corners(
    path: &[(Point, Real)],
    model: &dyn ClearanceModel,
    rays: &Rays,
    cell: Real,
) -> Vec<(Point, Real)> {
    let mut out = vec![path[0]];
    for k in 1..path.len() - 1 {
        let (a, v, b) = (out[out.len() - 1].0, path[k].0, path[k + 1].0);
        let (ta, tb) = (path[k].1, path[k + 1].1);
        let target = ta.min(tb);
        let cut_at = |s: Real| {
            let (w1, w2) = (v + (a - v) * s, v + (b - v) * s);
            let ok = target > 0.0
                && clear_at_least(model, w1, w2, target, cell)
                && rays.sweep_is_clear(
                    &[w1, v, w2],
                    &[w1, Point::from((w1.coords + w2.coords) * 0.5), w2],
                );
            ok.then_some((w1, w2))
        };
        let mut best = None;
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..CUT_STEPS {
            let s = 0.5 * (lo + hi);
            match cut_at(s) {
                Some(w) => {
                    best = Some(w);
                    lo = s;
                }
                None => hi = s,
            }
        }
        match best {
            Some((w1, w2)) if (w1 - v).norm() > 0.05 * cell && (w2 - v).norm() > 0.05 * cell => {
                out.push((w1, ta));
                out.push((w2, target));
            }
            _ => out.push(path[k]),
        }
    }
    out.push(path[path.len() - 1]);
    out
}

/// Halving steps of [`cut_corners`]' search.
const CUT_STEPS: usize = 6;

/// One pass of [`pull_taut`] over `path`, whose points carry the margin of the segment that
/// ends at them. `checked`: each chord must also enclose no obstacle with the stretch it
/// replaces (their loop's word is empty), which proves that the pass keeps the class.
fn pull_pass(
    path: &[(Point, Real)],
    model: &dyn ClearanceModel,
    rays: &Rays,
    cell: Real,
    checked: bool,
) -> Vec<(Point, Real)> {
    // A point every cell, each with the least margin of the segments it is on.
    let mut dense = vec![path[0].0];
    let mut margin = vec![path.get(1).map_or(0.0, |p| p.1)];
    for (k, w) in path.windows(2).enumerate() {
        let n = ((w[1].0 - w[0].0).norm() / cell).ceil().max(1.0) as usize;
        let next = path.get(k + 2).map_or(w[1].1, |p| p.1.min(w[1].1));
        for j in 1..n {
            dense.push(w[0].0 + (w[1].0 - w[0].0) * (j as Real / n as Real));
            margin.push(w[1].1);
        }
        // The vertex itself, exactly (the goal stays the goal).
        dense.push(w[1].0);
        margin.push(next);
    }
    let target = |i: usize, j: usize| {
        margin[i..=j]
            .iter()
            .copied()
            .fold(Real::INFINITY, Real::min)
    };
    let loop_is_trivial = |i: usize, j: usize| {
        let mut w = rays.signature(&dense[i..=j]);
        rays.cross_segment(&dense[j], &dense[i], &mut w);
        w.is_identity()
    };
    let ok = |i: usize, j: usize| {
        j == i + 1 || {
            let t = target(i, j);
            t > 0.0
                && clear_at_least(model, dense[i], dense[j], t, cell)
                && (!checked || loop_is_trivial(i, j))
        }
    };
    let last = dense.len() - 1;
    let mut out = vec![(dense[0], 0.0)];
    let mut i = 0;
    while i < last {
        // Doubling while the chord is admissible, then halving between the last
        // admissible and the first refused.
        let (mut good, mut step, mut bad) = (i + 1, 2, None);
        while good < last {
            let j = (i + step).min(last);
            if ok(i, j) {
                good = j;
                step *= 2;
            } else {
                bad = Some(j);
                break;
            }
        }
        if let Some(mut hi) = bad {
            while hi - good > 1 {
                let mid = good + (hi - good) / 2;
                if ok(i, mid) {
                    good = mid;
                } else {
                    hi = mid;
                }
            }
        }
        out.push((dense[good], target(i, good).max(0.0)));
        i = good;
    }
    out
}

/// Most passes of [`pull_taut`].
const PULL_PASSES: usize = 6;

/// The most clearance, in cells, a pulled chord must keep (less where the stretch it
/// replaces keeps less).
const PULL_MARGIN: Real = 1.0;

/// Shortcuts tried at each end of a seed, farthest first.
const SHORTCUT_TRIES: usize = 32;

/// Whether the segment `ab` keeps at least `target` clearance. First the model's bound on
/// the whole segment; else a march from `a`: the clearance is 1-Lipschitz, so from a point
/// `d` clear every point within `d - target` further on is at least `target` clear, and the
/// march steps that far (at least an eighth of a cell, the step then certified by the
/// model's bound on it) until it comes within `d(b) - target` of `b`. Each point's exact
/// clearance is computed once. `false` when a point, or an eighth-of-a-cell step, is not
/// certified.
fn clear_at_least(
    model: &dyn ClearanceModel,
    a: Point,
    b: Point,
    target: Real,
    cell: Real,
) -> bool {
    let (da, db) = (model.exact_clearance(&a), model.exact_clearance(&b));
    if da < target || db < target {
        return false;
    }
    if model.segment_clearance_between(&a, &b, da, db) >= target {
        return true;
    }
    let len = (b - a).norm();
    let dir = (b - a) / len;
    let end = len - (db - target);
    let min_step = 0.125 * cell;
    let (mut s, mut p, mut d) = (0.0, a, da);
    loop {
        if s + (d - target) >= end {
            return true;
        }
        if d - target >= min_step {
            s += d - target;
            p = a + dir * s;
            d = model.exact_clearance(&p);
            if d < target {
                return false;
            }
        } else {
            let next = (s + min_step).min(len);
            let q = a + dir * next;
            let dq = model.exact_clearance(&q);
            if dq < target || model.segment_clearance_between(&p, &q, d, dq) < target {
                return false;
            }
            (s, p, d) = (next, q, dq);
        }
    }
}

/// The graph's edges run along cell sides, so in a passage one cell wide a class path can lie
/// on an obstacle's boundary. This resamples the path every half cell and moves each inner
/// point up the clearance gradient, a quarter cell at a time, until it is two cells clear or
/// stops gaining: the seed runs down the middle of passages.
fn centre(poly: &[Point], model: &dyn ClearanceModel, cell: Real) -> Vec<Point> {
    let len: Real = poly.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let n = ((len / (0.5 * cell)).ceil() as usize).clamp(2, 20_000);
    let mut pts = resample(poly, n - 1);
    if pts.len() < 3 {
        // No inner point (a path of one point, start and goal at one node).
        return pts;
    }
    let last = pts.len() - 1;
    // Most points are already two cells clear: their clearances come in one batch.
    let clear = clearances_of(model, &pts);
    for (p, &c) in pts[1..last].iter_mut().zip(&clear[1..last]) {
        if c >= 2.0 * cell {
            continue;
        }
        for _ in 0..8 {
            let (d, g) = model.clearance(p);
            if d >= 2.0 * cell || g.norm() < 1e-9 {
                break;
            }
            let q = *p + g.normalize() * (0.25 * cell);
            if model.clearance_value(&q) <= d {
                break;
            }
            *p = q;
        }
    }
    pts
}

/// Via-points for a seed polyline: Douglas-Peucker vertices, the tolerance halved until the
/// spline through them is admissible (in the class, inside the bounds, clear of obstacles and
/// of the guard's floor); then evenly spaced points, more and more of them. The first
/// admissible set wins; `None` if none is.
fn seed_points(
    poly: &[Point],
    model: &dyn ClearanceModel,
    guard: &Guard<'_>,
    cfg: &GrowthConfig,
) -> Option<Vec<Point>> {
    let ok = |pts: &[Point]| {
        Spline::new(pts, cfg.parametrization, cfg.end).is_ok_and(|sp| {
            guard.cost(&sp, model, cfg).is_finite() && is_collision_free(&sp, model)
        })
    };
    let len: Real = poly.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let mut tol = len / 8.0;
    let limit = cfg.max_via_points + 2;
    for _ in 0..16 {
        let pts = homospline_geom::math::douglas_peucker(poly, tol, limit);
        if ok(&pts) {
            return Some(pts);
        }
        if pts.len() >= limit {
            break;
        }
        tol *= 0.5;
    }
    (1..=cfg.max_via_points)
        .map(|inner| resample(poly, inner))
        .find(|pts| ok(pts))
}

/// The densest evenly spaced via-points, when no set is admissible: the class is optimised
/// and reported as it ends up.
fn last_resort(poly: &[Point], cfg: &GrowthConfig) -> Vec<Point> {
    resample(poly, cfg.max_via_points)
}

/// Via-points for a seed polyline that runs through free cells (a map's ridge), by certified
/// subdivision: the Douglas-Peucker vertices at one cell, with no gap longer than
/// [`SEED_MAX_GAP`] cells, then a via-point added at the middle (by arc length along the
/// seed) of every spline segment that is not certified collision-free, until all are. As
/// via-points close in, the spline tends to the polyline, which has positive clearance, so
/// this ends; it is also stopped at one via-point per quarter cell of path. The count follows
/// the path: a long winding path gets many via-points, a straight one few. If the spline is
/// certified but leaves its class or the bounds, every segment is halved. With `max_points`,
/// `None` once the points would be more than that (always `Some` without).
fn subdivided_seed(
    poly: &[Point],
    model: &dyn ClearanceModel,
    guard: &Guard<'_>,
    cfg: &GrowthConfig,
    cell: Real,
    max_points: Option<usize>,
) -> Option<Vec<Point>> {
    let mut cum = Vec::with_capacity(poly.len());
    let mut acc = 0.0;
    cum.push(0.0);
    for w in poly.windows(2) {
        acc += (w[1] - w[0]).norm();
        cum.push(acc);
    }
    let total = acc;
    let at = |s: Real| -> Point {
        let i = cum.partition_point(|&c| c < s).clamp(1, poly.len() - 1);
        let seg = cum[i] - cum[i - 1];
        let f = if seg > 0.0 {
            ((s - cum[i - 1]) / seg).clamp(0.0, 1.0)
        } else {
            0.0
        };
        poly[i - 1] + (poly[i] - poly[i - 1]) * f
    };
    // Arc-length positions of the Douglas-Peucker vertices (a subsequence of the polyline).
    let kept = homospline_geom::math::douglas_peucker(poly, cell, usize::MAX);
    let mut params = Vec::with_capacity(kept.len());
    let mut k = 0;
    for (i, p) in poly.iter().enumerate() {
        if k < kept.len() && *p == kept[k] {
            params.push(cum[i]);
            k += 1;
        }
    }
    let max_gap = SEED_MAX_GAP * cell;
    let mut filled = vec![params[0]];
    for w in params.windows(2) {
        let n = ((w[1] - w[0]) / max_gap).ceil().max(1.0) as usize;
        for j in 1..=n {
            filled.push(w[0] + (w[1] - w[0]) * j as Real / n as Real);
        }
    }
    let mut params = filled;
    params.dedup();
    grade(&mut params);
    let cap = ((total / (0.25 * cell)).ceil() as usize).max(3);
    let cap = max_points.map_or(cap, |m| cap.min(m));
    loop {
        let pts: Vec<Point> = params.iter().map(|&s| at(s)).collect();
        if max_points.is_some_and(|m| pts.len() > m) {
            return None;
        }
        let Ok(sp) = Spline::new(&pts, cfg.parametrization, cfg.end) else {
            return Some(pts);
        };
        let mut bad = homospline_spline::certify::uncertified_segments(&sp, model);
        if bad.is_empty() {
            if guard.cost(&sp, model, cfg).is_finite() {
                return Some(pts);
            }
            bad = (0..sp.segments()).collect();
        }
        if params.len() + bad.len() > cap {
            return Some(pts);
        }
        let mut next = Vec::with_capacity(params.len() + bad.len());
        let mut b = bad.iter().peekable();
        for (i, &s) in params.iter().enumerate() {
            next.push(s);
            if b.peek() == Some(&&i) {
                b.next();
                next.push(0.5 * (s + params[i + 1]));
            }
        }
        params = next;
        grade(&mut params);
    }
}

/// Splits every gap longer than twice a neighbouring one, until none is: with uniform
/// parameters a spline through unevenly spaced via-points overshoots, and graded spacing
/// keeps it close to its polyline.
fn grade(params: &mut Vec<Real>) {
    loop {
        let gaps: Vec<Real> = params.windows(2).map(|w| w[1] - w[0]).collect();
        let split: Vec<bool> = (0..gaps.len())
            .map(|i| {
                let left = if i > 0 { gaps[i - 1] } else { Real::INFINITY };
                let right = gaps.get(i + 1).copied().unwrap_or(Real::INFINITY);
                gaps[i] > 2.0 * left.min(right)
            })
            .collect();
        if !split.iter().any(|&b| b) {
            return;
        }
        let mut next = Vec::with_capacity(params.len() * 2);
        for (i, &s) in params.iter().enumerate() {
            next.push(s);
            if split.get(i).copied().unwrap_or(false) {
                next.push(0.5 * (s + params[i + 1]));
            }
        }
        *params = next;
    }
}

/// The reported path of a certified curve: its arc-length samples, with curve points added
/// (by halving the parameter interval, up to 16 times) wherever the chord between two samples
/// is not clear although the curve is, as where a curve passes a corner at a small clearance:
/// the path that is checked segment by segment and reported is then clear too. With the
/// path, the least clearance of its segments (`ClearanceModel::polyline_clearance`), from
/// the same checks.
fn refine_samples(
    sp: &Spline,
    model: &dyn ClearanceModel,
    samples: &[(Real, Point)],
) -> (Vec<Point>, Real) {
    let mut out = Vec::with_capacity(samples.len());
    let mut least = Real::INFINITY;
    let Some(&(_, first)) = samples.first() else {
        return (out, least);
    };
    out.push(first);
    // Runs of REFINE_RUN segments whose box the model proves clear need no refinement, and
    // their segments are checked only if the box could hold the least of them (below).
    let margin = |d: Real| 1e-9 * (1.0 + d.abs());
    let mut proven: Vec<(Real, usize, usize)> = Vec::new();
    let mut stack = Vec::new();
    let segments = samples.len() - 1;
    let mut k0 = 0;
    while k0 < segments {
        let k1 = (k0 + REFINE_RUN).min(segments);
        let (mut lo, mut hi) = (samples[k0].1, samples[k0].1);
        for (_, p) in &samples[k0 + 1..=k1] {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let bound = model.box_clearance(&lo, &hi);
        if bound > margin(bound) {
            out.extend(samples[k0 + 1..=k1].iter().map(|s| s.1));
            proven.push((bound, k0, k1));
            k0 = k1;
            continue;
        }
        for w in samples[k0..=k1].windows(2) {
            stack.push((w[0], w[1], 0u32));
            while let Some(((ta, pa), (tb, pb), depth)) = stack.pop() {
                let d = model.segment_clearance(&pa, &pb);
                if depth >= 16 || d > 0.0 {
                    least = least.min(d);
                    out.push(pb);
                    continue;
                }
                let tm = 0.5 * (ta + tb);
                let pm = sp.position(tm);
                stack.push(((tm, pm), (tb, pb), depth + 1));
                stack.push(((ta, pa), (tm, pm), depth + 1));
            }
        }
        k0 = k1;
    }
    // The proven runs, least bound first, until a bound is clearer than the least segment
    // found: the least is the same as checking every segment.
    proven.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (bound, k0, k1) in proven {
        if bound > least + margin(least) {
            break;
        }
        for w in samples[k0..=k1].windows(2) {
            least = least.min(model.segment_clearance(&w[0].1, &w[1].1));
        }
    }
    (out, least)
}

/// Segments per run in [`refine_samples`]: a run's box is a unit or so on a scene's path.
const REFINE_RUN: usize = 16;

/// A scene's dense seed (a last resort that stayed in collision) has at most this many times
/// the points of a normal one (`max_via_points` and the ends); past that it is not tried.
pub const DENSE_SEED_SHARE: usize = 8;

/// Longest gap between a map seed's first via-points, cells.
pub const SEED_MAX_GAP: Real = 16.0;

fn resample(poly: &[Point], inner: usize) -> Vec<Point> {
    if poly.len() < 2 {
        // A class path of one point (start and goal at one node): nothing to spread.
        return poly.to_vec();
    }
    let cum: Vec<Real> = std::iter::once(0.0)
        .chain(poly.windows(2).scan(0.0, |acc, w| {
            *acc += (w[1] - w[0]).norm();
            Some(*acc)
        }))
        .collect();
    let total = *cum.last().unwrap_or(&0.0);
    let mut out = vec![poly[0]];
    for k in 1..=inner {
        let target = total * k as Real / (inner + 1) as Real;
        let i = cum
            .partition_point(|&c| c < target)
            .clamp(1, poly.len() - 1);
        let seg = cum[i] - cum[i - 1];
        let f = if seg > 0.0 {
            (target - cum[i - 1]) / seg
        } else {
            0.0
        };
        out.push(poly[i - 1] + (poly[i] - poly[i - 1]) * f);
    }
    out.push(poly[poly.len() - 1]);
    out.dedup();
    out
}

/// A class's growth settings (with the robot's start heading, when it has one and the class
/// does not start backwards) and its guard.
fn class_setup<'w>(
    world: &'w World<'_>,
    seed_poly: &[Point],
    signature: Option<&'w Signature>,
    cfg: &'w PlanConfig,
) -> (Cow<'w, GrowthConfig>, Guard<'w>) {
    let growth = match cfg.start_heading {
        Some(h) if seed_poly.len() > 1 && (seed_poly[1] - seed_poly[0]).dot(&h) > 0.0 => {
            let mut g = cfg.growth.clone();
            g.end = EndCondition::StartHeading { direction: h };
            Cow::Owned(g)
        }
        _ => Cow::Borrowed(&cfg.growth),
    };
    let guard = Guard {
        class: signature.map(|s| (&world.rays, s)),
        bounds: world.bounds,
        collision_free: signature.is_some(),
        clearance_floor: if cfg.clearance_floor > 0.0 {
            cfg.clearance_floor
        } else {
            Real::NEG_INFINITY
        },
        // The target is `dm` plus the certification's tolerance: a curve held exactly at `dm`
        // certifies up to that tolerance below it and would be reported unsafe (and ranked
        // after costlier safe classes) by the tolerance's chance.
        clearance_target: match signature {
            Some(sig) if cfg.dm_rule => {
                let dm = growth.cost.dm + cfg.certify_tolerance.max(0.0);
                let share = DM_RULE_SHARE * bottleneck(seed_poly, world.model);
                if share >= dm
                    || world
                        .circles
                        .is_some_and(|c| keeps_dm(world, c, seed_poly, sig, dm))
                {
                    dm
                } else {
                    share
                }
            }
            _ => Real::NEG_INFINITY,
        },
        proven: Default::default(),
    };
    (growth, guard)
}

/// A guard that only keeps candidates in the class, in bounds and clear: a seed need only be
/// collision-free (the growth loop's ratchet raises it to the floor).
fn without_floor<'w>(guard: &Guard<'w>) -> Guard<'w> {
    Guard {
        clearance_floor: Real::NEG_INFINITY,
        ..guard.clone()
    }
}

/// The repair round of every class that could rank first ([`ClassTask::repair`]): one whose
/// loop ended on a curve that its cost's `m(C)` took to keep the target but that is not
/// proven to, and that costs less than every class reported certified safe (at the
/// clearance floor). Each is reported again in its place in `runs`.
fn repair_contenders(
    world: &World<'_>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    tasks: &mut [(usize, ClassTask<'_>)],
    runs: &mut [(usize, ClassRun)],
) {
    let best_safe = runs
        .iter()
        .filter(|(_, (c, _))| {
            c.collision_free && c.safe && c.certified_clearance >= cfg.clearance_floor
        })
        .map(|(_, (c, _))| c.cost.total)
        .fold(Real::INFINITY, Real::min);
    let contenders: Vec<usize> = runs
        .iter()
        .filter(|(_, (c, _))| c.collision_free && c.cost.total < best_safe)
        .map(|(i, _)| *i)
        .collect();
    if contenders.is_empty() {
        return;
    }
    let model = world.model;
    let repaired: Vec<(usize, ClassRun)> = in_pool(pool, || {
        tasks
            .par_iter_mut()
            .with_max_len(1)
            .filter(|(i, _)| contenders.contains(i))
            .filter_map(|(i, task)| task.repair(model).then(|| (*i, task.report(world, cfg))))
            .collect()
    });
    for (i, run) in repaired {
        if let Some(slot) = runs.iter_mut().find(|(j, _)| *j == i) {
            slot.1 = run;
        }
    }
}

/// The order of the plan's ranking: collision-free and safe first, then collision-free,
/// then the rest; within each by cost, then by signature.
fn rank_order(a: &ClassPlan, b: &ClassPlan) -> std::cmp::Ordering {
    let group = |c: &ClassPlan| match (c.collision_free, c.safe) {
        (true, true) => 0,
        (true, false) => 1,
        _ => 2,
    };
    group(a)
        .cmp(&group(b))
        .then(a.cost.total.total_cmp(&b.cost.total))
        .then(a.signature.cmp(&b.signature))
}

/// Whether the plan may choose the class: collision-free and certified at least as clear as
/// the floor. The chosen class is the first such in [`rank_order`].
fn choosable(c: &ClassPlan, cfg: &PlanConfig) -> bool {
    c.collision_free && c.certified_clearance >= cfg.clearance_floor
}

/// [`PlanConfig::polish`]: the class the plan will choose (first in [`rank_order`] among
/// the [`choosable`] classes) runs its polish
/// rounds and is reported again in its place in `runs`. The polish is kept only if the
/// class's new report still stands where the old one did: the same class, collision-free,
/// at least as clear as the floor, safe if it was, and no dearer (so it stays first);
/// otherwise its curve is put back, its rounds and evaluations still counted. (Without a
/// finite clearance target, under `--soft-dm` or from a straight seed, the rounds have
/// nothing else to hold them.) A class stopped by the pruning is not polished.
/// Without polish rounds, [`PlanConfig::finish_within`]: if the classes' evaluations so far
/// are fewer, the chosen class gets the finish alone ([`Growth::finish`]) with what is left,
/// kept or put back the same way.
fn polish_chosen(
    world: &World<'_>,
    cfg: &PlanConfig,
    tasks: &mut [(usize, ClassTask<'_>)],
    runs: &mut [(usize, ClassRun)],
) {
    if world.grid_is_exact {
        // Scenes only: a map's classes are optimised while its search goes on.
        return;
    }
    let spent: usize = runs.iter().map(|(_, (c, _))| c.evaluations).sum();
    let finish_cap = cfg.finish_within.unwrap_or(0).saturating_sub(spent);
    if cfg.polish == 0 && finish_cap == 0 {
        return;
    }
    let Some((chosen, old)) = runs
        .iter()
        .filter(|(_, (c, _))| choosable(c, cfg))
        .min_by(|(_, (a, _)), (_, (b, _))| rank_order(a, b))
        .map(|(i, (c, _))| (*i, c.clone()))
    else {
        return;
    };
    let Some((_, task)) = tasks.iter_mut().find(|(i, _)| *i == chosen) else {
        return;
    };
    let saved = task.state.clone();
    let ran = if cfg.polish > 0 {
        task.polish(world.model, cfg.polish)
    } else {
        task.finish(world.model, finish_cap)
    };
    if !ran {
        return;
    }
    let mut run = task.report(world, cfg);
    let new = &run.0;
    let stands = new.signature == old.signature
        && choosable(new, cfg)
        && (new.safe || !old.safe)
        && new.cost.total <= old.cost.total;
    if !stands {
        if let (Some(g), Some(earlier)) = (task.state.as_mut(), saved) {
            g.undo_to(earlier);
        }
        run = task.report(world, cfg);
    }
    if let Some(slot) = runs.iter_mut().find(|(i, _)| *i == chosen) {
        slot.1 = run;
    }
}

/// A class's task from its seed: on a map the seed is first pulled taut in its class.
fn start_class<'w>(
    world: &'w World<'_>,
    cfg: &'w PlanConfig,
    poly: &[Point],
    sig: Option<&'w Signature>,
    gcost: Real,
    cell: Option<Real>,
) -> ClassTask<'w> {
    let poly = match (sig, cell) {
        (Some(s), Some(cell)) if world.grid_is_exact => {
            pull_taut(poly, world.model, &world.rays, cell, s)
        }
        _ => poly.to_vec(),
    };
    ClassTask::new(world, poly, sig, gcost, cfg, cell)
}

/// A class path made into a seed: its ends at the start and the goal (the class path runs
/// from the start node to the goal node, which sit there), shortcut where the attach route
/// meets the ridge behind them ([`shortcut_ends`]), and on a scene centred ([`centre`]:
/// a rasterised scene's class path runs along cell sides; a map's already runs along the
/// ridge through free cells, and is pulled taut in its class's own task), each change kept
/// only if the class stays.
fn class_seed(
    world: &World<'_>,
    cell: Real,
    polyline: &[Point],
    signature: &Signature,
) -> Vec<Point> {
    let rays = &world.rays;
    let mut poly = polyline.to_vec();
    poly[0] = world.start;
    let last = poly.len() - 1;
    poly[last] = world.goal;
    let poly = shortcut_ends(&poly, world.model, cell, |p| {
        rays.signature(p) == *signature
    });
    if world.grid_is_exact {
        return poly;
    }
    let centred = centre(&poly, world.model, cell);
    if rays.signature(&centred) == *signature {
        centred
    } else {
        poly
    }
}

/// One class optimised, and whether it is worth the dense second pass
/// ([`ClassTask::dense`]): its seed was a scene's last resort (no via-point set was
/// admissible) and the curve it gave is not proven clear.
type ClassRun = (ClassPlan, bool);

/// One class's work: its seed, its settings and guard, and its growth loop, which runs one
/// round at a time so that the planner can stop a class that cannot win between rounds.
struct ClassTask<'w> {
    /// The class path the seed came from (pulled taut on a map).
    seed_poly: Vec<Point>,
    signature: Option<&'w Signature>,
    graph_cost: Real,
    growth: GrowthConfig,
    guard: Guard<'w>,
    /// The via-points the growth loop started from.
    seed: Vec<Point>,
    /// The seed is the last resort of a scene's class.
    resorted: bool,
    /// `None` when the growth loop could not start.
    state: Option<Growth>,
    /// Milliseconds spent so far.
    time_ms: Real,
    /// Stopped after its first round by [`outclassed`].
    pruned: bool,
}

impl<'w> ClassTask<'w> {
    /// The class's setup and seed; no round run yet.
    fn new(
        world: &'w World<'_>,
        seed_poly: Vec<Point>,
        signature: Option<&'w Signature>,
        graph_cost: Real,
        cfg: &'w PlanConfig,
        graph_cell: Option<Real>,
    ) -> Self {
        let t = Instant::now();
        let model = world.model;
        let (growth, guard) = class_setup(world, &seed_poly, signature, cfg);
        let mut growth = growth.into_owned();
        // On scenes the first via-point set that already keeps the floor is preferred.
        let seed_guard = without_floor(&guard);
        let mut resorted = false;
        let mut seed = match (signature, graph_cell) {
            (Some(_), Some(cell)) if world.grid_is_exact => {
                subdivided_seed(&seed_poly, model, &seed_guard, &growth, cell, None)
                    .unwrap_or_else(|| seed_poly.clone())
            }
            (Some(_), _) => guard
                .clearance_floor
                .is_finite()
                .then(|| seed_points(&seed_poly, model, &guard, &growth))
                .flatten()
                .or_else(|| seed_points(&seed_poly, model, &seed_guard, &growth))
                .unwrap_or_else(|| {
                    resorted = true;
                    last_resort(&seed_poly, &growth)
                }),
            (None, _) => seed_poly.clone(),
        };
        // The ends are the start and goal to the bit: a map seed's interpolation ended a
        // class's path at 1.9999999999999998 for a goal at 2.
        if let (Some(first), Some(&s)) = (seed.first_mut(), seed_poly.first()) {
            *first = s;
        }
        if let (Some(last), Some(&t)) = (seed.last_mut(), seed_poly.last()) {
            *last = t;
        }
        // On a map the via-points follow the path (hundreds on a long one), and with uniform
        // parameters over [0, 1] the roughness grows with a power of their number (the
        // paper's form: the first; the energy: the third): it would swamp every other term.
        // There it is measured with one unit of parameter per segment, which is the same
        // integral divided by segments^power (`RoughnessForm::segment_power`).
        if world.grid_is_exact && seed.len() > 2 {
            growth.cost.w_roughness /=
                ((seed.len() - 1) as Real).powf(growth.cost.roughness.segment_power());
        }
        let state = Growth::new(&seed, model, &growth, &guard).ok();
        Self {
            seed_poly,
            signature,
            graph_cost,
            growth,
            guard,
            seed,
            resorted,
            state,
            time_ms: ms(t),
            pruned: false,
        }
    }

    /// The class as [`outclassed`] weighs it, after its first round (`class`: its index).
    fn score(&self, class: usize, model: &dyn ClearanceModel) -> Score {
        let Some(g) = self.state.as_ref() else {
            return Score {
                class,
                standing: Real::INFINITY,
                total: Real::INFINITY,
                reference: false,
                done: true,
            };
        };
        let sp = g.curve(&self.guard);
        let terms = evaluate_weighted(sp, model, &g.settings(&self.growth).cost);
        let standing = self.guard.value(&terms);
        let reference = standing < SHORT_OF_TARGET
            && self.guard.clearance_target >= self.growth.cost.dm
            && terms.total > 0.0
            && self.signature.is_some()
            && is_collision_free(sp, model);
        Score {
            class,
            standing,
            total: terms.total,
            reference,
            done: g.is_done(),
        }
    }

    /// `f` on the class's loop, its time added to the class's; `none` when the loop could
    /// not start.
    fn timed<R>(
        &mut self,
        none: R,
        f: impl FnOnce(&mut Growth, &GrowthConfig, &Guard<'w>) -> R,
    ) -> R {
        let t = Instant::now();
        let out = match self.state.as_mut() {
            Some(g) => f(g, &self.growth, &self.guard),
            None => none,
        };
        self.time_ms += ms(t);
        out
    }

    /// Runs one round; `false` when the loop has ended (or never started).
    fn step(&mut self, model: &dyn ClearanceModel) -> bool {
        self.timed(false, |g, cfg, guard| g.step(model, cfg, guard))
    }

    /// The class's repair round, if its loop ended on a curve whose clearance its cost
    /// overstated ([`Growth::repair`]); a class stopped by the pruning is not repaired.
    /// Returns whether it ran.
    fn repair(&mut self, model: &dyn ClearanceModel) -> bool {
        !self.pruned && self.timed(false, |g, cfg, guard| g.repair(model, cfg, guard))
    }

    /// The class's polish rounds ([`Growth::polish`]); a class stopped by the pruning is
    /// not polished. Returns whether a round ran (kept or undone).
    fn polish(&mut self, model: &dyn ClearanceModel, rounds: usize) -> bool {
        !self.pruned
            && self.timed(false, |g, cfg, guard| {
                let before = g.rounds().len();
                g.polish(model, cfg, guard, rounds);
                g.rounds().len() > before
            })
    }

    /// The class's finish-only polish round ([`Growth::finish`]) of at most `cap`
    /// evaluations; a class stopped by the pruning is not polished. Returns whether it ran.
    fn finish(&mut self, model: &dyn ClearanceModel, cap: usize) -> bool {
        !self.pruned
            && self.timed(false, |g, cfg, guard| {
                let before = g.rounds().len();
                g.finish(model, cfg, guard, cap);
                g.rounds().len() > before
            })
    }

    /// [`ClassTask::step`] that can be called off ([`Growth::step_unless`]).
    fn step_unless(&mut self, model: &dyn ClearanceModel, stop: &dyn Fn() -> bool) -> Option<bool> {
        self.timed(Some(false), |g, cfg, guard| {
            g.step_unless(model, cfg, guard, stop)
        })
    }

    /// The evaluation budget of its rounds left ([`Growth::budget_left`]).
    fn budget_left(&self) -> usize {
        self.state
            .as_ref()
            .map_or(0, |g| g.budget_left(&self.growth))
    }

    /// Runs the rounds left.
    fn run(&mut self, model: &dyn ClearanceModel) {
        while self.step(model) {}
    }

    /// The task with every round run, for a caller that does not stop classes early.
    fn optimised(mut self, model: &dyn ClearanceModel) -> Self {
        self.run(model);
        self
    }

    /// The class's plan from its best curve so far, and whether it is worth the dense pass.
    fn report(&self, world: &World<'_>, cfg: &PlanConfig) -> ClassRun {
        let t = Instant::now();
        let model = world.model;
        let grown = self
            .state
            .as_ref()
            .map(|g| g.result(model, &self.growth, &self.guard));
        let retry = self.resorted
            && grown
                .as_ref()
                .is_none_or(|g| !is_collision_free(&g.spline, model));
        let plan = report_class(world, self, cfg, grown, self.seed.clone());
        (
            ClassPlan {
                time_ms: self.time_ms + ms(t),
                pruned: self.pruned,
                ..plan
            },
            retry,
        )
    }

    /// The dense second pass of a class marked by [`ClassTask::report`] (it runs only when
    /// no class of the plan came out clear): the via-points follow the graph's path, as on a
    /// map, up to [`DENSE_SEED_SHARE`] times as many, if the path is clear (a winding passage
    /// too narrow for a spline through `max_via_points` via-points; L-BFGS cannot even start
    /// from a colliding seed). `Some` only if the curve comes out clear; its evaluations and
    /// time include the first pass's.
    fn dense(
        &self,
        world: &World<'_>,
        cfg: &PlanConfig,
        graph_cell: Option<Real>,
        first: &ClassPlan,
    ) -> Option<ClassPlan> {
        let t = Instant::now();
        let model = world.model;
        let (growth, guard) = (&self.growth, &self.guard);
        let cell = graph_cell.filter(|_| model.polyline_clearance(&self.seed_poly) > 0.0)?;
        let dense = subdivided_seed(
            &self.seed_poly,
            model,
            &without_floor(guard),
            growth,
            cell,
            Some(DENSE_SEED_SHARE * (growth.max_via_points + 2)),
        )?;
        let mut grown = grow(&dense, model, growth, guard).ok()?;
        if !is_collision_free(&grown.spline, model) {
            return None;
        }
        grown.evaluations += first.evaluations;
        let plan = report_class(world, self, cfg, Some(grown), dense);
        Some(ClassPlan {
            time_ms: first.time_ms + ms(t),
            ..plan
        })
    }
}

/// A class after its first round, as [`outclassed`] weighs it.
#[derive(Clone, Copy)]
struct Score {
    /// The class's index among the seeds (ties).
    class: usize,
    /// The outer guard's value of its curve: short of the target ranks after every class
    /// that keeps it.
    standing: Real,
    /// Its weighted cost.
    total: Real,
    /// It can be the reference: its curve keeps the dm rule's target, the target is `dm`
    /// itself, and it is certified clear.
    reference: bool,
    /// Its loop ended with its first round (nothing to stop).
    done: bool,
}

/// The classes stopped after their first round ([`outclassed`]) and the cost that stopped
/// them.
struct Pruning {
    /// One flag per class, in the order of the scores: stopped.
    stop: Vec<bool>,
    /// The reference class's weighted cost after its first round.
    reference_cost: Real,
}

/// Which classes cannot win after their first round, by the ratio `ratio` ([`PlanConfig::
/// prune`]). The reference is the class that ranks first now among those sure to rank in
/// the first group at the end (collision-free and safe): its curve keeps the dm rule's
/// target, and the target is `dm` itself (not a narrow passage's share of it), it meets the
/// floor, and it is certified clear. Its cost only falls in later rounds (the growth loop
/// returns its best curve), and it stays in the first group (its curves keep the target), so
/// a class whose cost exceeds `ratio` times the reference's would have to lower its own by
/// more than the ratio in the rounds it skips to overtake it. `None` when no class
/// qualifies (no dm rule, or no class at `dm` yet) or none would be stopped.
fn outclassed(scores: &[Option<Score>], ratio: Real) -> Option<Pruning> {
    let r = scores
        .iter()
        .enumerate()
        .filter_map(|(pos, s)| s.filter(|s| s.reference).map(|s| (pos, s)))
        .min_by(|(_, a), (_, b)| {
            a.standing
                .total_cmp(&b.standing)
                .then(a.class.cmp(&b.class))
        })?;
    let (reference, reference_cost) = (r.0, r.1.total);
    let bar = ratio * reference_cost;
    let stop: Vec<bool> = scores
        .iter()
        .enumerate()
        .map(|(pos, s)| pos != reference && s.is_some_and(|s| !s.done && s.total > bar))
        .collect();
    stop.contains(&true).then_some(Pruning {
        stop,
        reference_cost,
    })
}

/// A class's plan from its grown curve (`None`: the growth loop could not start, and the
/// seed's via-points are reported): the path sampled for the report, its certification and
/// its checks. The time is left at 0 for the caller.
fn report_class(
    world: &World<'_>,
    task: &ClassTask<'_>,
    cfg: &PlanConfig,
    grown: Option<Grown>,
    seed: Vec<Point>,
) -> ClassPlan {
    let (model, rays) = (world.model, &world.rays);
    let (seed_poly, signature, graph_cost) = (&task.seed_poly, task.signature, task.graph_cost);
    let (via_points, spline, terms, rounds, evaluations) = match grown {
        Some(g) => (g.points, Some(g.spline), g.terms, g.rounds, g.evaluations),
        None => (seed, None, CostTerms::default(), Vec::new(), 0),
    };
    let (path, length, min_clear, certified, free, in_class) = match &spline {
        Some(sp) => {
            let length = sp.length();
            let mut cert = min_clearance(sp, model, cfg.certify_tolerance);
            if !cert.collision_free() && cert.upper > 0.0 && is_collision_free(sp, model) {
                // Proven clear, but closer than the tolerance to an obstacle (a one-cell
                // door): bracket it tightly enough to say so.
                cert = min_clearance(sp, model, 1e-9_f64.max(1e-6 * cert.upper));
            }
            let samples = sp.sample_by_arc_length(crate::growth::report_spacing(length));
            let (path, min_clear) = if cert.collision_free() {
                refine_samples(sp, model, &samples)
            } else {
                let path: Vec<Point> = samples.into_iter().map(|(_, p)| p).collect();
                let least = model.polyline_clearance(&path);
                (path, least)
            };
            let inside = path.iter().all(|p| world.bounds.contains(p));
            let in_class = signature.is_none_or(|s| &rays.signature(&path) == s);
            (
                path,
                length,
                min_clear,
                cert.lower,
                min_clear > 0.0 && cert.collision_free() && inside,
                in_class,
            )
        }
        None => (
            Vec::new(),
            0.0,
            Real::NEG_INFINITY,
            Real::NEG_INFINITY,
            false,
            false,
        ),
    };
    let sig_text = match signature {
        Some(s) => s.to_string(),
        None => rays.signature(&path).to_string(),
    };
    ClassPlan {
        rank: 0,
        signature: sig_text,
        seed_path: seed_poly.to_vec(),
        via_points,
        path,
        cost: terms,
        length,
        min_clearance: min_clear,
        certified_clearance: certified,
        collision_free: free,
        safe: certified >= cfg.growth.cost.dm,
        in_class,
        iterations: rounds.len(),
        rounds,
        evaluations,
        time_ms: 0.0,
        graph_cost,
        overlap: 0.0,
        pruned: false,
    }
}

/// Candidates searched per class wanted when the selection limits overlap.
pub const DIVERSE_CANDIDATES: usize = 4;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_avoided_class_must_be_written_as_signatures_print() {
        for ok in ["e", "-1", "+3-1+12", "-12"] {
            assert_eq!(avoid_misfit(ok, 12), None, "{ok}");
        }
        for (bad, why) in [
            ("abc", "not a class"),
            ("", "not a class"),
            ("1-2", "not a class"),
            ("-", "not a class"),
            ("-1+", "not a class"),
            ("+0", "not a class"),
            ("-01", "not a class"),
            ("-1x", "not a class"),
            ("E", "not a class"),
            ("-13", "ray 13: there are 12 rays here"),
        ] {
            let got = avoid_misfit(bad, 12).unwrap_or_default();
            assert!(got.contains(why), "{bad}: {got}");
        }
    }
    use homospline_geom::Circle;
    use homospline_spline::CircleModel;
    use proptest::prelude::*;

    /// Rounds run ahead of the pruning decision and undone for the classes it stops leave
    /// no trace: on one thread, with every class's rounds run ahead before the next class
    /// starts, the plans of the scenes with a stopped class are those of the plain order.
    #[test]
    fn rounds_run_ahead_and_undone_leave_the_plan_as_it_was() {
        use std::sync::atomic::Ordering;
        let one = PlanConfig {
            threads: Some(1),
            ..PlanConfig::default()
        };
        let bare = |mut p: Plan| {
            p.timing = Timing::default();
            for c in &mut p.classes {
                c.time_ms = 0.0;
            }
            p
        };
        let scenes: Vec<Scene> = homospline_testkit::fixture_scenes()
            .into_iter()
            .filter(|s| ["convex", "narrow-pass", "two-homotopies"].contains(&s.name.as_str()))
            .collect();
        assert_eq!(scenes.len(), 3);
        for scene in &scenes {
            board::AHEAD_FIRST.store(false, Ordering::Relaxed);
            let plain = bare(plan(scene, &one).unwrap());
            assert!(
                plain.classes.iter().any(|c| c.pruned),
                "{}: nothing stopped",
                scene.name
            );
            board::AHEAD_FIRST.store(true, Ordering::Relaxed);
            let before = board::UNDONE.load(Ordering::Relaxed);
            let ahead = bare(plan(scene, &one).unwrap());
            let undone = board::UNDONE.load(Ordering::Relaxed) - before;
            board::AHEAD_FIRST.store(false, Ordering::Relaxed);
            assert!(undone > 0, "{}: no round undone", scene.name);
            assert_eq!(plain, ahead, "{}", scene.name);
        }
    }

    /// The least exact clearance over `n` evenly spaced points of `ab`, ends included.
    fn sampled(model: &CircleModel, a: Point, b: Point, n: usize) -> Real {
        (0..=n)
            .map(|k| model.exact_clearance(&(a + (b - a) * (k as Real / n as Real))))
            .fold(Real::INFINITY, Real::min)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// The march never certifies a segment that a dense sampling finds less clear than
        /// the target, and does certify one whose every point keeps the target with room.
        #[test]
        fn clear_at_least_is_sound(
            circles in prop::collection::vec((0.0..40.0f64, 0.0..40.0f64, 0.3..4.0f64), 1..12),
            ax in 0.0..40.0f64, ay in 0.0..40.0f64, bx in 0.0..40.0f64, by in 0.0..40.0f64,
            target in 0.0..2.0f64,
        ) {
            let model = CircleModel::new(circles.iter().map(|&(x, y, r)| Circle::new(x, y, r)).collect());
            let (a, b) = (Point::new(ax, ay), Point::new(bx, by));
            let dense = sampled(&model, a, b, 4000);
            if clear_at_least(&model, a, b, target, 0.25) {
                prop_assert!(dense >= target - 1e-9, "certified at {target} but {dense}");
            }
            // The circle model's segment distance is exact: a segment clear by a margin
            // is certified.
            if model.segment_clearance(&a, &b) >= target + 1e-6 {
                prop_assert!(clear_at_least(&model, a, b, target, 0.25));
            }
        }

        /// Pulled class paths of random scenes keep their ends and their class, are no
        /// longer than the graph's path, and every chord is clear of the circles.
        #[test]
        fn pulled_seeds_keep_their_class_and_are_clear_and_shorter(seed in 0u64..1_000) {
            let scene = homospline_testkit::random_scene("pull", seed, 60.0, 10, 3);
            let (_, _, graph) = homospline_voronoi::build(&scene, 4.0).unwrap();
            let rays = Rays::for_scene(&scene);
            let model = CircleModel::new(scene.circles());
            let search = SearchConfig { k: 4, ..SearchConfig::default() };
            let length = |p: &[Point]| -> Real { p.windows(2).map(|w| (w[1] - w[0]).norm()).sum() };
            for c in k_best_classes(&graph, &rays, &search).unwrap().classes {
                let mut poly = c.polyline.clone();
                poly[0] = scene.start;
                let last = poly.len() - 1;
                poly[last] = scene.goal;
                // Only paths that are clear to begin with are pulled taut.
                if poly.windows(2).any(|w| sampled(&model, w[0], w[1], 50) <= 0.0) {
                    continue;
                }
                let pulled = pull_taut(&poly, &model, &rays, 0.25, &c.signature);
                prop_assert_eq!(pulled[0], scene.start);
                prop_assert_eq!(pulled[pulled.len() - 1], scene.goal);
                prop_assert_eq!(rays.signature(&pulled), c.signature.clone());
                prop_assert!(length(&pulled) <= length(&poly) + 1e-9);
                for w in pulled.windows(2) {
                    let d = sampled(&model, w[0], w[1], 400);
                    prop_assert!(d > 0.0, "a chord comes {d} from the circles");
                }
            }
        }

        /// The reported path's least clearance comes from the same checks that refine it:
        /// it is the model's polyline clearance of the path, bit for bit.
        #[test]
        fn refined_paths_report_their_polyline_clearance(
            circles in prop::collection::vec((0.0..40.0f64, 0.0..40.0f64, 0.3..4.0f64), 1..12),
            via in prop::collection::vec((0.0..40.0f64, 0.0..40.0f64), 1..5),
            spacing in 0.2..2.0f64,
        ) {
            let model = CircleModel::new(circles.iter().map(|&(x, y, r)| Circle::new(x, y, r)).collect());
            let mut pts = vec![Point::new(-1.0, -1.0)];
            pts.extend(via.iter().map(|&(x, y)| Point::new(x, y)));
            pts.push(Point::new(41.0, 41.0));
            let Ok(sp) = Spline::new(&pts, homospline_spline::Parametrization::Uniform, EndCondition::Natural) else {
                return Ok(());
            };
            let (path, least) = refine_samples(&sp, &model, &sp.sample_by_arc_length(spacing));
            prop_assert_eq!(least.to_bits(), model.polyline_clearance(&path).to_bits());
        }
    }
}
