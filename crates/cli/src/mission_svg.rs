//! The animated SVG of a mission (`homospline simulate --svg`): the prior map, what the
//! team discovers, every adopted path and the robots moving along their tracks.

use std::fmt::Write;

use homospline_front::mission::fmt_opt;
use homospline_geom::Bounds;
use homospline_geom::{Point, Real};
use homospline_mission::{EventKind, MapWorld, MissionResult, MissionWorld};

use crate::picture::{View, label_at, text_width};

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

/// The caption's font size.
const CAPTION_FONT: Real = 13.0;
/// A caption line's height.
const CAPTION_LINE: Real = 17.0;

/// Words of `text` in lines no wider than `width` at the caption's font size.
fn wrap(text: &str, width: Real) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), CAPTION_FONT) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

/// The caption: the mission's figures, then the key.
fn caption(r: &MissionResult) -> [String; 2] {
    [
        format!(
            "{} · policy {} · {} scout{} · {} · UGV {:.1} (truth plan {}) · re-plans {} · switches {}",
            r.world,
            r.policy.name(),
            r.scouts,
            if r.scouts == 1 { "" } else { "s" },
            if r.reached { "reached" } else { "NOT reached" },
            r.ugv_distance,
            fmt_opt(r.truth_plan_length),
            r.replans,
            r.switches
        ),
        "grey: map; red: not on the map; blue: UGV; orange: scouts; dashed: plans; x: re-plans"
            .to_owned(),
    ]
}

fn svg_with(
    b: &Bounds,
    y_down: bool,
    ends: (Point, Point),
    r: &MissionResult,
    layers: &mut Layers<'_>,
) -> String {
    let f = View::fit(b, y_down, 800.0);
    let (pw, ph) = (f.w(), f.h());
    let lines: Vec<String> = caption(r).iter().flat_map(|c| wrap(c, pw - 12.0)).collect();
    let total_h = ph + 12.0 + CAPTION_LINE * lines.len() as Real;
    let k = ANIMATION_SECONDS / r.time.max(1e-9);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{pw:.0}" height="{total_h:.0}" viewBox="0 0 {pw:.1} {total_h:.1}">"#,
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
    layers(&mut s, &|v| f.x(v), &|v| f.y(v), f.scale, &when_scaled);
    plans_and_tracks(&mut s, &f, r);
    events_and_ends(&mut s, &f, r, ends);
    robots(&mut s, &f, r);
    s.push_str("<g id=\"legend\">\n");
    for (i, line) in lines.iter().enumerate() {
        let _ = writeln!(
            s,
            r##"<text x="6" y="{:.1}" font-size="{CAPTION_FONT}" font-family="sans-serif">{}</text>"##,
            ph + 6.0 + CAPTION_LINE * (i + 1) as Real,
            xml_escape(line)
        );
    }
    s.push_str("</g>\n</svg>\n");
    s
}

/// Every adopted plan (dashed), the scouts' and the UGV's tracks.
fn plans_and_tracks(s: &mut String, f: &View, r: &MissionResult) {
    s.push_str("<g id=\"plans\">\n");
    for a in &r.adopted {
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#1f77b4" stroke-opacity="0.45" stroke-width="1.2" stroke-dasharray="5 4"/>"##,
            f.points(&mut a.path.iter().copied())
        );
    }
    s.push_str("</g>\n<g id=\"tracks\">\n");
    for t in &r.uavs {
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#ff7f0e" stroke-width="1.3" stroke-opacity="0.8"/>"##,
            f.points(&mut t.samples.iter().map(|(_, p)| *p))
        );
    }
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#1f4e9c" stroke-width="2.4"/>"##,
        f.points(&mut r.ugv.samples.iter().map(|(_, p)| *p))
    );
    s.push_str("</g>\n");
}

/// Re-plan points (x) and the start and goal, their labels kept inside the drawing.
fn events_and_ends(s: &mut String, f: &View, r: &MissionResult, (start, goal): (Point, Point)) {
    s.push_str("<g id=\"events\">\n");
    for e in &r.events {
        if matches!(e.kind, EventKind::Replanned { .. }) {
            let (cx, cy) = (f.x(e.at.x), f.y(e.at.y));
            let _ = writeln!(
                s,
                r##"<path d="M{:.1},{:.1} l8,8 m0,-8 l-8,8" stroke="#000" stroke-width="2"/>"##,
                cx - 4.0,
                cy - 4.0
            );
        }
    }
    s.push_str("</g>\n<g id=\"endpoints\">\n");
    for (p, label) in [(start, "S"), (goal, "T")] {
        let (x, y) = (f.x(p.x), f.y(p.y));
        let (lx, ly) = label_at((x, y), text_width(label, 14.0), 14.0, (f.w(), f.h()));
        let _ = writeln!(
            s,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="5" fill="#2ca02c"/><text x="{lx:.2}" y="{ly:.2}" font-size="14" font-family="sans-serif">{label}</text>"##,
        );
    }
    s.push_str("</g>\n");
}

/// The robots, each drawn at its start and moving along its track (the mission plays in
/// [`ANIMATION_SECONDS`] and repeats); a static view shows them at their start.
fn robots(s: &mut String, f: &View, r: &MissionResult) {
    s.push_str("<g id=\"robots\">\n");
    for t in &r.uavs {
        mover(s, f, r.time, &t.samples, "#ff7f0e", 5.0);
    }
    mover(s, f, r.time, &r.ugv.samples, "#1f4e9c", 7.0);
    s.push_str("</g>\n");
}

/// One robot: a circle at its first sample, moved by offsets from there.
fn mover(
    s: &mut String,
    f: &View,
    time: Real,
    samples: &[(Real, Point)],
    colour: &str,
    radius: Real,
) {
    let Some(&(_, first)) = samples.first() else {
        return;
    };
    let step = samples.len().div_ceil(KEY_FRAMES).max(1);
    let mut keys: Vec<(Real, Point)> = samples.iter().step_by(step).copied().collect();
    if keys.last() != samples.last() {
        keys.extend(samples.last().copied());
    }
    let total = time.max(1e-9);
    if keys.first().is_some_and(|k| k.0 > 0.0) {
        keys.insert(0, (0.0, keys[0].1));
    }
    if keys.last().is_some_and(|k| k.0 < total) {
        let last = keys[keys.len() - 1].1;
        keys.push((total, last));
    }
    let (x0, y0) = (f.x(first.x), f.y(first.y));
    let values = keys
        .iter()
        .map(|(_, p)| format!("{:.2},{:.2}", f.x(p.x) - x0, f.y(p.y) - y0))
        .collect::<Vec<_>>()
        .join(";");
    let times = keys
        .iter()
        .map(|(t, _)| format!("{:.5}", (t / total).clamp(0.0, 1.0)))
        .collect::<Vec<_>>()
        .join(";");
    let _ = writeln!(
        s,
        r##"<circle cx="{x0:.2}" cy="{y0:.2}" r="{radius}" fill="{colour}" stroke="#000"><animateMotion dur="{ANIMATION_SECONDS}s" repeatCount="indefinite" calcMode="linear" values="{values}" keyTimes="{times}"/></circle>"##
    );
}
