//! One class's optimisation ([`ClassTask`]): its growth settings and guard (the dm rule's
//! target), its seed's via-points, its growth loop run a round at a time, its repair, polish
//! and finish, its report, and the dense second pass of a seed that stayed in collision.

use std::borrow::Cow;
use std::time::Instant;

use homospline_geom::{Bounds, Point, Real};
use homospline_homotopy::Signature;
use homospline_spline::{ClearanceModel, EndCondition, evaluate_weighted, is_collision_free};

use super::clearance::bottleneck;
use super::config::{DM_RULE_SHARE, PlanConfig};
use super::pull::pull_taut;
use super::rank::Score;
use super::report::{ClassPlan, Origin, ms, report_class};
use super::via::{SEED_MAX_GAP, last_resort, seed_points, subdivided_seed};
use super::world::{KEEPS_DM_LENGTH, World, keeps_dm, taut_at, taut_within_bounds};
use crate::growth::{Growth, GrowthConfig, Guard, SHORT_OF_TARGET};

/// A scene's dense seed (a last resort that stayed in collision) has at most this many times
/// the points of a normal one (`max_via_points` and the ends); past that it is not tried.
pub const DENSE_SEED_SHARE: usize = 8;

/// A class's task from its seed: on a map the seed is first pulled taut in its class; on a
/// scene the class's taut path is offered as its seed where the class path runs along the
/// bounds ([`taut_seed`]).
pub(super) fn start_class<'w>(
    world: &'w World<'_>,
    cfg: &'w PlanConfig,
    poly: &[Point],
    sig: Option<&'w Signature>,
    gcost: Real,
    cell: Option<Real>,
) -> ClassTask<'w> {
    let (poly, hugs) = match (sig, cell) {
        (Some(s), Some(cell)) if world.grid_is_exact => {
            (pull_taut(poly, world.model, &world.rays, cell, s), false)
        }
        (Some(_), Some(cell)) => (
            poly.to_vec(),
            world.circles.is_some() && along_bounds(poly, &world.bounds, cell) >= HUG_CELLS * cell,
        ),
        _ => (poly.to_vec(), false),
    };
    ClassTask::new(world, poly, hugs, sig, gcost, cfg, cell)
}

/// A scene's class path that runs along the bounds for this many cells or more is offered
/// its class's taut path as a seed ([`taut_seed`]).
pub(super) const HUG_CELLS: Real = 8.0;

/// How far `poly` runs along `bounds`: the length of its segments whose ends both lie within
/// `cell` of the same side. A class path does that where the start or the goal
/// is on a wall: its attach route follows the wall, and the curve through it does too. The
/// optimiser cannot pull such a curve off the wall (every candidate that crosses the side is
/// out of bounds), and planned an L along two walls, 85.8 long, where the straight line, 62.2
/// long and 17.3 units clear, was in the class.
pub(super) fn along_bounds(poly: &[Point], b: &Bounds, cell: Real) -> Real {
    let near = |p: &Point| -> [bool; 4] {
        [
            p.x - b.min.x <= cell,
            b.max.x - p.x <= cell,
            p.y - b.min.y <= cell,
            b.max.y - p.y <= cell,
        ]
    };
    poly.windows(2)
        .filter(|w| {
            let (a, c) = (near(&w[0]), near(&w[1]));
            (0..4).any(|k| a[k] && c[k])
        })
        .map(|w| (w[1] - w[0]).norm())
        .sum()
}

/// The class's exact shortest path ([`taut_at`]) at the clearance `min(1.1 target, 0.999
/// ends)` (`ends`, the less clear of the start's and the goal's clearance), if that path is at
/// most [`KEEPS_DM_LENGTH`] times as long as the class path `poly` and in the class; `None`
/// otherwise, or with no circles. [`start_class`] offers it to a scene's class path that runs
/// along the bounds ([`along_bounds`], [`HUG_CELLS`] cells or more), at the class's clearance
/// target ([`taut_points`]: `dm` and the certification's tolerance, less through a passage
/// narrower than that, the floor's target above `dm`; `dm` and the tolerance under
/// `--soft-dm`). The optimiser cannot pull a curve off a wall (every candidate across it is
/// out of bounds): a goal on a room's wall was reached by an L along two walls, 85.8 long,
/// where the straight line of the class was 62.2 long and 17.3 units clear; and through a gap
/// of 1 between a disc and a side, the curve ran on along that side and down another, 116.67
/// long, where the taut path at the class's target leads to 102.59 (at `dm` there is none
/// through the gap). [`ClassTask::new`] takes it if a spline through it keeps the class's
/// target and costs less than the class path's seed (or that seed is the last resort), else
/// the class path stands (on a scene 20,000 units wide the taut path at `dm` took a class
/// from 39.1 clear to 0.79).
///
/// Offered also where an end is less clear than the target and the class path is 1.1 times
/// the taut path or longer (a review's bowed detour, 27.20 against 22.65 long), it shortened
/// the plans of that scene scaled by 10 to 10,000 by 15 to 26 %, but made 13 of the
/// review's 366 scenes plan longer than without it (up to 9 %; one class's cost rose from
/// 388 to 643): not kept.
fn taut_seed(
    world: &World<'_>,
    poly: &[Point],
    signature: &Signature,
    target: Real,
) -> Option<Vec<Point>> {
    let ends = world
        .model
        .clearance_value(&world.start)
        .min(world.model.clearance_value(&world.goal));
    let clearance = (1.1 * target).min(0.999 * ends);
    if clearance.is_nan() || clearance <= 0.0 {
        return None;
    }
    let length = super::polyline_length(poly);
    let taut = taut_at(world, signature, clearance, KEEPS_DM_LENGTH * length)?;
    (taut.len() >= 2 && world.rays.signature(&taut) == *signature).then_some(taut)
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
        class: signature.map(|s| (&*world.rays, s)),
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
        // A clearance floor above that target is the target: the floor alone only stops the
        // clearance falling (a ratchet), and a class that could keep it stayed below it, so
        // that `--clearance-floor 6` on narrow-pass answered "no plan" where the class
        // keeps 6 once asked to climb.
        clearance_target: floor_target(signature, cfg).max(match signature {
            Some(sig) if cfg.dm_rule => {
                let dm = dm_target(&growth, cfg);
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
        }),
        proven: Default::default(),
        tube: Default::default(),
    };
    (growth, guard)
}

/// The clearance a class's curve must climb to for the plan's floor: the floor plus the
/// certification's tolerance (as for `dm`), for a class (with a signature) under a positive
/// floor, where the dm rule holds (scenes, without `--soft-dm`); else `-inf`, and the floor
/// is a ratchet only, as on maps.
fn floor_target(signature: Option<&Signature>, cfg: &PlanConfig) -> Real {
    if signature.is_some() && cfg.dm_rule && cfg.clearance_floor > 0.0 {
        cfg.clearance_floor + cfg.certify_tolerance.max(0.0)
    } else {
        Real::NEG_INFINITY
    }
}

/// The via-points of a class's seed from its class path: on a map its certified subdivision;
/// on a scene the first admissible set that keeps the floor, else the first that is clear,
/// else the last resort (`true` with it); without a signature (a straight seed), the path
/// itself.
fn class_path_seed(
    world: &World<'_>,
    seed_poly: &[Point],
    signature: Option<&Signature>,
    graph_cell: Option<Real>,
    guard: &Guard<'_>,
    growth: &GrowthConfig,
) -> (Vec<Point>, bool) {
    let model = world.model;
    let seed_guard = without_floor(guard);
    match (signature, graph_cell) {
        (Some(_), Some(cell)) if world.grid_is_exact => (
            subdivided_seed(seed_poly, model, &seed_guard, growth, cell, None)
                .unwrap_or_else(|| seed_poly.to_vec()),
            false,
        ),
        (Some(_), _) => guard
            .clearance_floor
            .is_finite()
            .then(|| seed_points(seed_poly, model, guard, growth))
            .flatten()
            .or_else(|| seed_points(seed_poly, model, &seed_guard, growth))
            .map_or_else(|| (last_resort(seed_poly, growth), true), |p| (p, false)),
        (None, _) => (seed_poly.to_vec(), false),
    }
}

/// The class's taut path ([`taut_seed`]) at its clearance target (`dm` and the certification's
/// tolerance where no target holds, under `--soft-dm`), and the via-points of a spline
/// through it that is admissible and keeps the class's target and the plan's floor (under
/// `--soft-dm` only the floor); `None` if there is no such path or spline.
fn taut_points(
    world: &World<'_>,
    cfg: &PlanConfig,
    seed_poly: &[Point],
    signature: &Signature,
    guard: &Guard<'_>,
    growth: &GrowthConfig,
) -> Option<(Vec<Point>, Vec<Point>)> {
    let target = if guard.clearance_target.is_finite() {
        guard.clearance_target
    } else {
        dm_target(growth, cfg)
    };
    let p = taut_seed(world, seed_poly, signature, target)?;
    let held = Guard {
        clearance_floor: guard.clearance_target.max(guard.clearance_floor),
        ..guard.clone()
    };
    *held.proven.borrow_mut() = Some(p.clone());
    let points = seed_points(&p, world.model, &held, growth)?;
    Some((p, points))
}

/// `dm` and the certification's tolerance: the dm rule's target (a curve held exactly at `dm`
/// certifies up to that tolerance below it).
fn dm_target(growth: &GrowthConfig, cfg: &PlanConfig) -> Real {
    growth.cost.dm + cfg.certify_tolerance.max(0.0)
}

/// A guard that only keeps candidates in the class, in bounds and clear: a seed need only be
/// collision-free (the growth loop's ratchet raises it to the floor).
fn without_floor<'w>(guard: &Guard<'w>) -> Guard<'w> {
    Guard {
        clearance_floor: Real::NEG_INFINITY,
        ..guard.clone()
    }
}

/// One class optimised, and whether it is worth the dense second pass
/// ([`ClassTask::dense`]): its seed was a scene's last resort (no via-point set was
/// admissible) and the curve it gave is not proven clear.
pub(super) type ClassRun = (ClassPlan, bool);

/// One class's work: its seed, its settings and guard, and its growth loop, which runs one
/// round at a time so that the planner can stop a class that cannot win between rounds.
pub(super) struct ClassTask<'w> {
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
    pub(super) state: Option<Growth>,
    /// Milliseconds spent so far.
    pub(super) time_ms: Real,
    /// Stopped after its first round by [`outclassed`](super::rank::outclassed).
    pub(super) pruned: bool,
}

impl<'w> ClassTask<'w> {
    /// The class's setup and seed; no round run yet.
    fn new(
        world: &'w World<'_>,
        seed_poly: Vec<Point>,
        hugs: bool,
        signature: Option<&'w Signature>,
        graph_cost: Real,
        cfg: &'w PlanConfig,
        graph_cell: Option<Real>,
    ) -> Self {
        let t = Instant::now();
        let model = world.model;
        let (growth, guard) = class_setup(world, &seed_poly, signature, cfg);
        // The seed's polyline is in the class (the class path, its chords proven), so the
        // guard's first candidate is compared with it rather than given its signature.
        if signature.is_some() {
            *guard.proven.borrow_mut() = Some(seed_poly.clone());
        }
        let mut growth = growth.into_owned();
        // On scenes the first via-point set that already keeps the floor is preferred.
        let (mut seed, mut resorted) =
            class_path_seed(world, &seed_poly, signature, graph_cell, &guard, &growth);
        let mut seed_poly = seed_poly;
        // The taut path offered ([`taut_seed`]) is the seed instead if a spline through it
        // keeps the class's target (its target set from the class path, as without it) and
        // costs less than the class path's seed, or that seed is the last resort; its
        // candidates are then compared with it (in the class: `taut_seed` checked its word).
        if let Some((p, points)) = signature
            .filter(|_| hugs)
            .and_then(|sig| taut_points(world, cfg, &seed_poly, sig, &guard, &growth))
        {
            let cost = |pts: &[Point]| {
                homospline_spline::Spline::new(pts, growth.parametrization, growth.end)
                    .map_or(Real::INFINITY, |sp| guard.cost(&sp, model, &growth))
            };
            if resorted || cost(&points) < cost(&seed) {
                *guard.proven.borrow_mut() = Some(p.clone());
                (seed_poly, seed, resorted) = (p, points, false);
            }
        }
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

    /// The class as [`outclassed`](super::rank::outclassed) weighs it, after its first round (`class`: its index).
    pub(super) fn score(&self, class: usize, model: &dyn ClearanceModel) -> Score {
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
    pub(super) fn step(&mut self, model: &dyn ClearanceModel) -> bool {
        self.timed(false, |g, cfg, guard| g.step(model, cfg, guard))
    }

    /// The class's repair round, if its loop ended on a curve whose clearance its cost
    /// overstated ([`Growth::repair`]); a class stopped by the pruning is not repaired.
    /// Returns whether it ran.
    pub(super) fn repair(&mut self, model: &dyn ClearanceModel) -> bool {
        !self.pruned && self.timed(false, |g, cfg, guard| g.repair(model, cfg, guard))
    }

    /// The class's polish rounds ([`Growth::polish`]); a class stopped by the pruning is
    /// not polished. Returns whether a round ran (kept or undone).
    pub(super) fn polish(&mut self, model: &dyn ClearanceModel, rounds: usize) -> bool {
        !self.pruned
            && self.timed(false, |g, cfg, guard| {
                let before = g.rounds().len();
                g.polish(model, cfg, guard, rounds);
                g.rounds().len() > before
            })
    }

    /// The class's finish-only polish round ([`Growth::finish`]) of at most `cap`
    /// evaluations; a class stopped by the pruning is not polished. Returns whether it ran.
    pub(super) fn finish(&mut self, model: &dyn ClearanceModel, cap: usize) -> bool {
        !self.pruned
            && self.timed(false, |g, cfg, guard| {
                let before = g.rounds().len();
                g.finish(model, cfg, guard, cap);
                g.rounds().len() > before
            })
    }

    /// [`ClassTask::step`] that can be called off ([`Growth::step_unless`]).
    pub(super) fn step_unless(
        &mut self,
        model: &dyn ClearanceModel,
        stop: &dyn Fn() -> bool,
    ) -> Option<bool> {
        self.timed(Some(false), |g, cfg, guard| {
            g.step_unless(model, cfg, guard, stop)
        })
    }

    /// The evaluation budget of its rounds left ([`Growth::budget_left`]).
    pub(super) fn budget_left(&self) -> usize {
        self.state
            .as_ref()
            .map_or(0, |g| g.budget_left(&self.growth))
    }

    /// Runs the rounds left.
    pub(super) fn run(&mut self, model: &dyn ClearanceModel) {
        while self.step(model) {}
    }

    /// Where the class came from, for its report.
    fn origin(&self) -> Origin<'_> {
        Origin {
            seed_poly: &self.seed_poly,
            signature: self.signature,
            graph_cost: self.graph_cost,
            in_class: &self.guard.proven,
        }
    }

    /// The class's plan from its best curve so far, and whether it is worth the dense pass.
    pub(super) fn report(&self, world: &World<'_>, cfg: &PlanConfig) -> ClassRun {
        let t = Instant::now();
        let model = world.model;
        // On a scene the segment S-T stands in for the loop's curve where it is better
        // ([`Growth::straight_if_better`]).
        let grown = self.state.as_ref().map(|g| {
            (!world.grid_is_exact && self.signature.is_some())
                .then(|| g.straight_if_better(model, &self.growth, &self.guard))
                .flatten()
                .unwrap_or_else(|| g.result(model, &self.growth, &self.guard))
        });
        let plan = report_class(world, self.origin(), cfg, grown, self.seed.clone());
        // A last resort whose curve is not reported collision-free (it stayed in collision,
        // or it leaves the bounds: a class path along a wall, from a start or goal on it,
        // bulges out at the corner) is worth the dense pass, which pulls the path taut first.
        let retry = self.resorted && !plan.collision_free;
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
    /// no class of the plan came out collision-free and inside the bounds): the graph's
    /// path, if it is clear, is pulled taut in its class as a map's is, and the via-points follow it, up to [`DENSE_SEED_SHARE`]
    /// times as many (a winding passage or a field of small obstacles that a spline through
    /// `max_via_points` via-points cannot keep to; L-BFGS cannot even start from a colliding
    /// seed). Its round's budget is that of a round at `max_via_points`. When the path is not
    /// clear or its curve does not come out collision-free, the via-points follow the
    /// class's exact taut path inside the bounds instead ([`taut_within_bounds`], scenes of
    /// circles). `Some` only if the curve is reported collision-free (clear and inside the
    /// bounds); its evaluations include the first pass's (not those of a dense try that
    /// failed), its time both passes' and every try's.
    ///
    /// Pulling taut first matters in clutter: a graph path winding between many small
    /// obstacles has a point per cell, far more than the via-points can follow; taut, it
    /// keeps only its corners (CHANGELOG, "Clutter planned").
    pub(super) fn dense(
        &self,
        world: &World<'_>,
        cfg: &PlanConfig,
        graph_cell: Option<Real>,
        first: &ClassPlan,
    ) -> Option<ClassPlan> {
        let t = Instant::now();
        let model = world.model;
        let pulled = graph_cell
            .filter(|_| model.polyline_clearance(&self.seed_poly) > 0.0)
            .map(|cell| {
                let poly = match self.signature {
                    Some(sig) => pull_taut(&self.seed_poly, model, &world.rays, cell, sig),
                    None => self.seed_poly.clone(),
                };
                (poly, cell)
            });
        if let Some(plan) =
            pulled.and_then(|(poly, cell)| self.dense_from(world, cfg, &poly, cell, first, t))
        {
            return Some(plan);
        }
        if cfg.interrupt.is_raised() {
            return None;
        }
        // A class path out of the bounds or into a circle (a gap between a circle and a
        // side, narrower than the grid's cells): the class's exact taut path inside the
        // bounds, on a scene of circles.
        let sig = self.signature?;
        let length = super::polyline_length(&self.seed_poly);
        let clearance = dm_target(&self.growth, cfg);
        let taut = taut_within_bounds(world, sig, clearance, KEEPS_DM_LENGTH * length)?;
        let cell = graph_cell.unwrap_or(length / 256.0);
        self.dense_from(world, cfg, &taut, cell, first, t)
    }

    /// [`ClassTask::dense`] from the polyline `pulled`, its via-points spaced by `cell`; `t`:
    /// when the dense pass began.
    fn dense_from(
        &self,
        world: &World<'_>,
        cfg: &PlanConfig,
        pulled: &[Point],
        cell: Real,
        first: &ClassPlan,
        t: Instant,
    ) -> Option<ClassPlan> {
        let model = world.model;
        let guard = &self.guard;
        // A round of the dense pass gets the budget of a round at `max_via_points` (its
        // evaluations cost in proportion to the via-points, and the seed is clear already).
        let mut growth = GrowthConfig::clone(&self.growth);
        growth.max_evaluations_per_round = growth
            .max_evaluations_per_round
            .min(2 * growth.max_via_points.max(1) * growth.evaluations_per_dimension.max(1));
        let growth = &growth;
        // Via-points at most SEED_MAX_GAP cells apart, but no more of them than half the cap
        // at first: a fine grid's cell (`--resolution 10` on 100 x 100) would space them
        // too closely for the cap before a single one is added where the curve needs it.
        let cap = DENSE_SEED_SHARE * (growth.max_via_points + 2);
        let length = super::polyline_length(pulled);
        let spacing = cell.max(2.0 * length / (SEED_MAX_GAP * cap as Real));
        let dense = subdivided_seed(
            pulled,
            model,
            &without_floor(guard),
            growth,
            spacing,
            Some(cap),
        )?;
        // `grow`, with every round called off by an interrupt (the plan then returns
        // `Interrupted`: this class's result is never read).
        let mut g = Growth::new(&dense, model, growth, guard).ok()?;
        let interrupted = || cfg.interrupt.is_raised();
        while g.step_unless(model, growth, guard, &interrupted) == Some(true) {}
        if interrupted() {
            return None;
        }
        g.repair(model, growth, guard);
        let mut grown = g.result(model, growth, guard);
        if !is_collision_free(&grown.spline, model) {
            return None;
        }
        grown.evaluations += first.evaluations;
        let plan = report_class(world, self.origin(), cfg, Some(grown), dense);
        plan.collision_free.then(|| ClassPlan {
            time_ms: first.time_ms + ms(t),
            ..plan
        })
    }
}
