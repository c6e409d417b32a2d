//! Criterion bench of the class search: k = 7 on the Voronoi graph of a 1024 x 1024 map with
//! 50 compound obstacles; the signature of a long polyline among 200 obstacles; and the exact
//! shortest path among 500 and 2,000 random circles (`plan --optimum`'s tangent graph), and
//! among 2,500 to 20,000 at one density (its growth with the circles).

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
    // Circles of radius 0.3 to 0.8 at random in [3, 97]^2, corner to corner, clearance 0.5.
    let mut g = c.benchmark_group("shortest");
    g.sample_size(10);
    for n in [500, 2000] {
        let mut rng = homospline_testkit::SplitMix(5);
        let circles: Vec<homospline_geom::Circle> = (0..n)
            .map(|_| {
                homospline_geom::Circle::new(
                    3.0 + 94.0 * rng.next_unit(),
                    3.0 + 94.0 * rng.next_unit(),
                    0.3 + 0.5 * rng.next_unit(),
                )
            })
            .collect();
        let (s, t) = (Point::new(1.0, 1.0), Point::new(99.0, 99.0));
        g.bench_function(format!("tangent_graph_optimum/{n}_circles"), |b| {
            b.iter(|| {
                homospline_geom::shortest::shortest_path_length(&s, &t, black_box(&circles), 0.5)
                    .unwrap()
            })
        });
    }
    // Near-linear: the same density (one circle per 2 square units, radius 0.2 to 0.6) in
    // ever larger squares, the whole tangent graph (no length bound), corner to corner,
    // clearance 0.05. Every pair's tangents were tested up to 2026-12-06: quadratic.
    for n in [2_500, 5_000, 10_000, 20_000] {
        let side = (2.0 * n as f64).sqrt();
        let mut rng = homospline_testkit::SplitMix(9);
        let circles: Vec<homospline_geom::Circle> = (0..n)
            .map(|_| {
                homospline_geom::Circle::new(
                    2.0 + (side - 4.0) * rng.next_unit(),
                    2.0 + (side - 4.0) * rng.next_unit(),
                    0.2 + 0.4 * rng.next_unit(),
                )
            })
            .collect();
        let (s, t) = (Point::new(1.0, 1.0), Point::new(side - 1.0, side - 1.0));
        g.bench_function(format!("tangent_graph_same_density/{n}_circles"), |b| {
            b.iter(|| {
                homospline_geom::shortest::shortest_path_length(&s, &t, black_box(&circles), 0.05)
                    .unwrap()
            })
        });
    }
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
