//! What every front end of homospline shares (the command line, the Python package,
//! `xtask`): the typed plan options and their checks ([`options`]), the plan's JSON and
//! tables ([`report`]), a mission's text and JSON ([`mission`]), what `check` says of maps and worlds ([`check`]), the memory check before a grid ([`memory`]), the MovingAI bench sweep
//! ([`bench`](mod@bench)), scene summaries, and reading input files that must be regular files. The
//! pictures and the command line's arguments belong to `homospline-cli`.

pub mod bench;
pub mod check;
pub mod memory;
pub mod mission;
pub mod options;
pub mod report;

pub use options::{Opt, OptionError, OrOff, PlanOptions, Spelling};

use std::fmt::Write;

/// The built-in example `homospline plan` uses without a scene: the paper's Fig. 5 (two
/// concave obstacles with a narrow pass).
pub const EXAMPLE_SCENE: &str = include_str!("../../../fixtures/scenes/narrow-pass.yaml");

use homospline_geom::{Placement, Scene};

/// A note for the obstacles of `scene` too small for its graph's grid at `resolution` (cells
/// per unit): every circle's radius, robot radius included, under `sqrt(2) / 2` cells, so
/// that it may hold no cell's centre. The grid, and so the homotopy classes, may not see
/// them: a pebble in the middle of a corridor left one class where there are two. (The
/// plans themselves are checked against the circles.) `None` when there is none.
pub fn unseen_obstacles(scene: &Scene, resolution: f64) -> Option<String> {
    let cell = 1.0 / resolution;
    let small: Vec<&str> = scene
        .obstacles
        .iter()
        .filter(|o| {
            o.circles
                .iter()
                .all(|c| c.radius + scene.robot_radius < std::f64::consts::FRAC_1_SQRT_2 * cell)
        })
        .map(|o| o.name.as_str())
        .collect();
    (!small.is_empty()).then(|| {
        let shown: Vec<String> = small.iter().take(5).map(|n| format!("'{n}'")).collect();
        format!(
            "note: {} obstacle{} ({}{}) {} smaller than the graph's cells ({} units): the classes may not go round {}; a finer --resolution shows {}",
            small.len(),
            if small.len() == 1 { "" } else { "s" },
            shown.join(", "),
            if small.len() > 5 { ", ..." } else { "" },
            if small.len() == 1 { "is" } else { "are" },
            if (1e-3..1e6).contains(&cell) {
                format!("{cell:.3}")
            } else {
                format!("{cell:.3e}")
            },
            if small.len() == 1 { "it" } else { "them" },
            if small.len() == 1 { "it" } else { "them" },
        )
    })
}

/// A note for each class of `avoid` (as given to the plan) that `plan` left nothing out
/// for: it matched none of the classes the search found (a well-formed id of a class
/// elsewhere, or of none). Empty when every avoided class was found.
///
/// # Examples
///
/// ```
/// use homospline_geom::Scene;
/// use homospline_optim::{PlanConfig, plan};
///
/// let text = std::fs::read_to_string("../../fixtures/scenes/convex.yaml")?;
/// let scene = Scene::from_str(&text, "convex.yaml")?;
/// let avoid = vec!["e".to_owned(), "#00000000".to_owned()];
/// let cfg = PlanConfig { avoid: avoid.clone(), classes: 2, ..PlanConfig::default() };
/// let p = plan(&scene, &cfg)?;
/// let notes = homospline_front::avoid_notes(&avoid, &p);
/// assert_eq!(notes.len(), 1);
/// assert!(notes[0].contains("'#00000000' matched none of the classes"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn avoid_notes(avoid: &[String], plan: &homospline_optim::Plan) -> Vec<String> {
    avoid
        .iter()
        .filter(|a| !plan.avoided.contains(&options::class_as_printed(a)))
        .map(|a| {
            format!(
                "note: --avoid '{a}' matched none of the classes the search found, so it left \
                 nothing out (a class is named by its id or signature as plan prints them)"
            )
        })
        .collect()
}

/// A note for a plan on `scene` with no collision-free class whose best curve crosses three
/// obstacles or more: it says how many the curve crosses, that a dense pass along the
/// class's graph path (pulled taut) did not come out clear either, and what to change. That
/// happens where obstacles are smaller than the graph's cells: the graph's paths pass within
/// a hair of them (10,000 discs of radius 0.05 in 100 x 100 at the default resolution; at
/// `--resolution 10` they plan). `None` when the plan has a collision-free class, or its best
/// curve crosses fewer than 3 obstacles.
pub fn clutter_note(scene: &Scene, plan: &homospline_optim::Plan) -> Option<String> {
    if plan.best.is_some() {
        return None;
    }
    let c = plan.classes.first()?;
    let circles = scene.circles();
    let owners = scene.circle_owners();
    let mut crossed: Vec<usize> = c
        .path
        .windows(2)
        .flat_map(|w| {
            circles.iter().enumerate().filter_map(move |(k, circle)| {
                homospline_geom::query::intersects_segment_circle(&w[0], &w[1], circle).then_some(k)
            })
        })
        .map(|k| owners[k])
        .collect();
    crossed.sort_unstable();
    crossed.dedup();
    let gaps = c.via_points.len().saturating_sub(1).max(1);
    let (n, via_gap) = (crossed.len(), c.length / gaps as f64);
    let name = format!(
        "{} (id {})",
        homospline_homotopy::class_letter(c.rank),
        homospline_homotopy::class_id(&c.signature)
    );
    (n >= 3).then(|| {
        format!(
            "note: the best curve (class {}) crosses {n} obstacles (one every {:.2} units along \
             it) with its {} via-points {:.2} apart, and a dense pass along each class's graph \
             path, pulled taut, did not come out clear either (where obstacles are smaller than \
             the graph's cells, its paths pass within a hair of them). A finer --resolution \
             gives the graph their gaps; or model such clutter coarser: merge nearby small obstacles into fewer, \
             larger ones, or leave out those the robot may brush",
            name,
            c.length / n as f64,
            c.via_points.len().saturating_sub(2),
            via_gap,
        )
    })
}

/// A human summary of a valid scene: what `homospline check` prints.
pub fn summary(scene: &Scene) -> String {
    let set = scene.circle_set();
    let topo = scene.topological_obstacles();
    let circles: usize = scene.obstacles.iter().map(|o| o.circles.len()).sum();
    let clear = |p| set.clearance(p).map_or(f64::INFINITY, |c| c.distance);
    let b = &scene.bounds;
    let mut s = String::new();
    let _ = writeln!(s, "scene      {}", scene.name);
    let _ = writeln!(
        s,
        "bounds     [{}, {}] .. [{}, {}]  ({} x {})",
        b.min.x,
        b.min.y,
        b.max.x,
        b.max.y,
        b.max.x - b.min.x,
        b.max.y - b.min.y
    );
    let _ = writeln!(
        s,
        "start      [{}, {}]  clearance {:.3}",
        scene.start.x,
        scene.start.y,
        clear(&scene.start)
    );
    let _ = writeln!(
        s,
        "goal       [{}, {}]  clearance {:.3}",
        scene.goal.x,
        scene.goal.y,
        clear(&scene.goal)
    );
    let _ = writeln!(s, "robot      radius {}", scene.robot_radius);
    // A group meeting the bounds belongs to the outer wall and one beyond them is not in the
    // free space at all: neither is a hole, though each keeps its ray (a signature stays a
    // homotopy invariant with a ray from any point outside the free space).
    let inflated = scene.circles();
    let places: Vec<Placement> = topo
        .iter()
        .map(|t| b.place_discs(t.circles.iter().map(|&i| &inflated[i])))
        .collect();
    let count = |p| places.iter().filter(|&&q| q == p).count();
    let (holes, on_wall, outside) = (
        count(Placement::Inside),
        count(Placement::OnWall),
        count(Placement::Outside),
    );
    let _ = if on_wall + outside == 0 {
        writeln!(
            s,
            "obstacles  {} listed, {} circles, {} topological (holes in free space)",
            scene.obstacles.len(),
            circles,
            topo.len()
        )
    } else {
        writeln!(
            s,
            "obstacles  {} listed, {} circles, {} topological: {holes} hole{} in free space, \
             {on_wall} meeting the bounds, {outside} beyond them",
            scene.obstacles.len(),
            circles,
            topo.len(),
            if holes == 1 { "" } else { "s" }
        )
    };
    let owners = scene.circle_owners();
    for (k, (t, place)) in topo.iter().zip(&places).enumerate() {
        let (label, why) = match place {
            Placement::Inside => ("hole", ""),
            Placement::OnWall => (
                "group",
                "; meets the bounds: part of the outer wall, not a hole",
            ),
            Placement::Outside => ("group", "; beyond the bounds: not a hole"),
        };
        let mut names: Vec<&str> = t
            .circles
            .iter()
            .map(|&i| scene.obstacles[owners[i]].name.as_str())
            .collect();
        names.dedup();
        let _ = writeln!(
            s,
            "  {label} {k}: {} circle{} from {}; representative [{:.3}, {:.3}]{why}",
            t.circles.len(),
            if t.circles.len() == 1 { "" } else { "s" },
            names.join(", "),
            t.representative.x,
            t.representative.y,
        );
    }
    if !scene.danger_points.is_empty()
        || !scene.critical_points.is_empty()
        || !scene.hazards.is_empty()
    {
        let _ = writeln!(
            s,
            "points     {} danger, {} critical, {} hazards",
            scene.danger_points.len(),
            scene.critical_points.len(),
            scene.hazards.len()
        );
    }
    s
}

/// Reads a whole input file, refusing anything but a regular file: a named pipe blocked the
/// command on open, and a device could be read forever.
pub fn read_regular(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a directory, pipe or device)",
        ));
    }
    std::fs::read(path)
}

/// [`read_regular`] as UTF-8 text.
pub fn read_regular_string(path: &std::path::Path) -> std::io::Result<String> {
    String::from_utf8(read_regular(path)?)
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"))
}
