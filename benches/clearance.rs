//! Criterion bench of the clearance queries, plain loop against parry's BVH, on 30 and on
//! 5,000 circles: the figures behind `CircleSet::BVH_THRESHOLD`; and of the exact shortest
//! path at dm on the fixture scenes (`geom::shortest`) and of the chosen class's own
//! (`homotopy::shortest_in_class`): what `plan --optimum` adds.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use homospline_geom::{Circle, CircleSet, Point, QueryBackend, Vector};
use std::hint::black_box;

use homospline_testkit::SplitMix;

/// `n` circles in a square sized so that about 15 % of it is covered.
fn scene(n: usize) -> (Vec<Circle>, Vec<Point>) {
    let mut rng = SplitMix(n as u64);
    let side = (n as f64 * std::f64::consts::PI * 4.0 / 0.15).sqrt();
    let circles = (0..n)
        .map(|_| {
            Circle::new(
                rng.next_unit() * side,
                rng.next_unit() * side,
                1.0 + 2.0 * rng.next_unit(),
            )
        })
        .collect();
    let points = (0..256)
        .map(|_| Point::new(rng.next_unit() * side, rng.next_unit() * side))
        .collect();
    (circles, points)
}

fn bench(c: &mut Criterion) {
    for n in [30usize, 128, 5000] {
        let (circles, points) = scene(n);
        for backend in [QueryBackend::Linear, QueryBackend::Bvh] {
            let set = CircleSet::with_backend(circles.clone(), backend);
            let id = |q: &str| BenchmarkId::new(format!("{q}/{backend:?}"), n);
            let mut g = c.benchmark_group("geom");
            g.bench_function(id("clearance"), |b| {
                let mut i = 0;
                b.iter(|| {
                    i = (i + 1) % points.len();
                    black_box(set.clearance(&points[i]))
                })
            });
            // Short segments, the size of one sampled step of a path.
            g.bench_function(id("segment_distance"), |b| {
                let mut i = 0;
                b.iter(|| {
                    i = (i + 1) % points.len();
                    let a = points[i];
                    black_box(set.distance_to_segment(&a, &(a + Vector::new(0.7, 0.3))))
                })
            });
            // Long sight lines across the map.
            g.bench_function(id("line_of_sight"), |b| {
                let mut i = 0;
                b.iter(|| {
                    i = (i + 1) % points.len();
                    let j = (i * 7 + 3) % points.len();
                    black_box(set.line_of_sight(&points[i], &points[j]))
                })
            });
            g.bench_function(id("ray_cast"), |b| {
                let mut i = 0;
                b.iter(|| {
                    i = (i + 1) % points.len();
                    let a = i as f64 * 0.7;
                    black_box(set.cast_ray(&points[i], &Vector::new(a.cos(), a.sin()), 1e6))
                })
            });
            g.finish();
        }
    }
}

fn shortest(c: &mut Criterion) {
    let mut g = c.benchmark_group("shortest");
    for scene in homospline_testkit::fixture_scenes() {
        let circles = scene.circle_set().circles().to_vec();
        g.bench_function(format!("{}/{}", scene.name, circles.len()), |b| {
            b.iter(|| {
                homospline_geom::shortest::shortest_path_length(
                    &scene.start,
                    &scene.goal,
                    black_box(&circles),
                    3.0,
                )
            })
        });
        // The chosen class's own optimum at its certified clearance, bounded by its length,
        // as `plan --optimum` searches it (graph included).
        let p = homospline_optim::plan(&scene, &homospline_optim::PlanConfig::default()).unwrap();
        let chosen = &p.classes[p.best.unwrap() - 1];
        let rays = homospline_homotopy::Rays::for_scene(&scene);
        let word = rays.signature(&chosen.path);
        g.bench_function(format!("{}/class", scene.name), |b| {
            b.iter(|| {
                let graph = homospline_geom::shortest::TangentGraph::build(
                    &scene.start,
                    &scene.goal,
                    black_box(&circles),
                    chosen.certified_clearance,
                )
                .unwrap()
                .unwrap();
                homospline_homotopy::shortest_in_class(
                    &graph,
                    &rays,
                    |w| *w == word,
                    chosen.length * (1.0 + 1e-9),
                )
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(1));
    targets = bench, shortest
}
criterion_main!(benches);
