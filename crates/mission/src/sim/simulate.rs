//! The entry points: a mission on a scene world ([`simulate`]) or on an occupancy map world
//! ([`simulate_map`]), with the truth plan to compare against.

use homospline_homotopy::Rays;
use homospline_optim::{GrowthConfig, PlanConfig, plan};

use super::config::{MissionConfig, MissionError};
use super::mission::run_mission;
use super::record::MissionResult;
use crate::known::map::MapKnown;
use crate::known::scene::SceneKnown;
use crate::world::types::{MapWorld, MissionWorld};

/// Simulates the mission in `world` with `cfg`. Deterministic: the same world and settings
/// give the same events and tracks (only `replan_ms` varies).
///
/// # Examples
///
/// A hidden disc blocks the way between two obstacles; the UGV finds it, re-plans round it
/// and reaches the goal:
///
/// ```
/// use homospline_geom::{Circle, Obstacle, Point, Scene};
/// use homospline_mission::{MissionConfig, MissionWorld, Policy, Team, Uav, simulate};
///
/// let scene = Scene::from_str(
///     "name: gap\nbounds: {min: [0, 0], max: [40, 30]}\nstart: [2, 15]\ngoal: [38, 15]\n\
///      obstacles:\n  - name: a\n    circles: [[20, 8, 5]]\n  - name: b\n    circles: [[20, 22, 5]]\n",
///     "gap.yaml",
/// )?;
/// let hidden = vec![Obstacle { name: "rock".into(), circles: vec![Circle::new(20.0, 15.0, 2.5)] }];
/// let mut team = Team::default();
/// team.uavs.push(Uav { start: scene.start, speed: 3.0, sensor_range: 8.0 });
/// let world = MissionWorld::new("gap-blocked", scene, hidden, Vec::new(), team)?;
/// let cfg = MissionConfig { policy: Policy::GUARD, ..MissionConfig::default() };
/// let r = simulate(&world, &cfg)?;
/// assert!(r.reached && r.replans >= 1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn simulate(world: &MissionWorld, cfg: &MissionConfig) -> Result<MissionResult, MissionError> {
    cfg.check()?;
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
    let known = SceneKnown::new(world, cfg);
    let team = cfg
        .policy
        .get()
        .verifies()
        .then(|| SceneKnown::new(world, cfg));
    let rays = Rays::for_scene(&world.prior);
    let (result, _) = run_mission(
        known,
        team,
        rays,
        &world.name,
        &world.team,
        truth_plan_length,
        cfg,
    )?;
    Ok(result)
}

/// Simulates the mission on an occupancy map world: the same loop as [`simulate`], with the
/// known map updated locally at each discovery (`MissionResult::map_updates`). Give it
/// [`MissionConfig::for_maps`] (the map defaults of `homospline_optim::PlanConfig::maps` for
/// via-points, the class search, the evaluation budget and the safety term), changed as you
/// like: the settings are taken as given (it had copied the map defaults over the caller's,
/// `dm` among them).
pub fn simulate_map(world: &MapWorld, cfg: &MissionConfig) -> Result<MissionResult, MissionError> {
    cfg.check()?;
    // The truth plan: the best-cost plan on the true map.
    let truth_plan_length =
        homospline_maps::PreparedMap::for_robot(&world.truth, world.team.ugv.radius)
            .ok()
            .and_then(|m| m.plan(world.start, world.goal, &cfg.plan).ok())
            .and_then(|p| p.chosen().map(|c| c.length));
    let known =
        MapKnown::new(world).map_err(|e| MissionError::Config(format!("{}: {e}", world.name)))?;
    let team = if cfg.policy.get().verifies() {
        Some(
            MapKnown::new(world)
                .map_err(|e| MissionError::Config(format!("{}: {e}", world.name)))?,
        )
    } else {
        None
    };
    let rays = known.naming_rays();
    let (mut result, known) = run_mission(
        known,
        team,
        rays,
        &world.name,
        &world.team,
        truth_plan_length,
        cfg,
    )?;
    result.map_updates = known.updates;
    Ok(result)
}
