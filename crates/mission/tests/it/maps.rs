//! Missions on occupancy maps (`fixtures/worlds/maps/`): a small map world whose truth blocks
//! the door on the prior's best path reaches the goal under every policy, deterministically,
//! without the UGV's track ever entering a truly occupied cell; the known map is updated
//! locally; a truth map of another size is refused with file, line, field and problem.

use std::path::{Path, PathBuf};

use homospline_geom::{Point, Real};
use homospline_maps::OccupancyMap;
use homospline_mission::world::load_any;
use homospline_mission::{
    AnyWorld, EventKind, MapWorld, MissionConfig, MissionResult, Policy, simulate_map,
};

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn map_world(name: &str) -> MapWorld {
    match load_any(&fixtures().join("worlds/maps").join(name), |p| {
        std::fs::read(p)
    }) {
        Ok(AnyWorld::Map(w)) => w,
        Ok(AnyWorld::Scene(_)) => panic!("{name}: a scene world"),
        Err(e) => panic!("{e}"),
    }
}

fn run(world: &MapWorld, policy: Policy) -> MissionResult {
    simulate_map(
        world,
        &MissionConfig {
            policy,
            ..MissionConfig::for_maps()
        },
    )
    .unwrap()
}

/// Whether the segment `ab` meets the interior of the square `[x0, x0 + s] x [y0, y0 + s]`
/// (Liang-Barsky clipping, strict).
fn segment_enters_square(a: Point, b: Point, x0: Real, y0: Real, s: Real) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0, 1.0);
    for (p, q) in [
        (-d.x, a.x - x0),
        (d.x, x0 + s - a.x),
        (-d.y, a.y - y0),
        (d.y, y0 + s - a.y),
    ] {
        if p == 0.0 {
            if q <= 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = Real::max(t0, r);
            } else {
                t1 = Real::min(t1, r);
            }
        }
    }
    t0 < t1
}

/// The first track segment that enters an occupied cell of `map`, if any.
fn entered_cell(map: &OccupancyMap, track: &[Point]) -> Option<(usize, usize, usize)> {
    for (k, w) in track.windows(2).enumerate() {
        let lo = |v: Real, o: Real| (((v - o) / map.cell).floor().max(0.0)) as usize;
        let (i0, i1) = (
            lo(w[0].x.min(w[1].x), map.origin.x),
            lo(w[0].x.max(w[1].x), map.origin.x),
        );
        let (j0, j1) = (
            lo(w[0].y.min(w[1].y), map.origin.y),
            lo(w[0].y.max(w[1].y), map.origin.y),
        );
        for j in j0..=j1.min(map.height - 1) {
            for i in i0..=i1.min(map.width - 1) {
                if map.occupied[j * map.width + i]
                    && segment_enters_square(
                        w[0],
                        w[1],
                        map.origin.x + i as Real * map.cell,
                        map.origin.y + j as Real * map.cell,
                        map.cell,
                    )
                {
                    return Some((k, i, j));
                }
            }
        }
    }
    None
}

#[test]
fn the_segment_check_sees_a_cell_entered() {
    let mut map = map_world("room-blocked.yaml").truth;
    map.occupied.iter_mut().for_each(|c| *c = false);
    map.occupied[3 * map.width + 3] = true;
    let track = [Point::new(1.5, 1.5), Point::new(5.5, 5.5)];
    assert_eq!(entered_cell(&map, &track), Some((0, 3, 3)));
    assert_eq!(
        entered_cell(&map, &[Point::new(1.5, 1.5), Point::new(1.5, 5.5)]),
        None
    );
}

#[test]
fn a_small_map_world_is_reached_under_every_policy_deterministically_and_safely() {
    let w = map_world("room-blocked.yaml");
    assert_eq!(w.changes.len(), 2, "{:?}", w.changes);
    assert!(w.changes.iter().any(|c| c.blocked && c.cells == [(12, 14)]));
    let truth_plan = run(&w, Policy::NONE).truth_plan_length;
    assert!(truth_plan.is_some(), "the truth has a path");
    for &policy in Policy::all() {
        let r = run(&w, policy);
        assert!(
            r.reached,
            "{}: not reached: {:?}",
            policy.name(),
            r.events.last()
        );
        assert_eq!(r.outcome(), run(&w, policy).outcome(), "{}", policy.name());
        // The blockage on the prior's best path was found and the UGV drove around it, or
        // the UGV had left that class before it came near (the freed cells open a better one
        // at 3 s; with `alternatives` the scout then verifies the new alternative, not the
        // blocked class).
        let seen = r.events.iter().any(|e| {
            matches!(
                &e.kind,
                EventKind::Discovered { obstacle, hidden: true, .. } if obstacle == "blocked-0"
            )
        });
        let left = r
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::Switched { .. }));
        assert!(seen || left, "{}: the blockage was not seen", policy.name());
        assert!(r.adopted.len() >= 2, "{}: no re-plan", policy.name());
        assert!(!r.map_updates.is_empty());
        let track: Vec<Point> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
        assert_eq!(
            entered_cell(&w.truth, &track),
            None,
            "{}: the track enters an occupied cell",
            policy.name()
        );
        // The truth plan is the best-cost plan on the true map, which keeps clear of walls
        // along its whole length: not a lower bound of the distance driven (a re-plan from
        // another position can be shorter). The straight line is one.
        assert!(r.ugv_distance >= (w.goal - w.start).norm());
        assert!(
            r.distance_ratio().is_some_and(|d| d > 0.5),
            "{:?}",
            r.distance_ratio()
        );
    }
}

#[test]
fn the_offline_plan_would_drive_through_the_blocked_door() {
    // Without the truth map's blockage the mission never re-plans: the prior's best path
    // itself goes through the door the truth blocks, so the test world tests something.
    let mut w = map_world("room-blocked.yaml");
    let r = run(&w, Policy::NONE);
    let first = &r.adopted[0].path;
    assert!(entered_cell(&w.truth, first).is_some());
    w.truth = w.prior.clone();
    w.changes.clear();
    let r = run(&w, Policy::AHEAD);
    assert!(r.reached);
    assert_eq!(r.replans, 0);
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("homospline-mission-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn load_error(dir: &Path, world: &str) -> String {
    let p = dir.join("w.yaml");
    std::fs::write(&p, world).unwrap();
    match load_any(&p, |p| std::fs::read(p)) {
        Ok(_) => panic!("accepted: {world}"),
        Err(e) => e,
    }
}

#[test]
fn a_truth_map_of_another_size_is_refused_with_file_line_field_and_problem() {
    let dir = temp_dir("size");
    let prior = fixtures().join("maps/movingai/room-32-32-4.map");
    let other = fixtures().join("maps/movingai/maze-32-32-2.map");
    std::fs::copy(&prior, dir.join("prior.map")).unwrap();
    // 32 x 31: one row fewer.
    let text = std::fs::read_to_string(&other).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    lines[1] = "height 31";
    lines.pop();
    std::fs::write(dir.join("short.map"), lines.join("\n")).unwrap();
    let e = load_error(
        &dir,
        "map: prior.map\ntruth_map: short.map\nstart: [1.5, 1.5]\ngoal: [30.5, 30.5]\n",
    );
    let p = dir.join("w.yaml").display().to_string();
    assert_eq!(
        e,
        format!(
            "{p}:2: truth_map: the truth map (short.map) is 32 x 31 cells; the prior map (prior.map) is 32 x 32: they must be the same size"
        )
    );
    let e = load_error(
        &dir,
        "map: prior.map\nstart: [1.5, 1.5]\ngoal: [30.5, 30.5]\n",
    );
    assert!(e.contains(":1: truth_map: missing"), "{e}");
    let e = load_error(
        &dir,
        "map: prior.map\ntruth_map: prior.map\nstart: [0.5, 0.5]\ngoal: [30.5, 30.5]\n",
    );
    assert!(
        e.contains(":3: start: (0.5, 0.5) is in an occupied cell"),
        "{e}"
    );
    let e = load_error(
        &dir,
        "map: prior.map\ntruth_map: nothing.map\nstart: [1.5, 1.5]\ngoal: [30.5, 30.5]\n",
    );
    assert!(
        e.contains(":2: truth_map: ") && e.contains("cannot read"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A corridor 9 cells wide with one cell blocked on its axis, where the kept graph's only
/// edge runs: closing that edge leaves no class on the kept graph, although the robot can
/// pass beside the blockage. The re-plan must fall back to the graph of the updated map and
/// still reach the goal, safely, with the graph kept in the update record.
#[test]
fn a_blockage_beside_which_the_robot_can_pass_does_not_close_the_corridor() {
    let (w, h) = (60, 11);
    let walls = |extra: Option<(usize, usize)>| {
        homospline_testkit::grid_map("corridor", (w, h), false, |i, j| {
            j == 0 || j == h - 1 || Some((i, j)) == extra
        })
    };
    let world = MapWorld::new(
        "corridor",
        walls(None),
        walls(Some((30, 5))),
        Point::new(2.5, 5.5),
        Point::new(57.5, 5.5),
        homospline_mission::Team::default(),
    )
    .unwrap();
    let r = run(&world, Policy::NONE);
    assert!(r.reached, "not reached");
    assert_eq!(r.map_updates.len(), 1);
    assert!(!r.map_updates[0].graph_rebuilt, "the graph was kept");
    assert!(
        r.events
            .iter()
            .any(|e| matches!(e.kind, EventKind::Replanned { .. }))
    );
    let track: Vec<Point> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
    assert_eq!(entered_cell(&world.truth, &track), None);
}

#[test]
fn a_disc_drives_through_a_diagonal_door_and_keeps_its_radius_from_every_true_cell() {
    // A wall splits a 16 x 10 map: column 7 from the bottom edge up to y = 4, column 9 from
    // y = 5 to the top edge. The only way across is the diagonal door between the corners
    // (8, 4) and (9, 5), 1.414 wide: a disc of radius 0.6 passes (0.707 at its middle), but
    // inflating the map square by square by 0.6 closes it (cell (8, 4) touches cell (7, 3)
    // at a corner). A hidden blockage in the open right-hand room makes it a mission.
    let map = homospline_testkit::diagonal_door_map;
    let radius = 0.6;
    let mut team = homospline_mission::Team::default();
    team.ugv.radius = radius;
    let world = MapWorld::new(
        "diagonal-door",
        map(None),
        map(Some((13, 2))),
        Point::new(3.5, 5.5),
        Point::new(13.5, 6.5),
        team,
    )
    .unwrap();
    for &policy in Policy::all() {
        let r = run(&world, policy);
        assert!(r.reached, "{policy}: not reached: {:?}", r.events.last());
        let track: Vec<Point> = r.ugv.samples.iter().map(|(_, p)| *p).collect();
        let through = track.windows(2).any(|s| {
            homospline_geom::math::distance_point_segment(&Point::new(8.5, 4.5), &s[0], &s[1])
                < 0.75
        });
        assert!(through, "{policy}: the track does not pass the door");
        let least = homospline_testkit::track_clearance(&world.truth, &track, radius + 2.0);
        assert!(
            least > radius,
            "{policy}: the track comes {least:.4} from a true occupied cell, inside the radius {radius}"
        );
    }
}

/// A caller's settings hold on a map world: `simulate_map` had copied the map defaults over
/// them, so any `dm` drove exactly as the profile's.
#[test]
fn a_callers_dm_holds_on_a_map_world() {
    let world = map_world("room-blocked.yaml");
    let with_dm = |dm: f64| {
        let mut cfg = MissionConfig {
            policy: Policy::NONE,
            ..MissionConfig::for_maps()
        };
        cfg.plan.growth.cost.dm = dm;
        simulate_map(&world, &cfg).unwrap()
    };
    let profile = MissionConfig::for_maps().plan.growth.cost.dm;
    let (given, more) = (with_dm(profile), with_dm(4.0 * profile));
    assert_ne!(
        given.adopted[0].path, more.adopted[0].path,
        "a dm four times the profile's plans another curve"
    );
}
