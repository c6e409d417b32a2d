//! The paper's iterative optimisation (method.md section 4): optimise the inner via-points,
//! add one via-point, warm-started from the current curve, and repeat until the round limit
//! or a round that fails to improve.

use homospline_geom::{Bounds, Point, Real};
use homospline_homotopy::{Rays, Signature};
use homospline_spline::{
    ClearanceModel, ClearanceSearch, CostConfig, CostTerms, EndCondition, Parametrization, Spline,
    SplineError, evaluate, evaluate_weighted_unless, gradient, is_clear_by, is_collision_free,
    min_clearance,
};
use std::borrow::Cow;
use std::cell::RefCell;

use crate::barrier::Barrier;
use crate::lbfgs::Lbfgs;
use crate::nelder_mead::NelderMead;

/// Which local optimiser a round uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Optimizer {
    /// Nelder-Mead, the paper's method (default).
    #[default]
    NelderMead,
    /// L-BFGS on the analytic gradient (uniform parameters).
    Lbfgs,
}

/// Settings of the growth loop.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthConfig {
    /// The cost.
    pub cost: CostConfig,
    /// Spline parameters.
    pub parametrization: Parametrization,
    /// Spline ends.
    pub end: EndCondition,
    /// Round limit (the paper's iteration limit).
    pub max_rounds: usize,
    /// No via-point is added beyond this many.
    pub max_via_points: usize,
    /// Evaluation budget of one round, per optimised coordinate.
    pub evaluations_per_dimension: usize,
    /// Evaluation budget of one round in all, whatever the dimension: with it the work of a
    /// round grows linearly with the via-points (each evaluation does), not quadratically.
    pub max_evaluations_per_round: usize,
    /// On curves of more segments than this (0: never), the round's budget shrinks in
    /// proportion, `max_evaluations_per_round * budget_segments / segments`, down to
    /// `min_evaluations_per_round`: a long map path's cost flattens out within tens of
    /// evaluations while each evaluation costs in proportion to its segments.
    pub budget_segments: usize,
    /// The floor of that shrinking budget.
    pub min_evaluations_per_round: usize,
    /// A round must lower the cost by this fraction to count as an improvement.
    pub min_improvement: Real,
    /// The optimiser.
    pub optimizer: Optimizer,
    /// Initial simplex step, as a fraction of the mean via-point spacing.
    pub step_fraction: Real,
    /// Samples per spline segment for the class and bounds checks of each candidate.
    pub guard_samples: usize,
    /// L-BFGS stops when an iteration improves the value by less than this, relatively
    /// (default 1e-10: in practice it runs to its budget; a mission's re-plans take 1e-5).
    pub lbfgs_value_tolerance: Real,
    /// A round that starts short of the guard's clearance target (the dm rule's) runs
    /// Nelder-Mead whatever `optimizer` says (default `true`; it changes nothing for
    /// Nelder-Mead). L-BFGS minimises the cost among curves no less clear than the round's
    /// start ([`Guard::cost`]'s step at the target has no gradient), so it does not climb to
    /// the target, and the class stays unsafe; the simplex ranks a curve short of the target
    /// by its shortfall and climbs. With `--optimizer lbfgs` under the dm rule, narrow-pass
    /// chooses `-1-2` at cost 130, as Nelder-Mead does; without the climb it chooses class
    /// `e` at 376, its two short classes stuck at 2.86 and 2.94
    /// (docs/decisions/0004-lbfgs-climbs-by-simplex.md).
    /// Missions turn it off (`homospline_mission::MissionConfig`'s default, as measured there).
    pub climb_by_simplex: bool,
}

impl GrowthConfig {
    /// The evaluation budget of a round on a curve of `segments` segments, before the
    /// per-coordinate one (see `budget_segments`).
    pub fn round_budget(&self, segments: usize) -> usize {
        if self.budget_segments == 0 || segments <= self.budget_segments {
            return self.max_evaluations_per_round;
        }
        let scaled = (self.max_evaluations_per_round as u128 * self.budget_segments as u128
            / segments as u128) as usize;
        scaled
            .max(self.min_evaluations_per_round)
            .min(self.max_evaluations_per_round)
    }
}

impl Default for GrowthConfig {
    fn default() -> Self {
        Self {
            cost: CostConfig::paper_voronoi(),
            parametrization: Parametrization::Uniform,
            end: EndCondition::Natural,
            max_rounds: 3,
            max_via_points: 10,
            evaluations_per_dimension: 30,
            max_evaluations_per_round: usize::MAX,
            budget_segments: 0,
            min_evaluations_per_round: 0,
            min_improvement: 1e-3,
            optimizer: Optimizer::NelderMead,
            step_fraction: 0.1,
            guard_samples: 8,
            lbfgs_value_tolerance: 1e-10,
            climb_by_simplex: true,
        }
    }
}

/// What keeps candidates in place: the class to stay in and the bounds.
#[derive(Clone, Debug)]
pub struct Guard<'a> {
    /// Ray system and the class's signature; `None` lets the curve change class.
    pub class: Option<(&'a Rays, &'a Signature)>,
    /// The robot stays inside.
    pub bounds: Bounds,
    /// Reject candidates whose clearance (at the quadrature nodes, refined near the minimum)
    /// is not positive: a seed that is collision-free stays so. Off for the straight seed,
    /// which starts in collision.
    pub collision_free: bool,
    /// Reject candidates whose clearance is below this (`-inf`: no floor). [`grow`] applies
    /// it as a ratchet: while the current curve is below the floor, a candidate may not fall
    /// below the current curve's clearance, so a seed below the floor can still climb to it.
    pub clearance_floor: Real,
    /// A clearance to reach and keep (the dm rule; `-inf`: none). A candidate below it is
    /// not rejected: it ranks after every candidate that keeps it, by how far it falls short
    /// (then by its cost). From a seed below it the optimiser first climbs to it, then keeps
    /// it while it lowers the cost: the cost is minimised under the constraint
    /// `m(C) >= target` (an extreme barrier once it holds). Nelder-Mead compares values
    /// only, so the ranking is all it needs; L-BFGS takes it as a ratchet like the floor.
    pub clearance_target: Real,
    /// The guard's own memory: the samples of the last candidate found in the class (start
    /// with `Default::default()`). A candidate whose straight-line sweep from it meets no
    /// obstacle's representative is in the class without its signature being computed
    /// ([`Rays::sweep_is_clear`]): on a map with thousands of obstacles the signature of every
    /// candidate was most of the optimisation's time.
    pub proven: RefCell<Option<Vec<Point>>>,
}

impl Guard<'_> {
    /// The cost of a candidate, or `+inf` when the guard rejects it.
    pub fn cost(&self, spline: &Spline, model: &dyn ClearanceModel, cfg: &GrowthConfig) -> Real {
        self.cost_below(spline, model, cfg, Real::INFINITY)
    }

    /// [`Guard::cost`] for an optimiser that needs the value only below `bound`
    /// ([`crate::nelder_mead::BoundedObjective`]): the exact value below it, else a value at
    /// or above it. The cost comes first, and stops early once terms bounding it reach the
    /// bound ([`homospline_spline::cost::evaluate_weighted_unless`]: [`Guard::value`] falls
    /// as the clearance rises and rises with the total); the class and bounds checks
    /// run only for a candidate whose value is below the bound, since a rejected candidate's
    /// `+inf` is at or above it too. Whether a candidate is in its class does not depend on
    /// which candidates were checked before it (the guard's memory only speeds the check).
    pub fn cost_below(
        &self,
        spline: &Spline,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        bound: Real,
    ) -> Real {
        let enough = |low: &CostTerms| self.value(low) >= bound;
        let value = match evaluate_weighted_unless(spline, model, &cfg.cost, &enough) {
            Ok(terms) => self.value(&terms),
            Err(low) => return self.value(&low),
        };
        if value >= bound {
            return value;
        }
        if admissible(spline, self, cfg.guard_samples) {
            value
        } else {
            Real::INFINITY
        }
    }

    /// The value of a candidate of cost terms `terms`: `+inf` when rejected, above
    /// [`SHORT_OF_TARGET`] when below the clearance target, else its cost.
    pub fn value(&self, terms: &CostTerms) -> Real {
        let m = terms.min_clearance;
        if self.rejects(m) {
            Real::INFINITY
        } else if m < self.clearance_target {
            SHORT_OF_TARGET * (1.0 + (self.clearance_target - m)) + terms.total
        } else {
            terms.total
        }
    }

    /// Whether the curve is certified collision-free where the guard asks for it (samples
    /// can miss a thin overlap) and stays inside the bounds between the guard's samples:
    /// what a round's result, a grown curve and a finish's stage must pass.
    pub fn certifies(&self, spline: &Spline, model: &dyn ClearanceModel) -> bool {
        (!self.collision_free || is_collision_free(spline, model))
            && stays_in_bounds(spline, &self.bounds)
    }

    /// Whether a candidate of minimum clearance `m` is rejected.
    pub fn rejects(&self, m: Real) -> bool {
        (self.collision_free && m <= 0.0) || m < self.clearance_floor
    }

    /// This guard with its floor lowered to `current` when the current curve is below it.
    fn ratchet(&self, current: Real) -> Self {
        let mut g = self.clone();
        if g.clearance_floor.is_finite() {
            g.clearance_floor = g.clearance_floor.min(current);
        }
        g
    }
}

/// How far below its clearance target a growth loop's final curve may be proven clear
/// before the loop takes its `m(C)` to have missed a dip ([`Growth::needs_repair`]): a
/// curve held at the target by the default search, whose least clearance Brent's method
/// finds to `1e-10` in `t`, passes.
pub const STRICT_SLACK: Real = 1e-9;

/// Whether `spline` is proven at least `clearance` clear ([`is_clear_by`], less
/// [`STRICT_SLACK`]); any curve is, against a clearance of `-inf`.
fn proven_at(spline: &Spline, model: &dyn ClearanceModel, clearance: Real) -> bool {
    !clearance.is_finite() || is_clear_by(spline, model, clearance - STRICT_SLACK)
}

/// The value of a candidate below the clearance target is more than this; every cost is
/// far less (the largest seen, on maps, are in the tens of thousands).
pub const SHORT_OF_TARGET: Real = 1e9;

/// One round's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct Round {
    /// Inner via-points in this round.
    pub via_points: usize,
    /// Cost at the end of the round.
    pub cost: Real,
    /// Evaluations in the round.
    pub evaluations: usize,
    /// A repair round ([`Growth::repair`]): `m(C)` searched between every two nodes, after
    /// the loop had ended.
    pub repair: bool,
    /// A polish round ([`Growth::polish`]): from a fresh simplex at the loop's best curve's
    /// via-points, after the loop had ended; or the interior-point finish alone at them
    /// ([`Growth::finish`]).
    pub polish: bool,
}

/// The optimised path of one seed.
#[derive(Clone, Debug, PartialEq)]
pub struct Grown {
    /// `S`, via-points, `T`.
    pub points: Vec<Point>,
    /// The curve.
    pub spline: Spline,
    /// Its cost terms.
    pub terms: CostTerms,
    /// Rounds run.
    pub rounds: Vec<Round>,
    /// Cost evaluations in all.
    pub evaluations: usize,
}

fn to_points(s: Point, t: Point, x: &[Real]) -> Vec<Point> {
    let mut v = Vec::with_capacity(x.len() / 2 + 2);
    v.push(s);
    v.extend(x.chunks(2).map(|c| Point::new(c[0], c[1])));
    v.push(t);
    v
}

/// Up to this many obstacles (rays), the class check computes the samples' signature
/// directly; beyond, it first tries the sweep's proof ([`Rays::sweep_is_clear`]). The answer
/// is the same either way. On the paper scenes (3 to 6 obstacles) the direct signature is
/// cheaper (plan bench, one noisy run each: convex 6.5 -> 5.8 ms, two-homotopies 10.2 -> 9.6
/// ms); on a map's thousands of wall pieces the sweep is.
pub const DIRECT_SIGNATURE_RAYS: usize = 64;

/// Whether the spline stays in bounds and (when asked) in its class, on dense samples. The
/// class holds when the samples' signature is the class's: with more than
/// [`DIRECT_SIGNATURE_RAYS`] obstacles, first tried by proving the sweep from the guard's
/// last in-class samples clear ([`Rays::sweep_is_clear`]); the samples in the class become
/// the guard's new reference. The collision test of a guarded candidate
/// is the cost's own `m(C)` (every quadrature node, refined near the worst one), checked
/// after the evaluation; a round's result is certified.
pub fn admissible(spline: &Spline, guard: &Guard<'_>, samples_per_segment: usize) -> bool {
    let pts = spline.sample_uniform(spline.segments() * samples_per_segment.max(2));
    if !pts.iter().all(|p| guard.bounds.contains(p)) {
        return false;
    }
    match guard.class {
        Some((rays, sig)) => {
            let mut proven = guard.proven.borrow_mut();
            // With few obstacles the signature costs less than the sweep's proof.
            let same = if rays.len() <= DIRECT_SIGNATURE_RAYS {
                &rays.signature(&pts) == sig
            } else {
                proven
                    .as_ref()
                    .is_some_and(|before| rays.sweep_is_clear(before, &pts))
                    || &rays.signature(&pts) == sig
            };
            if same {
                *proven = Some(pts);
            }
            same
        }
        None => true,
    }
}

/// Samples along a reported path, at most, before each segment's rounding up and the
/// refinement around its least clearance ([`report_spacing`]; together below twice this).
pub const MAX_REPORT_SAMPLES: Real = 100_000.0;

/// Spacing of the reported path's samples along a curve of length `length`: a thousandth of
/// it, at most half a unit (two samples per cell of a map), but no finer than
/// [`MAX_REPORT_SAMPLES`] along the curve: a scene of kilometres in metres has paths
/// of millions of half units (at 1e7 units across, 4.7 GB of samples and no end).
pub fn report_spacing(length: Real) -> Real {
    (length / 1000.0).min(0.5).max(length / MAX_REPORT_SAMPLES)
}

/// Whether the curve stays inside `bounds`: certified per segment by its Bezier control box,
/// else checked at the samples of the reported path (`report_spacing`).
pub fn stays_in_bounds(spline: &Spline, bounds: &Bounds) -> bool {
    let boxed = (0..spline.segments()).all(|i| {
        let (lo, hi) = spline.segment_box(i);
        bounds.contains(&lo) && bounds.contains(&hi)
    });
    boxed
        || spline
            .sample_by_arc_length(report_spacing(spline.length()))
            .iter()
            .all(|(_, p)| bounds.contains(p))
}

/// The curve before a growth whose grown curve fell short of the floor or the target, and
/// the clearance the next round must regain.
#[derive(Clone)]
struct Probation {
    points: Vec<Point>,
    spline: Spline,
    cost: Real,
    floor: Real,
}

/// The best curve of a growth loop so far, and its value.
#[derive(Clone)]
struct Best {
    value: Real,
    points: Vec<Point>,
    spline: Spline,
}

/// The spline's end condition for a round that starts from `pts`. A start heading's slope
/// depends on the first via-point; it is fixed for a round (from the round's first curve),
/// so that within a round the curve is linear in its via-points and the analytic gradient
/// holds.
fn fixed_end(pts: &[Point], cfg: &GrowthConfig) -> EndCondition {
    match cfg.end {
        EndCondition::StartHeading { .. } => {
            Spline::new(pts, cfg.parametrization, cfg.end).map_or(cfg.end, |sp| {
                EndCondition::ClampedStart {
                    start: sp.velocity(0.0),
                }
            })
        }
        e => e,
    }
}

fn build(pts: &[Point], end: EndCondition, cfg: &GrowthConfig) -> Option<Spline> {
    Spline::new(pts, cfg.parametrization, end).ok()
}

/// A curve's value by the outer guard: a curve below its floor ranks last.
fn outer_value(guard: &Guard<'_>, clearance: Real, value: Real) -> Real {
    if guard.rejects(clearance) {
        Real::INFINITY
    } else {
        value
    }
}

/// The growth loop as a solver that runs one round at a time: [`Growth::new`] takes the
/// seed, [`Growth::step`] runs a round and the growth after it, [`Growth::result`] gives
/// the best curve so far. [`grow`] runs it to the end; a planner can stop a class between rounds
/// (a class that cannot win) and still report its curve. Every call must get the same
/// model, settings and guard.
#[derive(Clone)]
pub struct Growth {
    s: Point,
    t: Point,
    end: EndCondition,
    spline: Spline,
    points: Vec<Point>,
    evaluations: usize,
    rounds: Vec<Round>,
    /// Clearance of the current curve, for the floor's ratchet.
    current: Real,
    best_cost: Real,
    probation: Option<Probation>,
    /// The best curve the loop has had, by the outer guard (a curve below its floor ranks
    /// last): a grown curve passes through one more point of the curve before it, but its
    /// knots move and its cost may be higher; if the rounds after it do not win that back,
    /// the loop returns the better curve it had before the growth.
    kept_best: Best,
    round: usize,
    done: bool,
    /// The cost's `m(C)` is searched between every two quadrature nodes
    /// ([`ClearanceSearch::EveryStretch`]): set by the repair round ([`Growth::repair`]).
    strict: bool,
}

impl Growth {
    /// The loop's state before its first round, from `seed` (`S`, initial via-points, `T`).
    pub fn new(
        seed: &[Point],
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        guard: &Guard<'_>,
    ) -> Result<Self, SplineError> {
        let end = fixed_end(seed, cfg);
        let spline = Spline::new(seed, cfg.parametrization, end)?;
        let current = evaluate(&spline, model, &cfg.cost).min_clearance;
        let best_cost = guard.ratchet(current).cost(&spline, model, cfg);
        Ok(Self {
            s: seed[0],
            t: seed[seed.len() - 1],
            end,
            kept_best: Best {
                value: outer_value(guard, current, best_cost),
                points: seed.to_vec(),
                spline: spline.clone(),
            },
            spline,
            points: seed.to_vec(),
            evaluations: 0,
            rounds: Vec::new(),
            current,
            best_cost,
            probation: None,
            round: 0,
            done: false,
            strict: false,
        })
    }

    /// The settings the loop evaluates its curves with: `cfg`, with the cost's `m(C)`
    /// searched between every two quadrature nodes once the loop has run its repair round
    /// ([`Growth::repair`]). A caller that weighs the loop's curve (a planner ranking
    /// classes) should evaluate it with these.
    pub fn settings<'a>(&self, cfg: &'a GrowthConfig) -> Cow<'a, GrowthConfig> {
        if self.strict && cfg.cost.clearance_search != ClearanceSearch::EveryStretch {
            let mut strict = cfg.clone();
            strict.cost.clearance_search = ClearanceSearch::EveryStretch;
            Cow::Owned(strict)
        } else {
            Cow::Borrowed(cfg)
        }
    }

    /// Whether the loop has stopped (its round limit, a round that did not improve, the
    /// via-point limit, or a growth that could not be kept).
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// Rounds run so far.
    pub fn rounds(&self) -> &[Round] {
        &self.rounds
    }

    /// The evaluation budget of the rounds left if every one of them runs and grows the curve
    /// by a via-point (up to `max_via_points`): an upper estimate of the loop's work left, for
    /// a scheduler (0 once the loop is done).
    pub fn budget_left(&self, cfg: &GrowthConfig) -> usize {
        if self.done {
            return 0;
        }
        // A bare segment's first round may start by growing a via-point (`round_and_grow`).
        let via = match self.points.len() - 2 {
            0 if self.round == 0 => cfg.max_via_points.min(1),
            v => v,
        };
        (0..cfg.max_rounds.max(1).saturating_sub(self.round))
            .map(|k| {
                let v = (via + k).min(cfg.max_via_points.max(via));
                cfg.evaluations_per_dimension
                    .saturating_mul(2 * v)
                    .min(cfg.round_budget(v + 1))
            })
            .fold(0usize, usize::saturating_add)
    }

    /// The curve [`Growth::result`] gives now.
    pub fn curve(&self, guard: &Guard<'_>) -> &Spline {
        self.best(guard).1
    }

    /// The best curve so far and its points: the kept best when it beats the current curve
    /// by the outer guard.
    fn best(&self, guard: &Guard<'_>) -> (&[Point], &Spline) {
        if self.kept_best.value < outer_value(guard, self.current, self.best_cost) {
            (&self.kept_best.points, &self.kept_best.spline)
        } else {
            (&self.points, &self.spline)
        }
    }

    /// Runs one round (the optimiser from the current curve) and the growth after it;
    /// returns whether another round follows.
    pub fn step(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
    ) -> bool {
        if !self.done {
            let settings = self.settings(cfg);
            let ended = !self.round_and_grow(model, &settings, outer, &|| false, Finish::No);
            self.count_round(ended, cfg);
        }
        !self.done
    }

    /// Counts a round just run (`ended`: the loop's own reason to stop) against the limit.
    fn count_round(&mut self, ended: bool, cfg: &GrowthConfig) {
        self.done = ended;
        self.round += 1;
        if self.round >= cfg.max_rounds.max(1) {
            self.done = true;
        }
    }

    /// [`Growth::step`] that can be called off: once `stop()` returns `true` the round's
    /// remaining evaluations are not taken (each counts as infeasible, at no cost, until the
    /// optimiser ends), the growth after the round is skipped, and the call returns `None`
    /// with the loop as it was before it. While `stop()` is `false` it is [`Growth::step`],
    /// to the bit. For a planner that runs a round ahead on an idle core and may find that it
    /// was not wanted.
    pub fn step_unless(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        stop: &dyn Fn() -> bool,
    ) -> Option<bool> {
        if self.done {
            return Some(false);
        }
        let before = self.clone();
        let settings = self.settings(cfg);
        let ended = !self.round_and_grow(model, &settings, outer, stop, Finish::No);
        if stop() {
            *self = before;
            return None;
        }
        self.count_round(ended, cfg);
        Some(!self.done)
    }

    /// The loop's result so far: its best curve, with its cost terms evaluated without
    /// truncation.
    pub fn result(
        &self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        guard: &Guard<'_>,
    ) -> Grown {
        let (points, spline) = self.best(guard);
        let (points, spline) = (points.to_vec(), spline.clone());
        // The reported terms leave nothing out (no truncation of far circles' potential).
        let exact = CostConfig {
            tolerance: 0.0,
            ..self.settings(cfg).cost.clone()
        };
        let terms = evaluate(&spline, model, &exact);
        Grown {
            points,
            spline,
            terms,
            rounds: self.rounds.clone(),
            evaluations: self.evaluations,
        }
    }

    /// The body of one round; `false` ends the loop.
    fn round_and_grow(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        stop: &dyn Fn() -> bool,
        finish: Finish,
    ) -> bool {
        // A seed with no via-point (a class path pulled taut to the segment S-T) has nothing
        // to move. Where it falls short of the clearance target, the segment's midpoint
        // becomes one (with natural ends the curve is the same line), so that the round can
        // bend the curve up
        // to the target: else the class stayed on its seed, unsafe, while a curve of the
        // class keeping dm was often barely longer (on generated scenes, 0.4 % longer, while
        // the class chosen instead was 24 % longer; found by the class's exact optimum,
        // `homospline_homotopy::shortest_in_class`).
        if self.points.len() == 2
            && self.round == 0
            && self.current < outer.clearance_target
            && cfg.max_via_points >= 1
            && !self.grow_one(model, cfg, outer, &outer.ratchet(self.current))
        {
            return false;
        }
        let (s, t, end) = (self.s, self.t, self.end);
        let round_guard = outer.ratchet(self.current);
        let guard = &round_guard;
        let x0: Vec<Real> = self.points[1..self.points.len() - 1]
            .iter()
            .flat_map(|p| [p.x, p.y])
            .collect();
        if x0.is_empty() {
            return false;
        }
        let mut count = 0usize;
        let mut objective = |x: &[Real], bound: Real| -> Real {
            count += 1;
            if stop() {
                return Real::INFINITY;
            }
            let pts = to_points(s, t, x);
            build(&pts, end, cfg).map_or(Real::INFINITY, |sp| {
                guard.cost_below(&sp, model, cfg, bound)
            })
        };
        let spacing = self
            .points
            .windows(2)
            .map(|w| (w[1] - w[0]).norm())
            .sum::<Real>()
            / (self.points.len() - 1) as Real;
        let step = (cfg.step_fraction * spacing).max(1e-6);
        let budget = cfg
            .evaluations_per_dimension
            .saturating_mul(x0.len())
            .min(cfg.round_budget(self.points.len() - 1));
        let current = self.current;
        let optimizer = if cfg.climb_by_simplex && current < guard.clearance_target {
            Optimizer::NelderMead
        } else {
            cfg.optimizer
        };
        let (x, value) = match (finish, optimizer) {
            (Finish::Only { .. }, _) => (x0.clone(), self.best_cost),
            (_, Optimizer::NelderMead) => {
                let nm = NelderMead::new(x0.len())
                    .with_initial_step(vec![step; x0.len()])
                    .and_then(|n| n.with_tolerances(1e-7, 1e-4 * spacing))
                    .and_then(|n| n.with_max_evaluations(budget.max(x0.len() + 2)));
                match nm {
                    Ok(nm) => {
                        let out = nm.minimize_bounded(&mut objective, &x0, &mut ());
                        (out.x, out.value)
                    }
                    Err(_) => (x0.clone(), self.best_cost),
                }
            }
            (_, Optimizer::Lbfgs) => {
                let lb = Lbfgs {
                    max_evaluations: budget.max(4) / 4,
                    value_tolerance: cfg.lbfgs_value_tolerance,
                    ..Lbfgs::default()
                };
                let mut fg = |x: &[Real]| -> (Real, Vec<Real>) {
                    count += 1;
                    if stop() {
                        return (Real::INFINITY, vec![0.0; x.len()]);
                    }
                    let pts = to_points(s, t, x);
                    build(&pts, end, cfg).map_or((Real::INFINITY, vec![0.0; x.len()]), |sp| {
                        guarded_gradient(&sp, model, cfg, guard, current)
                    })
                };
                let out = lb.minimize(&mut fg, &x0);
                (out.x, out.value)
            }
        };
        let finish_budget = match finish {
            Finish::No => None,
            Finish::After => Some(budget),
            Finish::Only { cap } => Some((budget / 2).min(cap)),
        };
        let (x, value) = if let Some(b) = finish_budget
            && !stop()
        {
            let (x, value, spent) =
                interior_finish(model, cfg, guard, (s, t, end), x, value, b, current);
            count += spent;
            (x, value)
        } else {
            (x, value)
        };
        if stop() {
            // Called off: the caller puts the loop back as it was.
            return false;
        }
        self.evaluations += count;
        let before = self.best_cost;
        let improved = value < before - cfg.min_improvement * before.abs().max(1e-12);
        if value < self.best_cost {
            let candidate = to_points(s, t, &x);
            // A guarded round's result must also be certified clear (samples can miss a thin
            // overlap) and stay inside the bounds between the guard's samples; otherwise the
            // round's starting curve stands.
            if let Some(sp) = build(&candidate, end, cfg)
                && guard.certifies(&sp, model)
            {
                self.current = evaluate(&sp, model, &cfg.cost).min_clearance;
                self.points = candidate;
                self.spline = sp;
                self.best_cost = value;
            }
        }
        self.rounds.push(Round {
            via_points: self.points.len() - 2,
            cost: self.best_cost,
            evaluations: count,
            repair: false,
            polish: false,
        });
        let improved = improved && self.best_cost < before;
        if let Some(p) = self.probation.take()
            && self.current < p.floor
        {
            // The round after a growth on probation did not regain the floor.
            self.points = p.points;
            self.spline = p.spline;
            self.best_cost = p.cost;
            if let Some(r) = self.rounds.last_mut() {
                r.via_points = self.points.len() - 2;
                r.cost = self.best_cost;
            }
            return false;
        }
        let value = outer_value(outer, self.current, self.best_cost);
        if value < self.kept_best.value {
            self.kept_best = Best {
                value,
                points: self.points.clone(),
                spline: self.spline.clone(),
            };
        }
        if !improved && self.round > 0 {
            return false;
        }
        if self.points.len() - 2 >= cfg.max_via_points || self.round + 1 >= cfg.max_rounds {
            return false;
        }
        self.grow_one(model, cfg, outer, guard)
    }

    /// Whether the loop has ended on a curve that keeps the clearance target by the cost's
    /// `m(C)` but is not proven to ([`homospline_spline::is_clear_by`], less
    /// [`STRICT_SLACK`]): the default search of `m(C)`, around the worst quadrature node,
    /// missed a dip between two other nodes, and the optimiser steered by a constraint it
    /// did not see ([`Growth::repair`]).
    pub fn needs_repair(
        &self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
    ) -> bool {
        let target = outer.clearance_target;
        // Nothing to repair when the loop searched every stretch already, or when the model
        // cannot say where to look (a map's grid).
        if !self.done
            || self.strict
            || !target.is_finite()
            || cfg.cost.clearance_search == ClearanceSearch::EveryStretch
            || model.bend_radius().is_none()
        {
            return false;
        }
        let spline = self.best(outer).1;
        evaluate(spline, model, &cfg.cost).min_clearance >= target
            && !proven_at(spline, model, target)
    }

    /// If the loop [`Growth::needs_repair`], one more round from its best curve with `m(C)`
    /// searched between every two nodes ([`ClearanceSearch::EveryStretch`]), which first
    /// climbs back to the target; every curve the loop holds is valued so from then on
    /// ([`Growth::settings`]). That search costs 1.6 times an evaluation, and the
    /// round a round's budget: a planner repairs only the classes that could rank first.
    /// The round grows no via-point after it, and its record says it was a repair
    /// ([`Round::repair`]). Returns whether it ran.
    pub fn repair(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
    ) -> bool {
        if !self.needs_repair(model, cfg, outer) {
            return false;
        }
        let (points, spline) = {
            let (p, sp) = self.best(outer);
            (p.to_vec(), sp.clone())
        };
        self.strict = true;
        let strict = self.settings(cfg).into_owned();
        self.restart_from(points, spline, model, &strict, outer);
        let before = self.rounds.len();
        self.round_and_grow(model, &strict, outer, &|| false, Finish::No);
        if self.rounds.len() > before
            && let Some(r) = self.rounds.last_mut()
        {
            r.repair = true;
        }
        self.done = true;
        true
    }

    /// Up to `rounds` more rounds after the loop has ended, from its best curve and at its
    /// via-points: no via-point is grown, and each round starts a fresh simplex where the
    /// last one stopped. A round at the default budget stops far from the best curve of its
    /// via-points (on the paper scenes one more round from the chosen curve, with its
    /// finish, lowers its cost by 0.4 to 23 % without [`Growth::finish`] before it;
    /// docs/decisions/0015-polish-opt-in.md),
    /// and a growth's new curve starts off the curve before it, so a planner spends these
    /// on the class it chose.
    /// Under a clearance target, on a model that bounds how the clearance bends, the rounds
    /// search `m(C)` between every two nodes ([`ClearanceSearch::EveryStretch`], as a
    /// repair round does), from then on for every curve the loop holds.
    /// Each round ends with an interior-point finish (`interior_finish`: L-BFGS on the cost
    /// plus a [`crate::barrier::Barrier`] on the clearance, its weight falling in three
    /// stages), which moves the curve along the clearance constraint where Nelder-Mead
    /// stalls on it (field: 155.8 after the simplex round, 121.8 after the finish).
    /// The rounds are marked ([`Round::polish`]). If the best curve was proven to keep the
    /// target ([`homospline_spline::is_clear_by`], less [`STRICT_SLACK`]) and a round's is
    /// not, the loop's curve goes back to the one before that round and the polish ends;
    /// the round and its evaluations stay counted ([`Growth::undo_to`]). The rounds stop
    /// early when one improves the cost by less than the loop's `min_improvement`. Without
    /// a finite target (`--soft-dm`, a straight seed) nothing here checks the clearance: a
    /// caller that needs the polished curve as safe as before checks its report (the
    /// planner does). Returns the rounds kept (0 when the loop has not ended or has
    /// nothing to move).
    pub fn polish(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        rounds: usize,
    ) -> usize {
        self.polish_rounds(model, cfg, outer, rounds, Finish::After)
    }

    /// One polish round of the finish alone ([`Growth::polish`] without the simplex before
    /// the finish): from the loop's best curve, at its via-points, `interior_finish` with half
    /// a round's budget, at most `cap` evaluations (a value with its gradient counts one).
    /// A `cap` below [`MIN_FINISH_EVALUATIONS`] runs nothing (each of the finish's stages
    /// takes at least two evaluations, so a smaller one would spend more than `cap`).
    /// At a full round's budget, on the 320 scanned scenes, this planned about as well as a
    /// full polish round for 16 to 44 % less of its work
    /// (docs/decisions/0016-finish-within-budget.md). Kept or put back as
    /// a polish round is; returns whether it was kept.
    pub fn finish(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        cap: usize,
    ) -> bool {
        if cap < MIN_FINISH_EVALUATIONS || !self.done {
            return false;
        }
        let before = self.clone();
        let kept = self.polish_rounds(model, cfg, outer, 1, Finish::Only { cap }) > 0;
        if self.evaluations == before.evaluations {
            // The finish had nothing to do: no clearance to hold (no target, floor or
            // collision check, as on a straight seed) or a curve short of its target: no
            // round is recorded.
            *self = before;
            return false;
        }
        kept
    }

    fn polish_rounds(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        rounds: usize,
        finish: Finish,
    ) -> usize {
        if !self.done || rounds == 0 {
            return 0;
        }
        let target = outer.clearance_target;
        let proven = |g: &Growth| proven_at(g.best(outer).1, model, target);
        let before = self.clone();
        let was_proven = proven(self);
        // The loop's best curve, as the loop valued it.
        let (points, spline) = {
            let (p, sp) = self.best(outer);
            (p.to_vec(), sp.clone())
        };
        // Against the clearance the curve has, where the model bounds how it bends: a
        // polished curve passes for the chosen one.
        if target.is_finite() && model.bend_radius().is_some() {
            self.strict = true;
        }
        let settings = self.settings(cfg).into_owned();
        self.restart_from(points, spline, model, &settings, outer);
        let mut ran = 0;
        let mut kept = before;
        for _ in 0..rounds {
            let (n, cost) = (self.rounds.len(), self.best_cost);
            self.round_and_grow(model, &settings, outer, &|| false, finish);
            let Some(r) = self.rounds.get_mut(n) else {
                // Nothing to move (no via-point): the loop stands as it was.
                self.undo_to(kept);
                return ran;
            };
            r.polish = true;
            self.done = true;
            if was_proven && !proven(self) {
                // Put back the curve before this round; its round and evaluations count.
                self.undo_to(kept);
                return ran;
            }
            ran += 1;
            kept = self.clone();
            // A round that did not improve would start the next one where it started.
            if self.best_cost >= cost - settings.min_improvement * cost.abs().max(1e-12) {
                break;
            }
        }
        ran
    }

    /// Puts the ended loop on `points` and `spline` (one of its own curves) for a round after
    /// its end, valued by `settings` (the loop's best kept curve too): the round starts from
    /// that very curve, with its own ends (a start heading's slope as that curve's round
    /// fixed it), and at the round limit, so that no via-point is grown after it.
    fn restart_from(
        &mut self,
        points: Vec<Point>,
        spline: Spline,
        model: &dyn ClearanceModel,
        settings: &GrowthConfig,
        outer: &Guard<'_>,
    ) {
        let value_of = |sp: &Spline| {
            let m = evaluate(sp, model, &settings.cost).min_clearance;
            (m, outer.ratchet(m).cost(sp, model, settings))
        };
        let (m, cost) = value_of(&self.kept_best.spline);
        self.kept_best.value = outer_value(outer, m, cost);
        self.end = spline.end_condition();
        (self.current, self.best_cost) = value_of(&spline);
        self.points = points;
        self.spline = spline;
        self.probation = None;
        self.round = self.round.max(settings.max_rounds.max(1) - 1);
    }

    /// The loop as it was at `earlier` (one of its own past states), with the rounds and
    /// evaluations it has run since still counted: for a caller that undoes rounds whose
    /// result it does not keep ([`Growth::polish`], the planner's check of a polished class).
    pub fn undo_to(&mut self, earlier: Growth) {
        let (rounds, evaluations) = (std::mem::take(&mut self.rounds), self.evaluations);
        *self = earlier;
        self.rounds = rounds;
        self.evaluations = evaluations;
    }

    /// One more via-point on the current curve, where it helps most: in the segment that
    /// holds the point of least clearance (the path is most threatened there), else the
    /// longest segment. The curve through one more point of itself is nearly the same curve,
    /// but not quite: the knots move, and a short curve can shift by a unit. It is kept if it
    /// is still admissible, no less clear than the floor's ratchet allows, and (if the curve
    /// keeps the dm rule's target) no less clear than the target. A curve held at the floor
    /// or the target often fails that by a hair, so the other segments are tried (longest
    /// first), then the curve resampled at the new knots. If none keeps it, the clearest
    /// admissible one seeds the next round on probation: that round must bring the curve
    /// back, or the loop ends on the curve before the growth. `false` when no grown curve is
    /// admissible.
    fn grow_one(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        guard: &Guard<'_>,
    ) -> bool {
        let (s, t) = (self.s, self.t);
        let sp = &self.spline;
        let clear = min_clearance(sp, model, 1e-3);
        let mut order: Vec<usize> = (0..sp.segments()).collect();
        order.sort_by(|&a, &b| sp.segment_length(b).total_cmp(&sp.segment_length(a)));
        if clear.upper < cfg.cost.dm {
            let worst = sp.locate(clear.at).0;
            order.retain(|&i| i != worst);
            order.insert(0, worst);
        }
        let k = sp.knots();
        let n = self.points.len();
        let points = &self.points;
        let inserted = order.iter().map(|&seg| {
            let mut grown = points.clone();
            grown.insert(seg + 1, sp.position(0.5 * (k[seg] + k[seg + 1])));
            grown
        });
        let resampled = (0..=n)
            .map(|i| match i {
                0 => s,
                i if i == n => t,
                i => sp.position(i as Real / n as Real),
            })
            .collect::<Vec<_>>();
        // A grown curve must keep the ratchet's floor, and the target if the curve keeps it.
        let grown_guard = outer.ratchet(self.current);
        let floor = grown_guard.clearance_floor;
        let target = guard.clearance_target;
        let need = if self.current >= target {
            target
        } else {
            floor
        };
        let unfloored = Guard {
            clearance_floor: Real::NEG_INFINITY,
            ..guard.clone()
        };
        // Without a floor or a target (maps) only the first choice is tried, as the paper
        // does.
        let tries = if need.is_finite() { usize::MAX } else { 1 };
        let mut clearest: Option<(Vec<Point>, EndCondition, Spline, CostTerms)> = None;
        let mut kept = None;
        for grown in inserted.chain(std::iter::once(resampled)).take(tries) {
            let grown_end = fixed_end(&grown, cfg);
            let Some(sp2) = build(&grown, grown_end, cfg) else {
                continue;
            };
            if !(admissible(&sp2, &unfloored, cfg.guard_samples) && guard.certifies(&sp2, model)) {
                continue;
            }
            let terms = evaluate(&sp2, model, &cfg.cost);
            let m = terms.min_clearance;
            if grown_guard.rejects(m) {
                continue;
            }
            if m >= need {
                kept = Some((grown, grown_end, sp2, terms));
                break;
            }
            if clearest.as_ref().is_none_or(|c| m > c.3.min_clearance) {
                clearest = Some((grown, grown_end, sp2, terms));
            }
        }
        let Some((grown, grown_end, sp2, terms)) = kept.or_else(|| {
            self.probation = clearest.is_some().then(|| Probation {
                points: self.points.clone(),
                spline: self.spline.clone(),
                cost: self.best_cost,
                floor: need,
            });
            clearest
        }) else {
            return false;
        };
        self.best_cost = guard.value(&terms);
        self.current = terms.min_clearance;
        self.points = grown;
        self.spline = sp2;
        self.end = grown_end;
        true
    }
}

/// Runs the growth loop from `seed` (`S`, initial via-points, `T`) to its end, and its
/// repair round if it needs one ([`Growth::repair`]).
pub fn grow(
    seed: &[Point],
    model: &dyn ClearanceModel,
    cfg: &GrowthConfig,
    guard: &Guard<'_>,
) -> Result<Grown, SplineError> {
    let mut g = Growth::new(seed, model, cfg, guard)?;
    while g.step(model, cfg, guard) {}
    g.repair(model, cfg, guard);
    Ok(g.result(model, cfg, guard))
}

/// The cost of a candidate that the round's guard admits and its gradient with respect to
/// the inner via-points (x, y interleaved), else `+inf` (a gradient optimiser's line search
/// backs off): out of the class or the bounds, rejected, or below the clearance target or
/// the round's starting clearance, whichever is less (a ratchet).
fn guarded_gradient(
    sp: &Spline,
    model: &dyn ClearanceModel,
    cfg: &GrowthConfig,
    guard: &Guard<'_>,
    current: Real,
) -> (Real, Vec<Real>) {
    let inner = 2 * sp.points().len().saturating_sub(2);
    if !admissible(sp, guard, cfg.guard_samples) {
        return (Real::INFINITY, vec![0.0; inner]);
    }
    let (terms, g) = gradient(sp, model, &cfg.cost);
    let m = terms.min_clearance;
    if guard.rejects(m) || m < guard.clearance_target.min(current) {
        (Real::INFINITY, vec![0.0; inner])
    } else {
        (terms.total, g.iter().flat_map(|v| [v.x, v.y]).collect())
    }
}

/// The barrier weights of the interior-point finish's stages, as fractions of the cost it
/// starts from: each stage runs L-BFGS on the cost plus the barrier from where the last
/// stopped, so the curve comes closer to the clearance it must keep as the weight falls.
pub const FINISH_WEIGHTS: [Real; 3] = [1e-2, 1e-3, 1e-4];

/// What a round does after (or instead of) its optimiser: [`interior_finish`] or not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Finish {
    /// The optimiser alone (the loop's rounds, a repair).
    No,
    /// The optimiser, then the finish with the round's budget (a polish round).
    After,
    /// The finish alone, with half the round's budget, at most `cap` evaluations.
    Only { cap: usize },
}

/// The least budget [`Growth::finish`] runs with: two evaluations for each of the finish's
/// stages.
pub const MIN_FINISH_EVALUATIONS: usize = 2 * FINISH_WEIGHTS.len();

/// Barrier samples per segment in the finish.
pub const FINISH_SAMPLES: usize = 16;

/// A polish round's finish ([`Growth::polish`]): from the round's result `x0` (of value
/// `value0`), L-BFGS on the cost plus a [`Barrier`] on the clearance at the round's
/// clearance to keep (the target, or the round's starting clearance if less, or the floor,
/// or 0 for a collision-free guard), in the stages of [`FINISH_WEIGHTS`], each with a third
/// of the round's `budget` (a value with its gradient counts one evaluation). Nelder-Mead at
/// a round's budget stops far from the best curve of its via-points where the constraint
/// `m(C) >= target` binds (field: 28 % above it); L-BFGS against the guard's rejection alone
/// stalls on that constraint, while the barrier lets it slide along it. A stage's curve is
/// kept only if it is certified collision-free (for a collision-free guard) and inside the
/// bounds, and proven at the target and the floor ([`is_clear_by`] less [`STRICT_SLACK`],
/// on models that bound how the clearance bends), and the stages stop at the first that is
/// not: L-BFGS presses against the constraint, and the cost's search of `m(C)` can miss a
/// dip that it found. Returns the last kept stage's point and its guard value if that is
/// below `value0`, else `x0` and `value0`, with the evaluations spent (a value with its
/// gradient counts one, though it costs 1.7 times a value on the paper scenes). Only for
/// uniform parameters (the spline is then linear in its points); otherwise it returns `x0`
/// at once.
#[allow(clippy::too_many_arguments)]
fn interior_finish(
    model: &dyn ClearanceModel,
    cfg: &GrowthConfig,
    guard: &Guard<'_>,
    (s, t, end): (Point, Point, EndCondition),
    x0: Vec<Real>,
    value0: Real,
    budget: usize,
    current: Real,
) -> (Vec<Real>, Real, usize) {
    let keep = guard
        .clearance_target
        .min(current)
        .max(guard.clearance_floor)
        .max(if guard.collision_free {
            0.0
        } else {
            Real::NEG_INFINITY
        });
    if cfg.parametrization != Parametrization::Uniform
        || x0.is_empty()
        || value0.is_nan()
        || value0 >= SHORT_OF_TARGET
        || !keep.is_finite()
    {
        return (x0, value0, 0);
    }
    let width = if cfg.cost.dm > 0.0 {
        cfg.cost.dm / 6.0
    } else {
        0.5
    };
    // What the round's acceptance and the polish will ask of the curve, asked of each
    // stage's: certified collision-free and inside the bounds, proven at the floor and at
    // the target (where the model bounds how the clearance bends). Without it a stage's
    // curve that failed later would cost the round the simplex's result too.
    let certifiable = model.bend_radius().is_some();
    let proven = |x: &[Real]| {
        build(&to_points(s, t, x), end, cfg).is_some_and(|sp| {
            guard.certifies(&sp, model)
                && (!certifiable
                    || (proven_at(&sp, model, guard.clearance_target)
                        && proven_at(&sp, model, guard.clearance_floor)))
        })
    };
    let mut spent = 0usize;
    let mut x = x0.clone();
    for fraction in FINISH_WEIGHTS {
        let barrier = Barrier {
            at: keep,
            width,
            weight: fraction * value0.abs().max(1.0),
            samples_per_segment: FINISH_SAMPLES,
        };
        let mut fg = |y: &[Real]| -> (Real, Vec<Real>) {
            spent += 1;
            let Some(sp) = build(&to_points(s, t, y), end, cfg) else {
                return (Real::INFINITY, vec![0.0; y.len()]);
            };
            let (v, mut g) = guarded_gradient(&sp, model, cfg, guard, current);
            if !v.is_finite() {
                return (v, g);
            }
            match barrier.value_and_gradient(&sp, model) {
                Some((b, bg)) => {
                    for (gi, bv) in g.chunks_exact_mut(2).zip(&bg) {
                        gi[0] += bv.x;
                        gi[1] += bv.y;
                    }
                    (v + b, g)
                }
                None => (Real::INFINITY, g),
            }
        };
        let lb = Lbfgs {
            max_evaluations: (budget / FINISH_WEIGHTS.len()).max(2),
            value_tolerance: cfg.lbfgs_value_tolerance,
            ..Lbfgs::default()
        };
        let out = lb.minimize(&mut fg, &x);
        if !out.value.is_finite() || !proven(&out.x) {
            break;
        }
        x = out.x;
    }
    let value = build(&to_points(s, t, &x), end, cfg)
        .map_or(Real::INFINITY, |sp| guard.cost(&sp, model, cfg));
    if value < value0 {
        (x, value, spent)
    } else {
        (x0, value0, spent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_candidate_short_of_the_target_ranks_after_every_one_that_keeps_it() {
        let guard = Guard {
            class: None,
            bounds: Bounds {
                min: Point::new(0.0, 0.0),
                max: Point::new(1.0, 1.0),
            },
            collision_free: true,
            clearance_floor: Real::NEG_INFINITY,
            clearance_target: 3.0,
            proven: Default::default(),
        };
        let at = |m: Real, total: Real| CostTerms {
            min_clearance: m,
            total,
            ..CostTerms::default()
        };
        let keeps = guard.value(&at(3.0, 1e6));
        let short = guard.value(&at(2.999, 1.0));
        let shorter = guard.value(&at(2.5, 1.0));
        assert_eq!(keeps, 1e6);
        assert!(keeps < short && short < shorter && shorter.is_finite());
        // Equally short: the cost decides.
        assert!(guard.value(&at(2.5, 1.0)) < guard.value(&at(2.5, 2.0)));
        assert_eq!(guard.value(&at(0.0, 1.0)), Real::INFINITY);
        let floored = Guard {
            clearance_floor: 2.0,
            ..guard.clone()
        };
        assert_eq!(floored.value(&at(1.9, 1.0)), Real::INFINITY);
        assert_eq!(
            floored.ratchet(1.5).value(&at(1.9, 1.0)),
            guard.value(&at(1.9, 1.0))
        );
    }

    #[test]
    fn a_round_called_off_leaves_the_loop_as_it_was_and_one_not_called_off_is_a_step() {
        use homospline_geom::Circle;
        use homospline_spline::CircleModel;
        use std::cell::Cell;
        let model = CircleModel::new(vec![
            Circle::new(5.0, 0.3, 1.0),
            Circle::new(9.0, -1.0, 0.8),
        ]);
        let seed = [
            Point::new(0.0, 0.0),
            Point::new(3.0, 2.0),
            Point::new(7.0, 2.5),
            Point::new(12.0, 0.0),
        ];
        let guard = Guard {
            class: None,
            bounds: Bounds {
                min: Point::new(-5.0, -10.0),
                max: Point::new(20.0, 10.0),
            },
            collision_free: true,
            clearance_floor: Real::NEG_INFINITY,
            clearance_target: Real::NEG_INFINITY,
            proven: Default::default(),
        };
        let cfg = GrowthConfig::default();
        let mut stepped = Growth::new(&seed, &model, &cfg, &guard).unwrap();
        // Two via-points, three rounds growing one each: 30 x (4 + 6 + 8) evaluations.
        assert_eq!(stepped.budget_left(&cfg), 30 * (4 + 6 + 8));
        let mut unless = stepped.clone();
        let mut called_off = stepped.clone();
        // Never called off: the same rounds, the same result, to the bit.
        loop {
            let more = stepped.step(&model, &cfg, &guard);
            assert_eq!(
                unless.step_unless(&model, &cfg, &guard, &|| false),
                Some(more)
            );
            if !more {
                break;
            }
        }
        assert_eq!(
            stepped.result(&model, &cfg, &guard),
            unless.result(&model, &cfg, &guard)
        );
        assert_eq!(stepped.budget_left(&cfg), 0);
        // Called off after 25 evaluations of its first round: nothing of it is kept, and the
        // round run again afterwards is the first round of an untouched loop.
        let before = called_off.result(&model, &cfg, &guard);
        let asked = Cell::new(0usize);
        let stop = || {
            asked.set(asked.get() + 1);
            asked.get() > 25
        };
        assert_eq!(called_off.step_unless(&model, &cfg, &guard, &stop), None);
        assert!(asked.get() > 25);
        assert_eq!(called_off.result(&model, &cfg, &guard), before);
        while called_off.step(&model, &cfg, &guard) {}
        assert_eq!(
            called_off.result(&model, &cfg, &guard),
            stepped.result(&model, &cfg, &guard)
        );
    }

    #[test]
    fn long_curves_get_a_proportionally_smaller_budget_down_to_the_floor() {
        let cfg = GrowthConfig {
            max_evaluations_per_round: 800,
            budget_segments: 40,
            min_evaluations_per_round: 320,
            ..GrowthConfig::default()
        };
        assert_eq!(cfg.round_budget(10), 800);
        assert_eq!(cfg.round_budget(40), 800);
        assert_eq!(cfg.round_budget(80), 400);
        assert_eq!(cfg.round_budget(100), 320);
        assert_eq!(cfg.round_budget(10_000), 320);
        let off = GrowthConfig {
            max_evaluations_per_round: 800,
            ..GrowthConfig::default()
        };
        assert_eq!(off.round_budget(10_000), 800);
    }
}
