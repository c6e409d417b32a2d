//! Fuzz-style property tests of every reader a user's file reaches: world files, MovingAI
//! maps and scenario files, ROS map YAML and images, saved graphs. Arbitrary bytes and
//! mutations of the fixtures (bytes flipped, lines cut, numbers replaced by extreme ones)
//! must give a value or an error, never a panic, and each within a second. Cases per
//! property: `PROPTEST_CASES` (CI: 256).

use std::time::{Duration, Instant};

use homospline_maps::{movingai, ros};
use homospline_mission::WorldFile;
use homospline_voronoi::VoronoiGraph;
use proptest::prelude::*;

use crate::common::mutate;

fn fixture(path: &str) -> Vec<u8> {
    std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../").to_owned() + path).unwrap()
}

/// Runs `read` on `bytes`, which must return within a second (a panic fails the test).
fn bounded(what: &str, read: impl FnOnce()) {
    let t = Instant::now();
    read();
    assert!(
        t.elapsed() < Duration::from_secs(1),
        "{what}: {:?}",
        t.elapsed()
    );
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

proptest! {
    #[test]
    fn every_reader_survives_arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        let t = text(&bytes);
        bounded("world", || { let _ = WorldFile::from_str(&t, "w.yaml"); });
        bounded("map", || { let _ = movingai::read_map(&t, "m.map"); });
        bounded("scen", || { let _ = movingai::read_scen(&t, "m.scen"); });
        bounded("ros yaml", || { let _ = ros::read_yaml(&t, "r.yaml"); });
        bounded("graph", || { let _ = VoronoiGraph::from_msgpack(&bytes); });
    }

    #[test]
    fn every_reader_survives_mutated_fixtures(
        flips in prop::collection::vec((any::<usize>(), 1u8..=255), 0..6),
        cut in (any::<usize>(), any::<usize>()),
        number in any::<usize>(),
    ) {
        let world = mutate(&fixture("fixtures/worlds/maps/room-blocked.yaml"), &flips, cut, number);
        bounded("world", || { let _ = WorldFile::from_str(&text(&world), "w.yaml"); });
        let map = mutate(&fixture("fixtures/maps/movingai/room-32-32-4.map"), &flips, cut, number);
        bounded("map", || { let _ = movingai::read_map(&text(&map), "m.map"); });
        let scen = mutate(&fixture("fixtures/maps/movingai/room-32-32-4-random-1.scen"), &flips, cut, number);
        bounded("scen", || { let _ = movingai::read_scen(&text(&scen), "m.scen"); });
        let yaml = mutate(&fixture("fixtures/maps/ros/turtlebot3_world/map.yaml"), &flips, cut, number);
        bounded("ros", || {
            if let Ok(y) = ros::read_yaml(&text(&yaml), "r.yaml") {
                let pgm = mutate(&fixture("fixtures/maps/ros/turtlebot3_world/map.pgm"), &flips, cut, number);
                let _ = ros::read_map(&y, "r.yaml", &pgm, "r.pgm");
            }
        });
    }
}

/// A saved graph with its bytes mutated: refused or read, and a graph that is read passes
/// its own validation.
#[test]
fn mutated_saved_graphs_are_refused_or_valid() {
    let map = movingai::read_map(
        &text(&fixture("fixtures/maps/movingai/room-32-32-4.map")),
        "room",
    )
    .unwrap();
    let bytes = homospline_maps::PreparedMap::new(&map)
        .unwrap()
        .graph
        .graph
        .to_msgpack();
    let mut rng = homospline_testkit::SplitMix(5);
    for _ in 0..400 {
        let mut b = bytes.clone();
        for _ in 0..3 {
            let k = (rng.next_unit() * b.len() as f64) as usize;
            b[k] ^= 1 + (rng.next_unit() * 254.0) as u8;
        }
        // A graph that reads must also be taken, or refused, by the map it claims to be of.
        bounded("graph", || {
            if let Ok(g) = VoronoiGraph::from_msgpack(&b) {
                let _ = homospline_maps::PreparedMap::with_graph(&map, g, 0.0);
            }
        });
    }
}
