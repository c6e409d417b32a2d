//! Scout policies: what each scout looks at next, given what the team has seen, the UGV's
//! route and its alternatives ([`ScoutPolicy`]), and the registry the CLI, Python and
//! `cargo xtask missions` enumerate ([`Policy::all`]).
//!
//! # Adding a policy
//! Write one file in `sim/policy/` with a unit struct implementing [`ScoutPolicy`], and add
//! one line `module::Type,` to the `registry!` call below. The command line
//! (`simulate --policy`), Python (`simulate(policy=...)`), the JSON and `cargo xtask
//! missions` pick it up by its [`ScoutPolicy::name`].

use homospline_geom::{Point, Real};

use crate::world::types::Uav;

pub use super::coverage::Coverage;
pub use super::route::Polyline;

/// A scout's job: waypoints to fly, and what they inspect (`""`: the UGV's own route, else
/// the class verified).
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// Waypoints, in order (the scout flies straight between them).
    pub waypoints: Vec<Point>,
    /// `""` for the UGV's route, else the class.
    pub label: String,
}

/// A scout as a policy sees it.
#[derive(Clone, Copy, Debug)]
pub struct ScoutView<'a> {
    /// Where it is.
    pub at: Point,
    /// Its speed and sensor range.
    pub uav: &'a Uav,
    /// Whether it still has waypoints to fly (a busy scout keeps its job).
    pub busy: bool,
    /// The labels of its jobs since the UGV's last (re-)plan, the current one last.
    pub jobs: &'a [String],
}

/// A class the UGV could drive: its name and its route from where it was planned.
#[derive(Clone, Copy, Debug)]
pub struct Lane<'a> {
    /// The class's name.
    pub class: &'a str,
    /// Its route to the goal.
    pub line: &'a Polyline,
}

/// What a policy decides on: the UGV's route and how far along it is (its position is
/// `route.at(s)`), its alternatives (best first), the scouts and what the team has seen.
#[derive(Clone, Copy, Debug)]
pub struct Situation<'a> {
    /// The UGV's sensor range.
    pub ugv_range: Real,
    /// The UGV's route, from where it was (re-)planned to the goal.
    pub route: &'a Polyline,
    /// How far along `route` the UGV is (arc length).
    pub s: Real,
    /// The UGV's class.
    pub class: &'a str,
    /// The other collision-free classes of the last (re-)plan, best first.
    pub alternatives: &'a [Lane<'a>],
    /// Every scout.
    pub scouts: &'a [ScoutView<'a>],
    /// What any robot has seen so far.
    pub seen: &'a Coverage,
    /// The UGV holds where it is until the scouts have verified one of `alternatives`
    /// (policies that [`ScoutPolicy::verifies`]): its route is known blocked ahead.
    pub holding: bool,
}

/// A way of using the scouts.
///
/// The mission asks [`ScoutPolicy::assign`] for jobs right after every (re-)plan of the
/// UGV (every scout idle) and whenever a scout has finished its job; and, when the robots
/// find the UGV's route blocked ahead, whether the UGV weighs driving on against re-planning
/// at once ([`ScoutPolicy::weighs_driving_on`]).
pub trait ScoutPolicy: Sync {
    /// The name on the command line, in Python and in the JSON.
    fn name(&self) -> &'static str;
    /// One line saying what the scouts do, for `--help` and the guide.
    fn summary(&self) -> &'static str;
    /// Whether any scout flies (`false`: the UGV finds blockages itself).
    fn flies(&self) -> bool {
        true
    }
    /// Jobs for the idle scouts (`situation.scouts[i].busy == false`), as `(index, job)`;
    /// an idle scout given none holds where it is.
    fn assign(&self, situation: &Situation<'_>) -> Vec<(usize, Job)>;
    /// Whether, when the robots find the UGV's route blocked ahead, the UGV compares
    /// re-planning now with driving on until it would see the blockage itself and
    /// re-planning there (what a UGV without scouts does), and takes the shorter.
    fn weighs_driving_on(&self) -> bool {
        false
    }
    /// Whether the UGV acts on the scouts' finds only where they block its own route, and
    /// then leaves it early only for a class the robots have seen clear all along (`false`:
    /// every find goes on the UGV's map and any re-plan may switch). Such a UGV drives as a
    /// UGV without scouts would, except for the verified detours: what the scouts see beside
    /// its route (a pebble that blocks nothing) does not move it.
    fn verifies(&self) -> bool {
        false
    }
    /// Whether, for a policy that [`verifies`](ScoutPolicy::verifies), the UGV holds at the
    /// start until the scouts have swept its route whole or found it blocked (for at most the
    /// time one scout takes to sweep it): a blockage found then costs no distance, at the
    /// price of the wait.
    fn holds_at_start(&self) -> bool {
        false
    }
}

/// A registered scout policy: a cheap handle, compared by name.
///
/// # Examples
///
/// ```
/// use homospline_mission::Policy;
///
/// assert_eq!(Policy::default(), Policy::SURVEY);
/// let names: Vec<&str> = Policy::all().iter().map(|p| p.name()).collect();
/// assert_eq!(
///     names,
///     ["none", "ahead", "alternatives", "guard", "verified", "survey"]
/// );
/// assert_eq!(Policy::named("ahead"), Some(Policy::AHEAD));
/// ```
#[derive(Clone, Copy)]
pub struct Policy(&'static dyn ScoutPolicy);

/// Declares the policy modules and the registry, in the order tables list them.
macro_rules! registry {
    ($($module:ident :: $ty:ident),* $(,)?) => {
        $(mod $module;)*
        /// Every registered policy.
        static REGISTRY: &[Policy] = &[$(Policy(&$module::$ty)),*];
    };
}

registry! {
    none::NoScouts,
    ahead::Ahead,
    alternatives::Alternatives,
    guard::Guard,
    verified::Verified,
    survey::Survey,
}

impl Policy {
    /// No scouts fly: the UGV finds blockages itself (the baseline).
    pub const NONE: Policy = Policy(&none::NoScouts);
    /// Scouts inspect the far half of the UGV's route.
    pub const AHEAD: Policy = Policy(&ahead::Ahead);
    /// Scouts verify the next best classes.
    pub const ALTERNATIVES: Policy = Policy(&alternatives::Alternatives);
    /// Scouts sweep the UGV's route ahead, then verify alternatives; the UGV re-plans early
    /// only when that is shorter.
    pub const GUARD: Policy = Policy(&guard::Guard);
    /// Scouts sweep the UGV's route ahead; a blockage they find there makes the UGV hold and
    /// wait for a class they have seen clear all along, if that is shorter.
    pub const VERIFIED: Policy = Policy(&verified::Verified);
    /// As [`Policy::VERIFIED`], and the UGV holds at the start while the scouts sweep its
    /// route, then sets off on a cheaper and shorter class if they found one (the default).
    pub const SURVEY: Policy = Policy(&survey::Survey);

    /// Every registered policy, in registry order.
    pub fn all() -> &'static [Policy] {
        REGISTRY
    }

    /// The policy called `name`.
    pub fn named(name: &str) -> Option<Policy> {
        REGISTRY.iter().copied().find(|p| p.name() == name)
    }

    /// The registered names, `none, ahead, ...`, for messages.
    pub fn names() -> String {
        REGISTRY
            .iter()
            .map(|p| p.name())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The policy's name.
    pub fn name(self) -> &'static str {
        self.0.name()
    }

    /// What its scouts do, in one line.
    pub fn summary(self) -> &'static str {
        self.0.summary()
    }

    /// The policy itself.
    pub fn get(self) -> &'static dyn ScoutPolicy {
        self.0
    }
}

impl Default for Policy {
    /// [`Policy::SURVEY`]: on `cargo xtask missions` it drives the least on average and in
    /// the worst case, and is worse than flying no scouts on no world; its price is the wait
    /// at the start (measured: docs/performance.md, "Missions").
    fn default() -> Self {
        Policy::SURVEY
    }
}

impl PartialEq for Policy {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for Policy {}

impl std::fmt::Debug for Policy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Policy({})", self.name())
    }
}

impl std::fmt::Display for Policy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The first point of `line` farther than `range` from every segment of `rest` (the UGV's
/// route ahead): where an alternative leaves it.
pub(crate) fn leaves_at(line: &Polyline, rest: &[Point], range: Real) -> Option<usize> {
    line.pts.iter().position(|p| {
        rest.windows(2)
            .map(|w| homospline_geom::math::distance_point_segment(p, &w[0], &w[1]))
            .fold(Real::INFINITY, Real::min)
            > range
    })
}
