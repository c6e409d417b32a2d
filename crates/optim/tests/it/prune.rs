//! Successive halving of the classes (`PlanConfig::prune`): a plan that stops the classes
//! which cannot win after their first round chooses the same class, with the same curve, as
//! a plan that runs every class to its end; the stopped classes are marked and certified.

use homospline_geom::Scene;
use homospline_optim::planner::DEFAULT_PRUNE;
use homospline_optim::{Plan, PlanConfig, plan};
use homospline_testkit::{fixture_scenes, random_fixture_scenes, scan_scenes};

/// The fixture scenes and the seeded random scenes of `fixtures/random`.
fn scenes() -> Vec<Scene> {
    let mut v = fixture_scenes();
    v.extend(random_fixture_scenes());
    v
}

/// The chosen class's finish is left out (`finish_within`): whether it runs depends on the
/// evaluations spent, which the pruning changes.
fn with_prune(prune: Option<f64>) -> PlanConfig {
    PlanConfig {
        prune,
        finish_within: None,
        ..PlanConfig::default()
    }
}

#[test]
fn pruning_keeps_the_chosen_class_and_its_curve() {
    let mut pruned_classes = 0;
    for scene in scenes() {
        let full = plan(&scene, &with_prune(None)).unwrap();
        let fast = plan(&scene, &with_prune(Some(DEFAULT_PRUNE))).unwrap();
        assert!(full.classes.iter().all(|c| !c.pruned), "{}", scene.name);
        let (a, b) = (full.chosen(), fast.chosen());
        assert_eq!(a.is_some(), b.is_some(), "{}", scene.name);
        if let (Some(a), Some(b)) = (a, b) {
            assert_eq!(a.signature, b.signature, "{}", scene.name);
            assert_eq!(a.via_points, b.via_points, "{}", scene.name);
            assert_eq!(a.path, b.path, "{}", scene.name);
            assert_eq!(a.cost.total, b.cost.total, "{}", scene.name);
            assert!(!b.pruned, "{}", scene.name);
        }
        // The same classes, each run to its end unless stopped; a stopped class ran one
        // round, is certified like every other, and costs at least as much as it would
        // have after every round.
        assert_eq!(full.classes.len(), fast.classes.len(), "{}", scene.name);
        for c in &fast.classes {
            let f = full
                .classes
                .iter()
                .find(|f| f.signature == c.signature)
                .unwrap_or_else(|| panic!("{}: class {} missing", scene.name, c.signature));
            if c.pruned {
                pruned_classes += 1;
                assert_eq!(c.iterations, 1, "{} {}", scene.name, c.signature);
                assert!(c.in_class, "{} {}", scene.name, c.signature);
                assert!(
                    c.cost.total >= f.cost.total * (1.0 - 1e-9),
                    "{} {}: {} below the full run's {}",
                    scene.name,
                    c.signature,
                    c.cost.total,
                    f.cost.total
                );
                let chosen_cost = fast.chosen().map_or(f64::INFINITY, |b| b.cost.total);
                assert!(
                    c.cost.total > DEFAULT_PRUNE * chosen_cost * (1.0 - 1e-5),
                    "{} {}",
                    scene.name,
                    c.signature
                );
            } else {
                assert_eq!(c.path, f.path, "{} {}", scene.name, c.signature);
            }
        }
    }
    // The test means something only if classes were stopped.
    assert!(pruned_classes >= 10, "{pruned_classes} classes pruned");
}

#[test]
fn without_the_dm_rule_nothing_is_pruned() {
    // The reference must be sure to rank in the first group (safe) at the end; with `dm` a
    // penalty only, no class is.
    for scene in fixture_scenes() {
        let p = plan(
            &scene,
            &PlanConfig {
                dm_rule: false,
                ..PlanConfig::default()
            },
        )
        .unwrap();
        assert!(p.classes.iter().all(|c| !c.pruned), "{}", scene.name);
    }
}

#[test]
fn a_ratio_below_one_is_refused() {
    let scene = &fixture_scenes()[0];
    for r in [0.5, f64::NAN, f64::INFINITY] {
        let e = plan(scene, &with_prune(Some(r))).unwrap_err();
        assert!(e.to_string().contains("prune"), "{e}");
    }
}

/// The scan behind the default ratio (run by hand: `cargo test --release -p homospline-optim
/// --test it prune:: -- --ignored --nocapture`, about 3 minutes on 2 cores): on the fixture
/// scenes, the random fixtures and 1000 generated 60 x 60 scenes (the mission worlds'
/// generator), how many plans choose another class or curve than the plan without pruning,
/// at each ratio, how much more the chosen plan then costs (its regret against the full
/// plan's), and the evaluations saved, in all and on the five paper scenes.
/// `SCAN_RATIOS=1.5,2.5` sets the ratios, `SCAN_SCENES=N` the generated scenes (1000); the
/// README's *Decisions* has the table.
#[test]
#[ignore]
fn scan_the_ratio() {
    let all = scan_scenes(1000);
    // `scan_scenes` starts with the fixture scenes: the paper's.
    let paper_scenes = fixture_scenes().len();
    let fulls: Vec<Plan> = all
        .iter()
        .map(|s| plan(s, &with_prune(None)).unwrap())
        .collect();
    let full_evals: usize = fulls.iter().map(Plan::evaluations).sum();
    let ratios: Vec<f64> = std::env::var("SCAN_RATIOS")
        .unwrap_or("1.5,2.0,2.5,3.0,4.0".into())
        .split(',')
        .map(|r| r.parse().expect("a ratio"))
        .collect();
    for ratio in ratios {
        let mut changed = Vec::new();
        let mut regrets = Vec::new();
        let mut saved = 0usize;
        let mut paper = Vec::new();
        for (i, (s, full)) in all.iter().zip(&fulls).enumerate() {
            let fast = plan(s, &with_prune(Some(ratio))).unwrap();
            saved += full.evaluations() - fast.evaluations();
            if i < paper_scenes {
                paper.push(format!(
                    "{} {}/{}",
                    s.name,
                    fast.evaluations(),
                    full.evaluations()
                ));
            }
            let same = match (full.chosen(), fast.chosen()) {
                (Some(a), Some(b)) => {
                    regrets.push(b.cost.total / a.cost.total);
                    a.signature == b.signature && a.path == b.path
                }
                (None, None) => true,
                _ => false,
            };
            if !same {
                changed.push(s.name.clone());
            }
        }
        regrets.sort_by(f64::total_cmp);
        let over = |x: f64| regrets.iter().filter(|&&r| r > x).count();
        println!(
            "ratio {ratio}: {} of {} plans chose otherwise {changed:?}; regret worst {:.4}, {} \
             above 1 %, {} above 5 %; evaluations saved {:.1} %; paper scenes (evaluations, \
             pruned/full) {}",
            changed.len(),
            all.len(),
            regrets.last().copied().unwrap_or(1.0),
            over(1.01),
            over(1.05),
            100.0 * saved as f64 / full_evals as f64,
            paper.join(", ")
        );
    }
}
