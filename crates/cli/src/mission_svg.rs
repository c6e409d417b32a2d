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
pub const ANIMATION_SECONDS: Real = 20.0;

/// At most this many key frames per moving robot.
const KEY_FRAMES: usize = 400;

/// An animated picture of the mission: the prior map (grey), obstacles not on it (red, faint
/// until discovered), mapped obstacles that are gone (fading when discovered), every adopted
/// path (dashed), the UGV's (blue) and the scouts' (orange) tracks, re-plan points, and the
/// robots moving along their tracks (the mission plays in 20 s and repeats). With `at`, a
/// still instead: the mission as it stood `at` seconds in (tracks and plans up to then, the
/// robots where they were, what had been discovered by then drawn as discovered).
pub fn mission_svg(world: &MissionWorld, r: &MissionResult, at: Option<Real>) -> String {
    svg_with(
        &world.prior.bounds,
        false,
        (world.prior.start, world.prior.goal),
        r,
        at,
        &mut |s, x, y, scale, when, still| scene_layers(s, world, (x, y, scale), when, still),
    )
}

/// The same for a map world: the prior map as the raster picture of `plan`'s map SVGs, and
/// the cells that differ in the truth, faint until discovered (red: blocked; green: freed).
pub fn map_mission_svg(world: &MapWorld, r: &MissionResult, at: Option<Real>) -> String {
    let map = &world.prior;
    svg_with(
        &map.bounds(),
        map.y_down,
        (world.start, world.goal),
        r,
        at,
        &mut |s, x, y, scale, when, still| {
            let b = map.bounds();
            let (ya, yb) = (y(b.min.y), y(b.max.y));
            let _ = match crate::picture::occupancy_href(map, map.y_down) {
                Ok(href) => writeln!(
                    s,
                    r#"<g id="map"><image x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" preserveAspectRatio="none" image-rendering="optimizeSpeed" style="image-rendering: pixelated" href="{href}"/></g>"#,
                    x(b.min.x),
                    ya.min(yb),
                    (b.max.x - b.min.x) * scale,
                    (ya - yb).abs(),
                ),
                // Said in the picture rather than left out unseen.
                Err(e) => writeln!(
                    s,
                    r#"<g id="map"><text x="{:.2}" y="{:.2}">the map's cells could not be drawn: {}</text></g>"#,
                    x(b.min.x),
                    ya.min(yb) + 14.0,
                    e.replace('&', "&amp;").replace('<', "&lt;"),
                ),
            };
            s.push_str("<g id=\"hidden\">\n");
            for c in &world.changes {
                let colour = if c.blocked { "#d62728" } else { "#2ca02c" };
                // A box round the change's cells, at least MIN_MARKER pixels a side, so that
                // a one-cell door shows on a map of thousands of cells.
                if let Some(((i0, j0), (i1, j1))) = cell_box(&c.cells) {
                    let (x0, x1) = (
                        x(map.origin.x + i0 as Real * map.cell),
                        x(map.origin.x + (i1 + 1) as Real * map.cell),
                    );
                    let (ya, yb) = (
                        y(map.origin.y + j0 as Real * map.cell),
                        y(map.origin.y + (j1 + 1) as Real * map.cell),
                    );
                    let (w, h) = ((x1 - x0).max(MIN_MARKER), (ya - yb).abs().max(MIN_MARKER));
                    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (ya + yb));
                    let _ = writeln!(
                        s,
                        r#"<rect class="change-box" x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="{colour}" stroke-width="1.5" stroke-dasharray="3 2"/>"#,
                        cx - 0.5 * w - 2.0,
                        cy - 0.5 * h - 2.0,
                        w + 4.0,
                        h + 4.0,
                    );
                }
                for &(i, j) in &c.cells {
                    let (x0, y0) = (
                        map.origin.x + i as Real * map.cell,
                        map.origin.y + j as Real * map.cell,
                    );
                    let (ya, yb) = (y(y0), y(y0 + map.cell));
                    let (opacity, animate) = fade(0.2, 0.9, when(&c.name), still);
                    let _ = writeln!(
                        s,
                        r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{colour}" fill-opacity="{opacity}">{animate}</rect>"#,
                        x(x0),
                        ya.min(yb),
                        map.cell * scale,
                        (ya - yb).abs()
                    );
                }
            }
            s.push_str("</g>\n");
        },
    )
}

/// The picture's x and y of a world coordinate, and its pixels per unit.
type Transform<'a> = (&'a dyn Fn(Real) -> Real, &'a dyn Fn(Real) -> Real, Real);

/// The scene's layers: the map's circles and the hidden ones.
fn scene_layers(
    s: &mut String,
    world: &MissionWorld,
    (x, y, scale): Transform<'_>,
    when: &dyn Fn(&str) -> Option<Real>,
    still: bool,
) {
    let rr = world.prior.robot_radius;
    s.push_str("<g id=\"map\">\n");
    for o in &world.prior.obstacles {
        let gone = world.cleared.contains(&o.name);
        for c in &o.circles {
            let (opacity, animate) = fade(0.85, 0.12, when(&o.name).filter(|_| gone), still);
            let _ = writeln!(
                s,
                r##"<circle cx="{:.2}" cy="{:.2}" r="{:.2}" fill="#666" fill-opacity="{opacity}">{animate}</circle>"##,
                x(c.center.x),
                y(c.center.y),
                (c.radius + rr) * scale
            );
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
            let (opacity, animate) = fade(0.12, 0.85, when(&o.name), still);
            let (cx, cy, r) = (x(c.center.x), y(c.center.y), (c.radius + rr) * scale);
            let _ = writeln!(
                s,
                r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{r:.2}" fill="#d62728" fill-opacity="{opacity}" stroke="#d62728" stroke-dasharray="4 3">{animate}</circle>"##,
            );
            // A blockage smaller than a marker on screen gets a box that shows where.
            if 2.0 * r < MIN_MARKER {
                let side = MIN_MARKER + 4.0;
                let _ = writeln!(
                    s,
                    r##"<rect class="change-box" x="{:.2}" y="{:.2}" width="{side:.2}" height="{side:.2}" fill="none" stroke="#d62728" stroke-width="1.5" stroke-dasharray="3 2"/>"##,
                    cx - 0.5 * side,
                    cy - 0.5 * side,
                );
            }
        }
    }
    s.push_str("</g>\n");
}

/// Layers drawn under the plans and tracks: `(svg, x, y, scale, when an obstacle is
/// discovered, still)`. Animated, `when` gives the animation time of the discovery; in a
/// still, `Some` for what was discovered by the still's time.
type Layers<'a> = dyn FnMut(
        &mut String,
        &dyn Fn(Real) -> Real,
        &dyn Fn(Real) -> Real,
        Real,
        &dyn Fn(&str) -> Option<Real>,
        bool,
    ) + 'a;

/// The smallest side of a marker on screen, pixels: a change of one cell on a map of
/// thousands shows.
pub const MIN_MARKER: Real = 8.0;

/// A shape's opacity and its animation: `from` until its discovery at `when`, then `to`. A
/// still takes the opacity of the moment (`when` is `Some` once discovered) and no animation.
fn fade(from: Real, to: Real, when: Option<Real>, still: bool) -> (Real, String) {
    match (when, still) {
        (Some(_), true) => (to, String::new()),
        (None, _) => (from, String::new()),
        (Some(t), false) => (
            from,
            format!(
                r#"<animate attributeName="fill-opacity" from="{from}" to="{to}" begin="{t:.2}s" dur="0.5s" fill="freeze"/>"#
            ),
        ),
    }
}

/// The least and greatest column and row of `cells`.
fn cell_box(cells: &[(usize, usize)]) -> Option<((usize, usize), (usize, usize))> {
    let (&(i, j), rest) = cells.split_first()?;
    Some(
        rest.iter()
            .fold(((i, j), (i, j)), |((i0, j0), (i1, j1)), &(i, j)| {
                ((i0.min(i), j0.min(j)), (i1.max(i), j1.max(j)))
            }),
    )
}

/// The caption's font size.
const CAPTION_FONT: Real = 13.0;
/// A caption line's height.
const CAPTION_LINE: Real = 17.0;
/// Space between two cells of the caption's table, pixels.
const CELL_GAP: Real = 18.0;

/// The caption's figures as (label, value) cells, and the key's entries.
fn caption(r: &MissionResult, at: Option<Real>) -> (Vec<(String, String)>, Vec<&'static str>) {
    let mut cells = vec![
        ("world".to_owned(), r.world.clone()),
        ("policy".to_owned(), r.policy.name().to_owned()),
        ("scouts".to_owned(), r.scouts.to_string()),
        (
            "goal".to_owned(),
            if r.reached { "reached" } else { "NOT reached" }.to_owned(),
        ),
        ("UGV distance".to_owned(), format!("{:.1}", r.ugv_distance)),
        ("truth plan".to_owned(), fmt_opt(r.truth_plan_length)),
        ("re-plans".to_owned(), r.replans.to_string()),
        ("switches".to_owned(), r.switches.to_string()),
    ];
    if let Some(t) = at {
        cells.insert(0, ("at".to_owned(), format!("{t:.1} s of {:.1} s", r.time)));
    }
    let key = vec![
        "grey: map",
        "red: not on the map (dashed box: where)",
        "green: gone from the map",
        "blue: UGV",
        "orange: scouts",
        "dashed: plans",
        "x: re-plans",
    ];
    (cells, key)
}

/// Lays out units of text (each never split) in rows no wider than `width`: for the cells, a
/// table of equal columns; for the key, entries one after another. Each row's units with
/// their x offsets.
fn rows(units: &[String], width: Real, columns_equal: bool) -> Vec<Vec<(Real, String)>> {
    let widths: Vec<Real> = units.iter().map(|u| text_width(u, CAPTION_FONT)).collect();
    let mut rows: Vec<Vec<(Real, String)>> = Vec::new();
    if columns_equal {
        let column = widths.iter().copied().fold(0.0, Real::max) + CELL_GAP;
        let per_row = ((width / column).floor() as usize).max(1);
        for chunk in units.chunks(per_row) {
            rows.push(
                chunk
                    .iter()
                    .enumerate()
                    .map(|(k, u)| (k as Real * column, u.clone()))
                    .collect(),
            );
        }
    } else {
        let mut x = 0.0;
        for (u, w) in units.iter().zip(&widths) {
            if rows.is_empty() || (x > 0.0 && x + w > width) {
                rows.push(Vec::new());
                x = 0.0;
            }
            if let Some(row) = rows.last_mut() {
                row.push((x, u.clone()));
            }
            x += w + CELL_GAP;
        }
    }
    rows
}

fn svg_with(
    b: &Bounds,
    y_down: bool,
    ends: (Point, Point),
    r: &MissionResult,
    at: Option<Real>,
    layers: &mut Layers<'_>,
) -> String {
    let f = View::fit(b, y_down, 800.0);
    let (pw, ph) = (f.w(), f.h());
    let (cells, key) = caption(r, at);
    let cells: Vec<String> = cells.iter().map(|(l, v)| format!("{l}: {v}")).collect();
    let key: Vec<String> = key.iter().map(|k| (*k).to_owned()).collect();
    let mut lines = rows(&cells, pw - 12.0, true);
    lines.extend(rows(&key, pw - 12.0, false));
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
    let shown = |name: &str| match at {
        Some(t) => when(name).filter(|&d| d <= t),
        None => when(name).map(|d| d * k),
    };
    layers(
        &mut s,
        &|v| f.x(v),
        &|v| f.y(v),
        f.scale,
        &shown,
        at.is_some(),
    );
    let until = at.unwrap_or(Real::INFINITY);
    plans_and_tracks(&mut s, &f, r, until);
    events_and_ends(&mut s, &f, r, ends, until);
    robots(&mut s, &f, r, at);
    s.push_str("<g id=\"legend\">\n");
    for (i, row) in lines.iter().enumerate() {
        for (x, text) in row {
            let _ = writeln!(
                s,
                r##"<text x="{:.1}" y="{:.1}" font-size="{CAPTION_FONT}" font-family="sans-serif">{}</text>"##,
                6.0 + x,
                ph + 6.0 + CAPTION_LINE * (i + 1) as Real,
                xml_escape(text)
            );
        }
    }
    s.push_str("</g>\n</svg>\n");
    s
}

/// The samples of a track up to time `until`, the last one where the robot was then.
fn track_until(samples: &[(Real, Point)], until: Real) -> Vec<Point> {
    let mut pts: Vec<Point> = samples
        .iter()
        .take_while(|(t, _)| *t <= until)
        .map(|(_, p)| *p)
        .collect();
    if let Some(p) = position_at(samples, until)
        && pts.last() != Some(&p)
    {
        pts.push(p);
    }
    pts
}

/// Where a robot was at time `t` (linear between samples; its last sample after them).
fn position_at(samples: &[(Real, Point)], t: Real) -> Option<Point> {
    let k = samples.partition_point(|(s, _)| *s <= t);
    match (k.checked_sub(1).map(|i| samples[i]), samples.get(k)) {
        (Some((t0, p0)), Some(&(t1, p1))) if t1 > t0 => {
            Some(p0 + (p1 - p0) * ((t - t0) / (t1 - t0)).clamp(0.0, 1.0))
        }
        (Some((_, p)), _) => Some(p),
        (None, Some(&(_, p))) => Some(p),
        (None, None) => None,
    }
}

/// Every plan adopted by `until` (dashed), the scouts' and the UGV's tracks up to then.
fn plans_and_tracks(s: &mut String, f: &View, r: &MissionResult, until: Real) {
    s.push_str("<g id=\"plans\">\n");
    for a in r.adopted.iter().filter(|a| a.t <= until) {
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
            f.points(&mut track_until(&t.samples, until).into_iter())
        );
    }
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#1f4e9c" stroke-width="2.4"/>"##,
        f.points(&mut track_until(&r.ugv.samples, until).into_iter())
    );
    s.push_str("</g>\n");
}

/// Re-plan points (x) up to `until`, and the start and goal, their labels kept inside the
/// drawing.
fn events_and_ends(
    s: &mut String,
    f: &View,
    r: &MissionResult,
    (start, goal): (Point, Point),
    until: Real,
) {
    s.push_str("<g id=\"events\">\n");
    for e in r.events.iter().filter(|e| e.t <= until) {
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

/// The robots: animated, each drawn at its start and moving along its track (the mission
/// plays in [`ANIMATION_SECONDS`] and repeats); in a still at `at`, where each was then.
fn robots(s: &mut String, f: &View, r: &MissionResult, at: Option<Real>) {
    s.push_str("<g id=\"robots\">\n");
    let one = |s: &mut String, samples: &[(Real, Point)], colour: &str, radius: Real| match at {
        None => mover(s, f, r.time, samples, colour, radius),
        Some(t) => {
            if let Some(p) = position_at(samples, t) {
                let _ = writeln!(
                    s,
                    r##"<circle cx="{:.2}" cy="{:.2}" r="{radius}" fill="{colour}" stroke="#000"/>"##,
                    f.x(p.x),
                    f.y(p.y)
                );
            }
        }
    };
    for t in &r.uavs {
        one(s, &t.samples, "#ff7f0e", 5.0);
    }
    one(s, &r.ugv.samples, "#1f4e9c", 7.0);
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
