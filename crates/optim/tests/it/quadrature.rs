//! The scan behind the cost's quadrature default (`CostConfig::nodes` and `pieces`): what
//! each quadrature's chosen plans cost when evaluated by a dense reference quadrature, and
//! how far each quadrature's value of a curve is from the reference's.
//!
//! Measured on 320 scenes (the 20 fixtures and 300 generated worlds), reference 16 nodes by
//! 8 pieces: every quadrature cheaper than the default 5 x 2 chose dearer plans (regret
//! geometric mean 1.022 at 5 x 2, 1.031 at 4 x 2, 1.037 at 3 x 2, 1.053 at 4 x 1, 1.060 at
//! 5 x 1; p90 1.029 against 1.034 to 1.129) with as many evaluations, so 5 x 2 stays
//! (docs/decisions/0010-cost-accuracy.md).

use homospline_geom::Scene;
use homospline_optim::{PlanConfig, plan};
use homospline_spline::{CircleModel, Spline, cost::evaluate};
use homospline_testkit::scan_scenes;

fn with_quadrature(nodes: usize, pieces: usize) -> PlanConfig {
    let mut cfg = PlanConfig::default();
    cfg.growth.cost.nodes = nodes;
    cfg.growth.cost.pieces = pieces;
    cfg
}

/// Run by hand: `cargo test --release -p homospline-optim --test it quadrature:: -- --ignored
/// --nocapture`. `SCAN_SCENES=N` generated scenes (300), `SCAN_QUADS=5x2,5x1` the
/// quadratures (nodes x pieces; the default's first).
#[test]
#[ignore]
fn scan_the_quadrature() {
    let all: Vec<Scene> = scan_scenes(300);
    let quads: Vec<(usize, usize)> = std::env::var("SCAN_QUADS")
        .unwrap_or("5x2,5x1,4x2,4x1,3x2".into())
        .split(',')
        .map(|b| {
            let (n, p) = b.split_once('x').expect("NODESxPIECES");
            (n.parse().unwrap(), p.parse().unwrap())
        })
        .collect();
    let reference = {
        let mut c = PlanConfig::default().growth.cost;
        c.nodes = 16;
        c.pieces = 8;
        c
    };
    // Per quadrature, per scene: the chosen curve's reference cost, its own cost's relative
    // error against the reference, and the plan's evaluations.
    let runs: Vec<Vec<Option<(f64, f64, usize)>>> = quads
        .iter()
        .map(|&(n, p)| {
            let cfg = with_quadrature(n, p);
            all.iter()
                .map(|s| {
                    let pl = plan(s, &cfg).unwrap();
                    let c = pl.chosen()?;
                    let model = CircleModel::new(s.circles());
                    let sp = Spline::new(&c.via_points, cfg.growth.parametrization, cfg.growth.end)
                        .ok()?;
                    let r = evaluate(&sp, &model, &reference).total;
                    let own = evaluate(&sp, &model, &cfg.growth.cost).total;
                    Some((r, (own - r).abs() / r, pl.evaluations()))
                })
                .collect()
        })
        .collect();
    let best: Vec<Option<f64>> = (0..all.len())
        .map(|i| {
            runs.iter()
                .filter_map(|r| r[i].map(|x| x.0))
                .min_by(f64::total_cmp)
        })
        .collect();
    for (q, run) in quads.iter().zip(&runs) {
        let mut regrets: Vec<f64> = run
            .iter()
            .zip(&best)
            .filter_map(|(r, b)| Some(r.as_ref()?.0 / (*b)?))
            .collect();
        regrets.sort_by(f64::total_cmp);
        let mut errs: Vec<f64> = run.iter().flatten().map(|r| r.1).collect();
        errs.sort_by(f64::total_cmp);
        let geo = (regrets.iter().map(|r| r.ln()).sum::<f64>() / regrets.len() as f64).exp();
        let e: usize = run.iter().flatten().map(|r| r.2).sum();
        let fixtures: Vec<String> = run[..5]
            .iter()
            .map(|r| r.map_or("-".into(), |c| format!("{:.2}", c.0)))
            .collect();
        println!(
            "quadrature {}x{}: evaluations {e}; regret geo-mean {geo:.4}, median {:.4}, p90 {:.4}, worst {:.3}, {} >= 1 %, {} without a plan; error median {:.1e} p90 {:.1e} worst {:.1e}; paper scenes {}",
            q.0,
            q.1,
            regrets[regrets.len() / 2],
            regrets[regrets.len() * 9 / 10],
            regrets[regrets.len() - 1],
            regrets.iter().filter(|&&r| r >= 1.01).count(),
            run.iter().filter(|r| r.is_none()).count(),
            errs[errs.len() / 2],
            errs[errs.len() * 9 / 10],
            errs[errs.len() - 1],
            fixtures.join(" ")
        );
    }
}
