//! The growth loop's settings ([`GrowthConfig`], [`Optimizer`]) and their defaults.

use homospline_geom::Real;
use homospline_spline::{CostConfig, EndCondition, Parametrization};

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
    /// start ([`Guard::cost`](super::Guard::cost)'s step at the target has no gradient), so it does not climb to
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
