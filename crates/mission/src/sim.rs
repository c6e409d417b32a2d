//! The mission simulation: the k best classes on the prior map offline, then time steps in
//! which the UGV drives its plan, the scouts fly their routes, discoveries update the map,
//! and the UGV re-plans from where it is, keeping its heading, when its path is blocked.

use std::time::Instant;

use homospline_geom::{Point, Real, Scene, Vector};
use homospline_homotopy::Rays;
use homospline_optim::{GrowthConfig, Optimizer, Plan, PlanConfig, default_resolution, plan};
use homospline_spline::{CircleModel, ClearanceModel, EndCondition, Spline, evaluate};
use thiserror::Error;

use crate::map::{MapKnown, MapUpdate, MapWorld};
use crate::world::{MissionWorld, Team, Uav, Ugv};

/// How the scouts are used.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Policy {
    /// No scouts fly: the UGV finds blockages itself (the baseline).
    #[default]
    None,
    /// Scouts inspect the far half of the UGV's route while it drives the near half.
    Ahead,
    /// Scouts verify the next best classes, one each; scouts left over fly `ahead`.
    Alternatives,
}

impl Policy {
    /// Every policy.
    pub const ALL: [Policy; 3] = [Policy::None, Policy::Ahead, Policy::Alternatives];

    /// `none`, `ahead` or `alternatives`.
    pub fn name(self) -> &'static str {
        match self {
            Policy::None => "none",
            Policy::Ahead => "ahead",
            Policy::Alternatives => "alternatives",
        }
    }
}

/// Settings of [`simulate`].
#[derive(Clone, Debug, PartialEq)]
pub struct MissionConfig {
    /// The planner, offline and for every re-plan. Defaults to 5 classes and L-BFGS (re-plans
    /// are on the clock).
    pub plan: PlanConfig,
    /// Scout policy.
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
    /// shorter stop.
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

/// A re-plan on `scene` as a mission makes it, with the planner's settings `cfg`: on the
/// graph of resolution `coarse` when given, and on `cfg`'s own when that one has no
/// collision-free class (or when `coarse` is `None`).
pub fn replan_scene(scene: &Scene, cfg: &PlanConfig, coarse: Option<Real>) -> Option<Plan> {
    if let Some(r) = coarse {
        let quick = PlanConfig {
            resolution: Some(r),
            ..cfg.clone()
        };
        let p = plan(scene, &quick).ok();
        if p.as_ref()
            .is_some_and(|p| p.classes.iter().any(|c| c.collision_free))
        {
            return p;
        }
    }
    plan(scene, cfg).ok()
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
            policy: Policy::None,
            scouts: None,
            dt: 0.25,
            switch_margin: 0.1,
            min_switch_interval: 10.0,
            max_time: None,
            replan_classes: 2,
            replan_value_tolerance: 1e-5,
            replan_coarsening: 2.0,
        }
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

/// Most scouts.
pub const MAX_SCOUTS: usize = 64;

/// Who saw something.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Robot {
    /// The ground robot.
    Ugv,
    /// Scout `i`.
    Uav(usize),
}

/// What happened.
#[derive(Clone, Debug, PartialEq)]
pub enum EventKind {
    /// The offline plan on the prior map.
    Planned {
        /// Collision-free classes found.
        classes: usize,
        /// The class chosen.
        class: String,
    },
    /// An obstacle not on the map (`hidden`), or the absence of one that is, was seen.
    Discovered {
        /// Its name.
        obstacle: String,
        /// `true`: a new obstacle; `false`: a mapped obstacle found gone.
        hidden: bool,
        /// Who saw it.
        by: Robot,
    },
    /// A class other than the UGV's was found blocked.
    ClassClosed {
        /// The class.
        class: String,
    },
    /// The UGV's path was found blocked.
    Blocked {
        /// Its class.
        class: String,
    },
    /// A re-plan from the UGV's position.
    Replanned {
        /// Blocked path (`true`) or a discovery that may open a better class.
        forced: bool,
        /// Collision-free classes found.
        classes: usize,
        /// The class driven next.
        class: String,
    },
    /// The UGV changed class.
    Switched {
        /// From.
        from: String,
        /// To.
        to: String,
    },
    /// The new path leaves more than [`TURN_ANGLE_DEG`] off the heading (it starts backwards
    /// or sideways): the UGV turns on the spot.
    TurnedAround,
    /// The goal is reached.
    Reached,
    /// The mission stopped without reaching the goal.
    Stuck {
        /// Why.
        reason: String,
    },
}

/// An event at a time and place (the UGV's position).
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Seconds from the start.
    pub t: Real,
    /// The UGV's position.
    pub at: Point,
    /// What.
    pub kind: EventKind,
}

/// A robot's positions over time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Track {
    /// `ugv` or `uav-I`.
    pub name: String,
    /// `(t, position)`, one per time step while moving, and the last one.
    pub samples: Vec<(Real, Point)>,
}

/// A path the UGV adopted.
#[derive(Clone, Debug, PartialEq)]
pub struct Adopted {
    /// When.
    pub t: Real,
    /// Its class (signature on the prior map's rays).
    pub class: String,
    /// The sampled curve.
    pub path: Vec<Point>,
}

/// The outcome of a mission.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionResult {
    /// World name.
    pub world: String,
    /// Policy used.
    pub policy: Policy,
    /// Scouts flown.
    pub scouts: usize,
    /// The goal was reached.
    pub reached: bool,
    /// Seconds until the goal (or until the mission stopped).
    pub time: Real,
    /// The time step the mission ran at: [`MissionConfig::dt`], or less where a robot would
    /// travel more than half its sensor range between two looks ([`time_step`]).
    pub dt: Real,
    /// Distance the UGV drove.
    pub ugv_distance: Real,
    /// Length of the best plan on the true world from the start (`None` if it has none).
    pub truth_plan_length: Option<Real>,
    /// Re-plans after the offline plan.
    pub replans: usize,
    /// Class changes.
    pub switches: usize,
    /// Distance driven on paths later abandoned (blocked or switched away from), counted
    /// from when each was adopted.
    pub abandoned_distance: Real,
    /// Distance flown by all scouts.
    pub uav_distance: Real,
    /// Everything that happened, in time order.
    pub events: Vec<Event>,
    /// The UGV's track.
    pub ugv: Track,
    /// Each scout's track.
    pub uavs: Vec<Track>,
    /// Every path the UGV adopted.
    pub adopted: Vec<Adopted>,
    /// Wall time of each re-plan (map update, classes, optimisation), milliseconds: not part
    /// of the deterministic outcome.
    pub replan_ms: Vec<Real>,
    /// On maps, each update of the known map (what was updated locally, wall times); empty
    /// on scenes.
    pub map_updates: Vec<MapUpdate>,
}

impl MissionResult {
    /// What is the same from run to run and for any thread count: this result with every
    /// wall time left out (`replan_ms` emptied; each map update's times zeroed, what it
    /// changed and how kept).
    pub fn outcome(&self) -> MissionResult {
        MissionResult {
            replan_ms: Vec::new(),
            map_updates: self
                .map_updates
                .iter()
                .map(|u| MapUpdate {
                    field_ms: 0.0,
                    graph_ms: 0.0,
                    model_ms: 0.0,
                    ..u.clone()
                })
                .collect(),
            ..self.clone()
        }
    }

    /// UGV distance over the truth plan's length.
    pub fn distance_ratio(&self) -> Option<Real> {
        self.truth_plan_length
            .filter(|&l| l > 0.0 && self.reached)
            .map(|l| self.ugv_distance / l)
    }

    /// Mission time over the truth plan's driving time.
    pub fn time_ratio(&self, ugv_speed: Real) -> Option<Real> {
        self.truth_plan_length
            .filter(|&l| l > 0.0 && self.reached)
            .map(|l| self.time / (l / ugv_speed))
    }
}

/// A path being driven or flown, with cumulative arc length.
#[derive(Clone, Debug)]
struct Polyline {
    pts: Vec<Point>,
    cum: Vec<Real>,
}

impl Polyline {
    fn new(pts: Vec<Point>) -> Self {
        let mut cum = Vec::with_capacity(pts.len());
        let mut acc = 0.0;
        for (i, p) in pts.iter().enumerate() {
            if i > 0 {
                acc += (p - pts[i - 1]).norm();
            }
            cum.push(acc);
        }
        Self { pts, cum }
    }

    fn length(&self) -> Real {
        self.cum.last().copied().unwrap_or(0.0)
    }

    /// The point at arc length `s` and the index of the segment it is on.
    fn at(&self, s: Real) -> (Point, usize) {
        let n = self.pts.len();
        if n == 1 || s <= 0.0 {
            return (self.pts[0], 0);
        }
        if s >= self.length() {
            return (self.pts[n - 1], n - 2);
        }
        let i = self.cum.partition_point(|&c| c <= s).clamp(1, n - 1);
        let seg = self.cum[i] - self.cum[i - 1];
        let f = if seg > 0.0 {
            (s - self.cum[i - 1]) / seg
        } else {
            0.0
        };
        (self.pts[i - 1] + (self.pts[i] - self.pts[i - 1]) * f, i - 1)
    }

    /// The direction of travel at arc length `s`.
    fn heading(&self, s: Real) -> Vector {
        let (_, i) = self.at(s);
        let d = self.pts[(i + 1).min(self.pts.len() - 1)] - self.pts[i];
        if d.norm() > 0.0 {
            d / d.norm()
        } else {
            Vector::zeros()
        }
    }

    /// The part from arc length `a` to `b`.
    fn slice(&self, a: Real, b: Real) -> Vec<Point> {
        let (pa, ia) = self.at(a);
        let (pb, ib) = self.at(b);
        let mut out = vec![pa];
        out.extend(self.pts[ia + 1..=ib].iter().copied());
        out.push(pb);
        out.dedup();
        out
    }
}

/// A class path the UGV may drive.
#[derive(Clone, Debug)]
struct Route {
    /// The signature, on the naming rays, of the UGV's track up to where the route was
    /// planned followed by the route: a class's name does not change as the UGV drives past
    /// a ray (a route's own word from the UGV's position would).
    class: String,
    line: Polyline,
    via: Vec<Point>,
    cost: Real,
    /// Samples of the UGV's track when the route was planned (for renaming).
    track_len: usize,
}

/// A scout in flight.
struct Scout {
    uav: Uav,
    pos: Point,
    /// Waypoints still to reach.
    route: Vec<Point>,
    flown: Real,
    track: Track,
    /// Jobs since the last (re-)plan: the classes verified (policy `alternatives`), or ""
    /// for a part of the UGV's route.
    jobs: Vec<String>,
}

impl Scout {
    fn step(&mut self, dt: Real, t: Real) {
        let mut budget = self.uav.speed * dt;
        let moved = !self.route.is_empty();
        while budget > 0.0 && !self.route.is_empty() {
            let d = self.route[0] - self.pos;
            let n = d.norm();
            if n <= budget {
                self.pos = self.route.remove(0);
                budget -= n;
                self.flown += n;
            } else {
                self.pos += d * (budget / n);
                self.flown += budget;
                budget = 0.0;
            }
        }
        if moved {
            self.track.samples.push((t, self.pos));
        }
    }
}

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

/// Seen from `p` within `range`: any circle of the obstacle comes that close.
fn within(p: &Point, range: Real, o: &homospline_geom::Obstacle) -> bool {
    o.circles
        .iter()
        .any(|c| (p - c.center).norm() - c.radius <= range)
}

/// What the team knows of the world while the mission runs, and the truth its sensors read:
/// a scene of circles or an occupancy map. The simulation loop is the same for both.
pub(crate) trait Known {
    /// The UGV's start.
    fn start(&self) -> Point;
    /// The goal.
    fn goal(&self) -> Point;
    /// A plan from `from` to the goal on the known world (`None`: no plan); `online`: a
    /// re-plan during the mission (not the offline plan).
    fn plan_from(&self, from: Point, cfg: &PlanConfig, online: bool) -> Option<Plan>;
    /// The clearance model of the known world.
    fn model(&self) -> &dyn ClearanceModel;
    /// What a robot at `p` seeing `range` discovers now: `(name, hidden)` for each
    /// difference between the known world and the truth that comes within range (`hidden`:
    /// something is there that the known world lacks). Marked known; the known world itself
    /// changes at [`Known::update`].
    fn sense(&mut self, p: &Point, range: Real) -> Vec<(String, bool)>;
    /// Applies what was sensed since the last update to the known world; its wall time, ms.
    fn update(&mut self) -> Real;
    /// The rays that name classes, when mapped obstacles found gone renamed them.
    fn renamed(&self) -> Option<Rays>;
}

/// The known world of a scene mission: the prior scene with the obstacles found so far.
struct SceneKnown<'w> {
    world: &'w MissionWorld,
    known: Scene,
    model: CircleModel,
    known_cleared: rustc_hash::FxHashSet<String>,
    /// The truth's hidden obstacles not found yet, by index, in order: sensing scans these
    /// only (a scan of every obstacle with a name lookup in a list took 11 s for 2,000
    /// hidden obstacles).
    pending_hidden: Vec<usize>,
    /// The prior's cleared obstacles not found gone yet, by index, in order.
    pending_cleared: Vec<usize>,
    /// The re-plans' coarser graph resolution ([`MissionConfig::replan_resolution`]).
    replan_resolution: Option<Real>,
}

impl Known for SceneKnown<'_> {
    fn start(&self) -> Point {
        self.world.prior.start
    }

    fn goal(&self) -> Point {
        self.world.prior.goal
    }

    fn plan_from(&self, from: Point, cfg: &PlanConfig, online: bool) -> Option<Plan> {
        let mut scene = self.known.clone();
        scene.start = from;
        if scene.validate("mission").is_err() {
            return None;
        }
        replan_scene(&scene, cfg, self.replan_resolution.filter(|_| online))
    }

    fn model(&self) -> &dyn ClearanceModel {
        &self.model
    }

    fn sense(&mut self, p: &Point, range: Real) -> Vec<(String, bool)> {
        let world = self.world;
        let mut found = Vec::new();
        let known = &mut self.known;
        self.pending_hidden.retain(|&i| {
            let o = &world.truth.obstacles[i];
            let seen = within(p, range, o);
            if seen {
                known.obstacles.push(o.clone());
                found.push((o.name.clone(), true));
            }
            !seen
        });
        let mut gone = rustc_hash::FxHashSet::default();
        self.pending_cleared.retain(|&i| {
            let o = &world.prior.obstacles[i];
            let seen = within(p, range, o);
            if seen {
                gone.insert(o.name.clone());
                found.push((o.name.clone(), false));
            }
            !seen
        });
        if !gone.is_empty() {
            known.obstacles.retain(|k| !gone.contains(&k.name));
            self.known_cleared.extend(gone);
        }
        found
    }

    fn update(&mut self) -> Real {
        let t0 = Instant::now();
        self.model = CircleModel::new(self.known.circles());
        t0.elapsed().as_secs_f64() * 1e3
    }

    fn renamed(&self) -> Option<Rays> {
        // Classes are named by the obstacles of the map that are still there.
        let mut named = self.world.prior.clone();
        named
            .obstacles
            .retain(|o| !self.known_cleared.contains(&o.name));
        Some(Rays::for_scene(&named))
    }
}

/// Everything the mission needs while it runs.
struct Run<'a, K: Known> {
    cfg: &'a MissionConfig,
    rays: Rays,
    known: K,
    events: Vec<Event>,
    replan_ms: Vec<Real>,
    /// Wall time of map updates not yet counted in a re-plan.
    pending_ms: Real,
}

impl<K: Known> Run<'_, K> {
    fn event(&mut self, t: Real, at: Point, kind: EventKind) {
        self.events.push(Event { t, at, kind });
    }

    /// The events of driving `next` instead of `current` from `at`: a class switch if the
    /// class changes, and a turn on the spot if `next` leaves off `heading`. Whether the
    /// class changed.
    fn adopt(
        &mut self,
        t: Real,
        at: Point,
        heading: Vector,
        current: &Route,
        next: &Route,
    ) -> bool {
        let switched = next.class != current.class;
        if switched {
            self.event(
                t,
                at,
                EventKind::Switched {
                    from: current.class.clone(),
                    to: next.class.clone(),
                },
            );
        }
        if turns_on_the_spot(&next.line, heading) {
            self.event(t, at, EventKind::TurnedAround);
        }
        switched
    }

    /// The collision-free classes of a plan from `from` on the known map, best first
    /// (`online`: a re-plan during the mission, not the offline plan).
    fn routes_from(
        &mut self,
        from: Point,
        heading: Option<Vector>,
        online: bool,
        track: &[(Real, Point)],
    ) -> Vec<Route> {
        let cfg = match heading {
            Some(h) => self.cfg.replan_config(h),
            None => self.cfg.plan.clone(),
        };
        let t0 = Instant::now();
        let p: Option<Plan> = self.known.plan_from(from, &cfg, online);
        let ms = t0.elapsed().as_secs_f64() * 1e3 + std::mem::take(&mut self.pending_ms);
        self.replan_ms.push(ms);
        let driven: Vec<Point> = track.iter().map(|&(_, p)| p).collect();
        let prefix = self.rays.signature(&driven);
        p.map(|p| {
            p.classes
                .into_iter()
                .filter(|c| c.collision_free)
                .map(|c| Route {
                    class: prefix.concat(&self.rays.signature(&c.path)).to_string(),
                    line: Polyline::new(c.path),
                    via: c.via_points,
                    cost: c.cost.total,
                    track_len: track.len(),
                })
                .collect()
        })
        .unwrap_or_default()
    }

    /// A route's class name on the current naming rays (see [`Route::class`]).
    fn name(&self, route: &Route, track: &[(Real, Point)]) -> String {
        let mut pts: Vec<Point> = track[..route.track_len.min(track.len())]
            .iter()
            .map(|&(_, p)| p)
            .collect();
        pts.extend(route.line.pts.iter().copied());
        self.rays.signature(&pts).to_string()
    }

    /// The cost of driving the rest of `route` from arc length `s` on the known map: the
    /// spline through the UGV's position and the via-points still ahead.
    fn remaining_cost(&self, route: &Route, s: Real, heading: Vector) -> Real {
        let (pos, _) = route.line.at(s);
        let goal = *route.via.last().unwrap_or(&pos);
        let ahead_of = |p: &Point| {
            // A via-point is ahead if the path reaches its nearest sample after `s`.
            let k = (0..route.line.pts.len())
                .min_by(|&a, &b| {
                    (route.line.pts[a] - p)
                        .norm_squared()
                        .total_cmp(&(route.line.pts[b] - p).norm_squared())
                })
                .unwrap_or(0);
            route.line.cum[k] > s
        };
        let mut pts = vec![pos];
        let inner = route
            .via
            .get(1..route.via.len().saturating_sub(1))
            .unwrap_or(&[]);
        pts.extend(inner.iter().filter(|p| ahead_of(p)));
        pts.push(goal);
        pts.dedup();
        let end = EndCondition::StartHeading { direction: heading };
        match Spline::new(&pts, self.cfg.plan.growth.parametrization, end) {
            Ok(sp) => evaluate(&sp, self.known.model(), &self.cfg.plan.growth.cost).total,
            Err(_) => Real::INFINITY,
        }
    }
}

/// Simulates the mission in `world` with `cfg`. Deterministic: the same world and settings
/// give the same events and tracks (only `replan_ms` varies).
pub fn simulate(world: &MissionWorld, cfg: &MissionConfig) -> Result<MissionResult, MissionError> {
    check_config(cfg)?;
    // The scene's danger points, critical points and hazards join the cost of every plan.
    let plan_cfg = PlanConfig {
        growth: GrowthConfig {
            cost: cfg.plan.growth.cost.clone().with_scene_points(&world.prior),
            ..cfg.plan.growth.clone()
        },
        ..cfg.plan.clone()
    };
    let cfg = &MissionConfig {
        plan: plan_cfg,
        ..cfg.clone()
    };
    // The truth plan: the best-cost plan on the true world.
    let truth_plan_length = plan(&world.truth, &cfg.plan)
        .ok()
        .and_then(|p| p.chosen().map(|c| c.length));
    let known = SceneKnown {
        world,
        known: world.prior.clone(),
        model: CircleModel::new(world.prior.circles()),
        known_cleared: Default::default(),
        pending_hidden: {
            let hidden: rustc_hash::FxHashSet<&str> =
                world.hidden.iter().map(String::as_str).collect();
            (0..world.truth.obstacles.len())
                .filter(|&i| hidden.contains(world.truth.obstacles[i].name.as_str()))
                .collect()
        },
        pending_cleared: {
            let cleared: rustc_hash::FxHashSet<&str> =
                world.cleared.iter().map(String::as_str).collect();
            (0..world.prior.obstacles.len())
                .filter(|&i| cleared.contains(world.prior.obstacles[i].name.as_str()))
                .collect()
        },
        replan_resolution: cfg.replan_resolution(&world.prior),
    };
    let rays = Rays::for_scene(&world.prior);
    let (result, _) = run_mission(
        known,
        rays,
        &world.name,
        &world.team,
        truth_plan_length,
        cfg,
    )?;
    Ok(result)
}

/// Simulates the mission on an occupancy map world: the same loop as [`simulate`], with the
/// known map updated locally at each discovery (`MissionResult::map_updates`). The planner
/// takes the map defaults of `homospline_maps::map_config` for via-points, the class search
/// and the evaluation budget (rounds on long curves stop at 40 evaluations: the seeds are
/// pulled taut, and the chosen costs are then within 0.6 % of those at 80).
pub fn simulate_map(world: &MapWorld, cfg: &MissionConfig) -> Result<MissionResult, MissionError> {
    check_config(cfg)?;
    let defaults = homospline_maps::map_config();
    let mut plan_cfg = cfg.plan.clone();
    plan_cfg.growth.max_via_points = defaults.growth.max_via_points;
    plan_cfg.growth.max_evaluations_per_round = defaults.growth.max_evaluations_per_round;
    plan_cfg.growth.budget_segments = defaults.growth.budget_segments;
    plan_cfg.growth.min_evaluations_per_round = defaults.growth.min_evaluations_per_round;
    plan_cfg.search.one_path_per_state = defaults.search.one_path_per_state;
    plan_cfg.search.max_expansions = defaults.search.max_expansions;
    plan_cfg.growth.cost.safety_along = defaults.growth.cost.safety_along;
    plan_cfg.growth.cost.dm = defaults.growth.cost.dm;
    plan_cfg.growth.cost.omega = defaults.growth.cost.omega;
    let cfg = &MissionConfig {
        plan: plan_cfg,
        ..cfg.clone()
    };
    // The truth plan: the best-cost plan on the true map.
    let truth_plan_length = homospline_maps::PreparedMap::new(&world.truth)
        .ok()
        .and_then(|m| m.plan(world.start, world.goal, &cfg.plan).ok())
        .and_then(|p| p.chosen().map(|c| c.length));
    let known =
        MapKnown::new(world).map_err(|e| MissionError::Config(format!("{}: {e}", world.name)))?;
    let rays = known.naming_rays();
    let (mut result, known) = run_mission(
        known,
        rays,
        &world.name,
        &world.team,
        truth_plan_length,
        cfg,
    )?;
    result.map_updates = known.updates;
    Ok(result)
}

/// The settings' ranges.
fn check_config(cfg: &MissionConfig) -> Result<(), MissionError> {
    if cfg.replan_classes == 0 || cfg.plan.classes == 0 {
        return Err(MissionError::Config(
            "--classes: plans need at least 1 class".into(),
        ));
    }
    if !(cfg.dt.is_finite() && (MIN_DT..=10.0).contains(&cfg.dt)) {
        return Err(MissionError::Config(format!(
            "--dt {}: must be between {MIN_DT} and 10 seconds",
            cfg.dt
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
    if !(cfg.min_switch_interval.is_finite() && cfg.min_switch_interval >= 0.0) {
        return Err(MissionError::Config(format!(
            "minimum time between switches must be >= 0, got {}",
            cfg.min_switch_interval
        )));
    }
    Ok(())
}

/// The mission loop, on any known world: offline plan, then time steps of driving, flying,
/// sensing, map updates, re-checks and re-plans.
fn run_mission<K: Known>(
    known: K,
    rays: Rays,
    name: &str,
    team: &Team,
    truth_plan_length: Option<Real>,
    cfg: &MissionConfig,
) -> Result<(MissionResult, K), MissionError> {
    let (start, goal) = (known.start(), known.goal());
    let ugv = team.ugv.clone();
    let n_scouts = match cfg.policy {
        Policy::None => 0,
        _ => cfg.scouts.unwrap_or(team.uavs.len()),
    };
    let mut scouts: Vec<Scout> = (0..n_scouts)
        .map(|i| {
            let uav = team.uavs.get(i).cloned().unwrap_or(Uav {
                start,
                speed: 3.0,
                sensor_range: 10.0,
            });
            Scout {
                pos: uav.start,
                uav,
                route: Vec::new(),
                flown: 0.0,
                track: Track {
                    name: format!("uav-{i}"),
                    samples: vec![(0.0, team.uavs.get(i).map_or(start, |u| u.start))],
                },
                jobs: Vec::new(),
            }
        })
        .collect();
    let max_time = cfg
        .max_time
        .unwrap_or_else(|| 20.0 * (goal - start).norm() / ugv.speed + 60.0);
    let dt = time_step(cfg.dt, &ugv, scouts.iter().map(|sc| &sc.uav));
    if !(max_time.is_finite() && max_time > 0.0) || max_time / dt > MAX_STEPS {
        let hint = if dt < cfg.dt {
            format!(
                "the step is refined from --dt {} so that no robot travels more than half its sensor range between two looks: give the robots sensor ranges that suit their speeds",
                cfg.dt
            )
        } else {
            "raise --dt or the UGV's speed".to_owned()
        };
        return Err(MissionError::Config(format!(
            "the mission would take {:.0} time steps (time limit {max_time:.0} s over a step of {dt} s); at most {MAX_STEPS:.0}: {hint}",
            max_time / dt,
        )));
    }
    let mut run = Run {
        cfg,
        rays,
        known,
        events: Vec::new(),
        replan_ms: Vec::new(),
        pending_ms: 0.0,
    };
    let mut t = 0.0;
    let mut ugv_track = Track {
        name: "ugv".into(),
        samples: vec![(0.0, start)],
    };
    let mut adopted = Vec::new();
    let (mut replans, mut switches) = (0, 0);
    let (mut driven, mut abandoned) = (0.0, 0.0);
    let mut last_switch = Real::NEG_INFINITY;
    // Start and goal at one point: the best path is to stay (a plan's curve through them has
    // a length of rounding, and time over it read 166463).
    let truth_plan_length = if start == goal {
        Some(0.0)
    } else {
        truth_plan_length
    };
    // Offline: the classes on the prior map.
    let offline = run.routes_from(start, None, false, &ugv_track.samples);
    run.replan_ms.clear();
    let finish = |run: Run<'_, K>,
                  reached: bool,
                  t: Real,
                  driven: Real,
                  ugv_track: Track,
                  scouts: Vec<Scout>,
                  adopted: Vec<Adopted>,
                  (replans, switches, abandoned): (usize, usize, Real)| {
        let result = MissionResult {
            world: name.to_owned(),
            policy: cfg.policy,
            scouts: scouts.len(),
            reached,
            time: t,
            dt,
            ugv_distance: driven,
            truth_plan_length,
            replans,
            switches,
            abandoned_distance: abandoned,
            uav_distance: scouts.iter().fold(0.0, |acc, s| acc + s.flown),
            events: run.events,
            ugv: ugv_track,
            uavs: scouts.into_iter().map(|s| s.track).collect(),
            adopted,
            replan_ms: run.replan_ms,
            map_updates: Vec::new(),
        };
        (result, run.known)
    };
    let Some(first) = offline.first().cloned() else {
        run.event(
            0.0,
            start,
            EventKind::Stuck {
                reason: "no collision-free class on the prior map".into(),
            },
        );
        return Ok(finish(
            run,
            false,
            0.0,
            0.0,
            ugv_track,
            scouts,
            adopted,
            (0, 0, 0.0),
        ));
    };
    run.event(
        0.0,
        start,
        EventKind::Planned {
            classes: offline.len(),
            class: first.class.clone(),
        },
    );
    let mut route = first;
    let mut alternatives: Vec<Route> = offline[1..].to_vec();
    let mut s = 0.0; // arc length along `route`
    let mut adopted_at = 0.0; // distance driven when `route` was adopted
    adopted.push(Adopted {
        t: 0.0,
        class: route.class.clone(),
        path: route.line.pts.clone(),
    });
    assign(
        &mut scouts,
        cfg.policy,
        &route,
        s,
        &alternatives,
        ugv.sensor_range,
    );
    if start == goal {
        // Already there: reached before anything moves.
        run.event(0.0, start, EventKind::Reached);
        return Ok(finish(
            run,
            true,
            0.0,
            0.0,
            ugv_track,
            scouts,
            adopted,
            (0, 0, 0.0),
        ));
    }
    let mut reached = false;
    // The robots look around before anyone moves: a blockage within sensor range of the start
    // is known before the UGV drives into it.
    let mut standing = true;
    while t < max_time {
        if !standing {
            t += dt;
            // Move.
            let step = ugv.speed * dt;
            let left = route.line.length() - s;
            let moved = step.min(left);
            // The track follows the route's polyline, the certified path: every vertex
            // passed in the step is a sample (at the time the UGV passes it), so that no
            // segment of the track cuts a corner of the route.
            let t0 = t - dt;
            for (&c, &p) in route.line.cum.iter().zip(&route.line.pts) {
                if c > s && c < s + moved {
                    ugv_track.samples.push((t0 + dt * (c - s) / moved, p));
                }
            }
            s += moved;
            driven += moved;
            let (pos, _) = route.line.at(s);
            ugv_track.samples.push((t, pos));
            for sc in &mut scouts {
                sc.step(dt, t);
            }
            if left <= step {
                reached = true;
                run.event(t, pos, EventKind::Reached);
                break;
            }
        }
        standing = false;
        let (pos, _) = route.line.at(s);
        // Sense.
        let mut found_hidden = false;
        let mut found_cleared = false;
        let observers: Vec<(Robot, Point, Real)> =
            std::iter::once((Robot::Ugv, pos, ugv.sensor_range))
                .chain(
                    scouts
                        .iter()
                        .enumerate()
                        .map(|(i, sc)| (Robot::Uav(i), sc.pos, sc.uav.sensor_range)),
                )
                .collect();
        for (by, p, range) in observers {
            for (obstacle, hidden) in run.known.sense(&p, range) {
                run.event(
                    t,
                    pos,
                    EventKind::Discovered {
                        obstacle,
                        hidden,
                        by,
                    },
                );
                if hidden {
                    found_hidden = true;
                } else {
                    found_cleared = true;
                }
            }
        }
        if !found_hidden && !found_cleared {
            // A scout done with its route takes the next job.
            if scouts.iter().any(|sc| sc.route.is_empty()) {
                assign_idle(
                    &mut scouts,
                    cfg.policy,
                    &route,
                    s,
                    &alternatives,
                    ugv.sensor_range,
                );
            }
            continue;
        }
        run.pending_ms += run.known.update();
        if found_cleared && let Some(rays) = run.known.renamed() {
            run.rays = rays;
            route.class = run.name(&route, &ugv_track.samples);
            for a in &mut alternatives {
                a.class = run.name(a, &ugv_track.samples);
            }
        }
        let known = &run.known;
        let clear = |pts: &[Point]| pts.len() < 2 || known.model().polyline_clearance(pts) > 0.0;
        // Alternatives found blocked are closed.
        let mut closed = Vec::new();
        alternatives.retain(|a| {
            let ok = clear(&a.line.pts);
            if !ok {
                closed.push(a.class.clone());
            }
            ok
        });
        let heading = route.line.heading(s);
        let remaining = route.line.slice(s, route.line.length());
        let blocked = !clear(&remaining);
        for c in closed {
            run.event(t, pos, EventKind::ClassClosed { class: c });
        }
        let mut replanned = false;
        if blocked {
            run.event(
                t,
                pos,
                EventKind::Blocked {
                    class: route.class.clone(),
                },
            );
            replans += 1;
            let mut routes = run.routes_from(pos, Some(heading), true, &ugv_track.samples);
            if routes.is_empty() {
                // No curve leaving along the heading clears what was just found (a blockage
                // close ahead): the UGV stops and plans from a standstill, turning on the spot.
                routes = run.routes_from(pos, None, true, &ugv_track.samples);
                // One re-plan, one time: both tries count in it.
                if let (Some(second), Some(first)) = (run.replan_ms.pop(), run.replan_ms.last_mut())
                {
                    *first += second;
                }
            }
            let Some(best) = routes.first() else {
                run.event(
                    t,
                    pos,
                    EventKind::Stuck {
                        reason: "no collision-free class on the known map".into(),
                    },
                );
                abandoned += driven - adopted_at;
                break;
            };
            // Bonus for the current class: kept if within the margin of the best.
            let pick = routes
                .iter()
                .position(|r| {
                    r.class == route.class && r.cost <= (1.0 + cfg.switch_margin) * best.cost
                })
                .unwrap_or(0);
            let next = routes[pick].clone();
            run.event(
                t,
                pos,
                EventKind::Replanned {
                    forced: true,
                    classes: routes.len(),
                    class: next.class.clone(),
                },
            );
            if run.adopt(t, pos, heading, &route, &next) {
                switches += 1;
                last_switch = t;
            }
            abandoned += driven - adopted_at;
            alternatives = routes
                .iter()
                .enumerate()
                .filter(|&(i, _)| i != pick)
                .map(|(_, r)| r.clone())
                .collect();
            route = next;
            replanned = true;
        } else {
            // The map changed but the path is still clear: a better class may have opened
            // (a mapped obstacle gone) or the current one may have become worse (a new
            // obstacle near it). Switch only through the hysteresis. (A re-plan that finds no
            // class leaves the valid path as it is and is not counted.)
            let routes = run.routes_from(pos, Some(heading), true, &ugv_track.samples);
            if routes.is_empty() {
                // Not a re-plan (below), and so not timed as one.
                run.replan_ms.pop();
            }
            if let Some(best) = routes.first() {
                replans += 1;
                // The price of staying: the rest of the current path, or the current class
                // as re-planned from here if that is cheaper. A re-plan alone can land in a
                // worse local optimum of the same class than the path being driven (its cost
                // moves by up to 2x between decisions on a tempting world), and switching on
                // that noise is the oscillation the hysteresis is there to prevent.
                let driving = run.remaining_cost(&route, s, heading);
                let current = routes
                    .iter()
                    .find(|r| r.class == route.class)
                    .map_or(driving, |r| r.cost.min(driving));
                let better = best.class != route.class
                    && should_switch(current, best.cost, t - last_switch, cfg);
                run.event(
                    t,
                    pos,
                    EventKind::Replanned {
                        forced: false,
                        classes: routes.len(),
                        class: if better {
                            best.class.clone()
                        } else {
                            route.class.clone()
                        },
                    },
                );
                if better {
                    run.adopt(t, pos, heading, &route, best);
                    switches += 1;
                    last_switch = t;
                    abandoned += driven - adopted_at;
                    alternatives = routes[1..].to_vec();
                    route = best.clone();
                    replanned = true;
                } else {
                    alternatives = routes
                        .into_iter()
                        .filter(|r| r.class != route.class)
                        .collect();
                }
            }
        }
        if replanned {
            s = 0.0;
            adopted_at = driven;
            adopted.push(Adopted {
                t,
                class: route.class.clone(),
                path: route.line.pts.clone(),
            });
        }
        assign(
            &mut scouts,
            cfg.policy,
            &route,
            s,
            &alternatives,
            ugv.sensor_range,
        );
    }
    if !reached
        && !run
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::Stuck { .. }))
    {
        let (pos, _) = route.line.at(s);
        run.event(
            t,
            pos,
            EventKind::Stuck {
                reason: format!("time limit {max_time:.0} s"),
            },
        );
    }
    for sc in &mut scouts {
        let last = sc.track.samples.last().copied();
        if last.is_none_or(|(lt, _)| lt < t) {
            sc.track.samples.push((t, sc.pos));
        }
    }
    Ok(finish(
        run,
        reached,
        t,
        driven,
        ugv_track,
        scouts,
        adopted,
        (replans, switches, abandoned),
    ))
}

/// The hysteresis: whether a plan of cost `current` that is still valid is given up for
/// another class of cost `candidate`, `since_last_switch` seconds after the last switch. Only
/// if the candidate is cheaper by the relative margin and the last switch is old enough.
pub fn should_switch(
    current: Real,
    candidate: Real,
    since_last_switch: Real,
    cfg: &MissionConfig,
) -> bool {
    candidate < (1.0 - cfg.switch_margin) * current && since_last_switch >= cfg.min_switch_interval
}

/// Whether a path leaves its start more than [`TURN_ANGLE_DEG`] off `heading`: the UGV
/// turns on the spot. A curve planned along the heading leaves exactly along it; one whose
/// class starts backwards, or sideways, is planned from a standstill.
fn turns_on_the_spot(line: &Polyline, heading: Vector) -> bool {
    line.pts.len() > 1 && {
        let d = line.pts[1] - line.pts[0];
        d.dot(&heading) < TURN_ANGLE_DEG.to_radians().cos() * d.norm() * heading.norm()
    }
}

/// The most a new path may leave off the UGV's heading without a turn on the spot, degrees.
pub const TURN_ANGLE_DEG: Real = 25.0;

/// The part of the route a scout `ahead` inspects: scout `j` of `n` takes the `j`-th of `n`
/// equal parts of the far half of what is left.
fn ahead_route(from: Point, route: &Route, s: Real, j: usize, n: usize) -> Vec<Point> {
    let left = route.line.length() - s;
    let a = s + left * (0.5 + 0.5 * j as Real / n as Real);
    let b = s + left * (0.5 + 0.5 * (j + 1) as Real / n as Real);
    let mut out = vec![from];
    out.extend(route.line.slice(a, b));
    out
}

/// An alternative's route for a scout: to where it leaves the UGV's route (farther than the
/// UGV's sensor range from it), then along it to the goal.
fn alternative_route(from: Point, alt: &Route, route: &Route, s: Real, range: Real) -> Vec<Point> {
    let rest = route.line.slice(s, route.line.length());
    let far = |p: &Point| {
        rest.windows(2)
            .map(|w| homospline_geom::math::distance_point_segment(p, &w[0], &w[1]))
            .fold(Real::INFINITY, Real::min)
            > range
    };
    let k = alt.line.pts.iter().position(far).unwrap_or(0);
    let mut out = vec![from];
    out.extend(alt.line.pts[k..].iter().copied());
    out
}

/// Routes for every scout after a (re-)plan.
fn assign(
    scouts: &mut [Scout],
    policy: Policy,
    route: &Route,
    s: Real,
    alts: &[Route],
    range: Real,
) {
    for sc in scouts.iter_mut() {
        sc.route.clear();
        sc.jobs.clear();
    }
    assign_idle(scouts, policy, route, s, alts, range);
}

/// Routes for the scouts that have none: an alternative no scout has taken since the last
/// (re-)plan (policy `alternatives`), else, for a scout with no job yet, a part of the far
/// half of the UGV's route; a scout whose job is done and has nothing left holds.
fn assign_idle(
    scouts: &mut [Scout],
    policy: Policy,
    route: &Route,
    s: Real,
    alts: &[Route],
    range: Real,
) {
    if policy == Policy::None {
        return;
    }
    let mut taken: Vec<String> = scouts
        .iter()
        .flat_map(|sc| sc.jobs.iter().cloned())
        .collect();
    // First the alternatives, one scout each; then the scouts left without a job share the
    // far half of the UGV's route between them.
    let mut ahead = Vec::new();
    for (j, sc) in scouts.iter_mut().enumerate() {
        if !sc.route.is_empty() {
            continue;
        }
        if policy == Policy::Alternatives
            && let Some(alt) = alts
                .iter()
                .find(|a| !taken.contains(&a.class) && a.class != route.class)
        {
            sc.route = alternative_route(sc.pos, alt, route, s, range);
            sc.jobs.push(alt.class.clone());
            taken.push(alt.class.clone());
        } else if sc.jobs.is_empty() {
            ahead.push(j);
        }
    }
    let n = ahead.len();
    for (part, &j) in ahead.iter().enumerate() {
        let sc = &mut scouts[j];
        sc.route = ahead_route(sc.pos, route, s, part, n);
        sc.jobs.push(String::new());
    }
}
