//! One round of the growth loop ([`Growth::step`]): the optimiser (Nelder-Mead or L-BFGS)
//! on the inner via-points from the current curve, an interior-point finish when asked,
//! the acceptance of its result, and the growth of a via-point after it.

use homospline_geom::{Point, Real};
use homospline_spline::{ClearanceModel, EndCondition, evaluate};

use super::config::{GrowthConfig, Optimizer};
use super::finish::{Finish, guarded_gradient, interior_finish};
use super::guard::Guard;
use super::state::{Best, Growth, Round, build, outer_value, to_points};
use crate::lbfgs::Lbfgs;
use crate::nelder_mead::NelderMead;

impl Growth {
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

    /// The body of one round; `false` ends the loop.
    pub(super) fn round_and_grow(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        stop: &dyn Fn() -> bool,
        finish: Finish,
    ) -> bool {
        if self.needs_midpoint(cfg, outer)
            && !self.grow_one(model, cfg, outer, &outer.ratchet(self.current))
        {
            return false;
        }
        let round_guard = outer.ratchet(self.current);
        let guard = &round_guard;
        let x0: Vec<Real> = self.points[1..self.points.len() - 1]
            .iter()
            .flat_map(|p| [p.x, p.y])
            .collect();
        if x0.is_empty() {
            return false;
        }
        let objective = Objective {
            s: self.s,
            t: self.t,
            end: self.end,
            model,
            cfg,
            guard,
            stop,
        };
        let (x, value, count) = self.optimise(&objective, x0, finish);
        if stop() {
            // Called off: the caller puts the loop back as it was.
            return false;
        }
        self.evaluations += count;
        let before = self.best_cost;
        let improved = value < before - cfg.min_improvement * before.abs().max(1e-12);
        if value < self.best_cost {
            self.accept(&objective, &x, value);
        }
        self.rounds.push(Round {
            via_points: self.points.len() - 2,
            cost: self.best_cost,
            evaluations: count,
            repair: false,
            polish: false,
        });
        let improved = improved && self.best_cost < before;
        if self.probation_failed() {
            return false;
        }
        self.keep_if_best(outer);
        if !improved && self.round > 0 {
            return false;
        }
        if self.points.len() - 2 >= cfg.max_via_points || self.round + 1 >= cfg.max_rounds {
            return false;
        }
        self.grow_one(model, cfg, outer, guard)
    }

    /// Whether the round starts by growing the segment's midpoint into a via-point: a seed
    /// with no via-point (a class path pulled taut to the segment S-T) has nothing to move.
    /// Where it falls short of the clearance target, the segment's midpoint becomes one
    /// (with natural ends the curve is the same line), so that the round can bend the curve
    /// up to the target: else the class stayed on its seed, unsafe, while a curve of the
    /// class keeping dm was often barely longer than the seed, and much shorter than the
    /// class chosen instead (found by the class's exact optimum,
    /// `homospline_homotopy::shortest_in_class`; measured: docs/performance.md,
    /// "Measurements behind the defaults").
    fn needs_midpoint(&self, cfg: &GrowthConfig, outer: &Guard<'_>) -> bool {
        self.points.len() == 2
            && self.round == 0
            && self.current < outer.clearance_target
            && cfg.max_via_points >= 1
    }

    /// The round's optimiser from `x0` (the inner via-points, x, y interleaved), then its
    /// finish ([`Finish`]): the point it ends on, that point's value and the evaluations
    /// spent.
    fn optimise(
        &self,
        objective: &Objective<'_>,
        x0: Vec<Real>,
        finish: Finish,
    ) -> (Vec<Real>, Real, usize) {
        let cfg = objective.cfg;
        let mut count = 0usize;
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
        let optimizer = if cfg.climb_by_simplex && current < objective.guard.clearance_target {
            Optimizer::NelderMead
        } else {
            cfg.optimizer
        };
        let (x, value) = match (finish, optimizer) {
            (Finish::Only { .. }, _) => (x0.clone(), self.best_cost),
            (_, Optimizer::NelderMead) => objective
                .nelder_mead(&x0, step, spacing, budget, &mut count)
                .unwrap_or_else(|| (x0.clone(), self.best_cost)),
            (_, Optimizer::Lbfgs) => objective.lbfgs(&x0, budget, current, &mut count),
        };
        let finish_budget = match finish {
            Finish::No => None,
            Finish::After => Some(budget),
            Finish::Only { cap } => Some((budget / 2).min(cap)),
        };
        if let Some(b) = finish_budget
            && !(objective.stop)()
        {
            let o = objective;
            let (x, value, spent) = interior_finish(
                o.model,
                cfg,
                o.guard,
                (o.s, o.t, o.end),
                x,
                value,
                b,
                current,
            );
            count += spent;
            (x, value, count)
        } else {
            (x, value, count)
        }
    }

    /// Takes the round's result `x` of value `value` (below the current cost) as the
    /// current curve if it is also certified clear (samples can miss a thin overlap) and
    /// stays inside the bounds between the guard's samples; otherwise the round's starting
    /// curve stands.
    fn accept(&mut self, objective: &Objective<'_>, x: &[Real], value: Real) {
        let Objective {
            s,
            t,
            end,
            model,
            cfg,
            guard,
            ..
        } = *objective;
        let candidate = to_points(s, t, x);
        if let Some(sp) = build(&candidate, end, cfg)
            && guard.certifies(&sp, model)
        {
            self.current = evaluate(&sp, model, &cfg.cost).min_clearance;
            self.points = candidate;
            self.spline = sp;
            self.best_cost = value;
        }
    }

    /// Whether the round after a growth on probation did not regain the floor: the loop
    /// then goes back to the curve before the growth (its round's record too), and ends.
    fn probation_failed(&mut self) -> bool {
        let Some(p) = self.probation.take() else {
            return false;
        };
        if self.current >= p.floor {
            return false;
        }
        self.points = p.points;
        self.spline = p.spline;
        self.best_cost = p.cost;
        if let Some(r) = self.rounds.last_mut() {
            r.via_points = self.points.len() - 2;
            r.cost = self.best_cost;
        }
        true
    }

    /// Keeps the current curve as the loop's best if the outer guard values it more.
    fn keep_if_best(&mut self, outer: &Guard<'_>) {
        let value = outer_value(outer, self.current, self.best_cost);
        if value < self.kept_best.value {
            self.kept_best = Best {
                value,
                points: self.points.clone(),
                spline: self.spline.clone(),
            };
        }
    }
}

/// A round's objective: the curve through `S`, the candidate's via-points and `T`, with the
/// round's end condition, valued by the round's guard, until `stop()` calls the round off.
#[derive(Clone, Copy)]
struct Objective<'a> {
    s: Point,
    t: Point,
    end: EndCondition,
    model: &'a dyn ClearanceModel,
    cfg: &'a GrowthConfig,
    guard: &'a Guard<'a>,
    stop: &'a dyn Fn() -> bool,
}

impl Objective<'_> {
    /// Nelder-Mead from `x0`, its first simplex `step` wide, until `budget` evaluations
    /// (at least enough for one simplex) or a simplex within `1e-4 spacing`: its best point
    /// and value, `None` when no simplex can be set up. Each evaluation adds one to `count`.
    fn nelder_mead(
        &self,
        x0: &[Real],
        step: Real,
        spacing: Real,
        budget: usize,
        count: &mut usize,
    ) -> Option<(Vec<Real>, Real)> {
        let nm = NelderMead::new(x0.len())
            .with_initial_step(vec![step; x0.len()])
            .and_then(|n| n.with_tolerances(1e-7, 1e-4 * spacing))
            .and_then(|n| n.with_max_evaluations(budget.max(x0.len() + 2)))
            .ok()?;
        let mut f = |x: &[Real], bound: Real| -> Real {
            *count += 1;
            self.value(x, bound)
        };
        let out = nm.minimize_bounded(&mut f, x0, &mut ());
        Some((out.x, out.value))
    }

    /// L-BFGS from `x0` on the guarded gradient against the round's starting clearance
    /// `current`, with a quarter of `budget` (at least one) evaluations: its point and
    /// value. Each evaluation adds one to `count`.
    fn lbfgs(
        &self,
        x0: &[Real],
        budget: usize,
        current: Real,
        count: &mut usize,
    ) -> (Vec<Real>, Real) {
        let lb = lbfgs_for(self.cfg.lbfgs_value_tolerance, budget.max(4) / 4);
        let mut fg = |x: &[Real]| -> (Real, Vec<Real>) {
            *count += 1;
            self.value_and_gradient(x, current)
        };
        let out = lb.minimize(&mut fg, x0);
        (out.x, out.value)
    }

    /// The guard's value of the candidate `x` for an optimiser that needs it only below
    /// `bound` ([`Guard::cost_below`]); `+inf` once the round is called off.
    fn value(&self, x: &[Real], bound: Real) -> Real {
        if (self.stop)() {
            return Real::INFINITY;
        }
        let pts = to_points(self.s, self.t, x);
        build(&pts, self.end, self.cfg).map_or(Real::INFINITY, |sp| {
            self.guard.cost_below(&sp, self.model, self.cfg, bound)
        })
    }

    /// The candidate's guarded cost and gradient ([`guarded_gradient`], against the round's
    /// starting clearance `current`); `+inf` once the round is called off.
    fn value_and_gradient(&self, x: &[Real], current: Real) -> (Real, Vec<Real>) {
        if (self.stop)() {
            return (Real::INFINITY, vec![0.0; x.len()]);
        }
        let pts = to_points(self.s, self.t, x);
        build(&pts, self.end, self.cfg).map_or((Real::INFINITY, vec![0.0; x.len()]), |sp| {
            guarded_gradient(&sp, self.model, self.cfg, self.guard, current)
        })
    }
}

/// L-BFGS with `tolerance` as its value tolerance and a budget of `evaluations` (at least
/// one). [`PlanConfig::check`](crate::PlanConfig::check) refuses a negative or non-finite
/// tolerance before any plan; a caller of [`crate::grow`] that gives one gets what the
/// solver did before it checked its settings: no stop on the value (tolerance 0).
pub(super) fn lbfgs_for(tolerance: Real, evaluations: usize) -> Lbfgs {
    let tolerance = if tolerance.is_finite() && tolerance >= 0.0 {
        tolerance
    } else {
        0.0
    };
    Lbfgs::default()
        .with_value_tolerance(tolerance)
        .and_then(|l| l.with_max_evaluations(evaluations.max(1)))
        .unwrap_or_default()
}
