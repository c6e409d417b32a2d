//! The growth loop's unit tests: the guard's ranking of candidates short of the target, its
//! tube, a round called off, and the shrinking round budget.

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
        tube: Default::default(),
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
        tube: Default::default(),
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

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// The guard's answer for a run of candidates, each a random move of the last from a
    /// curve in the class, is the samples' signature and bounds check, whatever the guard's
    /// tube holds; and small moves are decided by the tube (the shortcut is taken).
    #[test]
    fn the_tube_answers_as_the_signature(
        origins in proptest::collection::vec((-20.0..20.0, -15.0..15.0), 1..8),
        moves in proptest::collection::vec(
            (0usize..3, -1.0..1.0f64, -1.0..1.0f64, 0.0..6.0f64), 1..40),
    ) {
        use homospline_homotopy::Rays;
        use homospline_spline::{EndCondition, Parametrization, Spline};
        let origins: Vec<Point> = origins.iter().map(|&(x, y)| Point::new(x, y)).collect();
        let rays = Rays::new(origins);
        let bounds = Bounds { min: Point::new(-30.0, -20.0), max: Point::new(30.0, 20.0) };
        let mut pts = vec![
            Point::new(-25.0, 0.0),
            Point::new(-8.0, 16.0),
            Point::new(0.0, 17.0),
            Point::new(8.0, 16.0),
            Point::new(25.0, 0.0),
        ];
        let build = |p: &[Point]| Spline::new(p, Parametrization::Uniform, EndCondition::Natural).unwrap();
        let samples = |sp: &Spline| sp.sample_uniform(sp.segments() * 8);
        let sig = rays.signature(&samples(&build(&pts)));
        let guard = Guard {
            class: Some((&rays, &sig)),
            bounds,
            collision_free: true,
            clearance_floor: Real::NEG_INFINITY,
            clearance_target: Real::NEG_INFINITY,
            proven: Default::default(),
            tube: Default::default(),
        };
        for (k, dx, dy, size) in moves {
            pts[k + 1] += homospline_geom::Vector::new(dx, dy) * size;
            let sp = build(&pts);
            let s = samples(&sp);
            let in_class = rays.signature(&s) == sig;
            let expected = s.iter().all(|p| bounds.contains(p)) && in_class;
            let tubed = guard::in_tube_for_test(&sp, &guard, sp.segments() * 8);
            proptest::prop_assert_eq!(admissible(&sp, &guard, 8), expected);
            if tubed {
                proptest::prop_assert!(in_class);
            }
        }
        // A tiny move of a curve just proven in the class is decided by the tube.
        let sp = build(&pts);
        if admissible(&sp, &guard, 8) {
            pts[2] += homospline_geom::Vector::new(1e-9, 0.0);
            let moved = build(&pts);
            proptest::prop_assert!(guard::in_tube_for_test(&moved, &guard, moved.segments() * 8));
            proptest::prop_assert!(admissible(&moved, &guard, 8));
        }
    }
}

/// A review's two counterexamples to the shortcuts of `admissible`, which must answer as the
/// samples do: a curve whose last sample rounds past the bounds' edge (its goal on the edge)
/// while its Bezier boxes are inside; and a candidate whose last sample rounds to the other
/// side of a ray's line through the goal than the tube curve's.
#[test]
fn the_shortcuts_answer_as_the_samples_where_rounding_decides() {
    use homospline_homotopy::Rays;
    use homospline_spline::{EndCondition, Parametrization, Spline};
    let build =
        |p: &[Point]| Spline::new(p, Parametrization::Uniform, EndCondition::Natural).unwrap();
    let by_samples = |sp: &Spline, bounds: &Bounds, class: Option<(&Rays, &_)>| {
        let s = sp.sample_uniform(sp.segments() * 8);
        s.iter().all(|p| bounds.contains(p))
            && class.is_none_or(|(rays, sig): (&Rays, &homospline_homotopy::Signature)| {
                &rays.signature(&s) == sig
            })
    };
    // The goal on the bounds' edge.
    let bounds = Bounds {
        min: Point::new(0.0, 0.0),
        max: Point::new(40.0, 20.0),
    };
    let edge = build(&[
        Point::new(2.0, 10.0),
        Point::new(28.945755071768232, 5.808958725325004),
        Point::new(23.2893731860062, 4.309975630763914),
        Point::new(15.244915412299763, 3.8160246481160023),
        Point::new(40.0, 12.25),
    ]);
    let open = Guard {
        class: None,
        bounds,
        collision_free: true,
        clearance_floor: Real::NEG_INFINITY,
        clearance_target: Real::NEG_INFINITY,
        proven: Default::default(),
        tube: Default::default(),
    };
    assert_eq!(
        admissible(&edge, &open, 8),
        by_samples(&edge, &bounds, None)
    );
    // The goal on a ray's line: the tube curve, then a candidate close to it.
    let rays = Rays::new(vec![Point::new(20.0, 2.0)]);
    let goal = Point::new(20.0, 2.0) + rays.direction() * 15.0;
    let wide = Bounds {
        min: Point::new(-100.0, -100.0),
        max: Point::new(100.0, 100.0),
    };
    let through = |v: [(Real, Real); 3]| {
        let mut p = vec![Point::new(2.0, 10.0)];
        p.extend(v.iter().map(|&(x, y)| Point::new(x, y)));
        p.push(goal);
        build(&p)
    };
    let tube = through([
        (13.548544783240848, 5.824289033636886),
        (30.617862435174043, 17.86801577775511),
        (7.656288327341107, 15.406827556469784),
    ]);
    let candidate = through([
        (13.548723859586156, 5.824987502887981),
        (30.618274652680405, 17.867478193980556),
        (7.6555427932918505, 15.407739176347524),
    ]);
    let sig = rays.signature(&tube.sample_uniform(tube.segments() * 8));
    let guard = Guard {
        class: Some((&rays, &sig)),
        bounds: wide,
        ..open.clone()
    };
    assert!(admissible(&tube, &guard, 8));
    assert_eq!(
        admissible(&candidate, &guard, 8),
        by_samples(&candidate, &wide, Some((&rays, &sig)))
    );
}
