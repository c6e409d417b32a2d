//! A mission's settings: the scout policy's choice, the planner offline and on the move, the time
//! step and the hysteresis, with their ranges.

use std::fmt;

use homospline_geom::math::Num;
use homospline_geom::{Real, Scene, Vector};
use homospline_optim::planner::{ConfigError, MAX_CLASSES, Setting};
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
    /// Scout policy (default [`Policy::SURVEY`]).
    pub policy: Policy,
    /// Scouts to fly (`None`: every UAV of the world). More than the world lists are added
    /// at the UGV's start with speed 3 and sensor range 10.
    pub scouts: Option<usize>,
    /// Time step, seconds.
    pub dt: Real,
    /// Hysteresis: a valid plan is given up for another class only if that class costs at
    /// least this fraction less; and after a blockage, the current class is kept if it costs
    /// at most this fraction more than the best. In `[0, 1)`.
    pub switch_margin: Real,
    /// Hysteresis: seconds between two voluntary switches.
    pub min_switch_interval: Real,
    /// Give up after this many seconds (`None`: 20 times the straight-line time plus 60 s).
    pub max_time: Option<Real>,
    /// Classes optimised at a re-plan on the move (the offline plan takes `plan.classes`):
    /// the UGV's next class and the alternatives the scouts may verify. Fewer classes, a
    /// shorter stop. Default 2: a third class made the missions drive no less and the
    /// re-plans slower (measured: docs/performance.md, "Measurements behind the defaults").
    pub replan_classes: usize,
    /// A re-plan on the move stops each L-BFGS round when an iteration improves the cost by
    /// less than this, relatively (`GrowthConfig::lbfgs_value_tolerance`; the offline plan
    /// runs to its budget). 1e-5 cut the re-plans' tail latency with the missions'
    /// distances nearly those of the full budget (docs/decisions/0018-coarse-replans.md;
    /// measured: docs/performance.md, "Measurements behind the defaults").
    pub replan_value_tolerance: Real,
    /// On scene worlds, a re-plan's Voronoi graph is this many times coarser than the
    /// offline plan's (its resolution divided by it; 1: the same graph). Half the cells
    /// across (the default, 2) cut the graph's time several times over and the seeds'
    /// via-points with it; a re-plan whose coarse graph offers no collision-free class is planned again
    /// on the full one, so a passage narrower than a coarse cell is still found when it is
    /// the way left (docs/decisions/0018-coarse-replans.md). Maps keep their own grid.
    pub replan_coarsening: Real,
    /// The blockage prior `P`: a class the UGV re-plans into costs `1 + P u` times its plan's
    /// cost, `u` the share of its route no robot has seen, so that the UGV keeps to ways
    /// seen clear where a way not seen yet is barely shorter (0: plans as if the unseen were
    /// clear). Default 0.1: it cut every policy's distance over the truth plan on the
    /// generated missions, and a higher prior gave the same (measured: docs/performance.md,
    /// "Measurements behind the defaults").
    pub blockage_prior: Real,
}

impl MissionConfig {
    /// The planner's settings for a re-plan from a UGV on the move along `heading`: the
    /// curves leave along it, with [`MissionConfig::replan_classes`] classes and
    /// [`MissionConfig::replan_value_tolerance`].
    pub fn replan_config(&self, heading: Vector) -> PlanConfig {
        let mut cfg = PlanConfig {
            start_heading: Some(heading),
            classes: self.replan_classes.min(self.plan.classes).max(1),
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
                    // Every round is L-BFGS, as the mission figures were measured: the
                    // classes L-BFGS leaves short of dm are shorter, and the generated
                    // missions drove less than with the climb by Nelder-Mead
                    // (docs/decisions/0004-lbfgs-climbs-by-simplex.md; measured:
                    // docs/performance.md, "Measurements behind the defaults").
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
    /// the seeds are pulled taut), the class search, the safety term (`dm` 1.5 map units,
    /// along the whole path) and the detour rule. It keeps the missions' own dm rule and
    /// L-BFGS tolerance, where `plan` on a map has neither: without either the map worlds'
    /// distances rose (measured: CHANGELOG.md, "Measured and not adopted"). Change any of
    /// them after: `simulate_map` takes the settings as given.
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
    /// A setting is out of its range ([`MissionConfig::check`]).
    #[error(transparent)]
    Setting(#[from] MissionConfigError),
    /// The mission cannot run as set up: too many time steps, or a map world whose known
    /// map cannot be modelled.
    #[error("{0}")]
    Config(String),
}

/// A setting of [`MissionConfig`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MissionSetting {
    /// A setting of [`MissionConfig::plan`].
    Plan(Setting),
    /// [`MissionConfig::replan_classes`].
    ReplanClasses,
    /// [`MissionConfig::dt`].
    Dt,
    /// [`MissionConfig::scouts`].
    Scouts,
    /// [`MissionConfig::switch_margin`].
    SwitchMargin,
    /// [`MissionConfig::min_switch_interval`].
    MinSwitchInterval,
    /// [`MissionConfig::replan_value_tolerance`].
    ReplanValueTolerance,
    /// [`MissionConfig::replan_coarsening`].
    ReplanCoarsening,
    /// [`MissionConfig::blockage_prior`].
    BlockagePrior,
    /// [`MissionConfig::max_time`].
    MaxTime,
}

impl MissionSetting {
    /// Its field's path in [`MissionConfig`].
    pub fn field(self) -> String {
        match self {
            Self::Plan(s) => format!("plan.{}", s.field()),
            Self::ReplanClasses => "replan_classes".into(),
            Self::Dt => "dt".into(),
            Self::Scouts => "scouts".into(),
            Self::SwitchMargin => "switch_margin".into(),
            Self::MinSwitchInterval => "min_switch_interval".into(),
            Self::ReplanValueTolerance => "replan_value_tolerance".into(),
            Self::ReplanCoarsening => "replan_coarsening".into(),
            Self::BlockagePrior => "blockage_prior".into(),
            Self::MaxTime => "max_time".into(),
        }
    }
}

/// A [`MissionConfig`] setting out of its range, with the value given: the one check of each
/// value ([`MissionConfig::check`]), which the command line and Python report in their own
/// spelling.
///
/// # Examples
///
/// ```
/// use homospline_mission::MissionConfig;
/// use homospline_mission::sim::MissionSetting;
///
/// let cfg = MissionConfig { switch_margin: 1.0, ..MissionConfig::default() };
/// let e = cfg.check().unwrap_err();
/// assert_eq!(e.setting, MissionSetting::SwitchMargin);
/// assert_eq!(e.to_string(), "switch_margin 1: must be in [0, 1)");
/// ```
#[derive(Clone, Debug, Error, PartialEq)]
#[error("{}{}: {problem}", setting.field(), value.as_ref().map(|v| format!(" {v}")).unwrap_or_default())]
pub struct MissionConfigError {
    /// The setting at fault.
    pub setting: MissionSetting,
    /// Its value, when one is to blame.
    pub value: Option<String>,
    /// What is wrong.
    pub problem: String,
}

impl MissionConfigError {
    fn new(setting: MissionSetting, value: impl fmt::Display, problem: impl Into<String>) -> Self {
        Self {
            setting,
            value: Some(value.to_string()),
            problem: problem.into(),
        }
    }
}

impl From<ConfigError> for MissionConfigError {
    fn from(e: ConfigError) -> Self {
        Self {
            setting: MissionSetting::Plan(e.setting),
            value: e.value,
            problem: e.problem,
        }
    }
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

impl MissionConfig {
    /// Checks every setting against its range: the planner's ([`PlanConfig::check`]) and the
    /// mission's own. The one place each value is checked: [`simulate`](crate::simulate) and
    /// [`simulate_map`](crate::simulate_map) call it before any work, and the front ends on
    /// what their options built, spelling its [`MissionConfigError`] as their options.
    pub fn check(&self) -> Result<(), MissionConfigError> {
        use MissionSetting as S;
        self.plan.check()?;
        if !(1..=MAX_CLASSES).contains(&self.replan_classes) {
            return Err(MissionConfigError::new(
                S::ReplanClasses,
                self.replan_classes,
                format!("must be between 1 and {MAX_CLASSES}"),
            ));
        }
        if !(self.dt.is_finite() && (MIN_DT..=10.0).contains(&self.dt)) {
            return Err(MissionConfigError::new(
                S::Dt,
                Num(self.dt),
                format!("must be between {MIN_DT} and 10 seconds"),
            ));
        }
        if let Some(n) = self.scouts.filter(|&n| n > MAX_SCOUTS) {
            return Err(MissionConfigError::new(
                S::Scouts,
                n,
                format!("must be at most {MAX_SCOUTS}"),
            ));
        }
        if !(self.switch_margin.is_finite() && (0.0..1.0).contains(&self.switch_margin)) {
            return Err(MissionConfigError::new(
                S::SwitchMargin,
                Num(self.switch_margin),
                "must be in [0, 1)",
            ));
        }
        if let Some(t) = self.max_time
            && !(t.is_finite() && t > 0.0)
        {
            return Err(MissionConfigError::new(
                S::MaxTime,
                Num(t),
                "must be a positive number of seconds",
            ));
        }
        at_least(
            S::MinSwitchInterval,
            self.min_switch_interval,
            0.0,
            "must be >= 0 seconds",
        )?;
        at_least(
            S::ReplanValueTolerance,
            self.replan_value_tolerance,
            0.0,
            "must be a finite number >= 0",
        )?;
        at_least(
            S::ReplanCoarsening,
            self.replan_coarsening,
            1.0,
            "must be a finite number >= 1",
        )?;
        if !(self.blockage_prior.is_finite()
            && (0.0..=MAX_BLOCKAGE_PRIOR).contains(&self.blockage_prior))
        {
            return Err(MissionConfigError::new(
                S::BlockagePrior,
                Num(self.blockage_prior),
                format!("must be between 0 and {MAX_BLOCKAGE_PRIOR}"),
            ));
        }
        Ok(())
    }
}

/// `x` of `setting` is finite and at least `min`, or `problem`.
fn at_least(
    setting: MissionSetting,
    x: Real,
    min: Real,
    problem: &str,
) -> Result<(), MissionConfigError> {
    if x.is_finite() && x >= min {
        Ok(())
    } else {
        Err(MissionConfigError::new(setting, Num(x), problem))
    }
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
