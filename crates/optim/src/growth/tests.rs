//! The growth loop's unit tests: the guard's ranking of candidates short of the target, a
//! round called off, and the shrinking round budget.

use super::*;
use homospline_geom::{Bounds, Real};
use homospline_spline::CostTerms;

#[test]
fn a_candidate_short_of_the_target_ranks_after_every_one_that_keeps_it() {
    let guard = Guard {
        class: None,
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(1.0, 1.0),
        },
        collision_free: true,
        clearance_floor: Real::NEG_INFINITY,
        clearance_target: 3.0,
        proven: Default::default(),
    };
    let at = |m: Real, total: Real| CostTerms {
        min_clearance: m,
        total,
        ..CostTerms::default()
    };
    let keeps = guard.value(&at(3.0, 1e6));
    let short = guard.value(&at(2.999, 1.0));
    let shorter = guard.value(&at(2.5, 1.0));
    assert_eq!(keeps, 1e6);
    assert!(keeps < short && short < shorter && shorter.is_finite());
    // Equally short: the cost decides.
    assert!(guard.value(&at(2.5, 1.0)) < guard.value(&at(2.5, 2.0)));
    assert_eq!(guard.value(&at(0.0, 1.0)), Real::INFINITY);
    let floored = Guard {
        clearance_floor: 2.0,
        ..guard.clone()
    };
    assert_eq!(floored.value(&at(1.9, 1.0)), Real::INFINITY);
    assert_eq!(
        floored.ratchet(1.5).value(&at(1.9, 1.0)),
        guard.value(&at(1.9, 1.0))
    );
}

#[test]
fn a_round_called_off_leaves_the_loop_as_it_was_and_one_not_called_off_is_a_step() {
    use homospline_geom::Circle;
    use homospline_spline::CircleModel;
    use std::cell::Cell;
    let model = CircleModel::new(vec![
        Circle::new(5.0, 0.3, 1.0),
        Circle::new(9.0, -1.0, 0.8),
    ]);
    let seed = [
        Point::new(0.0, 0.0),
        Point::new(3.0, 2.0),
        Point::new(7.0, 2.5),
        Point::new(12.0, 0.0),
    ];
    let guard = Guard {
        class: None,
        bounds: Bounds {
            min: Point::new(-5.0, -10.0),
            max: Point::new(20.0, 10.0),
        },
        collision_free: true,
        clearance_floor: Real::NEG_INFINITY,
        clearance_target: Real::NEG_INFINITY,
        proven: Default::default(),
    };
    let cfg = GrowthConfig::default();
    let mut stepped = Growth::new(&seed, &model, &cfg, &guard).unwrap();
    // Two via-points, three rounds growing one each: 30 x (4 + 6 + 8) evaluations.
    assert_eq!(stepped.budget_left(&cfg), 30 * (4 + 6 + 8));
    let mut unless = stepped.clone();
    let mut called_off = stepped.clone();
    // Never called off: the same rounds, the same result, to the bit.
    loop {
        let more = stepped.step(&model, &cfg, &guard);
        assert_eq!(
            unless.step_unless(&model, &cfg, &guard, &|| false),
            Some(more)
        );
        if !more {
            break;
        }
    }
    assert_eq!(
        stepped.result(&model, &cfg, &guard),
        unless.result(&model, &cfg, &guard)
    );
    assert_eq!(stepped.budget_left(&cfg), 0);
    // Called off after 25 evaluations of its first round: nothing of it is kept, and the
    // round run again afterwards is the first round of an untouched loop.
    let before = called_off.result(&model, &cfg, &guard);
    let asked = Cell::new(0usize);
    let stop = || {
        asked.set(asked.get() + 1);
        asked.get() > 25
    };
    assert_eq!(called_off.step_unless(&model, &cfg, &guard, &stop), None);
    assert!(asked.get() > 25);
    assert_eq!(called_off.result(&model, &cfg, &guard), before);
    while called_off.step(&model, &cfg, &guard) {}
    assert_eq!(
        called_off.result(&model, &cfg, &guard),
        stepped.result(&model, &cfg, &guard)
    );
}

#[test]
fn long_curves_get_a_proportionally_smaller_budget_down_to_the_floor() {
    let cfg = GrowthConfig {
        max_evaluations_per_round: 800,
        budget_segments: 40,
        min_evaluations_per_round: 320,
        ..GrowthConfig::default()
    };
    assert_eq!(cfg.round_budget(10), 800);
    assert_eq!(cfg.round_budget(40), 800);
    assert_eq!(cfg.round_budget(80), 400);
    assert_eq!(cfg.round_budget(100), 320);
    assert_eq!(cfg.round_budget(10_000), 320);
    let off = GrowthConfig {
        max_evaluations_per_round: 800,
        ..GrowthConfig::default()
    };
    assert_eq!(off.round_budget(10_000), 800);
}
