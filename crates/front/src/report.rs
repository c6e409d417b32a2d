//! The plan result of `docs/formats.md` as JSON, and the table `homospline plan`
//! prints.

use std::fmt::Write;

use homospline_geom::shortest::TangentGraph;
use homospline_geom::{Point, Scene};
use homospline_homotopy::{Rays, class_id, class_letter, shortest_in_class};
use homospline_optim::Plan;
use homospline_spline::cost::TERMS;
use homospline_spline::{Choice, CostTerms};
use serde::Serialize;

/// How tables, legends and mission events name a class: by its letter (A, B, C... by rank;
/// in a mission, by first appearance), or by its letter and its id ([`class_id`]: the
/// signature when short, else a hash), which `--avoid` takes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ClassNames {
    /// `A`, `B`, `C`...
    #[default]
    Letter,
    /// `A -1-2`, `B #7de0d1cc`...
    Id,
}

impl Choice for ClassNames {
    const ALL: &'static [Self] = &[Self::Letter, Self::Id];
    fn name(self) -> &'static str {
        match self {
            Self::Letter => "letter",
            Self::Id => "id",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Self::Letter => "A, B, C... by rank (the default)",
            Self::Id => {
                "the letter and the class's id (its signature when short, else a hash), as --avoid takes it"
            }
        }
    }
}

impl ClassNames {
    /// The name of the class of rank `rank` (its letter, [`class_letter`]) and `signature`.
    pub fn ranked(self, rank: usize, signature: &str) -> String {
        let letter = class_letter(rank);
        match self {
            Self::Letter => letter,
            Self::Id => format!("{letter} {}", class_id(signature)),
        }
    }
}

#[derive(Serialize)]
struct PlanJson<'a> {
    scene: &'a str,
    seed: &'a str,
    /// What `safe` was judged by, and the floor `best` had to meet.
    dm: f64,
    /// Where `dm` came from when it was not given (a map's default).
    #[serde(skip_serializing_if = "Option::is_none")]
    dm_why: Option<&'a str>,
    clearance_floor: f64,
    classes: Vec<ClassJson<'a>>,
    best: Option<usize>,
    pareto: &'a [usize],
    timing_ms: TimingJson,
}

#[derive(Serialize)]
struct ClassJson<'a> {
    rank: usize,
    letter: String,
    id: String,
    signature: &'a str,
    seed_path: Vec<[f64; 2]>,
    via_points: Vec<[f64; 2]>,
    path: Vec<[f64; 2]>,
    cost: CostJson,
    length: f64,
    min_clearance: f64,
    certified_clearance: f64,
    collision_free: bool,
    safe: bool,
    in_class: bool,
    overlap: f64,
    pruned: bool,
    /// With `plan --optimum`: the shortest path's length at the certified clearance, in the
    /// class and of any class.
    #[serde(skip_serializing_if = "Option::is_none")]
    optimum_length: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    optimum_length_any_class: Option<f64>,
    iterations: usize,
    evaluations: usize,
    time_ms: f64,
}

/// Every cost term by its name in `homospline_spline::cost::TERMS`, after the total.
struct CostJson(CostTerms);

impl Serialize for CostJson {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = ser.serialize_map(Some(TERMS.len() + 1))?;
        m.serialize_entry("total", &finite(self.0.total))?;
        for t in &TERMS {
            m.serialize_entry(t.name, &finite((t.value)(&self.0)))?;
        }
        m.end()
    }
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

/// Decimals beyond the table's usual ones (2 for lengths, 3 for clearances) that a plan's
/// lengths need to show their leading digits: a scene a thousandth of a unit wide printed
/// lengths of `0.00` and clearances of `0.000`. `0` from a longest length of 1 up.
fn extra_digits(plan: &Plan) -> usize {
    let longest = plan
        .classes
        .iter()
        .map(|c| c.length)
        .filter(|l| l.is_finite() && *l > 0.0)
        .fold(0.0, f64::max);
    if longest <= 0.0 || longest >= 1.0 {
        0
    } else {
        ((-longest.log10()).ceil() as usize).min(12)
    }
}

/// Why a class's curve is not collision-free ([`fault`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// Proven clear of every obstacle: it is the bounds that it leaves.
    LeavesBounds,
    /// Clear where sampled, but its certificate does not prove it clear.
    Unproven,
    /// It comes into an obstacle.
    Collides,
}

impl Fault {
    /// The fault in capitals, for a picture's legend.
    pub fn shout(self) -> &'static str {
        match self {
            Self::LeavesBounds => "LEAVES THE BOUNDS",
            Self::Unproven => "NOT PROVEN CLEAR",
            Self::Collides => "COLLIDES",
        }
    }
}

/// What keeps the class's curve from being collision-free; `None` when it is.
pub fn fault(c: &homospline_optim::ClassPlan) -> Option<Fault> {
    if c.collision_free {
        None
    } else if c.min_clearance > 0.0 && c.certified_clearance > 0.0 {
        Some(Fault::LeavesBounds)
    } else if c.min_clearance > 0.0 {
        Some(Fault::Unproven)
    } else {
        Some(Fault::Collides)
    }
}

/// The plan as the JSON of `docs/formats.md` (plus `pareto`, `certified_clearance`, `safe`,
/// `in_class`, `overlap`, `pruned` and every cost term).
pub fn plan_json(plan: &Plan) -> String {
    plan_json_with(plan, &[])
}

/// [`plan_json`] with each class's optima ([`optima`]) as `optimum_length` (its class) and
/// `optimum_length_any_class` where known.
pub fn plan_json_with(plan: &Plan, optima: &[Option<Optimum>]) -> String {
    let doc = PlanJson {
        scene: &plan.scene,
        seed: plan.seed.name(),
        dm: plan.dm,
        dm_why: plan.dm_why.as_deref(),
        clearance_floor: plan.clearance_floor,
        classes: plan
            .classes
            .iter()
            .enumerate()
            .map(|(i, c)| ClassJson {
                rank: c.rank,
                letter: class_letter(c.rank),
                id: class_id(&c.signature),
                signature: &c.signature,
                seed_path: pts(&c.seed_path),
                via_points: pts(&c.via_points),
                path: pts(&c.path),
                cost: CostJson(c.cost),
                length: c.length,
                min_clearance: finite(c.min_clearance),
                certified_clearance: finite(c.certified_clearance),
                collision_free: c.collision_free,
                safe: c.safe,
                in_class: c.in_class,
                overlap: c.overlap,
                pruned: c.pruned,
                optimum_length: optima
                    .get(i)
                    .copied()
                    .flatten()
                    .and_then(|o| o.class.length()),
                optimum_length_any_class: optima.get(i).copied().flatten().and_then(|o| o.any),
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

/// The plan result of a plan that found no route (`plan` exits 1 with `why`): the contract's
/// fields with no class (`classes` empty, `best` null, zero times) and `no_route`, the
/// reason; so that a pipeline reading the file, not the exit code, finds no plan rather
/// than an older file's.
///
/// # Examples
///
/// ```
/// let json = homospline_front::report::no_route_json("field", "voronoi", "no route: ...");
/// let v: serde_json::Value = serde_json::from_str(&json).unwrap();
/// assert!(v["best"].is_null() && v["classes"].as_array().unwrap().is_empty());
/// assert_eq!(v["no_route"], "no route: ...");
/// ```
pub fn no_route_json(scene: &str, seed: &str, why: &str) -> String {
    #[derive(Serialize)]
    struct NoRoute<'a> {
        scene: &'a str,
        seed: &'a str,
        classes: [(); 0],
        best: Option<usize>,
        pareto: [usize; 0],
        timing_ms: TimingJson,
        no_route: &'a str,
    }
    let doc = NoRoute {
        scene,
        seed,
        classes: [],
        best: None,
        pareto: [],
        timing_ms: TimingJson {
            voronoi: 0.0,
            classes: 0.0,
            optimize: 0.0,
            total: 0.0,
        },
        no_route: why,
    };
    serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
}

/// The table `homospline plan` prints, classes named as `names` says.
pub fn plan_table(plan: &Plan, names: ClassNames) -> String {
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
        "{:>4}  {:<12} {:>8} {:>9} {:>11} {:>11} {:>6} {:>6} {:>8}  collision-free  safe",
        "rank", "class", "length", "clearance", "roughness", "cost", "rounds", "evals", "time ms"
    );
    let extra = extra_digits(plan);
    for c in &plan.classes {
        let row = format!(
            "{:>4}  {:<12} {:>8.l$} {:>9.m$} {:>11.1} {:>11.2} {:>6} {:>6} {:>8.1}  {:<14}  {:<4}  {}",
            c.rank,
            names.ranked(c.rank, &c.signature),
            c.length,
            c.min_clearance,
            c.cost.roughness,
            c.cost.total,
            c.iterations,
            c.evaluations,
            c.time_ms,
            if c.collision_free { "yes" } else { "NO" },
            if c.safe { "yes" } else { "no" },
            // One column each; the row is trimmed, so a short one ends without blanks.
            match (plan.pareto.contains(&c.rank), c.pruned) {
                (true, true) => "pareto  pruned",
                (true, false) => "pareto",
                (false, true) => "        pruned",
                (false, false) => "",
            },
            l = 2 + extra,
            m = 3 + extra,
        );
        let _ = writeln!(s, "{}", row.trim_end());
    }
    match plan.best {
        Some(b) => {
            let c = &plan.classes[b - 1];
            // Rounds after the ranking (`--polish`, or the finish within `--finish-within`)
            // are counted in `rounds` beyond `--rounds`: say so.
            let after = c.rounds.iter().filter(|r| r.polish).count();
            let _ = writeln!(
                s,
                "chosen: rank {b}, class {} (id {}), length {:.l$}, minimum clearance {:.m$}{}{}",
                class_letter(b),
                class_id(&c.signature),
                c.length,
                c.min_clearance,
                match (c.safe, &plan.dm_why) {
                    (true, None) => String::new(),
                    (true, Some(why)) => format!(
                        " (safe: keeps dm = {}, {why})",
                        homospline_geom::math::Num(plan.dm)
                    ),
                    (false, why) => format!(
                        " (below dm = {}{}: {})",
                        homospline_geom::math::Num(plan.dm),
                        why.as_ref().map_or(String::new(), |w| format!(", {w}")),
                        // On a map a shorter class can be chosen over one that keeps dm
                        // (no detour for nothing).
                        if plan.classes.iter().any(|o| o.collision_free && o.safe) {
                            "chosen over longer classes that keep it, as no detour for nothing"
                        } else {
                            "no collision-free class keeps it"
                        }
                    ),
                },
                match after {
                    0 => String::new(),
                    n => format!(
                        "; {n} of its {} rounds after the ranking (--polish, or the interior-point finish within --finish-within)",
                        c.iterations
                    ),
                },
                l = 2 + extra,
                m = 3 + extra,
            );
        }
        None => {
            let _ = writeln!(s, "{}", no_plan_line(plan, names));
        }
    }
    s
}

/// The table's last line when no class was chosen: why, naming the class that came
/// closest. The classes were found on the graph, which joins start and goal: a route
/// exists, and the line does not say otherwise.
fn no_plan_line(plan: &Plan, names: ClassNames) -> String {
    let name = |c: &homospline_optim::ClassPlan| {
        format!(
            "{} (id {})",
            names.ranked(c.rank, &c.signature),
            class_id(&c.signature)
        )
    };
    // The floor is met by the certified clearance; a curve is judged by its own.
    let clearest = |free: bool| {
        let key = |c: &homospline_optim::ClassPlan| match free {
            true => c.certified_clearance,
            false => c.min_clearance,
        };
        plan.classes
            .iter()
            .filter(|c| c.collision_free == free && key(c).is_finite())
            .max_by(|a, b| key(a).total_cmp(&key(b)))
    };
    let n = plan.classes.len();
    match (clearest(true), clearest(false)) {
        (Some(c), _) => format!(
            "no collision-free class meets the clearance floor {} (the clearest, class {}, \
             is certified {:.3} clear): no plan",
            homospline_geom::math::Num(plan.clearance_floor),
            name(c),
            c.certified_clearance
        ),
        (None, Some(c)) => format!(
            "no collision-free curve in the {n} class{} found (the closest, class {}, {}): \
             {}; no plan",
            if n == 1 { "" } else { "es" },
            name(c),
            match fault(c) {
                Some(Fault::LeavesBounds) => "leaves the bounds".to_owned(),
                Some(Fault::Unproven) => {
                    let x = c.certified_clearance;
                    format!(
                        "is not proven clear of the obstacles (its certificate: {})",
                        if x.abs() < 1e-3 {
                            format!("{x:.1e}")
                        } else {
                            format!("{x:.3}")
                        }
                    )
                }
                _ => format!("comes {:.3} into an obstacle", -c.min_clearance),
            },
            match plan.seed {
                homospline_optim::Seed::Voronoi => {
                    "the graph joins start and goal, but no smooth curve found keeps clear"
                }
                homospline_optim::Seed::Straight => {
                    "the straight seed tries one class; --seed voronoi tries each class of the graph"
                }
            }
        ),
        (None, None) => "no class found: no plan".to_owned(),
    }
}

/// What `plan --optimum` finds for one collision-free class: the length of the exact shortest
/// path from the scene's start to its goal that keeps the class's certified clearance from
/// every (inflated) circle, in the class of its reported path and of any class (the bounds
/// left out). No curve of that clearance is shorter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Optimum {
    /// The optimum of the class.
    pub class: ClassOptimum,
    /// The optimum of any class.
    pub any: Option<f64>,
}

/// The optimum of a class, as the search found it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClassOptimum {
    /// Its length.
    Found(f64),
    /// None is within the curve's length: the curve or its certificate would be wrong.
    NoneWithin,
    /// The search gave up (too many words within the length: many obstacles).
    GaveUp,
}

impl ClassOptimum {
    fn length(self) -> Option<f64> {
        match self {
            ClassOptimum::Found(l) => Some(l),
            _ => None,
        }
    }
}

/// Each class's [`Optimum`] (`None` for a class that is not collision-free).
pub fn optima(scene: &Scene, plan: &Plan) -> Vec<Option<Optimum>> {
    let circles = scene.circle_set().circles().to_vec();
    let rays = Rays::for_scene(scene);
    plan.classes
        .iter()
        .map(|c| {
            if !c.collision_free {
                return None;
            }
            // The class's curve keeps its certified clearance, so both optima are at most
            // its length: the graph needs only the routes within it.
            let bound = c.length * (1.0 + 1e-9) + 1e-9;
            let g = TangentGraph::build_within(
                &scene.start,
                &scene.goal,
                &circles,
                c.certified_clearance,
                bound,
            )
            .ok()
            .flatten()?;
            let word = rays.signature(&c.path);
            Some(Optimum {
                class: match shortest_in_class(&g, &rays, |w| *w == word, bound) {
                    Ok(Some(p)) => ClassOptimum::Found(p.length),
                    Ok(None) => ClassOptimum::NoneWithin,
                    Err(_) => ClassOptimum::GaveUp,
                },
                any: g.shortest().map(|p| p.length),
            })
        })
        .collect()
}

/// The lines `plan --optimum` adds to the table: each class's length against its optima.
pub fn optimum_table(plan: &Plan, optima: &[Option<Optimum>], names: ClassNames) -> String {
    let mut s = String::from(
        "optimum: the shortest path keeping each class's certified clearance, in its class and of any class (bounds left out)\n",
    );
    let pct = |len: f64, o: f64| 100.0 * (len / o - 1.0);
    for (c, o) in plan.classes.iter().zip(optima) {
        let name = names.ranked(c.rank, &c.signature);
        let _ = match o {
            Some(Optimum {
                class: ClassOptimum::Found(k),
                any,
            }) => writeln!(
                s,
                "  {name:<14} length {:>9.3}  at clearance {:.3}: its class {k:>9.3} (+{:.2} %), any class {:>9.3}",
                c.length,
                c.certified_clearance,
                pct(c.length, *k),
                any.unwrap_or(f64::NAN),
            ),
            Some(Optimum {
                class: ClassOptimum::GaveUp,
                any,
            }) => writeln!(
                s,
                "  {name:<14} length {:>9.3}  at clearance {:.3}: its class not searched to the end (too many words), any class {:>9.3}",
                c.length,
                c.certified_clearance,
                any.unwrap_or(f64::NAN),
            ),
            Some(Optimum {
                class: ClassOptimum::NoneWithin,
                ..
            }) => writeln!(
                s,
                "  {name:<14} CHECK FAILED: no path of its class keeping {:.3} is as short as its length {:.3}",
                c.certified_clearance, c.length
            ),
            None => writeln!(s, "  {name:<14} not collision-free: no optimum"),
        };
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_curve_that_is_not_collision_free_is_told_by_what_it_fails() {
        let scene = Scene::from_str(
            "bounds: {min: [0, 0], max: [20, 10]}\nstart: [1, 5]\ngoal: [19, 5]\n\
             obstacles:\n  - circles: [[10, 5, 2]]\n",
            "t.yaml",
        )
        .unwrap();
        let cfg = homospline_optim::PlanConfig {
            classes: 1,
            ..Default::default()
        };
        let mut plan = homospline_optim::plan(&scene, &cfg).unwrap();
        let c = plan.classes[0].clone();
        assert!(c.collision_free);
        assert_eq!(fault(&c), None);
        let with = |min: f64, certified: f64| homospline_optim::ClassPlan {
            collision_free: false,
            min_clearance: min,
            certified_clearance: certified,
            ..c.clone()
        };
        assert_eq!(fault(&with(2.0, 1.9)), Some(Fault::LeavesBounds));
        assert_eq!(fault(&with(2.0, -1e-10)), Some(Fault::Unproven));
        assert_eq!(fault(&with(-0.5, -0.5)), Some(Fault::Collides));
        assert_eq!(Fault::LeavesBounds.shout(), "LEAVES THE BOUNDS");
        // The no-plan line says the same.
        plan.classes[0] = with(2.0, 1.9);
        plan.best = None;
        let line = no_plan_line(&plan, ClassNames::default());
        assert!(line.contains("leaves the bounds"), "{line}");
        plan.classes[0] = with(-0.5, -0.5);
        let line = no_plan_line(&plan, ClassNames::default());
        assert!(line.contains("comes 0.500 into an obstacle"), "{line}");
    }

    #[test]
    fn a_tiny_scene_s_table_shows_its_lengths_leading_digits() {
        let scene = Scene::from_str(
            "bounds: {min: [0, 0], max: [0.002, 0.001]}\nstart: [0.0001, 0.0005]\n\
             goal: [0.0019, 0.0005]\nobstacles:\n  - circles: [[0.001, 0.0005, 0.0002]]\n",
            "t.yaml",
        )
        .unwrap();
        let cfg = homospline_optim::PlanConfig {
            classes: 1,
            ..Default::default()
        };
        let plan = homospline_optim::plan(&scene, &cfg).unwrap();
        assert_eq!(extra_digits(&plan), 3);
        let table = plan_table(&plan, ClassNames::default());
        let length = plan.classes[0].length;
        assert!(table.contains(&format!("length {length:.5}")), "{table}");
        assert!(!table.contains(" 0.00 "), "{table}");
    }
}
