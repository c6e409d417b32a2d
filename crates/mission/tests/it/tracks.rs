//! The UGV's track keeps the robot's radius from every true obstacle, segment by segment: on
//! the paper-like scene worlds (circles inflated by the robot radius), on a map world with
//! `team.ugv.radius` 1 (exact distance from each track segment to each occupied cell of the
//! true map), and on the fixture map world with a point robot. The track follows the route's
//! certified polyline: a track of one sample per time step cut corners of it (a chord across
//! a corner of the route next to a one-cell door came 0.008 cells into a wall).

use std::path::PathBuf;

use homospline_geom::{Point, Real};
use homospline_maps::OccupancyMap;
use homospline_mission::world::load_any;
use homospline_mission::{
    AnyWorld, MapWorld, MissionConfig, Policy, Team, Uav, Ugv, simulate, simulate_map,
};
use homospline_spline::{CircleModel, ClearanceModel};
use homospline_testkit::{segment_square, track_clearance};

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn cfg(policy: Policy) -> MissionConfig {
    MissionConfig {
        policy,
        ..MissionConfig::default()
    }
}

fn map_cfg(policy: Policy) -> MissionConfig {
    MissionConfig {
        policy,
        ..MissionConfig::for_maps()
    }
}

/// A 40 x 40 map with a wall down the middle and two 6-cell gaps; the truth blocks the lower
/// gap, on the prior's best path.
fn two_gaps(radius: Real) -> (OccupancyMap, OccupancyMap, Team) {
    let n = 40;
    let mut occupied = vec![false; n * n];
    for j in 0..n {
        if !(8..14).contains(&j) && !(26..32).contains(&j) {
            occupied[j * n + 20] = true;
        }
    }
    let prior = OccupancyMap {
        name: "two-gaps".into(),
        width: n,
        height: n,
        cell: 1.0,
        origin: Point::origin(),
        occupied,
        y_down: false,
    };
    let mut truth = prior.clone();
    for j in 8..14 {
        truth.occupied[j * n + 20] = true;
    }
    let team = Team {
        ugv: Ugv {
            speed: 1.0,
            sensor_range: 5.0,
            radius,
        },
        uavs: vec![Uav {
            start: Point::new(3.5, 15.5),
            speed: 3.0,
            sensor_range: 6.0,
        }],
    };
    (prior, truth, team)
}

#[test]
fn the_segment_distance_is_exact_on_known_cases() {
    let (a, b) = (Point::new(-1.0, 0.5), Point::new(3.0, 0.5));
    assert_eq!(
        segment_square(a, b, 1.0, 0.0, 1.0),
        0.0,
        "through the square"
    );
    let (a, b) = (Point::new(0.0, 3.0), Point::new(3.0, 0.0));
    // The line x + y = 3 passes the corner (1, 1) of [0, 1]^2 at sqrt(2) / 2.
    let d = segment_square(a, b, 0.0, 0.0, 1.0);
    assert!((d - 0.5 * 2f64.sqrt()).abs() < 1e-12, "{d}");
    let (a, b) = (Point::new(3.0, 0.5), Point::new(5.0, 0.5));
    assert!((segment_square(a, b, 0.0, 0.0, 1.0) - 2.0).abs() < 1e-12);
}

#[test]
fn a_map_mission_keeps_the_robot_radius_from_the_true_walls() {
    let radius = 1.0;
    let (prior, truth, team) = two_gaps(radius);
    let world = MapWorld::new(
        "two-gaps",
        prior,
        truth.clone(),
        Point::new(3.5, 15.5),
        Point::new(36.5, 15.5),
        team,
    )
    .unwrap();
    for &policy in Policy::all() {
        let r = simulate_map(&world, &map_cfg(policy)).unwrap();
        assert!(r.reached, "{}: not reached", policy.name());
        let track: Vec<Point> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
        let c = track_clearance(&truth, &track, radius + 1.0);
        assert!(
            c >= radius,
            "{}: the track comes {c} from a true wall, less than the radius {radius}",
            policy.name()
        );
        // The truth's blockage was driven around: the track passes the upper gap.
        assert!(
            track.iter().any(|p| p.x > 19.0 && p.x < 22.0 && p.y > 25.0),
            "{}: not through the upper gap",
            policy.name()
        );
    }
}

#[test]
fn a_map_world_refuses_a_start_closer_than_the_radius() {
    let (prior, truth, team) = two_gaps(1.0);
    let e = MapWorld::new(
        "two-gaps",
        prior,
        truth,
        Point::new(19.5, 5.5),
        Point::new(36.5, 15.5),
        team,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("has clearance 0.5000") && e.contains("team.ugv.radius 1"),
        "{e}"
    );
}

#[test]
fn the_fixture_map_world_tracks_stay_out_of_every_true_cell() {
    let w = match load_any(&fixtures().join("worlds/maps/room-blocked.yaml"), |p| {
        std::fs::read(p)
    }) {
        Ok(AnyWorld::Map(w)) => w,
        other => panic!("{:?}", other.err()),
    };
    for &policy in Policy::all() {
        let r = simulate_map(&w, &map_cfg(policy)).unwrap();
        let track: Vec<Point> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
        let c = track_clearance(&w.truth, &track, 1.0);
        assert!(
            c > 0.0,
            "{}: the track touches a true wall ({c})",
            policy.name()
        );
    }
}

#[test]
fn scene_world_tracks_keep_the_robot_radius_from_the_true_circles() {
    let mut worlds = 0;
    for entry in std::fs::read_dir(fixtures().join("worlds")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "yaml") {
            continue;
        }
        let w = match load_any(&path, |p| std::fs::read(p)) {
            Ok(AnyWorld::Scene(w)) => w,
            other => panic!("{}: {:?}", path.display(), other.err()),
        };
        // Circles inflated by the robot radius: a clearance >= 0 keeps the radius.
        let truth = CircleModel::new(w.truth.circles());
        for &policy in Policy::all() {
            let r = simulate(&w, &cfg(policy)).unwrap();
            let track: Vec<Point> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
            let c = truth.polyline_clearance(&track);
            assert!(
                c > 0.0,
                "{} {}: the track comes within {c} of a true obstacle",
                path.display(),
                policy.name()
            );
        }
        worlds += 1;
    }
    assert!(worlds >= 5);
}
