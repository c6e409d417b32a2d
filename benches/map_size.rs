//! Criterion bench of preparing large maps (`PreparedMap::new`: grid, brushfire, complete
//! Voronoi graph and its index, clearance model, rays) on seeded random maps with 20 % of
//! their cells occupied, the hardest case (a cycle every 14 cells), at 1024 x 1024 and
//! 4096 x 4096 cells: time per cell (throughput in cells; the prepared map is dropped
//! outside the timing). Peak memory per cell is
//! `cargo xtask map-memory`'s. Then a plan on the prepared 4096 x 4096 map, corner to
//! corner, 2 classes, the map defaults: the per-query graph, the class search over its
//! 3.95 M edges and the optimisation; and a short plan in its middle (64 cells along the
//! diagonal), whose search settles only what the route needs.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use homospline_maps::PreparedMap;
use homospline_optim::PlanConfig;
use std::hint::black_box;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("map_size");
    for n in [1024, 4096] {
        let map = homospline_testkit::random_map(n);
        if n > 1024 {
            g.sample_size(10);
        }
        g.throughput(Throughput::Elements((n * n) as u64));
        g.bench_function(format!("prepare_random20/{n}"), |b| {
            b.iter_with_large_drop(|| PreparedMap::new(black_box(&map)).unwrap())
        });
    }
    g.finish();

    let map = homospline_testkit::random_map(4096);
    let prepared = PreparedMap::new(&map).unwrap();
    let (s, t) = (
        homospline_testkit::free_diagonal_centre(&map, 10, 1),
        homospline_testkit::free_diagonal_centre(&map, 4000, -1),
    );
    let mut cfg = PlanConfig::maps();
    cfg.classes = 2;
    let mut g = c.benchmark_group("map_size");
    g.sample_size(10).measurement_time(Duration::from_secs(40));
    g.bench_function("plan_prepared_random20_2_classes/4096", |b| {
        b.iter(|| prepared.plan(black_box(s), black_box(t), &cfg).unwrap())
    });
    // A short query in the middle of the same map (64 cells along the diagonal): a local
    // re-plan, whose work should follow the route, not the map.
    let (s, t) = (
        homospline_testkit::free_diagonal_centre(&map, 2048, 1),
        homospline_testkit::free_diagonal_centre(&map, 2112, 1),
    );
    g.measurement_time(Duration::from_secs(5));
    g.bench_function("plan_prepared_random20_short/4096", |b| {
        b.iter(|| prepared.plan(black_box(s), black_box(t), &cfg).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
