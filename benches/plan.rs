//! Criterion bench of the full plan of each fixture scene with 5 classes (graph, classes,
//! seeding, growth loop, certification, ranking), Nelder-Mead and L-BFGS, Nelder-Mead
//! without the chosen class's finish within its work budget (`--finish-within off`), and
//! Nelder-Mead with one polish round for the chosen class (`--polish 1`).

use criterion::{Criterion, criterion_group, criterion_main};
use homospline_optim::{GrowthConfig, Optimizer, PlanConfig, plan};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("plan");
    for scene in homospline_testkit::fixture_scenes() {
        let budget = PlanConfig::default().finish_within;
        for (name, optimizer, polish, finish_within) in [
            ("nelder-mead", Optimizer::NelderMead, 0, budget),
            ("lbfgs", Optimizer::Lbfgs, 0, budget),
            ("nelder-mead-no-finish", Optimizer::NelderMead, 0, None),
            ("nelder-mead-polish-1", Optimizer::NelderMead, 1, budget),
        ] {
            let cfg = PlanConfig {
                growth: GrowthConfig {
                    optimizer,
                    ..GrowthConfig::default()
                },
                polish,
                finish_within,
                ..PlanConfig::default()
            };
            let p = plan(&scene, &cfg).unwrap();
            let evals = p.evaluations();
            let cost: f64 = p.classes.iter().map(|c| c.cost.total).sum();
            // The stages' wall times, the mean of 20 plans after the first (the first pays
            // for the thread pool and cold caches).
            let runs = 20;
            let mut stages = [0.0; 3];
            for _ in 0..runs {
                let t = plan(&scene, &cfg).unwrap().timing;
                for (s, v) in stages.iter_mut().zip([t.voronoi, t.classes, t.optimize]) {
                    *s += v / runs as f64;
                }
            }
            eprintln!(
                "{} {name}: {} classes, {} evaluations, summed cost {:.1}, stages (mean of {runs}) voronoi {:.2} ms classes {:.2} ms optimise {:.2} ms",
                scene.name,
                p.classes.len(),
                evals,
                cost,
                stages[0],
                stages[1],
                stages[2]
            );
            g.bench_function(format!("{}/{name}", scene.name), |b| {
                b.iter(|| plan(black_box(&scene), &cfg).unwrap())
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
