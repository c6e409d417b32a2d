//! The planner's settings ([`PlanConfig`], [`Seed`] and their defaults), the errors it
//! reports before any class is optimised ([`PlanError`]), and the checks of a configuration.

use std::fmt;

use homospline_geom::math::Num;
use homospline_geom::{Real, Vector};
use homospline_homotopy::{SearchConfig, SearchError};
use homospline_voronoi::BuildError;
use thiserror::Error;

use crate::growth::GrowthConfig;
#[cfg(doc)]
use crate::growth::{Growth, Guard};
use crate::lbfgs::Lbfgs;

/// How the initial spline is made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Seed {
    /// The paper's planner: one seed per class of the Voronoi graph.
    #[default]
    Voronoi,
    /// The original planner: `S`, the midpoint, `T` (one class).
    Straight,
}

impl Seed {
    /// `voronoi` or `straight`, as in the plan result.
    pub fn name(self) -> &'static str {
        match self {
            Seed::Voronoi => "voronoi",
            Seed::Straight => "straight",
        }
    }
}

/// The dm rule's target in a class whose graph path is less clear than `dm` (a passage
/// narrower than `2 dm`), as a share of that path's least clearance: the graph path runs
/// midway between obstacles, the most a path of the class can keep, and a smooth curve
/// through the passage keeps somewhat less.
pub const DM_RULE_SHARE: Real = 0.9;

/// Settings of [`plan`](super::plan): classes, seed, resolution, the growth loop and its
/// cost, the class search, the clearance floor. `Default` is the scene profile (5 classes,
/// Nelder-Mead); maps start from `homospline_optim::PlanConfig::maps()`.
///
/// # Examples
///
/// ```
/// use homospline_optim::PlanConfig;
///
/// // Three classes, each kept at least 0.5 from every obstacle.
/// let cfg = PlanConfig {
///     classes: 3,
///     clearance_floor: 0.5,
///     ..PlanConfig::default()
/// };
/// assert_eq!(cfg.classes, 3);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PlanConfig {
    /// Seeding.
    pub seed: Seed,
    /// Classes to optimise (the paper uses 5 to 7).
    pub classes: usize,
    /// Grid cells per map unit; `None` picks about 256 cells along the longer side.
    pub resolution: Option<Real>,
    /// Class search (its `k` is overridden by `classes`).
    pub search: SearchConfig,
    /// Growth loop and cost.
    pub growth: GrowthConfig,
    /// Worker threads, 1 to [`MAX_THREADS`]; `None` uses rayon's default. The result is the
    /// same for any count.
    pub threads: Option<usize>,
    /// Tolerance of the certified clearance, map units.
    pub certify_tolerance: Real,
    /// A hard margin: the growth loop rejects candidates whose clearance is below it (see
    /// [`Guard::clearance_floor`]), and the chosen class must be certified at least this
    /// clear. 0 (default): only collisions are rejected.
    pub clearance_floor: Real,
    /// The paper's rule that a path must keep `dm` (docs/method.md, *Safety as a rule*), applied
    /// inside the optimiser as a constraint ([`Guard::clearance_target`]): each class's
    /// curve first climbs to `dm` (or, in a passage narrower than `2 dm`, to
    /// [`DM_RULE_SHARE`] of its graph path's clearance), then lowers its cost while keeping
    /// it. Without it `dm` acts only through the penalty `D`, which at the paper's weights
    /// trades clearance for roughness and length (chosen paths short of dm). On
    /// (default) for scenes; off on maps, whose one-cell doors and corners sit far below
    /// any `dm` (see `homospline_optim::PlanConfig::maps`).
    pub dm_rule: bool,
    /// The robot's heading at the start, when it is moving (a re-plan on the way): curves
    /// leave along it, unless their class path starts backwards (the robot turns on the
    /// spot: it is omni-directional).
    pub start_heading: Option<Vector>,
    /// Classes to leave out, by signature text.
    pub avoid: Vec<String>,
    /// Limited overlap: a class is taken only if it shares at most this fraction of its
    /// graph path's length with every class already taken (k shortest paths with limited
    /// overlap). `None`: the k best classes, however alike.
    pub diverse: Option<Real>,
    /// Successive halving of the classes: after every class's first round, a class whose
    /// cost exceeds this ratio times that of the class ranked first (keeping `dm` itself as
    /// the dm rule's target, certified clear) runs no further rounds, and is reported from its
    /// first round's curve, marked [`ClassPlan::pruned`](super::ClassPlan::pruned). A heuristic: a first round can be a
    /// poor guide. The default [`DEFAULT_PRUNE`] of 1.5 was chosen on the fixtures and
    /// generated scenes (the ignored test `scan_the_ratio` in `tests/it/prune.rs`): it
    /// rarely changes the chosen class against running every class to its end, and saves
    /// a large share of the evaluations, with either optimiser; lower ratios change more choices,
    /// higher ones save less (measured: docs/performance.md, "Measurements behind the
    /// defaults"). `None`
    /// runs every class to its end (a mission does: its other classes are its alternatives).
    /// Applies where the classes are optimised after the search (scenes), not to a map's
    /// classes, optimised while the search goes on. At the defaults the evaluations it saves
    /// also decide whether the chosen class gets its finish ([`PlanConfig::finish_within`]):
    /// on a scene near that budget, with pruning it does and without it does not.
    pub prune: Option<Real>,
    /// Rounds of polish for the class the plan chooses ([`Growth::polish`]): after the
    /// classes are ranked, the first one's loop runs up to this many more rounds at its
    /// via-points, each from a fresh simplex and ending with an interior-point finish
    /// (L-BFGS with a barrier on the clearance), and is reported again. The polish is kept only
    /// if the class stays collision-free, at the floor, safe if it was, and no dearer, so it
    /// stays first; else its curve is put back. 0 (default): none. Scenes only, like the
    /// pruning; a class stopped by the pruning is not polished.
    pub polish: usize,
    /// A work budget, in cost evaluations, for the chosen class's interior-point finish:
    /// after the classes are ranked, if the plan has spent fewer evaluations than this, the
    /// class it chooses gets one finish-only polish round ([`Growth::finish`]: L-BFGS on the
    /// cost with a log barrier on the clearance, from its curve at its via-points) with half
    /// a round's budget, at most what is left of this one (nothing when fewer than
    /// [`crate::growth::MIN_FINISH_EVALUATIONS`] are left). It is kept as a polish is (the
    /// same class, collision-free, at the floor, safe if it was, no dearer), else undone.
    /// A deterministic stand-in for a latency budget: evaluations, not time, so the plan
    /// does not depend on the machine or its load (a value with its gradient counts one,
    /// though it costs about 2.5 times a simplex evaluation). `None` or 0: never. Scenes
    /// only, like [`PlanConfig::polish`], which replaces it when set; on an occupancy map
    /// neither runs.
    pub finish_within: Option<usize>,
    /// No detour for nothing: the chosen class gives way to a choosable class (collision-free,
    /// at the floor) that is more than [`Detour::length_ratio`] times shorter while keeping at
    /// least [`Detour::clearance_share`] of its least clearance, as often as one exists (each
    /// step shortens the choice by that ratio, so it ends). The class chosen so is ranked
    /// just before the one it replaced. `None` (scenes: the paper's choice by cost alone):
    /// never. On by default on maps (`homospline_optim::PlanConfig::maps`), where a safety term
    /// along the whole path could buy a few hundredths of a cell with a loop three times as
    /// long.
    pub detour: Option<Detour>,
    /// On an occupancy map, `dm` in cells of the map: the map's plan sets the cost's `dm` to
    /// this many cells (of the robot body's clearance) and weighs the safety term so that
    /// `g4 omega^(dm - d)` is what it was at the `dm` it replaces: the walls push the curve
    /// as far as before, and `safe` says whether the path keeps this margin. `None`: the
    /// cost's `dm` as it is (a scene, or a map given `--weight dm=`).
    pub map_dm: Option<Real>,
    /// The most cells of a scene's finer grid, when the first one cannot tell a narrow gap
    /// or an end next to a circle ([`homospline_voronoi::build_within`]); at most, and by
    /// default, [`homospline_voronoi::apart::REFINE_MAX_CELLS`]. Front ends set it from the
    /// memory their process may use, as they check the first grid.
    pub max_refined_cells: usize,
    /// A flag another thread may raise to end the plan early (a front end's Ctrl-C): no
    /// further growth round starts once it is raised, and the plan returns
    /// [`PlanError::Interrupted`]. Not a setting: two configurations compare equal whatever
    /// their flags.
    pub interrupt: Interrupt,
}

/// The flag of [`PlanConfig::interrupt`]: shared by its clones, raised by any of them.
///
/// # Examples
/// ```
/// use homospline_optim::{Interrupt, PlanConfig, PlanError, plan};
/// use homospline_geom::Scene;
///
/// let text = include_str!("../../../../fixtures/scenes/convex.yaml");
/// let scene = Scene::from_str(text, "convex.yaml").unwrap();
/// let cfg = PlanConfig::default();
/// cfg.interrupt.raise(); // as a signal handler on another thread would
/// assert!(matches!(plan(&scene, &cfg), Err(PlanError::Interrupted)));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Interrupt(std::sync::Arc<std::sync::atomic::AtomicBool>);

impl Interrupt {
    /// Raises the flag: every plan holding it stops after its running growth rounds.
    pub fn raise(&self) {
        self.0.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// Whether it was raised.
    pub fn is_raised(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

impl Interrupt {
    /// Raises the flag once `after` has passed, unless the returned [`Deadline`] is dropped
    /// first (a watchdog thread: `plan --time-limit`, `bench-scen --time-limit`). A plan
    /// holding the flag then stops at its next growth round or seed.
    ///
    /// # Examples
    /// ```
    /// use std::time::Duration;
    /// use homospline_optim::Interrupt;
    ///
    /// let flag = Interrupt::default();
    /// {
    ///     let _deadline = flag.raise_after(Duration::from_secs(60));
    ///     // work that ends well within the minute
    /// }
    /// assert!(!flag.is_raised()); // dropped in time: never raised
    /// let deadline = flag.raise_after(Duration::from_millis(1));
    /// std::thread::sleep(Duration::from_millis(50));
    /// drop(deadline);
    /// assert!(flag.is_raised());
    /// ```
    pub fn raise_after(&self, after: std::time::Duration) -> Deadline {
        let (done, wait) = std::sync::mpsc::channel::<()>();
        let flag = self.clone();
        let thread = std::thread::spawn(move || {
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(after) {
                flag.raise();
            }
        });
        Deadline {
            done: Some(done),
            thread: Some(thread),
        }
    }
}

/// The watchdog of [`Interrupt::raise_after`]: dropping it before its time ends the thread
/// without raising the flag (and waits for it).
#[derive(Debug)]
pub struct Deadline {
    done: Option<std::sync::mpsc::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Drop for Deadline {
    fn drop(&mut self) {
        drop(self.done.take());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl PartialEq for Interrupt {
    /// Always: the flag is no part of what a plan is asked for.
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// The rule of [`PlanConfig::detour`]: when a shorter class is as good as the chosen one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detour {
    /// A class this many times shorter (or more) than the chosen one replaces it...
    pub length_ratio: Real,
    /// ...if its least clearance is at least this share of the chosen one's.
    pub clearance_share: Real,
}

impl Default for Detour {
    /// 1.25 and 0.9: a quarter longer is a detour a user sees; a tenth of the clearance is
    /// within what the optimiser's budget moves.
    fn default() -> Self {
        Self {
            length_ratio: 1.25,
            clearance_share: 0.9,
        }
    }
}

impl Default for PlanConfig {
    fn default() -> Self {
        Self {
            seed: Seed::Voronoi,
            classes: 5,
            resolution: None,
            search: SearchConfig::default(),
            growth: GrowthConfig::default(),
            threads: None,
            certify_tolerance: 1e-3,
            clearance_floor: 0.0,
            dm_rule: true,
            start_heading: None,
            avoid: Vec::new(),
            diverse: None,
            prune: Some(DEFAULT_PRUNE),
            polish: 0,
            finish_within: Some(DEFAULT_FINISH_WITHIN),
            detour: None,
            map_dm: None,
            max_refined_cells: homospline_voronoi::apart::REFINE_MAX_CELLS,
            interrupt: Interrupt::default(),
        }
    }
}

/// The default of [`PlanConfig::finish_within`].
pub const DEFAULT_FINISH_WITHIN: usize = 1500;

/// The default of [`PlanConfig::prune`].
pub const DEFAULT_PRUNE: Real = 1.5;

/// Most worker threads a plan may ask for ([`PlanConfig::threads`]): far beyond the
/// classes a plan has, and a pool of thousands of threads is slow to start (measured:
/// docs/performance.md, "Measurements behind the defaults").
pub const MAX_THREADS: usize = 256;

/// Candidates searched per class wanted when the selection limits overlap.
pub const DIVERSE_CANDIDATES: usize = 4;

/// Why planning failed before any class was optimised.
#[derive(Debug, Error)]
pub enum PlanError {
    /// Grid or graph.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// Class search.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// A setting out of its range, or settings that do not go together.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// Thread pool.
    #[error("cannot start worker threads: {0}")]
    Threads(String),
    /// [`PlanConfig::interrupt`] was raised.
    #[error("interrupted")]
    Interrupted,
}

impl PlanError {
    /// Whether this is an answer, not a fault: start and goal are walled apart
    /// ([`homospline_voronoi::GraphError::Walled`]), so there is no route (exit 1 on the
    /// command line, as no collision-free class is).
    pub fn is_no_route(&self) -> bool {
        matches!(self, PlanError::Build(BuildError::Graph(g)) if g.is_no_route())
    }
}

/// Most classes a plan may ask for ([`PlanConfig::classes`]).
pub const MAX_CLASSES: usize = 64;

/// Most growth rounds ([`GrowthConfig::max_rounds`]).
pub const MAX_ROUNDS: usize = 100;

/// The largest [`GrowthConfig::max_via_points`].
pub const MAX_VIA_POINTS_CAP: usize = 200;

/// Most polish rounds ([`PlanConfig::polish`]).
pub const MAX_POLISH: usize = 10;

/// A setting of [`PlanConfig`], as a [`ConfigError`] names it; the front ends map each to
/// their own spelling (`--max-via`, `max_via=`) in one place.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Setting {
    /// [`PlanConfig::classes`].
    Classes,
    /// [`PlanConfig::avoid`].
    Avoid,
    /// [`PlanConfig::seed`] against the settings it cannot take.
    Seed,
    /// [`PlanConfig::threads`].
    Threads,
    /// [`PlanConfig::resolution`].
    Resolution,
    /// [`PlanConfig::clearance_floor`].
    ClearanceFloor,
    /// The cost's weights and parameters ([`GrowthConfig::cost`]).
    Cost,
    /// [`PlanConfig::diverse`].
    Diverse,
    /// [`PlanConfig::prune`].
    Prune,
    /// [`GrowthConfig::max_rounds`].
    MaxRounds,
    /// [`GrowthConfig::max_via_points`].
    MaxViaPoints,
    /// [`PlanConfig::polish`].
    Polish,
    /// [`GrowthConfig::lbfgs_value_tolerance`].
    LbfgsValueTolerance,
    /// A saved graph given with the configuration.
    Graph,
}

impl Setting {
    /// Its field's path in [`PlanConfig`].
    pub fn field(self) -> &'static str {
        match self {
            Setting::Classes => "classes",
            Setting::Avoid => "avoid",
            Setting::Seed => "seed",
            Setting::Threads => "threads",
            Setting::Resolution => "resolution",
            Setting::ClearanceFloor => "clearance_floor",
            Setting::Cost => "growth.cost",
            Setting::Diverse => "diverse",
            Setting::Prune => "prune",
            Setting::MaxRounds => "growth.max_rounds",
            Setting::MaxViaPoints => "growth.max_via_points",
            Setting::Polish => "polish",
            Setting::LbfgsValueTolerance => "growth.lbfgs_value_tolerance",
            Setting::Graph => "graph",
        }
    }
}

/// A [`PlanConfig`] setting out of its range (with the value given), or settings that do
/// not go together: the one check of each value ([`PlanConfig::check`]), which the command
/// line and Python report in their own spelling.
///
/// # Examples
///
/// ```
/// use homospline_optim::PlanConfig;
/// use homospline_optim::planner::Setting;
///
/// let cfg = PlanConfig { classes: 0, ..PlanConfig::default() };
/// let e = cfg.check().unwrap_err();
/// assert_eq!(e.setting, Setting::Classes);
/// assert_eq!(e.to_string(), "classes 0: must be between 1 and 64");
/// ```
#[derive(Clone, Debug, Error, PartialEq)]
#[error("{}{}: {problem}", setting.field(), value.as_ref().map(|v| format!(" {v}")).unwrap_or_default())]
pub struct ConfigError {
    /// The setting at fault.
    pub setting: Setting,
    /// Its value, when one is to blame.
    pub value: Option<String>,
    /// What is wrong.
    pub problem: String,
}

impl ConfigError {
    /// `setting` of `value` has `problem`.
    pub fn new(setting: Setting, value: impl fmt::Display, problem: impl Into<String>) -> Self {
        Self {
            setting,
            value: Some(value.to_string()),
            problem: problem.into(),
        }
    }

    /// `setting` cannot be given here: `problem` says why.
    pub fn given(setting: Setting, problem: impl Into<String>) -> Self {
        Self {
            setting,
            value: None,
            problem: problem.into(),
        }
    }
}

/// `x` of `setting` is in `range`, or "must be between a and b".
fn within(
    setting: Setting,
    x: usize,
    range: std::ops::RangeInclusive<usize>,
) -> Result<(), ConfigError> {
    if range.contains(&x) {
        Ok(())
    } else {
        Err(ConfigError::new(
            setting,
            x,
            format!("must be between {} and {}", range.start(), range.end()),
        ))
    }
}

/// The classes a plan asks for: 1 to [`MAX_CLASSES`].
pub fn check_classes(k: usize) -> Result<(), ConfigError> {
    within(Setting::Classes, k, 1..=MAX_CLASSES)
}

/// The limited overlap: a fraction in `[0, 1]`.
pub fn check_diverse(f: Real) -> Result<(), ConfigError> {
    if f.is_finite() && (0.0..=1.0).contains(&f) {
        Ok(())
    } else {
        Err(ConfigError::new(
            Setting::Diverse,
            Num(f),
            "must be a fraction in [0, 1]",
        ))
    }
}

impl PlanConfig {
    /// Checks every setting against its range, and the straight seed against the settings
    /// it cannot take: the one place each value is checked (the planner calls it before any
    /// work; the front ends call it on what their options built, and spell its
    /// [`ConfigError`] as their options). The classes a plan avoids are checked against a
    /// world's rays when it plans.
    pub fn check(&self) -> Result<(), ConfigError> {
        check_classes(self.classes)?;
        if self.seed == Seed::Straight && (!self.avoid.is_empty() || self.diverse.is_some()) {
            return Err(ConfigError::given(
                Setting::Seed,
                "avoid and diverse choose among the Voronoi seed's classes; the straight seed plans one class",
            ));
        }
        if let Some(n) = self.threads {
            within(Setting::Threads, n, 1..=MAX_THREADS)?;
        }
        if let Some(r) = self.resolution
            && !(r.is_finite() && r > 0.0)
        {
            return Err(ConfigError::new(
                Setting::Resolution,
                Num(r),
                "must be positive",
            ));
        }
        if !(self.clearance_floor.is_finite() && self.clearance_floor >= 0.0) {
            return Err(ConfigError::new(
                Setting::ClearanceFloor,
                Num(self.clearance_floor),
                "must be a finite number >= 0",
            ));
        }
        self.growth
            .cost
            .validate()
            .map_err(|e| ConfigError::given(Setting::Cost, e.to_string()))?;
        if let Some(f) = self.diverse {
            check_diverse(f)?;
        }
        if let Some(r) = self.prune
            && !(r.is_finite() && r >= 1.0)
        {
            return Err(ConfigError::new(
                Setting::Prune,
                Num(r),
                "expected off or a ratio of at least 1",
            ));
        }
        Lbfgs::default()
            .with_value_tolerance(self.growth.lbfgs_value_tolerance)
            .map_err(|_| {
                ConfigError::new(
                    Setting::LbfgsValueTolerance,
                    Num(self.growth.lbfgs_value_tolerance),
                    "must be a finite number >= 0",
                )
            })?;
        within(Setting::MaxRounds, self.growth.max_rounds, 1..=MAX_ROUNDS)?;
        within(
            Setting::MaxViaPoints,
            self.growth.max_via_points,
            1..=MAX_VIA_POINTS_CAP,
        )?;
        within(Setting::Polish, self.polish, 0..=MAX_POLISH)
    }
}

/// Why `text` names no class of a scene or map with `rays` rays, if it does not: a class is
/// written as its signature prints, `e` or ray crossings such as `-1+12` (rays from 1), or as
/// its short id (`#` and eight hex digits, [`homospline_homotopy::class_id`]). A mistyped
/// class was left out of nothing, silently.
pub(super) fn avoid_misfit(text: &str, rays: usize) -> Option<String> {
    if text == "e" || homospline_homotopy::is_hashed_id(text) {
        return None;
    }
    let mut rest = text;
    if rest.is_empty() {
        return Some(
            "not a class: e, ray crossings such as -1+2, or an id such as #3f9a01c2".into(),
        );
    }
    while let Some(sign) = rest.chars().next() {
        if sign != '+' && sign != '-' {
            return Some(
                "not a class: e, ray crossings such as -1+2, or an id such as #3f9a01c2".into(),
            );
        }
        let digits = rest[1..]
            .find(['+', '-'])
            .map_or(&rest[1..], |end| &rest[1..1 + end]);
        match digits.parse::<usize>() {
            Ok(k) if k >= 1 && k <= rays && !digits.starts_with('0') => {}
            Ok(k) if k >= 1 && !digits.starts_with('0') => {
                return Some(format!("ray {k}: there are {rays} rays here"));
            }
            _ => {
                return Some(
                    "not a class: e, ray crossings such as -1+2, or an id such as #3f9a01c2".into(),
                );
            }
        }
        rest = &rest[1 + digits.len()..];
    }
    None
}

/// Whether `cfg` can plan in a world of `rays` rays: [`PlanConfig::check`], and each
/// avoided class must name a class there.
pub(super) fn validate(cfg: &PlanConfig, rays: usize) -> Result<(), PlanError> {
    cfg.check()?;
    for a in &cfg.avoid {
        if let Some(why) = avoid_misfit(a, rays) {
            return Err(ConfigError::new(Setting::Avoid, format!("'{a}'"), why).into());
        }
    }
    Ok(())
}
