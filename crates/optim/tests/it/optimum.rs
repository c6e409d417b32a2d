//! No plan beats the geometry: every collision-free class's curve, and its reported path,
//! is at least as long as the exact shortest path that keeps the same clearance, of its own
//! class ([`homospline_homotopy::shortest`]) and so of any class
//! ([`homospline_geom::shortest`]). A certified clearance or a reported length that were
//! too good would break it.

use homospline_geom::shortest::{TangentGraph, shortest_path_length};
use homospline_geom::{Circle, Real, Scene};
use homospline_homotopy::{Rays, shortest_in_class};
use homospline_optim::{PlanConfig, plan};
use homospline_testkit::{fixture_scenes, random_fixture_scenes, world_scene};

fn polyline_length(p: &[homospline_geom::Point]) -> Real {
    p.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

#[test]
fn no_class_is_shorter_than_the_optimum_at_its_clearance() {
    let mut scenes: Vec<Scene> = fixture_scenes();
    scenes.extend(random_fixture_scenes());
    scenes.extend((0..40).map(world_scene));
    let mut checked = 0;
    for scene in &scenes {
        let circles: Vec<Circle> = scene.circle_set().circles().to_vec();
        let rays = Rays::for_scene(scene);
        let p = plan(scene, &PlanConfig::default()).unwrap();
        for c in p.classes.iter().filter(|c| c.collision_free) {
            let at = |clearance: Real| {
                shortest_path_length(&scene.start, &scene.goal, &circles, clearance)
                    .unwrap()
                    .unwrap_or_else(|| {
                        panic!(
                            "{} {}: no path keeps {clearance}, yet the class does",
                            scene.name, c.signature
                        )
                    })
            };
            // The curve: certified to keep `certified_clearance`; its length is a quadrature,
            // exact to far better than 1e-9. One tangent graph at that clearance serves the
            // optimum of any class and of the curve's own.
            let g = TangentGraph::build(&scene.start, &scene.goal, &circles, c.certified_clearance)
                .unwrap()
                .unwrap_or_else(|| panic!("{} {}: an end is too close", scene.name, c.signature));
            let curve_opt = g.shortest().map(|p| p.length).unwrap_or_else(|| {
                panic!(
                    "{} {}: no path keeps {}, yet the class does",
                    scene.name, c.signature, c.certified_clearance
                )
            });
            assert!(
                c.length >= curve_opt * (1.0 - 1e-9),
                "{} {}: curve {} shorter than the optimum {curve_opt} at clearance {}",
                scene.name,
                c.signature,
                c.length,
                c.certified_clearance
            );
            // Its class's optimum is within its length (it is a route of the class).
            let word = rays.signature(&c.path);
            let class_opt =
                shortest_in_class(&g, &rays, |w| *w == word, c.length * (1.0 + 1e-9) + 1e-9)
                    .unwrap_or_else(|e| panic!("{} {}: {e}", scene.name, c.signature));
            let class_opt = class_opt.unwrap_or_else(|| {
                panic!(
                    "{} {}: no path of its class keeping {} is as short as the curve {}",
                    scene.name, c.signature, c.certified_clearance, c.length
                )
            });
            assert!(
                class_opt.length >= curve_opt * (1.0 - 1e-9),
                "{} {}",
                scene.name,
                c.signature
            );
            // The reported path: a polyline whose segments were checked exactly to keep
            // `min_clearance`.
            let path_opt = at(c.min_clearance);
            let path_len = polyline_length(&c.path);
            assert!(
                path_len >= path_opt * (1.0 - 1e-12),
                "{} {}: path {path_len} shorter than the optimum {path_opt} at clearance {}",
                scene.name,
                c.signature,
                c.min_clearance
            );
            // The path's chords cut the curve's corners: never longer than the curve.
            assert!(
                path_len <= c.length * (1.0 + 1e-9),
                "{} {}",
                scene.name,
                c.signature
            );
            checked += 1;
        }
    }
    // Most classes of these scenes are collision-free: the check is not vacuous.
    assert!(checked > 150, "only {checked} classes checked");
}

/// Plans generated world `seed` with the defaults: the chosen class is safe and at most
/// `factor` times the shortest path of any class at `dm`.
fn chosen_is_safe_and_within(seed: u64, factor: Real) {
    let cfg = PlanConfig::default();
    let dm = cfg.growth.cost.dm;
    let scene = world_scene(seed);
    let circles: Vec<Circle> = scene.circle_set().circles().to_vec();
    let p = plan(&scene, &cfg).unwrap();
    let chosen = &p.classes[p.best.unwrap() - 1];
    let opt = shortest_path_length(&scene.start, &scene.goal, &circles, dm)
        .unwrap()
        .unwrap();
    assert!(
        chosen.safe,
        "{}: chosen {} unsafe",
        scene.name, chosen.signature
    );
    assert!(
        chosen.length <= opt * factor,
        "{}: chosen {} of length {} against the optimum {opt} at dm",
        scene.name,
        chosen.signature,
        chosen.length
    );
}

/// A class whose seed is the bare segment `S-T` (its graph path pulled taut) and falls
/// short of `dm` is bent up to it. It once stayed on its seed with no round run, unsafe,
/// and the plan chose a class 24 % longer (worlds 129 and 134), although a curve of that
/// class keeping `dm` is within 0.2 % of the shortest path of any class that keeps `dm`.
/// Checked against that optimum with 1 % to spare, and across the 65 scenes: no class
/// below `dm` is left without a round.
#[test]
fn a_straight_seed_short_of_dm_is_bent_up_to_it() {
    let cfg = PlanConfig::default();
    for seed in [129, 134] {
        chosen_is_safe_and_within(seed, 1.01);
    }
    let mut scenes: Vec<Scene> = fixture_scenes();
    scenes.extend(random_fixture_scenes());
    scenes.extend((0..40).map(world_scene));
    for scene in &scenes {
        for c in &plan(scene, &cfg).unwrap().classes {
            assert!(
                c.safe || c.iterations > 0,
                "{} {}: below dm ({}) with no round run",
                scene.name,
                c.signature,
                c.certified_clearance
            );
        }
    }
}

/// On worlds 77 and 205 a class can keep `dm` through a passage whose grid clearance said it
/// could not: its graph path was a cell short of `dm / 0.9`, the rule aimed it at 0.9 of that,
/// it ended a hair below `dm`, and a safe class 31 and 52 % longer than the optimum at `dm`
/// was chosen. The exact check (`keeps_dm`) gives such a class the target `dm`. The chosen
/// curve now comes within 15 % of the shortest path of any class at `dm` (a few via-points
/// cannot follow the taut path's arcs: 5 and 12 % measured).
#[test]
fn a_class_the_grid_thought_too_narrow_for_dm_keeps_it() {
    for seed in [77, 205] {
        chosen_is_safe_and_within(seed, 1.15);
    }
}
