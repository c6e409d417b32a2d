//! The scan behind Nelder-Mead's default budget (`GrowthConfig::evaluations_per_dimension`
//! and `max_rounds`): what each budget's chosen plans cost, against the cheapest plan any
//! budget found, on the fixture scenes and generated ones.

use homospline_geom::{Point, Real, Scene};
use homospline_homotopy::Rays;
use homospline_optim::{GrowthConfig, Guard, Optimizer, PlanConfig, grow, plan};
use homospline_spline::{CircleModel, is_collision_free};
use homospline_testkit::{SplitMix, fixture_scenes, scan_scenes};

fn with_budget(per_dimension: usize, rounds: usize) -> PlanConfig {
    PlanConfig {
        growth: GrowthConfig {
            evaluations_per_dimension: per_dimension,
            max_rounds: rounds,
            optimizer: if std::env::var("SCAN_OPTIMIZER").is_ok_and(|v| v == "lbfgs") {
                Optimizer::Lbfgs
            } else {
                Optimizer::NelderMead
            },
            ..GrowthConfig::default()
        },
        polish: count_from_env("SCAN_POLISH", 0) as usize,
        finish_within: match std::env::var("SCAN_FINISH") {
            Ok(v) if v == "off" => None,
            Ok(v) => Some(
                v.parse()
                    .expect("SCAN_FINISH: off or a number of evaluations"),
            ),
            Err(_) => PlanConfig::default().finish_within,
        },
        ..PlanConfig::default()
    }
}

/// A count from the environment variable `name`, else `default`.
fn count_from_env(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// `SCAN_BUDGETS=30x3,20x3`: evaluations per coordinate x rounds, in order.
fn budgets_from_env() -> Option<Vec<(usize, usize)>> {
    std::env::var("SCAN_BUDGETS").ok().map(|v| {
        v.split(',')
            .map(|b| {
                let (e, r) = b.split_once('x').expect("EPDxROUNDS");
                (e.parse().unwrap(), r.parse().unwrap())
            })
            .collect()
    })
}

/// Run by hand: `cargo test --release -p homospline-optim --test it budget:: -- --ignored
/// --nocapture` (about 80 s on 2 cores). For each budget (evaluations per dimension, rounds):
/// the evaluations against the first budget's (the default), and the chosen plan's cost
/// against the cheapest chosen plan of any budget on the same scene (its regret): geometric
/// mean, 90th percentile and worst, and how many plans are 5 % or more above the cheapest.
/// `SCAN_SCENES=N` sets the generated scenes (300), `SCAN_BUDGETS=30x3,20x3` the budgets
/// (the default's first), `SCAN_POLISH=N` gives every plan (and the jitter scan's) `N`
/// polish rounds, `SCAN_FINISH=N|off` sets `PlanConfig::finish_within` (default 1500),
/// `SCAN_OPTIMIZER=lbfgs` runs the rounds with L-BFGS, `SCAN_OUT=FILE`
/// writes every plan's chosen cost and evaluations (`budget scene cost evaluations` per
/// line) to compare runs of different code.
#[test]
#[ignore]
fn scan_the_budget() {
    let all: Vec<Scene> = scan_scenes(300);
    let from_env = budgets_from_env();
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

/// The chosen lengths on the day issue 13 was filed (squared roughness), by paper scene in
/// file-name order: its length target is 5 % over these.
const ISSUE_DAY_LENGTHS: [f64; 5] = [57.28, 56.42, 80.02, 94.91, 85.01];

/// Run by hand: `cargo test --release -p homospline-optim --test it budget::scan_the_jitter --
/// --ignored --nocapture` (a few seconds). Plans each paper scene with its start and goal
/// moved by up to `0.01` units (`SCAN_JITTER=N` draws, 16 by default; the first draw is the
/// scene itself) at each budget (`SCAN_BUDGETS`, as above; default 30x3), and prints the
/// chosen plan's length (median, least, greatest), its cost (median) and how many draws meet
/// issue 13's length target (within 5 % of the issue's day). A result on one input is one
/// draw from this spread: Nelder-Mead at the default budget does not converge, and where it
/// stops moves with the input's last digits.
#[test]
#[ignore]
fn scan_the_jitter() {
    let draws = count_from_env("SCAN_JITTER", 16);
    let budgets = budgets_from_env().unwrap_or(vec![(30, 3)]);
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        }
    };
    for &(e, r) in &budgets {
        let cfg = with_budget(e, r);
        for (scene, day) in fixture_scenes().iter().zip(ISSUE_DAY_LENGTHS) {
            let mut rng = SplitMix(13);
            let (mut lengths, mut costs, mut met) = (vec![], vec![], 0);
            for k in 0..draws {
                let mut s = scene.clone();
                let mut jitter = || {
                    if k == 0 {
                        0.0
                    } else {
                        0.02 * (rng.next_unit() - 0.5)
                    }
                };
                s.start.x += jitter();
                s.start.y += jitter();
                s.goal.x += jitter();
                s.goal.y += jitter();
                let p = plan(&s, &cfg).unwrap();
                let c = p.chosen().expect("a paper scene has a plan");
                met += usize::from(c.length <= 1.05 * day);
                lengths.push(c.length);
                costs.push(c.cost.total);
            }
            let (least, most) = (
                lengths.iter().copied().fold(f64::INFINITY, f64::min),
                lengths.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            );
            println!(
                "budget {e}x{r} {:<15} length median {:.2} ({:.2} to {:.2}), limit {:.2}, met {met} of {draws}; cost median {:.1}",
                scene.name,
                median(&mut lengths),
                least,
                most,
                1.05 * day,
                median(&mut costs),
            );
        }
    }
}

/// Run by hand: `cargo test --release -p homospline-optim --test it budget::scan_the_convergence
/// -- --ignored --nocapture` (about a minute). How far each paper scene's chosen curve is
/// from the best curve of its class with as many via-points, under the same guard (class,
/// bounds, the dm rule's target): one more round of the default budget from the chosen
/// curve, one of 300 evaluations per coordinate, and the best of 300 per coordinate from
/// `SCAN_STARTS` (24) starts, the chosen via-points each moved by up to 2 units. Growth is
/// off in all of them (one round, the via-point limit at the chosen count).
#[test]
#[ignore]
fn scan_the_convergence() {
    let starts = count_from_env("SCAN_STARTS", 24);
    let defaults = PlanConfig::default();
    for scene in fixture_scenes() {
        let p = plan(&scene, &defaults).unwrap();
        let chosen = p.chosen().expect("a paper scene has a plan");
        let model = CircleModel::new(scene.circles());
        let rays = Rays::for_scene(&scene);
        let class = rays.signature(&chosen.path);
        assert_eq!(class.to_string(), chosen.signature);
        let guard = Guard {
            class: Some((&rays, &class)),
            bounds: scene.bounds,
            collision_free: true,
            clearance_floor: Real::NEG_INFINITY,
            clearance_target: defaults.growth.cost.dm + defaults.certify_tolerance,
            proven: Default::default(),
            tube: Default::default(),
        };
        let inner = chosen.via_points.len() - 2;
        let one_round = |per_dimension: usize, seed: &[Point]| {
            let cfg = GrowthConfig {
                max_rounds: 1,
                max_via_points: inner,
                evaluations_per_dimension: per_dimension,
                ..GrowthConfig::default()
            };
            grow(seed, &model, &cfg, &guard)
                .ok()
                .filter(|g| {
                    g.terms.min_clearance >= guard.clearance_target
                        && is_collision_free(&g.spline, &model)
                })
                .map(|g| (g.terms.total, g.spline.length()))
        };
        let show = |r: Option<(Real, Real)>| {
            r.map_or("-".to_string(), |(c, l)| format!("{c:.2} at {l:.2}"))
        };
        let more = one_round(30, &chosen.via_points);
        let long = one_round(300, &chosen.via_points);
        let mut rng = SplitMix(5);
        let best = (0..starts)
            .filter_map(|_| {
                let mut seed = chosen.via_points.clone();
                for q in &mut seed[1..=inner] {
                    q.x += 4.0 * (rng.next_unit() - 0.5);
                    q.y += 4.0 * (rng.next_unit() - 0.5);
                }
                one_round(300, &seed)
            })
            .chain(long)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        println!(
            "{:<15} class {} with {inner} via-points: chosen {:.2} at {:.2}; one more round {}; \
             300 per coordinate {}; best of {starts} starts {}",
            scene.name,
            chosen.signature,
            chosen.cost.total,
            chosen.length,
            show(more),
            show(long),
            show(best),
        );
    }
}
