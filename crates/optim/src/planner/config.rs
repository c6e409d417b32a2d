//! The planner's settings ([`PlanConfig`], [`Seed`] and their defaults), the errors it
//! reports before any class is optimised ([`PlanError`]), and the checks of a configuration.

use homospline_geom::{Real, Vector};
use homospline_homotopy::{SearchConfig, SearchError};
use homospline_voronoi::BuildError;
use thiserror::Error;

use crate::growth::GrowthConfig;
#[cfg(doc)]
use crate::growth::{Growth, Guard};

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
/// Nelder-Mead); maps start from `homospline_maps::map_config()`.
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
    /// trades clearance for roughness and length (chosen paths at 0.8 to 1.0 dm). On
    /// (default) for scenes; off on maps, whose one-cell doors and corners sit far below
    /// any `dm` (see `homospline_maps::map_config`).
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
    /// poor guide (a class's cost fell by 54 % in its second round on one generated scene).
    /// On 1,020 scenes (the fixtures and 1,000 generated ones; the ignored test
    /// `scan_the_ratio` in `tests/it/prune.rs`, with [`PlanConfig::finish_within`] off), the
    /// default [`DEFAULT_PRUNE`] of 1.5 changes one chosen class against running every
    /// class to its end (world-030: a class whose
    /// first round cost 1.98 times the reference's won, and the plan chosen instead costs
    /// 1.4 % more), as do 1.4 to 1.75, while 1.25 changes three (one of them 45 % dearer)
    /// and 2 to 4 none; 1.5 saves 60 % of the evaluations there (2.5: 53 %), and on the
    /// paper scenes 30 to 47 % of them (2.5: none on three of the five). With either
    /// optimiser (L-BFGS plans take half the evaluations with it, the same chosen cost in 319
    /// of 320 scanned scenes, one 6.8 % dearer). `None`
    /// runs every class to its end (a mission does: its other classes are its alternatives).
    /// Applies where the classes are optimised after the search (scenes), not to a map's
    /// classes, optimised while the search goes on. At the defaults the evaluations it saves
    /// also decide whether the chosen class gets its finish ([`PlanConfig::finish_within`]):
    /// convex's does with pruning (1,324 evaluations) and not without (2,707).
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
    /// never. On by default on maps (`homospline_maps::map_config`), where a safety term
    /// along the whole path could buy a few hundredths of a cell with a loop three times as
    /// long.
    pub detour: Option<Detour>,
    /// On an occupancy map, `dm` in cells of the map: the map's plan sets the cost's `dm` to
    /// this many cells (of the robot body's clearance) and weighs the safety term so that
    /// `g4 omega^(dm - d)` is what it was at the `dm` it replaces: the walls push the curve
    /// as far as before, and `safe` says whether the path keeps this margin. `None`: the
    /// cost's `dm` as it is (a scene, or a map given `--weight dm=`).
    pub map_dm: Option<Real>,
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
            interrupt: Interrupt::default(),
        }
    }
}

/// The default of [`PlanConfig::finish_within`].
pub const DEFAULT_FINISH_WITHIN: usize = 1500;

/// The default of [`PlanConfig::prune`].
pub const DEFAULT_PRUNE: Real = 1.5;

/// Most worker threads a plan may ask for ([`PlanConfig::threads`]): far beyond the
/// classes a plan has, and a pool of 5,000 threads took longer to start than 20 s.
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
    /// Configuration.
    #[error("{0}")]
    Config(String),
    /// Thread pool.
    #[error("cannot start worker threads: {0}")]
    Threads(String),
    /// [`PlanConfig::interrupt`] was raised.
    #[error("interrupted")]
    Interrupted,
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

/// Whether `cfg` can plan in a world of `rays` rays: the class count, the avoided classes
/// (each must name a class there), the thread count, the clearance floor, the cost, the
/// overlap limit and the pruning ratio are checked before any work.
pub(super) fn validate(cfg: &PlanConfig, rays: usize) -> Result<(), PlanError> {
    if cfg.classes == 0 {
        return Err(PlanError::Config("classes must be at least 1".into()));
    }
    for a in &cfg.avoid {
        avoid_misfit(a, rays).map_or(Ok(()), |why| {
            Err(PlanError::Config(format!("avoid '{a}': {why}")))
        })?;
    }
    if cfg.seed == Seed::Straight && (!cfg.avoid.is_empty() || cfg.diverse.is_some()) {
        return Err(PlanError::Config(
            "avoid and diverse choose among the Voronoi seed's classes; the straight seed plans one class"
                .into(),
        ));
    }
    if let Some(n) = cfg.threads
        && !(1..=MAX_THREADS).contains(&n)
    {
        return Err(PlanError::Config(format!(
            "threads must be between 1 and {MAX_THREADS}, got {n}"
        )));
    }
    if !(cfg.clearance_floor.is_finite() && cfg.clearance_floor >= 0.0) {
        return Err(PlanError::Config(format!(
            "clearance floor must be finite and >= 0, got {}",
            cfg.clearance_floor
        )));
    }
    cfg.growth
        .cost
        .validate()
        .map_err(|e| PlanError::Config(e.to_string()))?;
    if let Some(f) = cfg.diverse
        && !(f.is_finite() && (0.0..=1.0).contains(&f))
    {
        return Err(PlanError::Config(format!(
            "diverse must be a fraction in [0, 1], got {f}"
        )));
    }
    if let Some(r) = cfg.prune
        && !(r.is_finite() && r >= 1.0)
    {
        return Err(PlanError::Config(format!(
            "prune must be a ratio of at least 1, got {r}"
        )));
    }
    Ok(())
}
