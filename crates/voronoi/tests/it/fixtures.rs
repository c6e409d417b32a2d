//! The graph of every fixture scene: its cycles, its attachments, its serialisation.

use homospline_testkit::fixture_scenes;

use homospline_geom::Scene;
use homospline_voronoi::{VoronoiGraph, build};
use std::path::Path;

#[test]
fn every_fixture_has_one_cycle_per_obstacle() {
    for scene in fixture_scenes() {
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
    for scene in fixture_scenes() {
        let (_, _, g) = build(&scene, 2.0).unwrap();
        let bytes = g.to_msgpack();
        assert_eq!(VoronoiGraph::from_msgpack(&bytes).unwrap(), g);
        // Cut short anywhere past its first key: said so (it read "not a graph saved by
        // `homospline graph --out`", the check of the version coming first).
        for cut in [17, bytes.len() / 2, bytes.len() - 1] {
            let e = VoronoiGraph::from_msgpack(&bytes[..cut])
                .unwrap_err()
                .to_string();
            assert!(e.contains("cut short"), "{} cut at {cut}: {e}", scene.name);
        }
        let json: serde_json::Value = serde_json::from_str(&g.to_json()).unwrap();
        assert_eq!(json["nodes"].as_array().unwrap().len(), g.nodes.len());
        assert_eq!(json["start"].as_u64(), g.start.map(|s| s as u64));
        assert!(json["nodes"][0]["kind"].is_string());
    }
}

#[test]
fn a_saved_graph_whose_edges_no_longer_join_start_and_goal_is_refused() {
    // A hand-edited graph without the goal's edges planned "0 classes" with no reason.
    let scene = fixture_scenes().remove(0);
    let (_, _, mut g) = build(&scene, 2.0).unwrap();
    let goal = g.goal.unwrap();
    g.edges.retain(|e| e.from != goal && e.to != goal);
    let e = VoronoiGraph::from_msgpack(&g.to_msgpack())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("its edges do not join the start (node")
            && e.contains("changed after it was saved"),
        "{e}"
    );
}

#[test]
fn short_dead_end_spurs_are_pruned_and_long_ones_kept() {
    use homospline_voronoi::{Edge, Node, NodeKind};
    let node = |id: usize, x: f64, kind: NodeKind| Node {
        id,
        at: [x, 0.0],
        clearance: 1.0,
        kind,
    };
    let edge = |from: usize, to: usize, length: f64| Edge {
        from,
        to,
        length,
        min_clearance: 1.0,
        mean_clearance: 1.0,
        polyline: vec![[from as f64, 0.0], [to as f64, 0.0]].into(),
    };
    // start - a - goal, with a short spur a - b - c (two edges) and a long spur a - d.
    let mut g = VoronoiGraph {
        resolution: 1.0,
        nodes: vec![
            node(0, 0.0, NodeKind::Start),
            node(1, 1.0, NodeKind::Junction),
            node(2, 2.0, NodeKind::Goal),
            node(3, 3.0, NodeKind::Junction),
            node(4, 4.0, NodeKind::DeadEnd),
            node(5, 5.0, NodeKind::DeadEnd),
        ],
        edges: vec![
            edge(0, 1, 1.0),
            edge(1, 2, 1.0),
            edge(1, 3, 0.5),
            edge(3, 4, 0.5),
            edge(1, 5, 9.0),
        ],
        start: Some(0),
        goal: Some(2),
        obstacles: vec![],
        built_for: None,
    };
    g.prune_spurs(2.0);
    // The spur's tip goes first, then the edge it leaves dangling; the long spur stays.
    assert_eq!(g.edges.len(), 3, "{:?}", g.edges);
    assert_eq!(g.nodes.len(), 4);
    assert!(g.edges.iter().any(|e| e.length == 9.0));
    let (s, t) = (g.start.unwrap(), g.goal.unwrap());
    assert_eq!(g.nodes[s].kind, NodeKind::Start);
    assert_eq!(g.nodes[t].kind, NodeKind::Goal);
    assert!(g.connected(s, t));
}

/// Generated world 452 with its blockage, from where the UGV found it
/// (`fixtures/cases/crack-apart-452.yaml`): the blockage touches the wall, and the free space
/// between the wall and itself has no crack, so the crack graph comes apart inside one free
/// region (start and goal on different pieces). The scene's graph is then the complete graph,
/// which joins them.
#[test]
fn a_crack_graph_that_comes_apart_inside_one_region_falls_back_to_the_complete_graph() {
    use homospline_voronoi::{DistanceField, GraphError, Grid};
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/cases/crack-apart-452.yaml");
    let bytes = std::fs::read(&path).unwrap();
    let scene = Scene::from_bytes(&bytes, &path.display().to_string()).unwrap();
    let e = scene.bounds.extent();
    let resolution = 256.0 / e.x.max(e.y);
    let grid = Grid::from_scene(&scene, resolution).unwrap();
    let field = DistanceField::build(&grid);
    assert_eq!(
        VoronoiGraph::build(&grid, &field, Some(scene.start), Some(scene.goal)),
        Err(GraphError::DifferentRegions),
        "the crack graph joins them: this test no longer exercises the fallback"
    );
    let (_, _, g) = build(&scene, resolution).expect("the complete graph");
    let (s, t) = (g.start.expect("a start"), g.goal.expect("a goal"));
    assert!(g.connected(s, t));
}
