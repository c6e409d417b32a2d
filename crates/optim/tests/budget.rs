//! The scan behind Nelder-Mead's default budget (`GrowthConfig::evaluations_per_dimension`
//! and `max_rounds`): what each budget's chosen plans cost, against the cheapest plan any
//! budget found, on the fixture scenes and generated ones.

use homospline_geom::Scene;
use homospline_optim::{GrowthConfig, PlanConfig, plan};
use homospline_testkit::scan_scenes;

fn with_budget(per_dimension: usize, rounds: usize) -> PlanConfig {
    PlanConfig {
        growth: GrowthConfig {
            evaluations_per_dimension: per_dimension,
            max_rounds: rounds,
            ..GrowthConfig::default()
        },
        ..PlanConfig::default()
    }
}

/// Run by hand: `cargo test --release -p homospline-optim --test budget -- --ignored
/// --nocapture` (about 80 s on 2 cores). For each budget (evaluations per dimension, rounds):
/// the evaluations against the first budget's (the default), and the chosen plan's cost
/// against the cheapest chosen plan of any budget on the same scene (its regret): geometric
/// mean, 90th percentile and worst, and how many plans are 5 % or more above the cheapest.
/// `SCAN_SCENES=N` sets the generated scenes (300), `SCAN_BUDGETS=30x3,20x3` the budgets
/// (the default's first), `SCAN_OUT=FILE` writes every plan's chosen cost and evaluations
/// (`budget scene cost evaluations` per line) to compare runs of different code.
#[test]
#[ignore]
fn scan_the_budget() {
    let all: Vec<Scene> = scan_scenes(300);
    let from_env: Option<Vec<(usize, usize)>> = std::env::var("SCAN_BUDGETS").ok().map(|v| {
        v.split(',')
            .map(|b| {
                let (e, r) = b.split_once('x').expect("EPDxROUNDS");
                (e.parse().unwrap(), r.parse().unwrap())
            })
            .collect()
    });
    let budgets = [
        (30, 3),
        (20, 3),
        (24, 3),
        (15, 4),
        (20, 4),
        (15, 6),
        (10, 6),
        (60, 3),
        (90, 6),
    ];
    let budgets = from_env.unwrap_or(budgets.to_vec());
    let runs: Vec<Vec<(Option<f64>, usize)>> = budgets
        .iter()
        .map(|&(e, r)| {
            all.iter()
                .map(|s| {
                    let p = plan(s, &with_budget(e, r)).unwrap();
                    (p.chosen().map(|c| c.cost.total), p.evaluations())
                })
                .collect()
        })
        .collect();
    if let Ok(path) = std::env::var("SCAN_OUT") {
        let mut text = String::new();
        for (b, run) in budgets.iter().zip(&runs) {
            for (i, r) in run.iter().enumerate() {
                text += &format!("{}x{} {i} {} {}\n", b.0, b.1, r.0.unwrap_or(f64::NAN), r.1);
            }
        }
        std::fs::write(path, text).unwrap();
    }
    let best: Vec<Option<f64>> = (0..all.len())
        .map(|i| runs.iter().filter_map(|r| r[i].0).min_by(f64::total_cmp))
        .collect();
    let base_evals: usize = runs[0].iter().map(|r| r.1).sum();
    for (b, run) in budgets.iter().zip(&runs) {
        let mut regrets: Vec<f64> = run
            .iter()
            .zip(&best)
            .filter_map(|(r, b)| Some(r.0? / (*b)?))
            .collect();
        let none = run.iter().filter(|r| r.0.is_none()).count();
        regrets.sort_by(f64::total_cmp);
        let geo = (regrets.iter().map(|r| r.ln()).sum::<f64>() / regrets.len() as f64).exp();
        let p90 = regrets[regrets.len() * 9 / 10];
        let worst = regrets[regrets.len() - 1];
        let over5 = regrets.iter().filter(|&&r| r >= 1.05).count();
        let e: usize = run.iter().map(|r| r.1).sum();
        let fixtures: Vec<String> = run[..5]
            .iter()
            .map(|r| r.0.map_or("-".into(), |c| format!("{c:.1}")))
            .collect();
        println!(
            "budget {:>2}/dim x {} rounds: evaluations {:.2} of the default's; regret geo-mean \
             {:.4}, p90 {:.4}, worst {:.3}, {over5} of {} >= 5 %, {none} without a plan; \
             paper scenes {}",
            b.0,
            b.1,
            e as f64 / base_evals as f64,
            geo,
            p90,
            worst,
            regrets.len(),
            fixtures.join(" ")
        );
    }
}
