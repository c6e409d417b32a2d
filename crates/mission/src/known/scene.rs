//! The known world of a scene mission: the prior scene with what was found so far, and the
//! re-plan on a scene.

use std::time::Instant;

use homospline_geom::{Point, Real, Scene};
use homospline_homotopy::Rays;
use homospline_optim::{Plan, PlanConfig, plan};
use homospline_spline::{CircleModel, ClearanceModel};

use super::Known;
use crate::sim::MissionConfig;
use crate::world::types::MissionWorld;

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

/// Seen from `p` within `range`: any circle of the obstacle comes that close.
fn within(p: &Point, range: Real, o: &homospline_geom::Obstacle) -> bool {
    o.circles
        .iter()
        .any(|c| (p - c.center).norm() - c.radius <= range)
}

/// The known world of a scene mission: the prior scene with the obstacles found so far.
pub(crate) struct SceneKnown<'w> {
    world: &'w MissionWorld,
    known: Scene,
    model: CircleModel,
    known_cleared: rustc_hash::FxHashSet<String>,
    /// The truth's hidden obstacles not found yet, by index, in order: sensing scans these
    /// only (a scan of every obstacle with a name lookup in a list made sensing quadratic in
    /// the hidden obstacles; measured: docs/performance.md, "Measurements behind the
    /// defaults").
    pending_hidden: Vec<usize>,
    /// The prior's cleared obstacles not found gone yet, by index, in order.
    pending_cleared: Vec<usize>,
    /// The re-plans' coarser graph resolution ([`MissionConfig::replan_resolution`]).
    replan_resolution: Option<Real>,
}

impl<'w> SceneKnown<'w> {
    /// The prior scene of `world`, nothing found yet; re-plans as `cfg` sets them.
    pub(crate) fn new(world: &'w MissionWorld, cfg: &MissionConfig) -> Self {
        Self {
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
        }
    }
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
