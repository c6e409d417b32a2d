//! `PlanConfig::check`, the one check of every setting's range: each setting out of its
//! range is named with its value, and the planner refuses it before any work.

use homospline_optim::planner::{ConfigError, Setting};
use homospline_optim::{PlanConfig, PlanError, Seed, plan};

/// The error of `cfg`, which must be refused.
fn refused(cfg: PlanConfig) -> ConfigError {
    cfg.check().expect_err("refused")
}

#[test]
fn every_setting_out_of_range_is_named_with_its_value() {
    let d = PlanConfig::default;
    let cases: Vec<(PlanConfig, Setting, &str)> = vec![
        (
            PlanConfig { classes: 0, ..d() },
            Setting::Classes,
            "classes 0: must be between 1 and 64",
        ),
        (
            PlanConfig { classes: 65, ..d() },
            Setting::Classes,
            "classes 65: must be between 1 and 64",
        ),
        (
            PlanConfig {
                threads: Some(0),
                ..d()
            },
            Setting::Threads,
            "threads 0: must be between 1 and 256",
        ),
        (
            PlanConfig {
                resolution: Some(f64::NAN),
                ..d()
            },
            Setting::Resolution,
            "resolution NaN: must be positive",
        ),
        (
            PlanConfig {
                clearance_floor: -1.0,
                ..d()
            },
            Setting::ClearanceFloor,
            "clearance_floor -1: must be a finite number >= 0",
        ),
        (
            PlanConfig {
                diverse: Some(1.5),
                ..d()
            },
            Setting::Diverse,
            "diverse 1.5: must be a fraction in [0, 1]",
        ),
        (
            PlanConfig {
                prune: Some(0.5),
                ..d()
            },
            Setting::Prune,
            "prune 0.5: expected off or a ratio of at least 1",
        ),
        (
            PlanConfig { polish: 11, ..d() },
            Setting::Polish,
            "polish 11: must be between 0 and 10",
        ),
        (
            PlanConfig {
                seed: Seed::Straight,
                avoid: vec!["-1".into()],
                ..d()
            },
            Setting::Seed,
            "seed: avoid and diverse choose among the Voronoi seed's classes; the straight seed plans one class",
        ),
    ];
    for (cfg, setting, text) in cases {
        let e = refused(cfg);
        assert_eq!((e.setting, e.to_string().as_str()), (setting, text));
    }
    let mut cfg = d();
    cfg.growth.max_rounds = 101;
    assert_eq!(
        refused(cfg.clone()).to_string(),
        "growth.max_rounds 101: must be between 1 and 100"
    );
    cfg.growth.max_rounds = 3;
    cfg.growth.max_via_points = 0;
    assert_eq!(refused(cfg).setting, Setting::MaxViaPoints);
    assert_eq!(d().check(), Ok(()));
}

#[test]
fn the_planner_refuses_a_setting_out_of_range_before_any_work() {
    let scene = homospline_testkit::fixture_scenes().remove(0);
    let cfg = PlanConfig {
        classes: 0,
        ..PlanConfig::default()
    };
    match plan(&scene, &cfg) {
        Err(PlanError::Config(e)) => assert_eq!(e.setting, Setting::Classes),
        other => panic!("{other:?}"),
    }
    // An avoided class must name a class of the scene.
    let cfg = PlanConfig {
        avoid: vec!["-99".into()],
        ..PlanConfig::default()
    };
    match plan(&scene, &cfg) {
        Err(PlanError::Config(e)) => {
            assert_eq!(e.setting, Setting::Avoid);
            assert!(e.to_string().starts_with("avoid '-99': ray 99"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}
