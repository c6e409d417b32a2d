//! The named profiles of [`PlanConfig`]: [`PlanConfig::scenes`], the paper's (Nelder-Mead,
//! five classes, the dm rule), and [`PlanConfig::maps`], for occupancy maps (L-BFGS, more
//! via-points, budgets that grow with the path, the safety term along the whole path).
//! Front ends apply their users' options on top of one of them, and check the result once
//! ([`PlanConfig::check`]).

use homospline_geom::Real;
use homospline_spline::CostConfig;

use super::config::{Detour, PlanConfig};

/// Via-points a map plan allows by default: one-cell doors and corridors need the curve held
/// close, more than the scenes' default of 10.
pub const MAX_VIA_POINTS: usize = 32;

/// Evaluation budget of one optimisation round on a map, whatever the path's length (each
/// L-BFGS evaluation, a cost and its gradient, counts as four budget units): the work per
/// plan grows linearly with the path.
pub const MAX_EVALUATIONS_PER_ROUND: usize = 800;

/// Curves of more segments than this get a smaller budget per round, in proportion, down to
/// [`MIN_EVALUATIONS_PER_ROUND`] (40 evaluations) from 100 segments on. The seeds are pulled
/// taut in their class before they are optimised, so a long curve starts close to where its
/// cost flattens out: on the full-scale MovingAI maps, halving the previous budget (40
/// segments, 80 evaluations) barely moved the chosen classes' cost (measured:
/// docs/performance.md, "Measurements behind the defaults"). Short curves (the small maps'
/// goldens) keep the whole budget: their rounds do improve with it.
pub const BUDGET_SEGMENTS: usize = 20;

/// The floor of the shrinking budget on long curves.
pub const MIN_EVALUATIONS_PER_ROUND: usize = 160;

/// Budget of the class search on a map: the graph of a whole map has thousands of cycles, and
/// past the classes near the shortest path each further one costs a wide sweep; when the
/// budget runs out the classes found so far are optimised (the result says so).
pub const MAX_EXPANSIONS: usize = 20_000;

/// `dm` of the safety term on maps, map units: kept along the path where the corridor allows.
pub const MAP_DM: Real = 1.5;

/// `omega` of the safety term on maps.
pub const MAP_OMEGA: Real = 1000.0;

/// The safety term of maps, set on `cost` (whatever preset it came from): it sees every
/// stretch of the path, not only its least clear point (a start next to a wall or a one-cell
/// door), so the whole path keeps away from walls where the corridor allows (docs/method.md,
/// 5.5); `dm` is [`MAP_DM`], what a stretch should keep where the corridor allows, and a
/// steep `omega` ([`MAP_OMEGA`]) tells a grazing stretch from one in the middle of a
/// one-cell gap (decision 0021). The one owner of these three values: [`PlanConfig::maps`], the
/// front ends' options and the missions' map profile all set them with it.
pub fn map_safety(cost: &mut CostConfig) {
    cost.safety_along = true;
    cost.dm = MAP_DM;
    cost.omega = MAP_OMEGA;
}

/// L-BFGS on maps stops at a step that lowers the cost by less than this share of it: the
/// last steps of a round bought less and ran its budget out (docs/method.md, 5.5).
pub const LBFGS_VALUE_TOLERANCE: Real = 1e-3;

/// The default `dm` on maps, in cells ([`PlanConfig::map_dm`]): a path that keeps a quarter
/// of a cell (beyond the robot's radius) from every occupied cell is `safe`. A map places a
/// wall only to within its cell; half a cell is what a point robot keeps through a one-cell
/// door at best, so a quarter cell can be kept through every passage the robot fits, and
/// a path that comes closer to a wall than that cuts a corner.
pub const MAP_DM_CELLS: Real = 0.25;

impl PlanConfig {
    /// The scene profile: [`PlanConfig::default`] (5 classes, the Voronoi seed,
    /// Nelder-Mead, the dm rule, pruning and the chosen class's finish).
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_optim::{Optimizer, PlanConfig};
    ///
    /// let scenes = PlanConfig::scenes();
    /// assert_eq!(scenes.classes, 5);
    /// assert_eq!(scenes.growth.optimizer, Optimizer::NelderMead);
    /// let maps = PlanConfig::maps();
    /// assert_eq!(maps.growth.optimizer, Optimizer::Lbfgs);
    /// assert!(maps.growth.cost.safety_along && !maps.dm_rule);
    /// assert_eq!(maps.check(), Ok(()));
    /// ```
    pub fn scenes() -> Self {
        Self::default()
    }

    /// The map profile: the planner's configuration for occupancy maps: [`PlanConfig::scenes`] with
    /// [`MAX_VIA_POINTS`] and L-BFGS. A map path needs up to 64 dimensions, where Nelder-Mead
    /// (the paper's optimiser, the default on scenes) is slower for the same success on the
    /// fixture maps (docs/performance.md).
    pub fn maps() -> Self {
        let mut cfg = Self::scenes();
        cfg.growth.max_via_points = MAX_VIA_POINTS;
        cfg.growth.optimizer = crate::Optimizer::Lbfgs;
        cfg.search.one_path_per_state = true;
        cfg.search.max_expansions = MAX_EXPANSIONS;
        cfg.growth.max_evaluations_per_round = MAX_EVALUATIONS_PER_ROUND;
        cfg.growth.budget_segments = BUDGET_SEGMENTS;
        cfg.growth.min_evaluations_per_round = MIN_EVALUATIONS_PER_ROUND;
        // A map's doors and corners are a cell or two wide: `dm` stays a penalty there, and a
        // hard margin is the user's `--clearance-floor`.
        cfg.dm_rule = false;
        map_safety(&mut cfg.growth.cost);
        // Like `--polish`, the chosen class's finish is for scenes: a map's classes are
        // optimised while the search goes on.
        cfg.finish_within = None;
        // No detour for nothing: the safety term along the path weighs every stretch, and a
        // loop far longer kept barely more clearance than the straight way (decision 0022).
        cfg.detour = Some(Detour::default());
        cfg.map_dm = Some(MAP_DM_CELLS);
        cfg.growth.lbfgs_value_tolerance = LBFGS_VALUE_TOLERANCE;
        cfg
    }
}
