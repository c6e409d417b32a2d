//! Rounds after the growth loop has ended, from its best curve: the repair round of a curve
//! whose clearance the cost's `m(C)` overstated ([`Growth::repair`]), polish rounds
//! ([`Growth::polish`]) and the finish alone ([`Growth::finish`]).

use homospline_geom::Point;
use homospline_spline::{ClearanceModel, ClearanceSearch, Spline, evaluate};

use super::config::GrowthConfig;
use super::finish::{Finish, MIN_FINISH_EVALUATIONS};
use super::guard::{Guard, proven_at};
use super::state::{Growth, outer_value};
#[cfg(doc)]
use super::{guard::STRICT_SLACK, state::Round};

impl Growth {
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
    /// finish, still lowers its cost when no [`Growth::finish`] ran before it;
    /// docs/decisions/0015-polish-opt-in.md; measured: docs/performance.md, "Measurements
    /// behind the defaults"),
    /// and a growth's new curve starts off the curve before it, so a planner spends these
    /// on the class it chose.
    /// Under a clearance target, on a model that bounds how the clearance bends, the rounds
    /// search `m(C)` between every two nodes ([`ClearanceSearch::EveryStretch`], as a
    /// repair round does), from then on for every curve the loop holds.
    /// Each round ends with an interior-point finish (`interior_finish`: L-BFGS on the cost
    /// plus a [`crate::barrier::Barrier`] on the clearance, its weight falling in three
    /// stages), which moves the curve along the clearance constraint where Nelder-Mead
    /// stalls on it.
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
    /// At a full round's budget, on the scanned scenes, this planned about as well as a
    /// full polish round for clearly less of its work
    /// (docs/decisions/0016-finish-within-budget.md; measured: docs/performance.md,
    /// "Measurements behind the defaults"). Kept or put back as
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
}
