//! `check` on every kind of input: which kind a file is (a world file by its keys), which
//! command takes a file another refused, and the summaries of an occupancy map and of a
//! world (a scene's is [`crate::summary`]).

use std::fmt::Write;
use std::path::Path;

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

/// What a file that a command refused is, and the command that takes it, for the message of
/// a command given the wrong kind of file: `simulate` is `true` for the world command, else
/// a command that takes a scene or a map (`plan`, `graph`). `None` when the file is of no
/// other kind it knows (its own parser's message then stands).
///
/// # Examples
///
/// ```
/// use std::path::Path;
/// use homospline_front::check::other_command;
///
/// let world = "scene: field.yaml\nteam:\n  ugv: {speed: 1, sensor_range: 5}\n";
/// let hint = other_command(Path::new("w.yaml"), Some(world), false).unwrap();
/// assert!(hint.contains("homospline simulate w.yaml"), "{hint}");
/// let scene = "bounds: {min: [0, 0], max: [9, 9]}\nstart: [1, 1]\ngoal: [8, 8]\n";
/// let hint = other_command(Path::new("s.yaml"), Some(scene), true).unwrap();
/// assert!(hint.contains("homospline plan s.yaml"), "{hint}");
/// assert!(other_command(Path::new("s.yaml"), Some(scene), false).is_none());
/// ```
pub fn other_command(path: &Path, text: Option<&str>, simulate: bool) -> Option<String> {
    let p = path.display();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    type Keys = std::collections::BTreeMap<String, serde::de::IgnoredAny>;
    let keys = text.and_then(|t| homospline_geom::scene::from_yaml::<Keys>(t).ok());
    let has = |k: &str| keys.as_ref().is_some_and(|keys| keys.contains_key(k));
    // `is_world` from the keys read once.
    let world = WORLD_KEYS.iter().any(|k| has(k));
    if simulate {
        let what = if ext.as_deref() == Some("map") {
            format!("a MovingAI map: `homospline plan {p} --start X,Y --goal X,Y` plans on it")
        } else if !world && has("image") && has("resolution") {
            format!("a ROS map: `homospline plan {p} --start X,Y --goal X,Y` plans on it")
        } else if !world && has("bounds") {
            format!("a scene: `homospline plan {p}` plans on it")
        } else {
            return None;
        };
        Some(format!(
            "{what}; simulate takes a world file (a scene or map with a team and hidden obstacles)"
        ))
    } else {
        let what = if ext.as_deref() == Some("scen") {
            format!("a MovingAI scenario file: `homospline bench-scen {p}` plans its scenarios")
        } else if world {
            format!("a world file: `homospline simulate {p}` runs its mission")
        } else {
            return None;
        };
        Some(format!("{what}; this command takes a scene or a map"))
    }
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
