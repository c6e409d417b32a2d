//! `check` on every kind of input: which kind a file is (a world file by its keys), and the
//! summaries of an occupancy map and of a world (a scene's is [`crate::summary`]).

use std::fmt::Write;

use homospline_maps::OccupancyMap;
use homospline_mission::world::AnyWorld;

/// The top-level keys of a world file (`docs/formats.md`, section 6), none of which a scene
/// file has.
const WORLD_KEYS: [&str; 6] = [
    "scene",
    "map",
    "truth_map",
    "hidden_obstacles",
    "cleared_obstacles",
    "team",
];

/// Whether `text` is a world file rather than a scene: a YAML or JSON mapping with one of a
/// world's own top-level keys. Text that is no mapping is no world (the scene reader then
/// says what is wrong with it).
///
/// # Examples
///
/// ```
/// use homospline_front::check::is_world;
///
/// assert!(is_world("scene: field.yaml\nteam:\n  ugv: {speed: 1, sensor_range: 5}\n"));
/// assert!(is_world("{\"map\": \"a.map\", \"truth_map\": \"b.map\"}"));
/// assert!(!is_world("name: x\nbounds: {min: [0, 0], max: [1, 1]}\n"));
/// assert!(!is_world("[1, 2]"));
/// ```
pub fn is_world(text: &str) -> bool {
    type Keys = std::collections::BTreeMap<String, serde::de::IgnoredAny>;
    homospline_geom::scene::from_yaml::<Keys>(text)
        .is_ok_and(|keys| WORLD_KEYS.iter().any(|k| keys.contains_key(*k)))
}

/// What `check` says about an occupancy map: its size, cell, origin and free cells.
pub fn map_summary(map: &OccupancyMap) -> String {
    let free = map.occupied.iter().filter(|&&o| !o).count();
    let cells = map.width * map.height;
    let b = map.bounds();
    let mut s = String::new();
    let _ = writeln!(s, "map        {}", map.name);
    let _ = writeln!(
        s,
        "cells      {} x {}, {}",
        map.width,
        map.height,
        if map.y_down {
            format!(
                "{} map unit each (MovingAI: row 0 at the top)",
                short(map.cell)
            )
        } else {
            format!("{} m each (ROS: y up from the origin)", short(map.cell))
        }
    );
    let _ = writeln!(
        s,
        "extent     [{}, {}] .. [{}, {}]",
        short(b.min.x),
        short(b.min.y),
        short(b.max.x),
        short(b.max.y)
    );
    let _ = writeln!(
        s,
        "free       {free} of {cells} cells ({:.1} %)",
        100.0 * free as f64 / cells.max(1) as f64
    );
    s
}

/// `v` to nine decimals, as short as it prints (`9.2`, not `9.200000000000003`).
fn short(v: f64) -> f64 {
    let r = (v * 1e9).round() / 1e9;
    if r.is_finite() { r } else { v }
}

/// `n` and `word`, plural unless `n` is 1.
fn count(n: usize, word: &str) -> String {
    format!("{n} {word}{}", if n == 1 { "" } else { "s" })
}

/// Whether `world`'s mission can run as `simulate` sets it up at its defaults: its time
/// steps fit ([`homospline_mission::sim::check_team`]); else the reason, as `simulate`
/// gives it.
pub fn world_fits(world: &AnyWorld) -> Result<(), homospline_mission::sim::MissionError> {
    let cfg = homospline_mission::sim::MissionConfig::default();
    let (team, start, goal) = match world {
        AnyWorld::Scene(w) => (&w.team, w.prior.start, w.prior.goal),
        AnyWorld::Map(w) => (&w.team, w.start, w.goal),
    };
    homospline_mission::sim::check_team(team, &cfg, start, goal)
}

/// What `check` says about a world: its prior and truth, what the truth hides or clears,
/// and the team.
pub fn world_summary(world: &AnyWorld) -> String {
    let mut s = String::new();
    let team = match world {
        AnyWorld::Scene(w) => {
            let _ = writeln!(s, "world      {} (a scene world)", w.name);
            let _ = writeln!(
                s,
                "prior      scene {}: {}, start [{}, {}], goal [{}, {}]",
                w.prior.name,
                count(w.prior.obstacles.len(), "obstacle"),
                w.prior.start.x,
                w.prior.start.y,
                w.prior.goal.x,
                w.prior.goal.y
            );
            let _ = writeln!(
                s,
                "truth      {} hidden, {} cleared",
                count(w.hidden.len(), "obstacle"),
                w.cleared.len()
            );
            &w.team
        }
        AnyWorld::Map(w) => {
            let _ = writeln!(s, "world      {} (a map world)", w.name);
            let _ = writeln!(
                s,
                "prior      map {}: {} x {} cells, start [{}, {}], goal [{}, {}]",
                w.prior.name,
                w.prior.width,
                w.prior.height,
                w.start.x,
                w.start.y,
                w.goal.x,
                w.goal.y
            );
            let differ = w
                .prior
                .occupied
                .iter()
                .zip(&w.truth.occupied)
                .filter(|(a, b)| a != b)
                .count();
            let _ = writeln!(
                s,
                "truth      map {}: {} differing from the prior",
                w.truth.name,
                count(differ, "cell")
            );
            &w.team
        }
    };
    let u = &team.ugv;
    let _ = writeln!(
        s,
        "ugv        speed {}, sensor range {}, radius {}",
        u.speed, u.sensor_range, u.radius
    );
    let _ = writeln!(s, "scouts     {}", team.uavs.len());
    s
}
