//! Criterion bench of preparing large maps (`PreparedMap::new`: grid, brushfire, complete
//! Voronoi graph and its index, clearance model, rays) on seeded random maps with 20 % of
//! their cells occupied, the hardest case (a cycle every 14 cells), at 1024 x 1024 and
//! 4096 x 4096 cells: time per cell (throughput in cells; the prepared map is dropped
//! outside the timing). Peak memory per cell is
//! `cargo xtask map-memory`'s.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use homospline_maps::PreparedMap;
use std::hint::black_box;

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
}

criterion_group!(benches, bench);
criterion_main!(benches);
