//! Criterion bench of planning on 512 x 512 occupancy maps: the map's preparation (grid,
//! brushfire, complete Voronoi graph, clearance model), the full plan with 5 classes on a
//! seeded city, time per plan against path length on maze512-8-0 (prepared once; one
//! scenario from each of five length bands of its `.scen`, up to 2,400 cells), and 20
//! scenarios of Boston_0_256 spread over every bucket, for a point and a disc of radius 1.

use criterion::{Criterion, criterion_group, criterion_main};
use homospline_geom::Point;
use homospline_maps::{OccupancyMap, PreparedMap, movingai, plan_map};
use homospline_optim::{GrowthConfig, Optimizer, PlanConfig};
use std::hint::black_box;

/// A 512 x 512 map of 60 seeded rectangular buildings (8 to 40 cells a side).
fn city() -> OccupancyMap {
    let n = 512;
    let mut occupied = vec![false; n * n];
    let mut rng = homospline_testkit::SplitMix(11);
    for _ in 0..60 {
        let (w, h) = (
            8 + (rng.next_unit() * 32.0) as usize,
            8 + (rng.next_unit() * 32.0) as usize,
        );
        let (x, y) = (
            20 + (rng.next_unit() * (n - 60) as f64) as usize,
            (rng.next_unit() * (n - h) as f64) as usize,
        );
        for j in y..(y + h).min(n) {
            for i in x..(x + w).min(n) {
                occupied[j * n + i] = true;
            }
        }
    }
    // Keep start and goal (left and right middle) free.
    for j in 240..272 {
        for i in (0..16).chain(496..512) {
            occupied[j * n + i] = false;
        }
    }
    OccupancyMap {
        name: "city-512".into(),
        width: n,
        height: n,
        cell: 1.0,
        origin: Point::origin(),
        occupied,
        y_down: true,
    }
}

/// A MovingAI map of `fixtures/maps/movingai/` and its scenarios (`NAME.map`,
/// `NAME.map.scen`).
fn fixture(name: &str) -> (OccupancyMap, Vec<movingai::Scenario>) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/maps/movingai/");
    let read = |file: String| std::fs::read_to_string(format!("{dir}{file}")).unwrap();
    let map = movingai::read_map(&read(format!("{name}.map")), &format!("{name}.map")).unwrap();
    let scen = format!("{name}.map.scen");
    (
        map,
        movingai::read_scen(&read(scen.clone()), &scen).unwrap(),
    )
}

fn bench(c: &mut Criterion) {
    let map = city();
    let (s, t) = (Point::new(8.5, 256.5), Point::new(503.5, 256.5));
    let cfg = PlanConfig::maps();
    let (plan, prepared) = plan_map(&map, s, t, &cfg).unwrap();
    eprintln!(
        "city-512: graph {} nodes {} edges; {} classes, best {:?}, free {}; stages voronoi {:.1} ms classes {:.2} ms optimise {:.1} ms",
        prepared.graph.graph.nodes.len(),
        prepared.graph.graph.edges.len(),
        plan.classes.len(),
        plan.best,
        plan.classes.iter().filter(|c| c.collision_free).count(),
        plan.timing.voronoi,
        plan.timing.classes,
        plan.timing.optimize
    );
    let mut g = c.benchmark_group("maps");
    g.bench_function("prepare/512", |b| {
        b.iter(|| PreparedMap::new(black_box(&map)).unwrap())
    });
    g.bench_function("plan_prepared_5_classes/512", |b| {
        b.iter(|| prepared.plan(s, t, &cfg).unwrap())
    });
    g.bench_function("plan_5_classes/512", |b| {
        b.iter(|| plan_map(black_box(&map), s, t, &cfg).unwrap())
    });
    // The same plan with Nelder-Mead (the paper's optimiser, the default on scenes), and
    // with the scenes' defaults (Nelder-Mead, 10 via-points).
    let nelder_mead = PlanConfig {
        growth: GrowthConfig {
            optimizer: Optimizer::NelderMead,
            ..cfg.growth.clone()
        },
        ..cfg.clone()
    };
    g.bench_function("plan_5_classes_nelder_mead/512", |b| {
        b.iter(|| plan_map(black_box(&map), s, t, &nelder_mead).unwrap())
    });
    let scene_defaults = PlanConfig::default();
    g.bench_function("plan_5_classes_scene_defaults/512", |b| {
        b.iter(|| plan_map(black_box(&map), s, t, &scene_defaults).unwrap())
    });
    g.finish();
    // Time per plan against path length, the map prepared once.
    let (maze, scen) = fixture("maze512-8-0");
    let prepared = PreparedMap::new(&maze).unwrap();
    let mut g = c.benchmark_group("maze512_by_length");
    for k in 1..=5 {
        let sc = &scen[k * (scen.len() - 1) / 5];
        let plan = prepared.plan(sc.start, sc.goal, &cfg).unwrap();
        eprintln!(
            "maze512 octile {:.0}: collision-free {}, length {:.1}",
            sc.optimal_length,
            plan.best.is_some(),
            plan.best.map_or(f64::NAN, |b| plan.classes[b - 1].length)
        );
        g.bench_function(format!("plan/{:.0}", sc.optimal_length), |b| {
            b.iter(|| prepared.plan(sc.start, sc.goal, &cfg).unwrap())
        });
    }
    g.finish();
    // The bench-scen figure on a diagonal city map: 20 scenarios spread over every bucket
    // of Boston_0_256's .scen, planned one after another on the prepared map (an
    // iteration's time over 20 is the mean per plan), for a point and for a disc of radius 1.
    let (boston, scen) = fixture("Boston_0_256");
    let picked: Vec<_> = homospline_maps::sweep::sample_indices(scen.len(), 20)
        .into_iter()
        .map(|i| &scen[i])
        .collect();
    let mut g = c.benchmark_group("movingai_sample");
    for radius in [0.0, 1.0] {
        let prepared = PreparedMap::for_robot(&boston, radius).unwrap();
        // At radius 1 some scenarios start too near a wall (refused) or have no route: those
        // are answered too, and timed.
        g.bench_function(format!("plan_20/Boston_0_256/radius_{radius}"), |b| {
            b.iter(|| {
                picked
                    .iter()
                    .filter(|sc| prepared.plan(sc.start, sc.goal, &cfg).is_ok())
                    .count()
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
