//! The scout policies: one registry that names each once, `survey` as the default, what
//! the robots have seen (`Coverage`), and `survey`, `verified` and `guard` against flying no
//! scouts on generated worlds.

use homospline_geom::Point;
use homospline_mission::sim::policy::{Coverage, Polyline};
use homospline_mission::{EventKind, MissionConfig, Policy, Robot, simulate};
use homospline_testkit::suite_world;

use crate::mission::run;

#[test]
fn the_registry_names_every_policy_once_and_finds_it_by_name() {
    let all = Policy::all();
    assert!(all.len() >= 4);
    for (i, p) in all.iter().enumerate() {
        assert_eq!(Policy::named(p.name()), Some(*p));
        assert!(!p.summary().is_empty());
        assert!(all[..i].iter().all(|q| q.name() != p.name()), "{p} twice");
        assert!(Policy::names().contains(p.name()));
    }
    assert_eq!(Policy::named("nonesuch"), None);
    assert!(!Policy::NONE.get().flies());
    assert!(Policy::GUARD.get().flies());
}

#[test]
fn survey_is_the_default_of_the_library() {
    assert_eq!(Policy::default(), Policy::SURVEY);
    assert_eq!(MissionConfig::default().policy, Policy::SURVEY);
    assert!(Policy::VERIFIED.get().verifies() && !Policy::VERIFIED.get().holds_at_start());
    assert!(Policy::SURVEY.get().verifies() && Policy::SURVEY.get().holds_at_start());
    assert!(!Policy::GUARD.get().verifies());
}

#[test]
fn a_look_marks_the_cells_its_disc_holds_whole_and_a_route_reports_what_is_unseen() {
    let mut seen = Coverage::new(1.0);
    seen.look(&Point::new(0.5, 0.5), 2.0);
    // The centre's cell and its side neighbours lie whole within 2 (their farthest
    // corners are sqrt(0.5) and sqrt(2.5) from the centre).
    assert!(seen.seen(&Point::new(0.5, 0.5)));
    assert!(seen.seen(&Point::new(1.5, 0.5)));
    assert!(seen.seen(&Point::new(-0.5, 0.5)));
    // A diagonal neighbour's far corner is sqrt(1.5^2 + 1.5^2) = 2.12 away: not whole.
    assert!(!seen.seen(&Point::new(1.5, 1.5)));
    assert!(!seen.seen(&Point::new(5.5, 0.5)));
    let line = Polyline::new(vec![Point::new(0.5, 0.5), Point::new(10.5, 0.5)]);
    let unseen = seen.unseen(&line, 0.0);
    assert_eq!(unseen.len(), 1, "{unseen:?}");
    let (a, b) = unseen[0];
    assert!((1.5..=2.5).contains(&a), "{a}");
    assert!((b - 10.0).abs() < 1e-9, "{b}");
    seen.look(&Point::new(6.0, 0.5), 6.0);
    assert!(seen.unseen(&line, 0.0).is_empty());
}

/// Distance over the truth plan of each policy on the first `n` generated scene worlds.
fn ratios(n: usize, policy: Policy) -> Vec<f64> {
    (0..)
        .filter_map(|seed| suite_world(seed, 2))
        .take(n)
        .map(|w| {
            let r = run(&w, policy);
            assert!(r.reached, "{} {policy}: not reached", w.name);
            r.distance_ratio().expect("a truth plan")
        })
        .collect()
}

#[test]
fn guard_drives_less_than_no_scouts_on_generated_worlds() {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (none, guard) = (ratios(12, Policy::NONE), ratios(12, Policy::GUARD));
    assert!(
        mean(&guard) < mean(&none),
        "guard {:.3} none {:.3}",
        mean(&guard),
        mean(&none)
    );
}

#[test]
fn verified_drives_no_farther_than_no_scouts_on_any_generated_world_and_less_on_average() {
    // The UGV takes in the scouts' finds only where they block its route, and leaves it
    // only for a class seen clear all along that is shorter than driving on: it drives as a
    // UGV without scouts would, or less. (Guard, which acts on every find, drove farther
    // than `none` on one of these, 1.151 against 1.101, when this test was written.)
    no_farther_than_none_and_less_on_average(Policy::VERIFIED);
}

#[test]
fn survey_drives_no_farther_than_no_scouts_on_any_generated_world_and_less_on_average() {
    no_farther_than_none_and_less_on_average(Policy::SURVEY);
}

/// On the first 16 generated worlds, `policy` drives at most 1 % farther than `none` (over
/// the truth plan) on each, and less on average.
fn no_farther_than_none_and_less_on_average(policy: Policy) {
    let (none, ours) = (ratios(16, Policy::NONE), ratios(16, policy));
    for (k, (n, v)) in none.iter().zip(&ours).enumerate() {
        assert!(*v <= 1.01 * n, "world {k}: {policy} {v:.3}, none {n:.3}");
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!(
        mean(&ours) < mean(&none),
        "{policy} {:.3} none {:.3}",
        mean(&ours),
        mean(&none)
    );
}

#[test]
fn survey_sets_off_on_a_shorter_class_when_the_scouts_see_a_pebble_beside_its_route() {
    // world-203-pebbles: a pebble that blocks nothing lies beside the prior's best class. A
    // UGV without scouts (and `verified`, which takes in only what blocks its route) sees it
    // 11 units in, switches and turns back; `survey` learns of it while it waits and sets off
    // on the other class from the start, before it has driven anywhere.
    let w = suite_world(203, 2).expect("world-203");
    assert_eq!(w.name, "world-203-pebbles");
    let none = run(&w, Policy::NONE);
    let survey = run(&w, Policy::SURVEY);
    let (n, s) = (
        none.distance_ratio().expect("a truth plan"),
        survey.distance_ratio().expect("a truth plan"),
    );
    assert!(n > 1.15, "none {n:.3}");
    assert!(s < 1.02, "survey {s:.3}");
    let start = survey.ugv.samples[0].1;
    let switch = survey
        .events
        .iter()
        .find(|e| matches!(e.kind, EventKind::Switched { .. }))
        .expect("survey switches");
    assert!(
        switch.t > 0.0 && (switch.at - start).norm() < 1e-9,
        "{switch:?}"
    );
    assert!(
        !survey
            .events
            .iter()
            .any(|e| e.t <= switch.t
                && matches!(e.kind, EventKind::Discovered { by: Robot::Ugv, .. }))
    );
}

#[test]
fn verified_holds_for_a_blockage_the_scouts_find_and_detours_through_a_class_seen_whole() {
    // Somewhere among the generated worlds a scout finds the UGV's route blocked ahead; the
    // UGV weighs it (a forced re-plan that keeps the class) and holds where it is until it
    // switches, later and at the same point.
    let held = (0..40).filter_map(|seed| suite_world(seed, 2)).any(|w| {
        let r = run(&w, Policy::VERIFIED);
        let ev = &r.events;
        ev.iter().enumerate().any(|(k, e)| {
            matches!(
                &e.kind,
                EventKind::Discovered {
                    by: Robot::Uav(_),
                    ..
                }
            ) && ev[k + 1..]
                .iter()
                .position(|f| matches!(&f.kind, EventKind::Replanned { forced: true, .. }))
                .is_some_and(|j| {
                    let weighed = &ev[k + 1 + j];
                    ev[k + 2 + j..].iter().any(|f| {
                        matches!(f.kind, EventKind::Switched { .. })
                            && f.t > weighed.t
                            && (f.at - weighed.at).norm() < 1e-9
                    })
                })
        })
    });
    assert!(held, "no world where verified held for a detour");
}

#[test]
fn survey_sets_off_once_its_scouts_have_swept_the_route_and_verified_at_once() {
    let w = suite_world(0, 2).expect("a world");
    let set_off = |policy: Policy| {
        let r = run(&w, policy);
        assert!(r.reached, "{policy}");
        let start = r.ugv.samples[0].1;
        r.ugv
            .samples
            .iter()
            .find(|(_, p)| (p - start).norm() > 1e-9)
            .map(|&(t, _)| t)
            .expect("the UGV moves")
    };
    let (verified, survey) = (set_off(Policy::VERIFIED), set_off(Policy::SURVEY));
    // One time step for `verified`; several seconds of sweeping for `survey`.
    assert!(verified <= 0.5, "{verified}");
    assert!(survey >= 2.0, "{survey}");
}

#[test]
fn guard_drives_on_toward_a_blockage_when_replanning_there_is_shorter() {
    // Somewhere among the generated worlds a scout finds the route blocked far ahead and
    // the UGV keeps its class (a forced re-plan that keeps the class, with no switch),
    // re-planning again later without a new discovery.
    let drove_on = (0..40).filter_map(|seed| suite_world(seed, 2)).any(|w| {
        let r = run(&w, Policy::GUARD);
        let ev = &r.events;
        ev.windows(2).enumerate().any(|(k, pair)| {
            matches!(&pair[0].kind, EventKind::Blocked { class: from }
                if matches!(&pair[1].kind, EventKind::Replanned { forced: true, class, .. } if class == from))
                && ev[k + 2..].iter().any(|e| matches!(e.kind, EventKind::Blocked { .. }))
        })
    });
    assert!(
        drove_on,
        "no world where guard drove on toward a blockage found ahead"
    );
}

#[test]
fn the_blockage_prior_is_checked_and_keeps_the_ugv_to_ways_seen() {
    let w = suite_world(0, 2).expect("a world");
    for bad in [-0.1, f64::NAN, 11.0] {
        let cfg = MissionConfig {
            blockage_prior: bad,
            ..MissionConfig::default()
        };
        let e = simulate(&w, &cfg).unwrap_err().to_string();
        assert!(e.starts_with("blockage_prior "), "{e}");
    }
    // Without scouts, over the first 16 generated worlds: the prior drives no farther on
    // average than planning as if the unseen were clear.
    let mean = |prior: f64| {
        let v: Vec<f64> = (0..)
            .filter_map(|seed| suite_world(seed, 2))
            .take(16)
            .map(|w| {
                let cfg = MissionConfig {
                    policy: Policy::NONE,
                    blockage_prior: prior,
                    ..MissionConfig::default()
                };
                simulate(&w, &cfg)
                    .unwrap()
                    .distance_ratio()
                    .expect("reached")
            })
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (clear, prior) = (mean(0.0), mean(0.1));
    assert!(prior <= clear, "prior 0.1: {prior:.4}, none: {clear:.4}");
}

#[test]
fn a_look_stays_cheap_when_sensor_ranges_differ_a_thousandfold() {
    // Cells sized by the least range alone made a UGV seeing 1,000 units mark 16 million
    // cells a look beside a scout seeing 1: the mission did not end.
    let mut w = suite_world(0, 1).expect("a world");
    w.team.ugv.sensor_range = 1000.0;
    w.team.uavs[0].sensor_range = 1.0;
    let t0 = std::time::Instant::now();
    let r = run(&w, Policy::GUARD);
    assert!(r.reached);
    assert!(t0.elapsed().as_secs() < 60, "{:?}", t0.elapsed());
}
