//! Criterion bench of the class search: k = 7 on the Voronoi graph of a 1024 x 1024 map with
//! 50 compound obstacles; and the signature of a long polyline among 200 obstacles.

use criterion::{Criterion, criterion_group, criterion_main};
use homospline_geom::Point;
use homospline_homotopy::{Rays, SearchConfig, k_best_classes};
use std::hint::black_box;

#[path = "scenes.rs"]
mod scenes;

fn bench(c: &mut Criterion) {
    let scene = scenes::compound_scene(1024.0, 50, 7);
    let (_, _, graph) = homospline_voronoi::build(&scene, 1.0).unwrap();
    let rays = Rays::for_scene(&scene);
    let mut g = c.benchmark_group("homotopy");
    for k in [5, 7] {
        let cfg = SearchConfig {
            k,
            ..SearchConfig::default()
        };
        let r = k_best_classes(&graph, &rays, &cfg).unwrap();
        assert_eq!(r.classes.len(), k);
        g.bench_function(format!("k_best/{k}/1024_50_obstacles"), |b| {
            b.iter(|| k_best_classes(black_box(&graph), &rays, &cfg).unwrap())
        });
    }
    let mut rng = homospline_testkit::SplitMix(3);
    let reps: Vec<Point> = (0..200)
        .map(|_| Point::new(rng.next_unit() * 1000.0, rng.next_unit() * 1000.0))
        .collect();
    let rays200 = Rays::new(reps);
    let path: Vec<Point> = (0..1000)
        .map(|i| Point::new(i as f64, 500.0 + 300.0 * (i as f64 * 0.02).sin()))
        .collect();
    g.bench_function("signature/1000_segments_200_obstacles", |b| {
        b.iter(|| rays200.signature(black_box(&path)))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
