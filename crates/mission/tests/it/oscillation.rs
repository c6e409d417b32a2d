//! Issue 14 at mission level: a world built to tempt switching back and forth between two
//! classes of nearly equal cost. Without hysteresis the UGV switches more than once (the test
//! checks that the world does tempt); with the default hysteresis it switches at most once.
//!
//! How the world was found (bump radius): at 5 each discovery moves a class's cost by more
//! than the 10 % margin, so both runs switch twice, rightly; at 2 to 3.5 the classes never
//! cross; at 4 they crossed by less than the margin, which is the temptation tested here.
//! Once `m(C)` took in every knot, the costs moved and a scan of radii 3.5 to 4.875 in steps
//! of 1/8 gave (voluntary switches without hysteresis / with the default): 1/1, 1/0, 1/0,
//! 2/1, 1/0, 2/2, 2/0, 0/0, 1/1, 2/2, 2/1, 2/0. Where both switch twice (4.125, 4.625) a
//! discovery moves a cost by more than the margin, and the second switch is the hysteresis
//! doing its job; 4.25 tempted (two crossings within the margin) and was the world tested.
//! Once the dm rule held each curve at `dm` from the bumps, and again when the truncation
//! tolerance went from 1e-7 to 1e-6, the tempting world moved. The scan
//! (`scan_for_a_tempting_world` below, ignored: heights of the upper bumps 46 to 51 in steps
//! of 1/2, radii 2.5 to 6.5 in steps of 1/4, 187 worlds) now finds 4 worlds that switch
//! twice without hysteresis and at most once with it, each alone among its neighbours:
//! the temptation is a knife edge by construction (two crossings within the margin), and any
//! change to the cost moves it. Height 47.5 and radius 4.75 (2 without, 1 with the default)
//! was the world tested; 5 others switched twice with the default too, where a discovery
//! moves a cost beyond the margin. When re-plans moved to a coarser graph and two classes it
//! moved once more; the same scan now finds 4 tempting worlds (2/1 at height 46.5 radius
//! 5.75, at 48.5 radius 3.75 and at 50.5 radius 4.5; 2/0 at 49 radius 4) and 5 that switch
//! twice with the default too. Height 49 and radius 4 was the world tested. When the growth
//! loop came to return the best curve of its rounds (not the last), the costs moved again;
//! the scan gave 2/0 at height 47.5 radius 3.5, 49.5 radius 5.75, 50 radii 5, 5.25 and 5.75,
//! and 51 radius 4.25, and 2/1 or 2/2 at 8 others. When the dm rule's target rose by the
//! certification's tolerance (1e-3) they moved once more: 2/0 at 48.5 radius 6.5, 50 radius
//! 5.25 and 51 radius 4.25; 2/1 or 2/2 at 4 others. Height 50 and radius 5.25, 2/0 in both
//! scans, is the world tested.

use homospline_geom::{Bounds, Circle, Obstacle, Point, Scene};
use homospline_mission::{
    EventKind, MissionConfig, MissionResult, MissionWorld, Policy, Team, Uav, Ugv, simulate,
};

fn obstacle(name: &str, circles: &[(f64, f64, f64)]) -> Obstacle {
    Obstacle {
        name: name.into(),
        circles: circles
            .iter()
            .map(|&(x, y, r)| Circle::new(x, y, r))
            .collect(),
    }
}

/// A corridor 10 wide along y = 40 from the start (x 5) to x 60 keeps the UGV's heading on
/// the axis; an island (x 84 to 136, radius 6) then splits the way into an upper and a lower
/// class of nearly equal cost. Each side has two mapped bumps on the island (radius 5.25, at
/// y 50 and 30) that are gone in truth, on alternating sides (upper at x 100 and 120, lower
/// at 110 and 130):
/// each one a scout finds gone makes its side cheaper. One scout (speed 6, range 8) verifies
/// the alternative while the UGV (speed 0.5) is still in the corridor.
fn tempting_world() -> MissionWorld {
    tempting_world_at(5.25, 50.0)
}

fn tempting_world_at(bump: f64, up: f64) -> MissionWorld {
    let mut obstacles = Vec::new();
    for (name, y) in [("wall-up", 48.0), ("wall-down", 32.0)] {
        let circles: Vec<_> = (0..=15).map(|i| (4.0 * i as f64, y, 3.0)).collect();
        obstacles.push(obstacle(name, &circles));
    }
    // Rightmost circle first: the representative (largest radius, lowest index), so the
    // island's ray rises at its far end, past every decision.
    let island: Vec<_> = (0..=8)
        .map(|i| (130.0 - 5.0 * i as f64, 40.0, 6.0))
        .collect();
    obstacles.push(obstacle("island", &island));
    let bumps = [
        ("a1", 100.0, up),
        ("a2", 120.0, up),
        ("b1", 110.0, 80.0 - up),
        ("b2", 130.0, 80.0 - up),
    ];
    for (name, x, y) in bumps {
        obstacles.push(obstacle(name, &[(x, y, bump)]));
    }
    let prior = Scene {
        name: "tempting".into(),
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(190.0, 80.0),
        },
        start: Point::new(5.0, 40.0),
        goal: Point::new(185.0, 40.0),
        robot_radius: 0.0,
        obstacles,
        danger_points: Vec::new(),
        critical_points: Vec::new(),
        hazards: Vec::new(),
    };
    let team = Team {
        ugv: Ugv {
            speed: 0.5,
            sensor_range: 6.0,
            radius: 0.0,
        },
        uavs: vec![Uav {
            start: prior.start,
            speed: 6.0,
            sensor_range: 8.0,
        }],
    };
    let cleared = bumps.iter().map(|b| b.0.to_owned()).collect();
    MissionWorld::new("tempting", prior, Vec::new(), cleared, team).unwrap()
}

/// Class switches on a re-plan that was not forced by a blockage.
fn voluntary_switches(r: &MissionResult) -> usize {
    r.events
        .iter()
        .filter(|e| matches!(e.kind, EventKind::Switched { .. }))
        .filter(|s| {
            r.events
                .iter()
                .any(|e| e.t == s.t && matches!(e.kind, EventKind::Replanned { forced: false, .. }))
        })
        .count()
}

fn run(world: &MissionWorld, switch_margin: f64, min_switch_interval: f64) -> MissionResult {
    let cfg = MissionConfig {
        policy: Policy::ALTERNATIVES,
        switch_margin,
        min_switch_interval,
        ..MissionConfig::default()
    };
    simulate(world, &cfg).unwrap()
}

#[test]
fn a_world_that_tempts_switching_switches_at_most_once_with_the_hysteresis() {
    let w = tempting_world();
    let none = run(&w, 0.0, 0.0);
    assert!(none.reached);
    // The world tempts: without hysteresis the UGV switches back and forth.
    assert!(
        voluntary_switches(&none) > 1,
        "without hysteresis: {} voluntary switches: {:#?}",
        voluntary_switches(&none),
        none.events
    );
    let default = run(&w, 0.1, 10.0);
    assert!(default.reached);
    eprintln!(
        "voluntary switches: {} without hysteresis, {} with the default",
        voluntary_switches(&none),
        voluntary_switches(&default)
    );
    assert!(
        voluntary_switches(&default) <= 1,
        "with the default hysteresis: {} voluntary switches: {:#?}",
        voluntary_switches(&default),
        default.events
    );
}

/// The scan that finds the world: `cargo test --release -p homospline-mission --test
/// oscillation -- --ignored --nocapture` prints, per height of the upper bumps (the lower
/// ones mirrored), the voluntary switches without hysteresis / with the default at bump
/// radii 2.5 to 6.5 in steps of 1/4. Rerun it when the cost or the planner changes.
#[test]
#[ignore]
fn scan_for_a_tempting_world() {
    for k in 0..11 {
        let up = 46.0 + 0.5 * k as f64;
        let mut line = format!("up {up}:");
        for i in 0..=16 {
            let r = 2.5 + 0.25 * i as f64;
            let w = tempting_world_at(r, up);
            let a = voluntary_switches(&run(&w, 0.0, 0.0));
            let b = voluntary_switches(&run(&w, 0.1, 10.0));
            line += &format!(" {a}/{b}");
        }
        eprintln!("{line}");
    }
}
