//! Criterion bench of planning on a 512 x 512 occupancy map: the graph (grid, brushfire,
//! Voronoi graph, clearance model) and the full plan with 5 classes.

use criterion::{Criterion, criterion_group, criterion_main};
use homospline_geom::Point;
use homospline_maps::{OccupancyMap, plan_map, prepare};
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

fn bench(c: &mut Criterion) {
    let map = city();
    let (s, t) = (Point::new(8.5, 256.5), Point::new(503.5, 256.5));
    let cfg = homospline_maps::map_config();
    let (plan, prepared) = plan_map(&map, s, t, &cfg).unwrap();
    eprintln!(
        "city-512: graph {} nodes {} edges; {} classes, best {:?}, free {}; stages voronoi {:.1} ms classes {:.2} ms optimise {:.1} ms",
        prepared.graph.nodes.len(),
        prepared.graph.edges.len(),
        plan.classes.len(),
        plan.best,
        plan.classes.iter().filter(|c| c.collision_free).count(),
        plan.timing.voronoi,
        plan.timing.classes,
        plan.timing.optimize
    );
    let mut g = c.benchmark_group("maps");
    g.bench_function("graph/512", |b| {
        b.iter(|| prepare(black_box(&map), s, t).unwrap())
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
