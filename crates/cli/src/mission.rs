//! What `homospline simulate` prints and writes: the events and figures of a mission, its
//! JSON (timeline and every trajectory) and an animated SVG.

use std::fmt::Write;

use homospline_geom::Bounds;
use homospline_geom::{Point, Real};
use homospline_mission::{EventKind, MapWorld, MissionResult, MissionWorld, Robot};
use serde_json::{Value, json};

fn who(r: Robot) -> String {
    match r {
        Robot::Ugv => "ugv".into(),
        Robot::Uav(i) => format!("uav-{i}"),
    }
}

/// A class name as the event lines print it. On a map a name can run to hundreds of letters
/// (one per ray crossed); past 48 characters it is cut to its head and tail, with its letter
/// count and a short hash (FNV-1a) that tells apart names with the same ends. The JSON keeps
/// names whole.
fn label(name: &str) -> String {
    if name.chars().count() <= 48 {
        return name.to_owned();
    }
    let chars: Vec<char> = name.chars().collect();
    let head: String = chars[..20].iter().collect();
    let tail: String = chars[chars.len() - 12..].iter().collect();
    let letters = name.matches(['+', '-']).count();
    let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    format!("{head}..{tail} ({letters} letters, #{:04x})", hash & 0xffff)
}

/// One line per event.
fn describe(kind: &EventKind) -> String {
    match kind {
        EventKind::Planned { classes, class } => {
            format!(
                "planned on the prior map: {classes} collision-free classes, driving {}",
                label(class)
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
            format!("class {} is blocked (an alternative)", label(class))
        }
        EventKind::Blocked { class } => {
            format!("the UGV's path (class {}) is blocked", label(class))
        }
        EventKind::Replanned {
            forced,
            classes,
            class,
        } => format!(
            "re-planned ({}): {classes} collision-free classes, driving {}",
            if *forced { "blocked" } else { "map changed" },
            label(class)
        ),
        EventKind::Switched { from, to } => {
            format!("switched class {} -> {}", label(from), label(to))
        }
        EventKind::TurnedAround => {
            "the new path leaves off the heading: the UGV turns on the spot".into()
        }
        EventKind::Reached => "goal reached".into(),
        EventKind::Stuck { reason } => format!("stopped: {reason}"),
    }
}

fn fmt_opt(x: Option<Real>) -> String {
    x.map_or("-".into(), |v| format!("{v:.3}"))
}

/// The events and the figures, as `homospline simulate` prints them.
pub fn mission_text(world: &MissionWorld, r: &MissionResult) -> String {
    let head = format!(
        "world {}  policy {}  scouts {}  hidden {}  cleared {}",
        r.world,
        r.policy.name(),
        r.scouts,
        world.hidden.len(),
        world.cleared.len()
    );
    text_with(&head, world.team.ugv.speed, r)
}

/// The same for a map world, with each update of the known map.
pub fn map_mission_text(world: &MapWorld, r: &MissionResult) -> String {
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
    let mut s = text_with(&head, world.team.ugv.speed, r);
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

fn text_with(head: &str, ugv_speed: Real, r: &MissionResult) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{head}");
    for e in &r.events {
        let _ = writeln!(
            s,
            "{:>8.2} s  ({:>7.2}, {:>7.2})  {}",
            e.t,
            e.at.x,
            e.at.y,
            describe(&e.kind)
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

/// Text safe inside an SVG element.
fn xml_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Seconds of animation for the whole mission.
const ANIMATION_SECONDS: Real = 20.0;

/// At most this many key frames per moving robot.
const KEY_FRAMES: usize = 400;

/// An animated picture of the mission: the prior map (grey), obstacles not on it (red, faint
/// until discovered), mapped obstacles that are gone (fading when discovered), every adopted
/// path (dashed), the UGV's (blue) and the scouts' (orange) tracks, re-plan points, and the
/// robots moving along their tracks (the mission plays in 20 s and repeats).
pub fn mission_svg(world: &MissionWorld, r: &MissionResult) -> String {
    svg_with(
        &world.prior.bounds,
        false,
        (world.prior.start, world.prior.goal),
        r,
        &mut |s, x, y, scale, when| scene_layers(s, world, x, y, scale, when),
    )
}

/// The same for a map world: the prior map as the raster picture of `plan`'s map SVGs, and
/// the cells that differ in the truth, faint until discovered (red: blocked; green: freed).
pub fn map_mission_svg(world: &MapWorld, r: &MissionResult) -> String {
    let map = &world.prior;
    svg_with(
        &map.bounds(),
        map.y_down,
        (world.start, world.goal),
        r,
        &mut |s, x, y, scale, when| {
            let b = map.bounds();
            let (ya, yb) = (y(b.min.y), y(b.max.y));
            let _ = writeln!(
                s,
                r#"<g id="map"><image x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" preserveAspectRatio="none" image-rendering="optimizeSpeed" style="image-rendering: pixelated" href="{}"/></g>"#,
                x(b.min.x),
                ya.min(yb),
                (b.max.x - b.min.x) * scale,
                (ya - yb).abs(),
                crate::picture::occupancy_href(map, map.y_down)
            );
            s.push_str("<g id=\"hidden\">\n");
            for c in &world.changes {
                let colour = if c.blocked { "#d62728" } else { "#2ca02c" };
                for &(i, j) in &c.cells {
                    let (x0, y0) = (
                        map.origin.x + i as Real * map.cell,
                        map.origin.y + j as Real * map.cell,
                    );
                    let (ya, yb) = (y(y0), y(y0 + map.cell));
                    let _ = write!(
                        s,
                        r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{colour}" fill-opacity="0.2">"#,
                        x(x0),
                        ya.min(yb),
                        map.cell * scale,
                        (ya - yb).abs()
                    );
                    if let Some(t) = when(&c.name) {
                        let _ = write!(
                            s,
                            r#"<animate attributeName="fill-opacity" from="0.2" to="0.9" begin="{t:.2}s" dur="0.5s" fill="freeze"/>"#
                        );
                    }
                    s.push_str("</rect>\n");
                }
            }
            s.push_str("</g>\n");
        },
    )
}

/// The scene's layers: the map's circles and the hidden ones.
fn scene_layers(
    s: &mut String,
    world: &MissionWorld,
    x: &dyn Fn(Real) -> Real,
    y: &dyn Fn(Real) -> Real,
    scale: Real,
    when: &dyn Fn(&str) -> Option<Real>,
) {
    let rr = world.prior.robot_radius;
    s.push_str("<g id=\"map\">\n");
    for o in &world.prior.obstacles {
        let gone = world.cleared.contains(&o.name);
        for c in &o.circles {
            let _ = write!(
                s,
                r##"<circle cx="{:.2}" cy="{:.2}" r="{:.2}" fill="#666" fill-opacity="0.85">"##,
                x(c.center.x),
                y(c.center.y),
                (c.radius + rr) * scale
            );
            if gone && let Some(t) = when(&o.name) {
                let _ = write!(
                    s,
                    r#"<animate attributeName="fill-opacity" from="0.85" to="0.12" begin="{t:.2}s" dur="0.5s" fill="freeze"/>"#,
                );
            }
            s.push_str("</circle>\n");
        }
    }
    s.push_str("</g>\n<g id=\"hidden\">\n");
    for o in world
        .truth
        .obstacles
        .iter()
        .filter(|o| world.hidden.contains(&o.name))
    {
        for c in &o.circles {
            let _ = write!(
                s,
                r##"<circle cx="{:.2}" cy="{:.2}" r="{:.2}" fill="#d62728" fill-opacity="0.12" stroke="#d62728" stroke-dasharray="4 3">"##,
                x(c.center.x),
                y(c.center.y),
                (c.radius + rr) * scale
            );
            if let Some(t) = when(&o.name) {
                let _ = write!(
                    s,
                    r#"<animate attributeName="fill-opacity" from="0.12" to="0.85" begin="{t:.2}s" dur="0.5s" fill="freeze"/>"#,
                );
            }
            s.push_str("</circle>\n");
        }
    }
    s.push_str("</g>\n");
}

/// Layers drawn under the plans and tracks: `(svg, x, y, scale, animation time of an
/// obstacle's discovery)`.
type Layers<'a> = dyn FnMut(
        &mut String,
        &dyn Fn(Real) -> Real,
        &dyn Fn(Real) -> Real,
        Real,
        &dyn Fn(&str) -> Option<Real>,
    ) + 'a;

fn svg_with(
    b: &Bounds,
    y_down: bool,
    (start, goal): (Point, Point),
    r: &MissionResult,
    layers: &mut Layers<'_>,
) -> String {
    let (w, h) = (b.max.x - b.min.x, b.max.y - b.min.y);
    let scale = 800.0 / w.max(h);
    let (pw, ph) = (w * scale, h * scale);
    let x = |v: Real| (v - b.min.x) * scale;
    let y = |v: Real| {
        if y_down {
            (v - b.min.y) * scale
        } else {
            (b.max.y - v) * scale
        }
    };
    let k = ANIMATION_SECONDS / r.time.max(1e-9);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {pw:.1} {:.1}">"#,
        pw,
        ph + 40.0,
        ph + 40.0
    );
    let _ = writeln!(
        s,
        r##"<rect x="0" y="0" width="{pw:.1}" height="{ph:.1}" fill="#fafafa" stroke="#333"/>"##
    );
    let when = |name: &str| {
        r.events.iter().find_map(|e| match &e.kind {
            EventKind::Discovered { obstacle, .. } if obstacle == name => Some(e.t),
            _ => None,
        })
    };
    let when_scaled = |name: &str| when(name).map(|t| t * k);
    layers(&mut s, &x, &y, scale, &when_scaled);
    let poly = |pts: &mut dyn Iterator<Item = Point>| {
        pts.map(|p| format!("{:.2},{:.2}", x(p.x), y(p.y)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    s.push_str("<g id=\"plans\">\n");
    for a in &r.adopted {
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#1f77b4" stroke-opacity="0.45" stroke-width="1.2" stroke-dasharray="5 4"/>"##,
            poly(&mut a.path.iter().copied())
        );
    }
    s.push_str("</g>\n<g id=\"tracks\">\n");
    for t in &r.uavs {
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#ff7f0e" stroke-width="1.3" stroke-opacity="0.8"/>"##,
            poly(&mut t.samples.iter().map(|(_, p)| *p))
        );
    }
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#1f4e9c" stroke-width="2.4"/>"##,
        poly(&mut r.ugv.samples.iter().map(|(_, p)| *p))
    );
    s.push_str("</g>\n<g id=\"events\">\n");
    for e in &r.events {
        if matches!(e.kind, EventKind::Replanned { .. }) {
            let (cx, cy) = (x(e.at.x), y(e.at.y));
            let _ = writeln!(
                s,
                r##"<path d="M{:.1},{:.1} l8,8 m0,-8 l-8,8" stroke="#000" stroke-width="2"/>"##,
                cx - 4.0,
                cy - 4.0
            );
        }
    }
    for (p, label) in [(start, "S"), (goal, "T")] {
        let _ = writeln!(
            s,
            r##"<circle cx="{:.2}" cy="{:.2}" r="5" fill="#2ca02c"/><text x="{:.2}" y="{:.2}" font-size="14" font-family="sans-serif">{label}</text>"##,
            x(p.x),
            y(p.y),
            x(p.x) + 7.0,
            y(p.y) - 7.0
        );
    }
    s.push_str("</g>\n");
    // Robots moving along their tracks.
    let mover = |s: &mut String, samples: &[(Real, Point)], colour: &str, radius: Real| {
        if samples.is_empty() {
            return;
        }
        let step = samples.len().div_ceil(KEY_FRAMES).max(1);
        let mut keys: Vec<(Real, Point)> = samples.iter().step_by(step).copied().collect();
        if keys.last() != samples.last() {
            keys.extend(samples.last().copied());
        }
        let total = r.time.max(1e-9);
        if keys.first().is_some_and(|k| k.0 > 0.0) {
            keys.insert(0, (0.0, keys[0].1));
        }
        if keys.last().is_some_and(|k| k.0 < total) {
            let last = keys[keys.len() - 1].1;
            keys.push((total, last));
        }
        let values = keys
            .iter()
            .map(|(_, p)| format!("{:.2},{:.2}", x(p.x), y(p.y)))
            .collect::<Vec<_>>()
            .join(";");
        let times = keys
            .iter()
            .map(|(t, _)| format!("{:.5}", (t / total).clamp(0.0, 1.0)))
            .collect::<Vec<_>>()
            .join(";");
        let _ = writeln!(
            s,
            r##"<circle r="{radius}" fill="{colour}" stroke="#000"><animateMotion dur="{ANIMATION_SECONDS}s" repeatCount="indefinite" calcMode="linear" values="{values}" keyTimes="{times}"/></circle>"##
        );
    };
    s.push_str("<g id=\"robots\">\n");
    for t in &r.uavs {
        mover(&mut s, &t.samples, "#ff7f0e", 5.0);
    }
    mover(&mut s, &r.ugv.samples, "#1f4e9c", 7.0);
    s.push_str("</g>\n");
    let _ = writeln!(
        s,
        r##"<text x="6" y="{:.1}" font-size="13" font-family="sans-serif">{} · policy {} · {} scouts · {} · UGV {:.1} (truth plan {}) · re-plans {} · switches {}  (grey: map; red: not on the map; blue: UGV; orange: scouts; dashed: plans; x: re-plans)</text>"##,
        ph + 25.0,
        xml_escape(&r.world),
        r.policy.name(),
        r.scouts,
        if r.reached { "reached" } else { "NOT reached" },
        r.ugv_distance,
        fmt_opt(r.truth_plan_length),
        r.replans,
        r.switches
    );
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::label;

    #[test]
    fn long_class_names_are_cut_but_told_apart() {
        assert_eq!(label("-1+2"), "-1+2");
        let a: String = (1..=60).map(|i| format!("-{i}")).collect();
        let b = a.replacen("-30", "+30", 1);
        let (la, lb) = (label(&a), label(&b));
        assert!(
            la.starts_with("-1-2-3-4-5-6-7-8-9-1..-57-58-59-60 (60 letters, #"),
            "{la}"
        );
        assert!(la.len() < 70);
        assert_ne!(
            la, lb,
            "names that differ in the middle keep different labels"
        );
    }
}
