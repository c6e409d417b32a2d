//! `homospline simulate`: a team's mission in a world file, its events and figures, its JSON
//! and its animated picture.

use homospline_front::mission;
use homospline_front::{OptionError, Spelling};
use homospline_geom::math::Num;
use homospline_mission::{AnyWorld, MissionConfig};
use homospline_optim::PlanConfig;

use crate::args::SimulateArgs;
use std::path::PathBuf;

use crate::input::{Reads, refused_input};
use crate::mission_svg;
use crate::out::{bad, check_outputs, write};

/// `simulate`: exit 0 when the UGV reaches the goal, 1 when not.
pub fn simulate(a: SimulateArgs) -> anyhow::Result<u8> {
    let reads = Reads::default();
    let world = homospline_mission::world::load_any(&a.world, |p| reads.read(p))
        .map_err(|e| refused_input(&a.world, e, true))?;
    // The world and the maps it names: none of them is overwritten.
    let inputs = reads.paths();
    check_outputs(
        &inputs.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
        &[
            ("--json", "mission JSON", a.json.as_deref()),
            ("--svg", "picture", a.svg.as_deref()),
            ("--png", "PNG picture", a.png.as_deref()),
        ],
    )?;
    let done = run(&a, &world, (a.svg.is_some(), a.png.is_some()))?;
    if done.result.dt < done.dt {
        say!(
            "time step {} s: --dt {} refined so that no robot travels more than half its sensor range between two looks",
            done.result.dt,
            done.dt
        );
    }
    say_raw!("{}", done.text);
    if let Some(p) = &a.json {
        write(p, "mission JSON", done.json.as_bytes())?;
    }
    if let (Some(p), Some(svg)) = (&a.svg, done.svg) {
        write(p, "picture", svg.as_bytes())?;
        say!("picture: {}", p.display());
    }
    if let (Some(p), Some(png)) = (&a.png, done.png) {
        crate::png::write_png(p, "PNG picture", &png)?;
    }
    Ok(if done.result.reached { 0 } else { 1 })
}

/// What `simulate` computes before it prints or writes anything; `homospline serve`
/// answers with it.
pub struct Mission {
    /// The mission.
    pub result: homospline_mission::MissionResult,
    /// The time step asked for (the result's may be finer).
    pub dt: f64,
    /// The events and figures as printed.
    pub text: String,
    /// The mission JSON.
    pub json: String,
    /// The picture (animated, or a still at `--svg-at`), when asked for.
    pub svg: Option<String>,
    /// The PNG's picture (a still), when asked for.
    pub png: Option<String>,
}

/// Checks the options and runs the mission in `world`, drawing the pictures `wants` (SVG,
/// PNG) asks for.
pub fn run(a: &SimulateArgs, world: &AnyWorld, wants: (bool, bool)) -> anyhow::Result<Mission> {
    if let Some(t) = a.svg_at
        && !(t.is_finite() && t >= 0.0)
    {
        return Err(bad(format!(
            "--svg-at {}: must be a time in seconds, >= 0",
            Num(t)
        )));
    }
    if let Some(t) = a.svg_at
        && wants == (false, false)
    {
        return Err(bad(format!(
            "--svg-at {}: draws the picture of --svg or --png, and neither is asked for",
            Num(t)
        )));
    }
    // The profile of the world's kind; the options go on top.
    let base = match world {
        AnyWorld::Scene(_) => MissionConfig::default(),
        AnyWorld::Map(_) => MissionConfig::for_maps(),
    };
    let cfg = MissionConfig {
        plan: PlanConfig {
            classes: a.classes,
            diverse: a.diverse,
            ..base.plan.clone()
        },
        policy: a.policy.unwrap_or_default(),
        scouts: a.scouts,
        dt: a.dt,
        switch_margin: a.switch_margin,
        min_switch_interval: a.min_switch_interval,
        blockage_prior: a.blockage_prior,
        ..base
    };
    // Every value's one check, spelled as the command line's options.
    cfg.check()
        .map_err(|e| bad(OptionError::from(e).spelled(Spelling::Flag)))?;
    let failed = |e: homospline_mission::MissionError| bad(format!("{}: {e}", a.world.display()));
    let (result, text, json, (svg, png)) = match world {
        AnyWorld::Scene(w) => {
            let r = homospline_mission::simulate(w, &cfg).map_err(failed)?;
            let (t, j) = (
                mission::mission_text(w, &r, a.class_names),
                mission::mission_json(w, &r),
            );
            let svg = pictures(a, wants, r.time, |at| mission_svg::mission_svg(w, &r, at));
            (r, t, j, svg)
        }
        AnyWorld::Map(w) => {
            let r = homospline_mission::simulate_map(w, &cfg).map_err(failed)?;
            let (t, j) = (
                mission::map_mission_text(w, &r, a.class_names),
                mission::map_mission_json(w, &r),
            );
            let svg = pictures(a, wants, r.time, |at| {
                mission_svg::map_mission_svg(w, &r, at)
            });
            (r, t, j, svg)
        }
    };
    Ok(Mission {
        result,
        dt: cfg.dt,
        text,
        json,
        svg,
        png,
    })
}

/// The pictures asked for: the SVG (animated, or a still at `--svg-at`) and the PNG's SVG
/// (a still at `--svg-at`, else at the mission's end `time`).
fn pictures(
    a: &SimulateArgs,
    (wants_svg, wants_png): (bool, bool),
    time: f64,
    draw: impl Fn(Option<f64>) -> String,
) -> (Option<String>, Option<String>) {
    let svg = wants_svg.then(|| draw(a.svg_at));
    let png = wants_png.then(|| match (&svg, a.svg_at) {
        (Some(s), Some(_)) => s.clone(),
        _ => draw(Some(a.svg_at.unwrap_or(time))),
    });
    (svg, png)
}
