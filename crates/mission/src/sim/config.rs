//! A mission's settings: the scout policy's choice, the planner offline and on the move, the time
//! step and the hysteresis, with their ranges.

use homospline_geom::math::Num;
use homospline_geom::{Real, Scene, Vector};
use homospline_optim::{GrowthConfig, Optimizer, PlanConfig, default_resolution};
use thiserror::Error;

use super::policy::Policy;
use crate::world::types::{Uav, Ugv};

/// Settings of [`simulate`](crate::sim::simulate).
#[derive(Clone, Debug, PartialEq)]
pub struct MissionConfig {
    /// The planner, offline and for every re-plan. Defaults to 5 classes and L-BFGS (re-plans
    /// are on the clock).
    pub plan: PlanConfig,
    /// Scout policy (default [`Policy::GUARD`]).
    pub policy: Policy,
    /// Scouts to fly (`None`: every UAV of the world). More than the world lists are added
    /// at the UGV's start with speed 3 and sensor range 10.
    pub scouts: Option<usize>,
    /// Time step, seconds.
    pub dt: Real,
    /// Hysteresis: a valid plan is given up for another class only if that class costs at
    /// least this fraction less; and after a blockage, the current class is kept if it costs
    /// at most this fraction more than the best.
    pub switch_margin: Real,
    /// Hysteresis: seconds between two voluntary switches.
    pub min_switch_interval: Real,
    /// Give up after this many seconds (`None`: 20 times the straight-line time plus 60 s).
    pub max_time: Option<Real>,
    /// Classes optimised at a re-plan on the move (the offline plan takes `plan.classes`):
    /// the UGV's next class and the alternatives the scouts may verify. Fewer classes, a
    /// shorter stop. Default 2: on `cargo xtask missions --worlds 200` 3 classes drove no
    /// less (`none` 1.075 against 1.064 of the truth plan, `guard` 1.003 against 1.001)
    /// and put the replayed re-plans' p99 at 7.4 ms (4.5 ms with 2).
    pub replan_classes: usize,
    /// A re-plan on the move stops each L-BFGS round when an iteration improves the cost by
    /// less than this, relatively (`GrowthConfig::lbfgs_value_tolerance`; the offline plan
    /// runs to its budget). 1e-5 cut the p99 re-plan latency in the missions from 12.2 to
    /// 8.75 ms with the distances over the optimum within 0.007 of the full budget's
    /// (docs/decisions/0018-coarse-replans.md).
    pub replan_value_tolerance: Real,
    /// On scene worlds, a re-plan's Voronoi graph is this many times coarser than the
    /// offline plan's (its resolution divided by it; 1: the same graph). Half the cells
    /// across (the default, 2) cut the graph's time about sevenfold and the seeds' via-points
    /// with it; a re-plan whose coarse graph offers no collision-free class is planned again
    /// on the full one, so a passage narrower than a coarse cell is still found when it is
    /// the way left (docs/decisions/0018-coarse-replans.md). Maps keep their own grid.
    pub replan_coarsening: Real,
    /// The blockage prior `P`: a class the UGV re-plans into costs `1 + P u` times its plan's
    /// cost, `u` the share of its route no robot has seen, so that the UGV keeps to ways
    /// seen clear where a way not seen yet is barely shorter (0: plans as if the unseen were
    /// clear). Default 0.1: on `cargo xtask missions --worlds 200` it cut the distance over
    /// the truth plan of every policy (`none` 1.065 -> 1.051, worst 2.07 -> 1.63; `guard`
    /// 1.001 -> 0.991), and 0.3 gave the same.
    pub blockage_prior: Real,
}

impl MissionConfig {
    /// The planner's settings for a re-plan from a UGV on the move along `heading`: the
    /// curves leave along it, with [`MissionConfig::replan_classes`] classes and
    /// [`MissionConfig::replan_value_tolerance`].
    pub fn replan_config(&self, heading: Vector) -> PlanConfig {
        let mut cfg = PlanConfig {
            start_heading: Some(heading),
            classes: self.replan_classes.clamp(1, self.plan.classes),
            ..self.plan.clone()
        };
        cfg.growth.lbfgs_value_tolerance = self.replan_value_tolerance;
        cfg
    }

    /// The resolution of a re-plan's graph on `scene` (cells per unit), when it is coarser
    /// than the offline plan's ([`MissionConfig::replan_coarsening`] above 1).
    pub fn replan_resolution(&self, scene: &Scene) -> Option<Real> {
        (self.replan_coarsening > 1.0).then(|| {
            self.plan
                .resolution
                .unwrap_or_else(|| default_resolution(scene))
                / self.replan_coarsening
        })
    }
}

impl Default for MissionConfig {
    fn default() -> Self {
        Self {
            plan: PlanConfig {
                growth: GrowthConfig {
                    optimizer: Optimizer::Lbfgs,
                    // Every round is L-BFGS, as the mission figures were measured. With the
                    // planner's default (a round short of the dm rule's target climbs by
                    // Nelder-Mead), the 200 generated worlds of `cargo xtask missions
                    // --worlds 200`, generated as before, drove 1.112 / 1.038 / 1.042 times
                    // the truth plan (`none` / `ahead` / `alternatives`) against
                    // 1.093 / 1.013 / 1.020: the classes L-BFGS leaves short of dm are
                    // shorter. On narrow-pass-blocked the other way round: the offline plan
                    // drives class `e` (139 long) where climbing makes `-1-2` (96) safe
                    // (docs/decisions/0004-lbfgs-climbs-by-simplex.md).
                    climb_by_simplex: false,
                    ..GrowthConfig::default()
                },
                // Every class runs to its end: the classes the UGV does not take are its
                // alternatives, compared by cost when it weighs a switch.
                prune: None,
                // No finish for the chosen class: a re-plan on the move waits for it, and
                // the missions were measured without it.
                finish_within: None,
                ..PlanConfig::default()
            },
            policy: Policy::default(),
            scouts: None,
            dt: 0.25,
            switch_margin: 0.1,
            min_switch_interval: 10.0,
            max_time: None,
            replan_classes: 2,
            replan_value_tolerance: 1e-5,
            replan_coarsening: 2.0,
            blockage_prior: 0.1,
        }
    }
}

impl MissionConfig {
    /// The settings of a mission on an occupancy-map world ([`simulate_map`](crate::simulate_map)):
    /// [`MissionConfig::default`] with the map defaults of `homospline_optim::PlanConfig::maps` for
    /// the via-points, the evaluation budget (rounds on long curves stop at 40 evaluations:
    /// the seeds are pulled taut), the class search, the safety term (`dm` a quarter cell,
    /// along the whole path) and the detour rule. Change any of them after: `simulate_map`
    /// takes the settings as given.
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_mission::MissionConfig;
    ///
    /// let mut cfg = MissionConfig::for_maps();
    /// assert_eq!(cfg.plan.growth.cost.dm, homospline_optim::PlanConfig::maps().growth.cost.dm);
    /// cfg.plan.growth.cost.dm = 0.5; // kept: nothing overwrites it
    /// ```
    pub fn for_maps() -> Self {
        let mut cfg = Self::default();
        let map = PlanConfig::maps();
        let (plan, growth) = (&mut cfg.plan, &map.growth);
        plan.growth.max_via_points = growth.max_via_points;
        plan.growth.max_evaluations_per_round = growth.max_evaluations_per_round;
        plan.growth.budget_segments = growth.budget_segments;
        plan.growth.min_evaluations_per_round = growth.min_evaluations_per_round;
        plan.search.one_path_per_state = map.search.one_path_per_state;
        plan.search.max_expansions = map.search.max_expansions;
        homospline_optim::planner::profile::map_safety(&mut plan.growth.cost);
        plan.detour = map.detour;
        cfg
    }
}

/// Why a mission could not be simulated at all.
#[derive(Debug, Error)]
pub enum MissionError {
    /// A setting is out of range.
    #[error("{0}")]
    Config(String),
}

/// Smallest time step, seconds.
pub const MIN_DT: Real = 1e-3;

/// Most time steps a mission may take (tracks hold one sample a step).
pub const MAX_STEPS: Real = 1e6;

/// The largest blockage prior ([`MissionConfig::blockage_prior`]).
pub const MAX_BLOCKAGE_PRIOR: Real = 10.0;

/// Most scouts.
pub const MAX_SCOUTS: usize = 64;

/// The most a new path may leave off the UGV's heading without a turn on the spot, degrees.
pub const TURN_ANGLE_DEG: Real = 25.0;

/// The time step a mission runs at: `requested` (`--dt`), refined where a robot would travel
/// more than half its sensor range between two looks. The robots sense once per step, so a
/// UGV stepping farther than its sensor range could drive through a hidden blockage it never
/// saw; at half the range, everything the next step's stretch of route (and the robot's body
/// around it, up to half the range wide) can touch was within range at the last look. A
/// scout stepping farther than that would leave gaps in what it saw.
pub fn time_step<'a>(requested: Real, ugv: &Ugv, uavs: impl IntoIterator<Item = &'a Uav>) -> Real {
    std::iter::once((ugv.speed, ugv.sensor_range))
        .chain(uavs.into_iter().map(|u| (u.speed, u.sensor_range)))
        .filter(|&(speed, _)| speed > 0.0)
        .map(|(speed, range)| 0.5 * range / speed)
        .fold(requested, Real::min)
}

/// The settings' ranges.
pub(super) fn check_config(cfg: &MissionConfig) -> Result<(), MissionError> {
    if cfg.replan_classes == 0 || cfg.plan.classes == 0 {
        return Err(MissionError::Config(
            "--classes: plans need at least 1 class".into(),
        ));
    }
    if !(cfg.dt.is_finite() && (MIN_DT..=10.0).contains(&cfg.dt)) {
        return Err(MissionError::Config(format!(
            "--dt {}: must be between {MIN_DT} and 10 seconds",
            Num(cfg.dt)
        )));
    }
    if cfg.scouts.is_some_and(|n| n > MAX_SCOUTS) {
        return Err(MissionError::Config(format!(
            "--scouts: at most {MAX_SCOUTS}"
        )));
    }
    if !(cfg.switch_margin.is_finite() && cfg.switch_margin >= 0.0) {
        return Err(MissionError::Config(format!(
            "switch margin must be >= 0, got {}",
            cfg.switch_margin
        )));
    }
    if !(cfg.replan_value_tolerance.is_finite() && cfg.replan_value_tolerance >= 0.0) {
        return Err(MissionError::Config(format!(
            "re-plan value tolerance must be a finite number >= 0, got {}",
            cfg.replan_value_tolerance
        )));
    }
    if !(cfg.replan_coarsening.is_finite() && cfg.replan_coarsening >= 1.0) {
        return Err(MissionError::Config(format!(
            "re-plan coarsening must be a finite number >= 1, got {}",
            cfg.replan_coarsening
        )));
    }
    if !(cfg.blockage_prior.is_finite() && (0.0..=MAX_BLOCKAGE_PRIOR).contains(&cfg.blockage_prior))
    {
        return Err(MissionError::Config(format!(
            "--blockage-prior {}: must be between 0 and {MAX_BLOCKAGE_PRIOR}",
            Num(cfg.blockage_prior)
        )));
    }
    if !(cfg.min_switch_interval.is_finite() && cfg.min_switch_interval >= 0.0) {
        return Err(MissionError::Config(format!(
            "minimum time between switches must be >= 0, got {}",
            cfg.min_switch_interval
        )));
    }
    Ok(())
}

/// The mission's length in steps is in range: a positive time limit `max_time` of at most
/// [`MAX_STEPS`] steps of `dt`.
pub(super) fn check_steps(
    cfg: &MissionConfig,
    max_time: Real,
    dt: Real,
) -> Result<(), MissionError> {
    if !(max_time.is_finite() && max_time > 0.0) || max_time / dt > MAX_STEPS {
        let hint = if dt < cfg.dt {
            format!(
                "the step is refined from --dt {} so that no robot travels more than half its sensor range between two looks: give the robots sensor ranges that suit their speeds",
                Num(cfg.dt)
            )
        } else {
            "raise --dt or the UGV's speed".to_owned()
        };
        return Err(MissionError::Config(format!(
            "the mission would take {} time steps (time limit {} s over a step of {} s); at most {MAX_STEPS:.0}: {hint}",
            Num((max_time / dt).round()),
            Num(max_time.round()),
            Num(dt),
        )));
    }
    Ok(())
}
