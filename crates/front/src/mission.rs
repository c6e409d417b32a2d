//! What `homospline simulate` prints and writes: the events and figures of a mission and
//! its JSON (timeline and every trajectory). The animated picture is the command line's.

use std::fmt::Write;

use homospline_geom::{Point, Real};
use homospline_mission::{EventKind, MapWorld, MissionResult, MissionWorld, Robot};
use serde_json::{Value, json};

use crate::report::ClassNames;

fn who(r: Robot) -> String {
    match r {
        Robot::Ugv => "ugv".into(),
        Robot::Uav(i) => format!("uav-{i}"),
    }
}

/// Class names as the event lines print them: letters in the order the mission first names
/// the classes (A is the first class driven), with the id `plan --avoid` takes when
/// [`ClassNames::Id`]. The JSON keeps signatures whole.
///
/// # Examples
///
/// ```
/// use homospline_front::report::ClassNames;
/// use homospline_front::mission::Labels;
///
/// let a: String = (1..=60).map(|i| format!("-{i}")).collect();
/// let b = a.replacen("-30", "+30", 1);
/// let mut letters = Labels::new(ClassNames::Letter);
/// assert_eq!(letters.label(&a), "A");
/// assert_eq!(letters.label("-1+2"), "B");
/// assert_eq!(letters.label(&a), "A", "a class keeps its letter");
/// assert_eq!(letters.label(&b), "C");
/// let mut ids = Labels::new(ClassNames::Id);
/// assert_eq!(ids.label("-1+2"), "A -1+2");
/// let (la, lb) = (ids.label(&a), ids.label(&b));
/// assert_eq!(la.len(), 2 + 9, "{la}");
/// // Signatures that differ in the middle keep different ids.
/// assert_ne!(la[2..], lb[2..]);
/// ```
#[derive(Clone, Debug)]
pub struct Labels {
    names: ClassNames,
    seen: Vec<String>,
}

impl Labels {
    /// No class named yet.
    pub fn new(names: ClassNames) -> Self {
        Self {
            names,
            seen: Vec::new(),
        }
    }

    /// The name of the class of `signature`: a new letter the first time.
    pub fn label(&mut self, signature: &str) -> String {
        let k = match self.seen.iter().position(|s| s == signature) {
            Some(k) => k,
            None => {
                self.seen.push(signature.to_owned());
                self.seen.len() - 1
            }
        };
        self.names.ranked(k + 1, signature)
    }
}

/// One line per event.
fn describe(kind: &EventKind, labels: &mut Labels) -> String {
    match kind {
        EventKind::Planned { classes, class } => {
            format!(
                "planned on the prior map: {classes} collision-free classes, driving {}",
                labels.label(class)
            )
        }
        EventKind::Discovered {
            obstacle,
            hidden,
            by,
        } => {
            if *hidden {
                format!("{} sees obstacle '{obstacle}', not on the map", who(*by))
            } else {
                format!("{} sees that obstacle '{obstacle}' is gone", who(*by))
            }
        }
        EventKind::ClassClosed { class } => {
            format!("class {} is blocked (an alternative)", labels.label(class))
        }
        EventKind::Blocked { class } => {
            format!("the UGV's path (class {}) is blocked", labels.label(class))
        }
        EventKind::Replanned {
            forced,
            classes,
            class,
        } => format!(
            "re-planned ({}): {classes} collision-free classes, driving {}",
            if *forced { "blocked" } else { "map changed" },
            labels.label(class)
        ),
        EventKind::Switched { from, to } => {
            let from = labels.label(from);
            format!("switched class {from} -> {}", labels.label(to))
        }
        EventKind::TurnedAround => {
            "the new path leaves off the heading: the UGV turns on the spot".into()
        }
        EventKind::Reached => "goal reached".into(),
        EventKind::Stuck { reason } => format!("stopped: {reason}"),
    }
}

/// A figure to three decimals, or `-` when there is none.
pub fn fmt_opt(x: Option<Real>) -> String {
    x.map_or("-".into(), |v| format!("{v:.3}"))
}

/// The events and the figures, as `homospline simulate` prints them.
pub fn mission_text(world: &MissionWorld, r: &MissionResult, names: ClassNames) -> String {
    let head = format!(
        "world {}  policy {}  scouts {}  hidden {}  cleared {}",
        r.world,
        r.policy.name(),
        r.scouts,
        world.hidden.len(),
        world.cleared.len()
    );
    text_with(&head, world.team.ugv.speed, r, names)
}

/// The same for a map world, with each update of the known map.
pub fn map_mission_text(world: &MapWorld, r: &MissionResult, names: ClassNames) -> String {
    let blocked = world.changes.iter().filter(|c| c.blocked).count();
    let head = format!(
        "world {}  map {} x {}  policy {}  scouts {}  blocked {}  freed {}",
        r.world,
        world.prior.width,
        world.prior.height,
        r.policy.name(),
        r.scouts,
        blocked,
        world.changes.len() - blocked
    );
    let mut s = text_with(&head, world.team.ugv.speed, r, names);
    for u in &r.map_updates {
        let _ = writeln!(
            s,
            "map update: {} cells, brushfire {} {:.2} ms, graph {} {:.1} ms, model {:.1} ms",
            u.cells,
            if u.local {
                "updated locally"
            } else {
                "rebuilt"
            },
            u.field_ms,
            if u.graph_rebuilt {
                "rebuilt"
            } else {
                "kept, edges through the blockage closed,"
            },
            u.graph_ms,
            u.model_ms
        );
    }
    s
}

fn text_with(head: &str, ugv_speed: Real, r: &MissionResult, names: ClassNames) -> String {
    let mut s = String::new();
    let mut labels = Labels::new(names);
    let _ = writeln!(s, "{head}");
    for e in &r.events {
        let _ = writeln!(
            s,
            "{:>8.2} s  ({:>7.2}, {:>7.2})  {}",
            e.t,
            e.at.x,
            e.at.y,
            describe(&e.kind, &mut labels)
        );
    }
    let ms = &r.replan_ms;
    let _ = writeln!(
        s,
        "reached {}  time {:.2} s  UGV distance {:.2}  truth plan (best-cost plan on the true map; not a lower bound) {}  distance / truth plan {}  time / truth plan {}",
        if r.reached { "yes" } else { "NO" },
        r.time,
        r.ugv_distance,
        fmt_opt(r.truth_plan_length),
        fmt_opt(r.distance_ratio()),
        fmt_opt(r.time_ratio(ugv_speed)),
    );
    let _ = writeln!(
        s,
        "re-plans {}  switches {}  driven on abandoned paths {:.2}  UAV distance {:.2}  re-plan ms {}",
        r.replans,
        r.switches,
        r.abandoned_distance,
        r.uav_distance,
        if ms.is_empty() {
            "-".to_owned()
        } else {
            ms.iter()
                .map(|m| format!("{m:.1}"))
                .collect::<Vec<_>>()
                .join(" ")
        }
    );
    s
}

fn xy(p: &Point) -> Value {
    json!([p.x, p.y])
}

/// The mission as JSON (`docs/formats.md`, mission result).
pub fn mission_json(world: &MissionWorld, r: &MissionResult) -> String {
    json_with(world.team.ugv.speed, r)
}

/// The same for a map world (`docs/formats.md`, mission result, with `map_updates`).
pub fn map_mission_json(world: &MapWorld, r: &MissionResult) -> String {
    json_with(world.team.ugv.speed, r)
}

fn json_with(ugv_speed: Real, r: &MissionResult) -> String {
    let events: Vec<Value> = r
        .events
        .iter()
        .map(|e| {
            let mut v = match &e.kind {
                EventKind::Planned { classes, class } => {
                    json!({"kind": "planned", "classes": classes, "class": class})
                }
                EventKind::Discovered {
                    obstacle,
                    hidden,
                    by,
                } => json!({"kind": "discovered", "obstacle": obstacle, "hidden": hidden, "by": who(*by)}),
                EventKind::ClassClosed { class } => json!({"kind": "class_closed", "class": class}),
                EventKind::Blocked { class } => json!({"kind": "blocked", "class": class}),
                EventKind::Replanned {
                    forced,
                    classes,
                    class,
                } => json!({"kind": "replanned", "forced": forced, "classes": classes, "class": class}),
                EventKind::Switched { from, to } => json!({"kind": "switched", "from": from, "to": to}),
                EventKind::TurnedAround => json!({"kind": "turned_around"}),
                EventKind::Reached => json!({"kind": "reached"}),
                EventKind::Stuck { reason } => json!({"kind": "stuck", "reason": reason}),
            };
            v["t"] = json!(e.t);
            v["at"] = xy(&e.at);
            v
        })
        .collect();
    let track = |t: &homospline_mission::Track| {
        json!({
            "name": t.name,
            "samples": t.samples.iter().map(|(t, p)| json!([t, p.x, p.y])).collect::<Vec<_>>(),
        })
    };
    let doc = json!({
        "world": r.world,
        "policy": r.policy.name(),
        "scouts": r.scouts,
        "reached": r.reached,
        "time": r.time,
        "dt": r.dt,
        "ugv_distance": r.ugv_distance,
        "truth_plan_length": r.truth_plan_length,
        "distance_ratio": r.distance_ratio(),
        "time_ratio": r.time_ratio(ugv_speed),
        "replans": r.replans,
        "switches": r.switches,
        "abandoned_distance": r.abandoned_distance,
        "uav_distance": r.uav_distance,
        "replan_ms": r.replan_ms,
        "events": events,
        "ugv": track(&r.ugv),
        "uavs": r.uavs.iter().map(track).collect::<Vec<_>>(),
        "adopted": r.adopted.iter().map(|a| json!({
            "t": a.t,
            "class": a.class,
            "path": a.path.iter().map(xy).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    });
    let mut doc = doc;
    if !r.map_updates.is_empty() {
        doc["map_updates"] = r
            .map_updates
            .iter()
            .map(|u| {
                json!({"cells": u.cells, "local": u.local, "field_ms": u.field_ms,
                       "graph_ms": u.graph_ms, "graph_rebuilt": u.graph_rebuilt,
                       "model_ms": u.model_ms})
            })
            .collect();
    }
    serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
}
