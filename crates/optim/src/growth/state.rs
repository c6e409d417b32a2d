//! The growth loop's state ([`Growth`]) and what it reports ([`Round`], [`Grown`]): the
//! loop's construction from a seed, its best curve, its result, and the undoing of rounds.
//! The rounds themselves, the via-point insertion and the rounds after the loop's end are
//! in the sibling modules.

use std::borrow::Cow;

use homospline_geom::{Point, Real};
use homospline_spline::{
    ClearanceModel, ClearanceSearch, CostConfig, CostTerms, EndCondition, Spline, SplineError,
    evaluate,
};

use super::config::GrowthConfig;
use super::guard::Guard;

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

/// `S`, the via-points whose coordinates are `x` (x, y interleaved), `T`.
pub(super) fn to_points(s: Point, t: Point, x: &[Real]) -> Vec<Point> {
    let mut v = Vec::with_capacity(x.len() / 2 + 2);
    v.push(s);
    v.extend(x.chunks(2).map(|c| Point::new(c[0], c[1])));
    v.push(t);
    v
}

/// The curve before a growth whose grown curve fell short of the floor or the target, and
/// the clearance the next round must regain.
#[derive(Clone)]
pub(super) struct Probation {
    pub(super) points: Vec<Point>,
    pub(super) spline: Spline,
    pub(super) cost: Real,
    pub(super) floor: Real,
}

/// The best curve of a growth loop so far, and its value.
#[derive(Clone)]
pub(super) struct Best {
    pub(super) value: Real,
    pub(super) points: Vec<Point>,
    pub(super) spline: Spline,
}

/// The spline's end condition for a round that starts from `pts`. A start heading's slope
/// depends on the first via-point; it is fixed for a round (from the round's first curve),
/// so that within a round the curve is linear in its via-points and the analytic gradient
/// holds.
pub(super) fn fixed_end(pts: &[Point], cfg: &GrowthConfig) -> EndCondition {
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

/// The spline through `pts` with the end condition `end`, if there is one.
pub(super) fn build(pts: &[Point], end: EndCondition, cfg: &GrowthConfig) -> Option<Spline> {
    Spline::new(pts, cfg.parametrization, end).ok()
}

/// A curve's value by the outer guard: a curve below its floor ranks last.
pub(super) fn outer_value(guard: &Guard<'_>, clearance: Real, value: Real) -> Real {
    if guard.rejects(clearance) {
        Real::INFINITY
    } else {
        value
    }
}

/// The growth loop as a solver that runs one round at a time: [`Growth::new`] takes the
/// seed, [`Growth::step`] runs a round and the growth after it, [`Growth::result`] gives
/// the best curve so far. [`grow`](super::grow) runs it to the end; a planner can stop a class between rounds
/// (a class that cannot win) and still report its curve. Every call must get the same
/// model, settings and guard.
#[derive(Clone)]
pub struct Growth {
    pub(super) s: Point,
    pub(super) t: Point,
    pub(super) end: EndCondition,
    pub(super) spline: Spline,
    pub(super) points: Vec<Point>,
    pub(super) evaluations: usize,
    pub(super) rounds: Vec<Round>,
    /// Clearance of the current curve, for the floor's ratchet.
    pub(super) current: Real,
    pub(super) best_cost: Real,
    pub(super) probation: Option<Probation>,
    /// The best curve the loop has had, by the outer guard (a curve below its floor ranks
    /// last): a grown curve passes through one more point of the curve before it, but its
    /// knots move and its cost may be higher; if the rounds after it do not win that back,
    /// the loop returns the better curve it had before the growth.
    pub(super) kept_best: Best,
    pub(super) round: usize,
    pub(super) done: bool,
    /// The cost's `m(C)` is searched between every two quadrature nodes
    /// ([`ClearanceSearch::EveryStretch`]): set by the repair round ([`Growth::repair`]).
    pub(super) strict: bool,
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
    pub(super) fn best(&self, guard: &Guard<'_>) -> (&[Point], &Spline) {
        if self.kept_best.value < outer_value(guard, self.current, self.best_cost) {
            (&self.kept_best.points, &self.kept_best.spline)
        } else {
            (&self.points, &self.spline)
        }
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

    /// The straight segment `S-T` as the loop's result, if it is a curve the loop could have
    /// ended on (natural ends, in the class, inside the bounds, certified clear, not below
    /// the floor) and the outer guard values it more than the loop's best curve: the
    /// shortest curve of all, with no roughness, which an optimiser started from a class
    /// path that bends away from it may never reach. A chosen curve 26.00 long and 4.58
    /// clear was reported where the segment, in the same class, was 21.26 long and 6.48
    /// clear. `None` otherwise.
    pub fn straight_if_better(
        &self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        guard: &Guard<'_>,
    ) -> Option<Grown> {
        if !matches!(cfg.end, EndCondition::Natural) {
            return None;
        }
        let points = vec![self.s, self.t];
        // Most classes are not the segment's: its word settles that at once.
        if let Some((rays, sig)) = guard.class
            && rays.signature(&points) != *sig
        {
            return None;
        }
        let spline = build(&points, EndCondition::Natural, cfg)?;
        if !(super::guard::admissible(&spline, guard, cfg.guard_samples)
            && guard.certifies(&spline, model))
        {
            return None;
        }
        let settings = self.settings(cfg);
        // The segment's least clearance searched along every stretch: its few nodes are far
        // apart, and the worst node's neighbours alone can miss a dip (the loop's own curve
        // gets that search in its repair round).
        let searched = CostConfig {
            clearance_search: ClearanceSearch::EveryStretch,
            ..settings.cost.clone()
        };
        let terms = evaluate(&spline, model, &searched);
        let value = outer_value(guard, terms.min_clearance, guard.value(&terms));
        let (best_points, best_spline) = self.best(guard);
        let best_terms = evaluate(best_spline, model, &settings.cost);
        let best = outer_value(guard, best_terms.min_clearance, guard.value(&best_terms));
        if value.is_nan() || value >= best || best_points.len() == 2 {
            return None;
        }
        let exact = CostConfig {
            tolerance: 0.0,
            ..searched
        };
        Some(Grown {
            terms: evaluate(&spline, model, &exact),
            points,
            spline,
            rounds: self.rounds.clone(),
            evaluations: self.evaluations,
        })
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
}
