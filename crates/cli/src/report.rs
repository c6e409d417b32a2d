//! The plan result of `docs/formats.md` as JSON, and the table `homospline plan`
//! prints.

use std::fmt::Write;

use homospline_geom::Point;
use homospline_optim::Plan;
use serde::Serialize;

#[derive(Serialize)]
struct PlanJson<'a> {
    scene: &'a str,
    seed: &'a str,
    classes: Vec<ClassJson<'a>>,
    best: Option<usize>,
    pareto: &'a [usize],
    timing_ms: TimingJson,
}

#[derive(Serialize)]
struct ClassJson<'a> {
    rank: usize,
    signature: &'a str,
    seed_path: Vec<[f64; 2]>,
    via_points: Vec<[f64; 2]>,
    path: Vec<[f64; 2]>,
    cost: CostJson,
    length: f64,
    min_clearance: f64,
    certified_clearance: f64,
    collision_free: bool,
    in_class: bool,
    iterations: usize,
    evaluations: usize,
    time_ms: f64,
}

#[derive(Serialize)]
struct CostJson {
    total: f64,
    topology: f64,
    roughness: f64,
    length: f64,
    safety: f64,
    max_clearance: f64,
    start_visibility: f64,
    goal_visibility: f64,
    danger: f64,
    critical: f64,
    sheltered: f64,
    passing_time: f64,
}

#[derive(Serialize)]
struct TimingJson {
    voronoi: f64,
    classes: f64,
    optimize: f64,
    total: f64,
}

fn pts(v: &[Point]) -> Vec<[f64; 2]> {
    v.iter().map(|p| [p.x, p.y]).collect()
}

/// JSON cannot hold infinities: a clearance with no obstacle at all is written as a large
/// finite number.
fn finite(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        x.signum() * f64::MAX
    }
}

/// The plan as the JSON of formats.md (plus `pareto`, `certified_clearance`, `in_class` and
/// every cost term).
pub fn plan_json(plan: &Plan) -> String {
    let doc = PlanJson {
        scene: &plan.scene,
        seed: plan.seed.name(),
        classes: plan
            .classes
            .iter()
            .map(|c| ClassJson {
                rank: c.rank,
                signature: &c.signature,
                seed_path: pts(&c.seed_path),
                via_points: pts(&c.via_points),
                path: pts(&c.path),
                cost: CostJson {
                    total: finite(c.cost.total),
                    topology: c.cost.topology,
                    roughness: c.cost.roughness,
                    length: c.cost.length,
                    safety: finite(c.cost.safety),
                    max_clearance: c.cost.max_clearance,
                    start_visibility: c.cost.start_visibility,
                    goal_visibility: c.cost.goal_visibility,
                    danger: c.cost.danger,
                    critical: c.cost.critical,
                    sheltered: c.cost.sheltered,
                    passing_time: c.cost.passing_time,
                },
                length: c.length,
                min_clearance: finite(c.min_clearance),
                certified_clearance: finite(c.certified_clearance),
                collision_free: c.collision_free,
                in_class: c.in_class,
                iterations: c.iterations,
                evaluations: c.evaluations,
                time_ms: c.time_ms,
            })
            .collect(),
        best: plan.best,
        pareto: &plan.pareto,
        timing_ms: TimingJson {
            voronoi: plan.timing.voronoi,
            classes: plan.timing.classes,
            optimize: plan.timing.optimize,
            total: plan.timing.total,
        },
    };
    serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
}

/// A signature cut to `n` characters for the table (the JSON keeps it whole).
fn short(sig: &str, n: usize) -> String {
    if sig.chars().count() <= n {
        sig.to_owned()
    } else {
        format!("{}..", sig.chars().take(n - 2).collect::<String>())
    }
}

/// The table `homospline plan` prints.
pub fn plan_table(plan: &Plan) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "scene {}  seed {}  {} classes  (voronoi {:.1} ms, classes {:.1} ms, optimise {:.1} ms, total {:.1} ms)",
        plan.scene,
        plan.seed.name(),
        plan.classes.len(),
        plan.timing.voronoi,
        plan.timing.classes,
        plan.timing.optimize,
        plan.timing.total
    );
    let _ = writeln!(
        s,
        "{:>4}  {:<14} {:>8} {:>9} {:>11} {:>11} {:>6} {:>6} {:>8}  collision-free",
        "rank", "class", "length", "clearance", "roughness", "cost", "rounds", "evals", "time ms"
    );
    for c in &plan.classes {
        let _ = writeln!(
            s,
            "{:>4}  {:<14} {:>8.2} {:>9.3} {:>11.1} {:>11.2} {:>6} {:>6} {:>8.1}  {}{}",
            c.rank,
            short(&c.signature, 14),
            c.length,
            c.min_clearance,
            c.cost.roughness,
            c.cost.total,
            c.iterations,
            c.evaluations,
            c.time_ms,
            if c.collision_free { "yes" } else { "NO" },
            if plan.pareto.contains(&c.rank) {
                "  pareto"
            } else {
                ""
            }
        );
    }
    match plan.best {
        Some(b) => {
            let c = &plan.classes[b - 1];
            let _ = writeln!(
                s,
                "chosen: rank {b}, class {}, length {:.2}, minimum clearance {:.3}",
                short(&c.signature, 40),
                c.length,
                c.min_clearance
            );
        }
        None => {
            let _ = writeln!(s, "no collision-free class: no plan");
        }
    }
    s
}
