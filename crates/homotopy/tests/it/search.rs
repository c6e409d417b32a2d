//! The k-best search against brute-force enumeration of all simple paths, on fixtures and on
//! random scenes; blocked passages; which classes use an edge.

use homospline_testkit::fixture_scenes;
use std::collections::BTreeMap;

use homospline_geom::{Bounds, Circle, Obstacle, Point, Scene};
use homospline_homotopy::{
    EdgeCost, Rays, SearchConfig, Signature, classes_through_edge, in_class, k_best_classes,
};
use homospline_voronoi::VoronoiGraph;
use proptest::prelude::*;

/// A partial path of the enumeration: node, nodes visited, edges walked, cost.
type Walk = (usize, Vec<usize>, Vec<(usize, bool)>, f64);

/// Every simple start-goal path: (cost, signature).
fn brute_force(
    g: &VoronoiGraph,
    rays: &Rays,
    cost: &dyn Fn(usize) -> f64,
    min_clearance: f64,
) -> Vec<(f64, Signature)> {
    let (s, t) = (g.start.unwrap(), g.goal.unwrap());
    let mut out = Vec::new();
    let mut stack: Vec<Walk> = vec![(s, vec![s], vec![], 0.0)];
    while let Some((node, visited, edges, c)) = stack.pop() {
        if node == t {
            let mut poly: Vec<Point> = Vec::new();
            for &(e, fwd) in &edges {
                let mut p: Vec<Point> = g.edges[e]
                    .polyline
                    .iter()
                    .map(|q| Point::new(q[0], q[1]))
                    .collect();
                if !fwd {
                    p.reverse();
                }
                poly.extend(p);
            }
            out.push((c, rays.signature(&poly)));
            continue;
        }
        for (i, e) in g.edges.iter().enumerate() {
            let connector = [e.from, e.to].iter().any(|&n| n == s || n == t);
            if !connector && e.min_clearance < min_clearance {
                continue;
            }
            for (a, b, fwd) in [(e.from, e.to, true), (e.to, e.from, false)] {
                if a == node && !visited.contains(&b) {
                    let mut v = visited.clone();
                    v.push(b);
                    let mut es = edges.clone();
                    es.push((i, fwd));
                    stack.push((b, v, es, c + cost(i)));
                }
            }
        }
    }
    out
}

/// Per class, its cheapest simple path's cost; sorted by cost.
fn best_per_class(all: Vec<(f64, Signature)>) -> Vec<(f64, Signature)> {
    let mut best: BTreeMap<Signature, f64> = BTreeMap::new();
    for (c, s) in all {
        let e = best.entry(s).or_insert(f64::INFINITY);
        *e = e.min(c);
    }
    let mut v: Vec<(f64, Signature)> = best.into_iter().map(|(s, c)| (c, s)).collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

fn check_against_brute_force(
    scene: &Scene,
    resolution: f64,
    cfg: &SearchConfig,
) -> Result<(), TestCaseError> {
    let Ok((_, _, g)) = homospline_voronoi::build(scene, resolution) else {
        return Ok(());
    };
    let rays = Rays::for_scene(scene);
    let cost = |i: usize| match cfg.cost {
        EdgeCost::Length => g.edges[i].length,
        EdgeCost::ClearancePenalty { weight } => {
            g.edges[i].length * (1.0 + weight / g.edges[i].mean_clearance.max(1e-6))
        }
    };
    let expected = best_per_class(brute_force(&g, &rays, &cost, cfg.min_clearance));
    let got = k_best_classes(
        &g,
        &rays,
        &SearchConfig {
            k: usize::MAX,
            ..cfg.clone()
        },
    )
    .unwrap();
    prop_assert!(got.complete);
    prop_assert_eq!(got.classes.len(), expected.len());
    for (c, (ec, _)) in got.classes.iter().zip(&expected) {
        prop_assert!(
            (c.cost - ec).abs() <= 1e-9 * (1.0 + ec),
            "cost {} vs {}",
            c.cost,
            ec
        );
    }
    let mut a: Vec<&Signature> = got.classes.iter().map(|c| &c.signature).collect();
    let mut b: Vec<&Signature> = expected.iter().map(|e| &e.1).collect();
    a.sort();
    b.sort();
    prop_assert_eq!(a, b);
    for c in &got.classes {
        prop_assert!(in_class(&rays, &c.polyline, &c.signature));
        prop_assert_eq!(c.nodes.first(), g.start.as_ref());
        prop_assert_eq!(c.nodes.last(), g.goal.as_ref());
    }
    Ok(())
}

fn random_scene(circles: &[(f64, f64, f64)]) -> Scene {
    Scene {
        name: "random".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(60.0, 40.0),
        },
        start: Point::new(2.0, 20.0),
        goal: Point::new(58.0, 20.0),
        robot_radius: 0.0,
        obstacles: circles
            .iter()
            .enumerate()
            .map(|(i, &(x, y, r))| Obstacle {
                name: format!("o{i}"),
                circles: vec![Circle::new(x, y, r)],
            })
            .collect(),
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn search_equals_brute_force_on_random_scenes(
        circles in prop::collection::vec((8.0..52.0, 5.0..35.0, 1.0..4.0), 0..5),
        penalty in any::<bool>(),
        min_clearance in prop::sample::select(vec![0.0, 2.0]),
    ) {
        let cost = if penalty { EdgeCost::ClearancePenalty { weight: 2.0 } } else { EdgeCost::Length };
        check_against_brute_force(&random_scene(&circles), 1.0, &SearchConfig { cost, min_clearance, ..SearchConfig::default() })?;
    }
}

#[test]
fn every_fixture_yields_min_k_available_distinct_classes() {
    for scene in fixture_scenes() {
        let (_, _, g) = homospline_voronoi::build(&scene, 2.0).unwrap();
        let rays = Rays::for_scene(&scene);
        let all = k_best_classes(
            &g,
            &rays,
            &SearchConfig {
                k: usize::MAX,
                ..SearchConfig::default()
            },
        )
        .unwrap();
        for k in [1, 5, 7] {
            let r = k_best_classes(
                &g,
                &rays,
                &SearchConfig {
                    k,
                    ..SearchConfig::default()
                },
            )
            .unwrap();
            assert_eq!(
                r.classes.len(),
                k.min(all.classes.len()),
                "{} k = {k}",
                scene.name
            );
            let mut sigs: Vec<_> = r.classes.iter().map(|c| c.signature.clone()).collect();
            sigs.sort();
            sigs.dedup();
            assert_eq!(
                sigs.len(),
                r.classes.len(),
                "{}: classes are distinct",
                scene.name
            );
            assert!(
                r.classes.windows(2).all(|w| w[0].cost <= w[1].cost),
                "{}: cheapest first",
                scene.name
            );
        }
        eprintln!("{}: {} classes in all", scene.name, all.classes.len());
    }
}

#[test]
fn fixtures_equal_brute_force() {
    for scene in fixture_scenes() {
        check_against_brute_force(&scene, 1.0, &SearchConfig::default()).unwrap();
    }
}

#[test]
fn blocking_the_edge_of_the_best_class_removes_that_class() {
    let scene = fixture_scenes()
        .into_iter()
        .find(|s| s.name == "two-homotopies")
        .unwrap();
    let (_, _, g) = homospline_voronoi::build(&scene, 2.0).unwrap();
    let rays = Rays::for_scene(&scene);
    let before = k_best_classes(&g, &rays, &SearchConfig::default()).unwrap();
    let best = &before.classes[0];
    // An edge of the best path that is not a start/goal connector.
    let &(edge, _) = best
        .edges
        .iter()
        .find(|&&(e, _)| {
            let ed = &g.edges[e];
            ![ed.from, ed.to]
                .iter()
                .any(|n| Some(*n) == g.start || Some(*n) == g.goal)
        })
        .unwrap();
    let hit = classes_through_edge(&before.classes, edge);
    assert!(hit.contains(&0));
    let after = k_best_classes(
        &g,
        &rays,
        &SearchConfig {
            blocked_edges: vec![edge],
            ..SearchConfig::default()
        },
    )
    .unwrap();
    for c in &after.classes {
        assert!(c.edges.iter().all(|&(e, _)| e != edge));
    }
    // Every class that did not use the edge is still offered, at the same cost.
    for (i, c) in before.classes.iter().enumerate() {
        if !hit.contains(&i) {
            assert!(
                after
                    .classes
                    .iter()
                    .any(|a| a.signature == c.signature && (a.cost - c.cost).abs() < 1e-9)
            );
        }
    }
    // A blocked region over the same edge does the same.
    let mid = g.edges[edge].polyline[g.edges[edge].polyline.len() / 2];
    let region = k_best_classes(
        &g,
        &rays,
        &SearchConfig {
            blocked_regions: vec![(Point::new(mid[0], mid[1]), 0.5)],
            ..SearchConfig::default()
        },
    )
    .unwrap();
    assert!(
        region
            .classes
            .iter()
            .all(|c| c.signature != best.signature || c.cost > best.cost)
    );
}
