//! Criterion bench of the optimiser's hot loop: building a 12-via-point spline and
//! evaluating the full cost (10) in a 60-circle scene (`m(C)` searched around the worst
//! node, and between every two nodes), its gradient, and the certified clearance.

use criterion::{Criterion, criterion_group, criterion_main};
use homospline_geom::{Circle, Point, Real};
use homospline_spline::{
    CircleModel, ClearanceSearch, CostConfig, RoughnessForm, Spline, evaluate, gradient,
    is_clear_by, min_clearance,
};
use std::hint::black_box;

/// 60 circles on a jittered 10 x 6 lattice over 90 x 66 units, radii 1.5 to 2.5.
fn scene() -> (Vec<Point>, CircleModel) {
    let circles = (0..60)
        .map(|i| {
            let (x, y) = ((i % 10) as Real * 9.0 + 5.0, (i / 10) as Real * 11.0 + 3.0);
            Circle::new(
                x + (i as Real * 0.7).sin() * 2.0,
                y,
                1.5 + (i % 3) as Real * 0.5,
            )
        })
        .collect();
    // Start, 12 via-points, goal: a path that weaves between the circles.
    let pts = (0..14)
        .map(|i| {
            let t = i as Real / 13.0;
            Point::new(2.0 + 86.0 * t, 35.0 + 9.0 * (t * 11.0).sin())
        })
        .collect();
    (pts, CircleModel::new(circles))
}

fn bench(c: &mut Criterion) {
    let (pts, model) = scene();
    let cfg = CostConfig::paper_voronoi();
    let spline = Spline::natural(&pts).unwrap();
    let mut g = c.benchmark_group("spline");
    g.bench_function("build_12_via_points", |b| {
        b.iter(|| Spline::natural(black_box(&pts)).unwrap())
    });
    g.bench_function("cost_paper_voronoi_12_via_60_circles", |b| {
        b.iter(|| evaluate(black_box(&spline), &model, &cfg))
    });
    g.bench_function("build_and_cost_12_via_60_circles", |b| {
        b.iter(|| evaluate(&Spline::natural(black_box(&pts)).unwrap(), &model, &cfg))
    });
    g.bench_function("cost_paper_original_12_via_60_circles", |b| {
        let cfg = CostConfig::paper_original();
        b.iter(|| evaluate(black_box(&spline), &model, &cfg))
    });
    for form in [RoughnessForm::Energy, RoughnessForm::Authors] {
        let cfg = CostConfig {
            roughness: form,
            ..CostConfig::paper_voronoi()
        };
        g.bench_function(
            format!("cost_paper_voronoi_{form}_12_via_60_circles"),
            |b| b.iter(|| evaluate(black_box(&spline), &model, &cfg)),
        );
    }
    g.bench_function("cost_paper_voronoi_every_stretch_12_via_60_circles", |b| {
        let cfg = CostConfig {
            clearance_search: ClearanceSearch::EveryStretch,
            ..CostConfig::paper_voronoi()
        };
        b.iter(|| evaluate(black_box(&spline), &model, &cfg))
    });
    g.bench_function("gradient_12_via_60_circles", |b| {
        b.iter(|| gradient(black_box(&spline), &model, &cfg))
    });
    g.bench_function("certified_clearance_1e-6", |b| {
        b.iter(|| min_clearance(black_box(&spline), &model, 1e-6))
    });
    g.bench_function("clear_by_least_less_1e-3", |b| {
        let least = min_clearance(&spline, &model, 1e-9).lower;
        b.iter(|| is_clear_by(black_box(&spline), &model, least - 1e-3))
    });
    g.bench_function("field_batch_156_nodes_60_circles", |b| {
        let pts: Vec<Point> = spline.sample_uniform(155);
        let mut out = vec![homospline_spline::clearance_model::FieldSample::default(); pts.len()];
        b.iter(|| {
            use homospline_spline::ClearanceModel;
            model.field_batch(black_box(&pts), 0.5, 0.0, &mut out);
            out[3].potential
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(1));
    targets = bench
}
criterion_main!(benches);
