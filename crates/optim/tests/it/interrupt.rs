//! [`PlanConfig::interrupt`]: a plan whose flag another thread raises ends early with
//! `PlanError::Interrupted`, and one whose flag stays down is not touched by it.

use homospline_geom::{Circle, Obstacle, Point, Scene};
use homospline_optim::{PlanConfig, PlanError, plan};

/// A square of 30 x 30 discs: 40 classes take seconds to optimise.
fn lattice() -> Scene {
    let obstacles = (0..30)
        .flat_map(|i| {
            (0..30).map(move |j| Obstacle {
                name: format!("o{i}_{j}"),
                circles: vec![Circle::new(3.0 + i as f64 * 3.1, 3.0 + j as f64 * 3.1, 0.8)],
            })
        })
        .collect();
    homospline_testkit::square_scene(
        "lattice".into(),
        96.0,
        Point::new(1.0, 1.0),
        Point::new(95.0, 95.0),
        obstacles,
    )
}

#[test]
fn a_raised_interrupt_ends_the_plan_early() {
    let scene = lattice();
    let cfg = PlanConfig {
        classes: 40,
        ..PlanConfig::default()
    };
    let flag = cfg.interrupt.clone();
    let raiser = std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_millis(300));
        flag.raise();
        std::time::Instant::now()
    });
    let result = plan(&scene, &cfg);
    let ended = std::time::Instant::now();
    let raised = raiser.join().unwrap();
    assert!(matches!(result, Err(PlanError::Interrupted)), "{result:?}");
    let late = ended.duration_since(raised).as_secs_f64();
    eprintln!("ended {late:.3} s after the interrupt");
    assert!(late < 2.0, "the plan ran {late:.1} s past its interrupt");
}

#[test]
fn an_interrupt_not_raised_changes_nothing() {
    let scene = homospline_testkit::fixture_scenes().remove(0);
    let cfg = PlanConfig::default();
    let a = plan(&scene, &cfg).unwrap();
    let b = plan(&scene, &PlanConfig::default()).unwrap();
    assert_eq!(a.classes.len(), b.classes.len());
    for (x, y) in a.classes.iter().zip(&b.classes) {
        assert_eq!(x.via_points, y.via_points);
    }
}
