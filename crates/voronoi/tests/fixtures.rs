//! The graph of every fixture scene: its cycles, its attachments, its serialisation.

use std::path::Path;

use homospline_geom::Scene;
use homospline_voronoi::{VoronoiGraph, build};

fn scenes() -> Vec<Scene> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| Scene::from_bytes(&std::fs::read(p).unwrap(), &p.display().to_string()).unwrap())
        .collect()
}

#[test]
fn every_fixture_has_one_cycle_per_obstacle() {
    for scene in scenes() {
        for resolution in [1.0, 2.0, 4.0] {
            let (_, _, g) =
                build(&scene, resolution).unwrap_or_else(|e| panic!("{}: {e}", scene.name));
            let holes = scene.topological_obstacles().len();
            eprintln!(
                "{} @ {resolution}: {} nodes, {} edges, {} cycles, {} obstacles ({} grid)",
                scene.name,
                g.nodes.len(),
                g.edges.len(),
                g.cycle_rank(),
                holes,
                g.obstacles.len()
            );
            assert_eq!(
                g.obstacles.len(),
                holes,
                "{} @ {resolution}: grid obstacles",
                scene.name
            );
            assert_eq!(
                g.cycle_rank(),
                holes,
                "{} @ {resolution}: cycles",
                scene.name
            );
            let (s, t) = (g.start.unwrap(), g.goal.unwrap());
            assert!(g.connected(s, t));
        }
    }
}

#[test]
fn graphs_round_trip_through_messagepack_and_json() {
    for scene in scenes() {
        let (_, _, g) = build(&scene, 2.0).unwrap();
        let bytes = g.to_msgpack();
        assert_eq!(VoronoiGraph::from_msgpack(&bytes).unwrap(), g);
        let json: serde_json::Value = serde_json::from_str(&g.to_json()).unwrap();
        assert_eq!(json["nodes"].as_array().unwrap().len(), g.nodes.len());
        assert_eq!(json["start"].as_u64(), g.start.map(|s| s as u64));
        assert!(json["nodes"][0]["kind"].is_string());
    }
}
