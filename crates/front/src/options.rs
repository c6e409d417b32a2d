//! The planner's options as every front end takes them (the command line, the Python
//! package): typed values, checked once by [`PlanOptions::validate`], with errors that name
//! the option as each front end spells it ([`Opt::flag`], [`Opt::keyword`]).

use homospline_geom::math::Num;
use std::fmt;
use std::str::FromStr;

use homospline_geom::Scene;
use homospline_mission::{MissionConfigError, MissionSetting};
use homospline_optim::planner::{ConfigError, Setting};
use homospline_optim::{GrowthConfig, Optimizer, PlanConfig, Seed};
use homospline_spline::{ClearanceSearch, Preset, RoughnessForm};

/// An option of a front end, by what it sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[allow(missing_docs)] // each variant is the option of the same name
pub enum Opt {
    Seed,
    Classes,
    Preset,
    Weight,
    Optimizer,
    Roughness,
    ClearanceSearch,
    Resolution,
    Threads,
    MaxVia,
    Rounds,
    ClearanceFloor,
    Avoid,
    Diverse,
    Prune,
    Polish,
    FinishWithin,
    Graph,
    RobotRadius,
    Sample,
    Limit,
    TimeLimit,
    Scouts,
    Dt,
    SwitchMargin,
    MinSwitchInterval,
    BlockagePrior,
}

impl Opt {
    /// The command line's spelling: `--classes`.
    pub fn flag(self) -> &'static str {
        match self {
            Self::Seed => "--seed",
            Self::Classes => "--classes",
            Self::Preset => "--preset",
            Self::Weight => "--weight",
            Self::Optimizer => "--optimizer",
            Self::Roughness => "--roughness",
            Self::ClearanceSearch => "--clearance-search",
            Self::Resolution => "--resolution",
            Self::Threads => "--threads",
            Self::MaxVia => "--max-via",
            Self::Rounds => "--rounds",
            Self::ClearanceFloor => "--clearance-floor",
            Self::Avoid => "--avoid",
            Self::Diverse => "--diverse",
            Self::Prune => "--prune",
            Self::Polish => "--polish",
            Self::FinishWithin => "--finish-within",
            Self::Graph => "--graph",
            Self::RobotRadius => "--robot-radius",
            Self::Sample => "--sample",
            Self::Limit => "--limit",
            Self::TimeLimit => "--time-limit",
            Self::Scouts => "--scouts",
            Self::Dt => "--dt",
            Self::SwitchMargin => "--switch-margin",
            Self::MinSwitchInterval => "--min-switch-interval",
            Self::BlockagePrior => "--blockage-prior",
        }
    }

    /// The Python keyword argument's spelling: `classes`.
    pub fn keyword(self) -> &'static str {
        match self {
            Self::Weight => "weights",
            other => &other.flag()[2..],
        }
    }
}

/// How an error spells the options it names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spelling {
    /// `--classes 0: ...` (the command line).
    Flag,
    /// `classes=0: ...` (Python's keyword arguments; underscores for dashes).
    Keyword,
}

impl Spelling {
    fn name(self, o: Opt) -> String {
        match self {
            Self::Flag => o.flag().to_owned(),
            Self::Keyword => o.keyword().replace('-', "_"),
        }
    }
}

/// An option whose value cannot be taken: which option, the value given and the problem. The
/// problem may name other options as `{Opt:...}` markers, spelled as the error is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OptionError {
    /// The option at fault.
    pub option: Opt,
    /// The value given, when one was.
    pub value: Option<String>,
    problem: String,
    others: Vec<Opt>,
}

impl OptionError {
    /// `option` given `value` has `problem`.
    pub fn new(option: Opt, value: impl fmt::Display, problem: impl Into<String>) -> Self {
        Self {
            option,
            value: Some(value.to_string()),
            problem: problem.into(),
            others: Vec::new(),
        }
    }

    /// `option` cannot be given here: `problem` says why.
    pub fn given(option: Opt, problem: impl Into<String>) -> Self {
        Self {
            option,
            value: None,
            problem: problem.into(),
            others: Vec::new(),
        }
    }

    /// The problem names `other`, written `{}` in it (in order).
    pub fn naming(mut self, other: Opt) -> Self {
        self.others.push(other);
        self
    }

    /// The message in `spelling`: `--classes 0: must be between 1 and 64` or
    /// `classes=0: must be between 1 and 64`.
    pub fn spelled(&self, spelling: Spelling) -> String {
        let mut problem = self.problem.clone();
        for o in &self.others {
            problem = problem.replacen("{}", &spelling.name(*o), 1);
        }
        let name = spelling.name(self.option);
        if let (Opt::Weight, Spelling::Keyword, Some(v)) = (self.option, spelling, &self.value)
            && let Some((key, value)) = v.split_once('=')
        {
            return format!("{name}['{key}']={value}: {problem}");
        }
        match (&self.value, spelling) {
            (Some(v), Spelling::Flag) => format!("{name} {v}: {problem}"),
            (Some(v), Spelling::Keyword) => format!("{name}={v}: {problem}"),
            (None, _) => format!("{name} {problem}"),
        }
    }
}

impl fmt::Display for OptionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.spelled(Spelling::Flag))
    }
}

impl std::error::Error for OptionError {}

/// A setting that can be switched off: `off`, or a value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OrOff<T> {
    /// `off`.
    Off,
    /// A value.
    On(T),
}

impl<T: FromStr> FromStr for OrOff<T> {
    type Err = T::Err;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "off" => Ok(Self::Off),
            v => v.parse().map(Self::On),
        }
    }
}

impl<T: fmt::Display> fmt::Display for OrOff<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Off => f.write_str("off"),
            Self::On(v) => v.fmt(f),
        }
    }
}

/// What a front end asks of a plan; `None` keeps the default of the scene or the map.
#[derive(Clone, Debug, Default)]
pub struct PlanOptions {
    /// How the splines are seeded.
    pub seed: Seed,
    /// Classes to optimise, 1 to 64 (`None`: 5). The straight seed plans one class and
    /// refuses any other count given.
    pub classes: Option<usize>,
    /// The cost preset.
    pub preset: Preset,
    /// Weights and parameters by name, in order.
    pub weights: Vec<(String, f64)>,
    /// The local optimiser.
    pub optimizer: Option<Optimizer>,
    /// The form of roughness (4).
    pub roughness: Option<RoughnessForm>,
    /// Where the optimiser's `m(C)` is searched between quadrature nodes.
    pub clearance_search: Option<ClearanceSearch>,
    /// Grid cells per map unit (scenes only).
    pub resolution: Option<f64>,
    /// Worker threads.
    pub threads: Option<usize>,
    /// Most via-points.
    pub max_via: Option<usize>,
    /// Growth rounds.
    pub rounds: Option<usize>,
    /// Hard clearance margin.
    pub clearance_floor: f64,
    /// `dm` as a penalty only: the dm rule off (maps never apply it).
    pub soft_dm: bool,
    /// Classes to leave out.
    pub avoid: Vec<String>,
    /// Limited overlap.
    pub diverse: Option<f64>,
    /// Successive halving of the classes: off, or a ratio of at least 1 (scenes only).
    pub prune: Option<OrOff<f64>>,
    /// Polish rounds for the chosen class, 0 to 10 (scenes only).
    pub polish: usize,
    /// The chosen class's finish: off, or a work budget in evaluations (scenes only).
    pub finish_within: Option<OrOff<usize>>,
    /// Whether a saved graph is given (the Voronoi seed's; the straight seed refuses it).
    pub graph: bool,
}

impl From<ConfigError> for OptionError {
    /// The planner's setting in the front ends' spelling (`plan_option`).
    fn from(e: ConfigError) -> Self {
        let text = e.to_string();
        Self::at(plan_option(e.setting), e.value, e.problem, text)
    }
}

impl From<MissionConfigError> for OptionError {
    /// A mission's setting in the front ends' spelling: the one map from
    /// [`MissionSetting`] to [`Opt`] (a plan's settings by `plan_option`).
    fn from(e: MissionConfigError) -> Self {
        let option = match e.setting {
            MissionSetting::Plan(s) => plan_option(s),
            MissionSetting::Dt => (Opt::Dt, true),
            MissionSetting::Scouts => (Opt::Scouts, true),
            MissionSetting::SwitchMargin => (Opt::SwitchMargin, true),
            MissionSetting::MinSwitchInterval => (Opt::MinSwitchInterval, true),
            MissionSetting::BlockagePrior => (Opt::BlockagePrior, true),
            MissionSetting::ReplanClasses => (Opt::Classes, false),
            MissionSetting::ReplanValueTolerance => (Opt::Optimizer, false),
            MissionSetting::ReplanCoarsening => (Opt::Resolution, false),
            MissionSetting::MaxTime => (Opt::Dt, false),
        };
        let text = e.to_string();
        Self::at(option, e.value, e.problem, text)
    }
}

/// The option a planner's setting is given by, and whether a front end offers it: a setting
/// none offers (the L-BFGS tolerance) comes only from a profile, and is named under the
/// option closest to it.
fn plan_option(setting: Setting) -> (Opt, bool) {
    let option = match setting {
        Setting::Classes => Opt::Classes,
        Setting::Avoid => Opt::Avoid,
        Setting::Seed => Opt::Seed,
        Setting::Threads => Opt::Threads,
        Setting::Resolution => Opt::Resolution,
        Setting::ClearanceFloor => Opt::ClearanceFloor,
        Setting::Cost => Opt::Weight,
        Setting::Diverse => Opt::Diverse,
        Setting::Prune => Opt::Prune,
        Setting::MaxRounds => Opt::Rounds,
        Setting::MaxViaPoints => Opt::MaxVia,
        Setting::Polish => Opt::Polish,
        Setting::LbfgsValueTolerance => return (Opt::Optimizer, false),
        Setting::Graph => Opt::Graph,
    };
    (option, true)
}

impl OptionError {
    /// A library setting's error at `option`: with its value and problem when a front end
    /// offers the option, else under it with the library's whole message `text` (which
    /// names the setting's field, so the message says which value is at fault).
    fn at(
        (option, offered): (Opt, bool),
        value: Option<String>,
        problem: String,
        text: String,
    ) -> Self {
        if !offered {
            return Self::given(option, text);
        }
        Self {
            option,
            value,
            problem,
            others: Vec::new(),
        }
    }
}

/// Problems of options that apply to scenes only, given with a map.
const SCENES_ONLY: &str = "applies to scenes; a map's classes are optimised while its search \
                           goes on";

impl PlanOptions {
    /// Checks every option and gives the planner's configuration for `scene` (its danger
    /// and critical points and hazards join the cost), or for a map when `scene` is `None`
    /// (the map defaults).
    ///
    /// # Examples
    ///
    /// The defaults are the planner's, for a scene and for a map:
    ///
    /// ```
    /// use homospline_front::{EXAMPLE_SCENE, OrOff, PlanOptions};
    /// use homospline_geom::Scene;
    /// use homospline_optim::PlanConfig;
    ///
    /// let scene = Scene::from_str(EXAMPLE_SCENE, "example").unwrap();
    /// let cfg = PlanOptions::default().validate(Some(&scene)).unwrap();
    /// let base = PlanConfig::default();
    /// assert_eq!(cfg.classes, base.classes);
    /// assert_eq!(cfg.prune, base.prune);
    /// assert_eq!(cfg.finish_within, base.finish_within);
    /// assert_eq!(cfg.growth.max_rounds, base.growth.max_rounds);
    /// let map = PlanOptions::default().validate(None).unwrap();
    /// assert_eq!(map.growth.cost, homospline_optim::PlanConfig::maps().growth.cost);
    /// // "off" reads as off.
    /// assert_eq!("off".parse::<OrOff<f64>>(), Ok(OrOff::Off));
    /// assert_eq!("2".parse::<OrOff<f64>>(), Ok(OrOff::On(2.0)));
    /// ```
    ///
    /// An error names the option as the command line spells it, or as Python does:
    ///
    /// ```
    /// use homospline_front::{PlanOptions, Spelling};
    /// use homospline_optim::Seed;
    ///
    /// let e = PlanOptions { seed: Seed::Straight, classes: Some(3), ..Default::default() }
    ///     .validate(None)
    ///     .unwrap_err();
    /// assert_eq!(
    ///     e.spelled(Spelling::Flag),
    ///     "--classes 3: --seed straight plans one class, from the straight line S-T"
    /// );
    /// assert_eq!(
    ///     e.spelled(Spelling::Keyword),
    ///     "classes=3: seed straight plans one class, from the straight line S-T"
    /// );
    /// let e = PlanOptions { clearance_floor: -1.0, ..Default::default() }
    ///     .validate(None)
    ///     .unwrap_err();
    /// assert_eq!(e.spelled(Spelling::Keyword), "clearance_floor=-1: must be a finite number >= 0");
    /// let e = PlanOptions { weights: vec![("safty".into(), 1.0)], ..Default::default() }
    ///     .validate(None)
    ///     .unwrap_err();
    /// assert!(e
    ///     .spelled(Spelling::Keyword)
    ///     .starts_with("weights['safty']=1: unknown weight or parameter 'safty'"));
    /// // Its Display is the command line's spelling.
    /// assert!(e.to_string().starts_with("--weight safty=1: unknown weight"));
    /// ```
    pub fn validate(&self, scene: Option<&Scene>) -> Result<PlanConfig, OptionError> {
        self.check_given(scene)?;
        self.check_seed()?;
        let base = match scene {
            Some(_) => PlanConfig::default(),
            None => PlanConfig::maps(),
        };
        let mut cost = self.preset.config();
        if let Some(s) = scene {
            cost = cost.with_scene_points(s);
        } else {
            // The map defaults of the safety term, whatever the preset; `--weight` may
            // change them below.
            homospline_optim::planner::profile::map_safety(&mut cost);
        }
        for (name, v) in &self.weights {
            cost.set(name.trim(), *v).map_err(|e| {
                OptionError::new(Opt::Weight, format!("{name}={}", Num(*v)), e.to_string())
            })?;
        }
        if let Some(form) = self.roughness {
            cost.roughness = form;
        }
        if let Some(search) = self.clearance_search {
            cost.clearance_search = search;
        }
        let prune = match self.prune {
            None => base.prune,
            Some(OrOff::Off) => None,
            Some(OrOff::On(r)) => Some(r),
        };
        let finish_within = match self.finish_within {
            None => base.finish_within,
            Some(OrOff::Off) => None,
            Some(OrOff::On(n)) => Some(n),
        };
        let cfg = PlanConfig {
            seed: self.seed,
            classes: self.classes.unwrap_or(base.classes),
            resolution: self.resolution,
            growth: GrowthConfig {
                cost,
                optimizer: self.optimizer.unwrap_or(base.growth.optimizer),
                max_via_points: self.max_via.unwrap_or(base.growth.max_via_points),
                max_rounds: self.rounds.unwrap_or(base.growth.max_rounds),
                ..base.growth.clone()
            },
            threads: self.threads,
            clearance_floor: self.clearance_floor,
            dm_rule: base.dm_rule && !self.soft_dm,
            avoid: self.avoid.iter().map(|a| class_as_printed(a)).collect(),
            // A finer grid within the memory the process may use, as the first one is.
            max_refined_cells: crate::memory::cells_within_limit().map_or(
                base.max_refined_cells,
                |c| {
                    base.max_refined_cells
                        .min(usize::try_from(c).unwrap_or(usize::MAX))
                },
            ),
            diverse: self.diverse,
            prune,
            polish: self.polish,
            finish_within,
            // A `dm` given with `--weight` is the user's, in map units.
            map_dm: base
                .map_dm
                .filter(|_| !self.weights.iter().any(|(n, _)| n.trim() == "dm")),
            ..base
        };
        cfg.check()?;
        Ok(cfg)
    }

    /// The scene-only options absent on a map (the values' ranges are the planner's:
    /// [`PlanConfig::check`]).
    fn check_given(&self, scene: Option<&Scene>) -> Result<(), OptionError> {
        if scene.is_some() {
            return Ok(());
        }
        if self.resolution.is_some() {
            return Err(OptionError::given(
                Opt::Resolution,
                "applies to scenes; a map's grid is its cells",
            ));
        }
        if let Some(OrOff::On(n)) = self.finish_within
            && n != 0
        {
            return Err(OptionError::given(Opt::FinishWithin, SCENES_ONLY));
        }
        if self.polish > 0 {
            return Err(OptionError::given(Opt::Polish, SCENES_ONLY));
        }
        Ok(())
    }

    /// The straight seed plans one class and takes no saved graph.
    fn check_seed(&self) -> Result<(), OptionError> {
        if self.seed != Seed::Straight {
            return Ok(());
        }
        if let Some(k @ 2..) = self.classes {
            return Err(OptionError::new(
                Opt::Classes,
                k,
                "{} straight plans one class, from the straight line S-T",
            )
            .naming(Opt::Seed));
        }
        if self.graph {
            return Err(OptionError::given(
                Opt::Graph,
                "gives the Voronoi seed's classes; {} straight plans one class from the \
                 straight line",
            )
            .naming(Opt::Seed));
        }
        Ok(())
    }
}

/// A class given to `--avoid` as plans print it: an id's hex digits in lower case
/// (`#DEADBEEF` is `#deadbeef`), and ray crossings with each crossing that the next one
/// undoes taken out (`+1-1` is `e`, `-2+3-3` is `-2`). Anything else is kept as it is, for
/// the planner's check to name.
///
/// # Examples
///
/// ```
/// use homospline_front::options::class_as_printed;
///
/// assert_eq!(class_as_printed("#DEADBEEF"), "#deadbeef");
/// assert_eq!(class_as_printed("+1-1"), "e");
/// assert_eq!(class_as_printed("-2+3-3+4"), "-2+4");
/// assert_eq!(class_as_printed("-1+2"), "-1+2");
/// assert_eq!(class_as_printed("abc"), "abc");
/// ```
pub fn class_as_printed(text: &str) -> String {
    if let Some(hex) = text.strip_prefix('#') {
        return format!("#{}", hex.to_ascii_lowercase());
    }
    // Crossings `+k` or `-k`, each sign followed by digits; else not a word to reduce.
    let mut word: Vec<(char, &str)> = Vec::new();
    let mut rest = text;
    while let Some(sign) = rest.chars().next().filter(|c| *c == '+' || *c == '-') {
        let digits = rest[1..]
            .find(['+', '-'])
            .map_or(&rest[1..], |end| &rest[1..1 + end]);
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return text.to_owned();
        }
        match word.last() {
            Some(&(s, d)) if d == digits && s != sign => {
                word.pop();
            }
            _ => word.push((sign, digits)),
        }
        rest = &rest[1 + digits.len()..];
    }
    if !rest.is_empty() || text.is_empty() {
        return text.to_owned();
    }
    if word.is_empty() {
        return "e".to_owned();
    }
    word.iter().map(|(s, d)| format!("{s}{d}")).collect()
}
