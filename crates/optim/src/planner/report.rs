//! What a plan reports ([`Plan`], [`ClassPlan`], [`Timing`]), and a class's report from its
//! grown curve: the path sampled and refined, its certification and its checks.

use std::cell::RefCell;
use std::time::Instant;

use homospline_geom::{Point, Real};
use homospline_homotopy::Signature;
use homospline_spline::{ClearanceModel, CostTerms, Spline, is_collision_free, min_clearance};
use homospline_voronoi::VoronoiGraph;

use super::config::{PlanConfig, Seed};
use super::world::World;
#[cfg(doc)]
use crate::growth::grow;
use crate::growth::{Grown, Round, in_class_beside, report_spacing};

/// One optimised class.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassPlan {
    /// 1 = best by the user's weights (collision-free classes first).
    pub rank: usize,
    /// Homotopy signature (stable text form).
    pub signature: String,
    /// The class path the seed came from (for `straight`: `S`, midpoint, `T`), or on a scene
    /// the class's taut path offered in its place and taken (a class path along the bounds).
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
    /// best of them: [`grow`]; or on a scene the segment `S-T` where it is better,
    /// `Growth::straight_if_better`).
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
    /// Where `dm` came from, when it was not given: on a map, the default derived from its
    /// cell ([`PlanConfig::map_dm`]).
    pub dm_why: Option<String>,
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
    /// The graph the classes were searched on (Voronoi seeds on a graph of its own, a
    /// scene's); `None` on a prepared map, whose query is not copied out of the map's graph
    /// (its graph: `PreparedMap::graph`, or a query's as a graph of its own:
    /// [`homospline_voronoi::QueryGraph::to_graph`]).
    pub graph: Option<VoronoiGraph>,
    /// The classes of [`PlanConfig::avoid`] that the class search found and left out, as
    /// given. One not here matched none of the classes the search offered (the k best and
    /// one more per avoided class), so it left nothing out: a front end says so.
    pub avoided: Vec<String>,
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

/// Milliseconds since `t`.
pub(super) fn ms(t: Instant) -> Real {
    t.elapsed().as_secs_f64() * 1e3
}

/// The plan when start and goal are one point: one class, `e`, the path that stays there,
/// with the point's clearance; nothing to optimise, and it costs nothing. (On a scene the
/// seeding panicked where the class path was one node, and elsewhere a curve looped a
/// thousandth of a unit; on a map the path was empty at clearance -inf, exit 1.)
pub(super) fn plan_to_stay(world: &World<'_>, cfg: &PlanConfig) -> Plan {
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
        dm_why: None,
        clearance_floor: cfg.clearance_floor,
        classes: vec![class],
        best,
        pareto: vec![1],
        timing: Timing::default(),
        graph: None,
        avoided: Vec::new(),
    }
}

/// Where a class's curve came from, as its report names it.
pub(super) struct Origin<'a> {
    /// The class path the seed came from (for `straight`: `S`, midpoint, `T`).
    pub seed_poly: &'a [Point],
    /// The class (none for the straight seed).
    pub signature: Option<&'a Signature>,
    /// Graph cost of the class path.
    pub graph_cost: Real,
    /// The guard's last in-class samples: the reported path's class is checked beside them
    /// ([`in_class_beside`]).
    pub in_class: &'a RefCell<Option<Vec<Point>>>,
}

/// A class's plan from its grown curve (`None`: the growth loop could not start, and the
/// seed's via-points are reported): the path sampled for the report, its certification and
/// its checks. The time is left at 0 for the caller.
pub(super) fn report_class(
    world: &World<'_>,
    origin: Origin<'_>,
    cfg: &PlanConfig,
    grown: Option<Grown>,
    seed: Vec<Point>,
) -> ClassPlan {
    let (model, rays) = (world.model, &world.rays);
    let Origin {
        seed_poly,
        signature,
        graph_cost,
        in_class: known,
    } = origin;
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
            let samples = sp.sample_by_arc_length(report_spacing(length));
            let (path, min_clear) = if cert.collision_free() {
                refine_samples(sp, model, &samples)
            } else {
                let path: Vec<Point> = samples.into_iter().map(|(_, p)| p).collect();
                let least = model.polyline_clearance(&path);
                (path, least)
            };
            let inside = path.iter().all(|p| world.bounds.contains(p));
            let in_class = signature
                .is_none_or(|s| in_class_beside(rays, s, known.borrow().as_deref(), &path));
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

/// The reported path of a certified curve: its arc-length samples, with curve points added
/// (by halving the parameter interval, up to 16 times) wherever the chord between two samples
/// is not clear although the curve is, as where a curve passes a corner at a small clearance:
/// the path that is checked segment by segment and reported is then clear too. With the
/// path, the least clearance of its segments (`ClearanceModel::polyline_clearance`), from
/// the same checks.
pub(super) fn refine_samples(
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
