//! Criterion bench of re-planning during missions, on the paper-like worlds and 100
//! generated worlds. As the missions run them: every re-plan event of every policy, three
//! runs, each timed whole in the simulation (map update, classes, optimisation); prints p50
//! and p99. Replayed: each event of the `ahead` missions planned again on the known map as
//! the UGV knew it then, from its position and heading, as the missions plan it (the
//! coarser graph, the full one when that has no clear class: `replan_scene`), timed by
//! criterion; prints p50, p99 and the slowest events' stages. On the 512 x 512 map world
//! (`fixtures/worlds/maps/16room-blocked.yaml`): the missions of every policy, each re-plan
//! timed whole (map update and plan) with the map update's parts, and the full rebuild of
//! the brushfire and of the graph for comparison. `mission/hidden_20000`: a mission among
//! 20,000 hidden obstacles no robot comes near (the sensors' scan at scale).

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use homospline_geom::{Circle, Obstacle, Point, Scene, Vector};
use homospline_mission::{EventKind, MissionConfig, MissionWorld, Policy, replan_scene, simulate};

/// The re-plan problems of one mission: the known map, the UGV's position and heading.
fn replans(world: &MissionWorld, cfg: &MissionConfig) -> Vec<(Scene, Vector)> {
    let r = simulate(world, cfg).expect("a mission");
    let mut out = Vec::new();
    for e in &r.events {
        if !matches!(e.kind, EventKind::Replanned { .. }) {
            continue;
        }
        let mut known = world.prior.clone();
        for d in r.events.iter().filter(|d| d.t <= e.t) {
            if let EventKind::Discovered {
                obstacle, hidden, ..
            } = &d.kind
            {
                if *hidden {
                    known.obstacles.extend(
                        world
                            .truth
                            .obstacles
                            .iter()
                            .filter(|o| &o.name == obstacle)
                            .cloned(),
                    );
                } else {
                    known.obstacles.retain(|o| &o.name != obstacle);
                }
            }
        }
        known.start = e.at;
        // The plan driven before the event (the offline plan for one at 0 s: a blockage in
        // sensor range of the start is seen before the UGV moves).
        let before = r
            .adopted
            .iter()
            .rev()
            .find(|a| a.t < e.t)
            .unwrap_or(&r.adopted[0]);
        let k = nearest(&before.path, &e.at).min(before.path.len() - 2);
        let heading = before.path[k + 1] - before.path[k];
        out.push((known, heading));
    }
    out
}

fn nearest(path: &[Point], p: &Point) -> usize {
    (0..path.len())
        .min_by(|&a, &b| (path[a] - p).norm().total_cmp(&(path[b] - p).norm()))
        .unwrap_or(0)
}

/// Generated worlds in the bench, beside the paper-like ones: the first of seeds 0, 1, ...
/// that give a world (every other one with its second class blocked too).
const GENERATED: usize = 100;

fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn bench(c: &mut Criterion) {
    let cfg = MissionConfig {
        policy: Policy::AHEAD,
        ..MissionConfig::default()
    };
    let mut worlds = homospline_testkit::fixture_worlds();
    worlds.extend(
        (0..200)
            .filter_map(|s| homospline_testkit::random_world(s, 2))
            .take(GENERATED),
    );
    // Every re-plan, and those of the worlds whose truth has a path (in the others the UGV
    // ends stuck, after re-plans that found nothing on the coarse graph, then on the full
    // one, along the heading, then from a standstill).
    let (mut in_missions, mut solvable): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    for _ in 0..3 {
        for w in &worlds {
            for &policy in Policy::all() {
                let c = MissionConfig {
                    policy,
                    ..MissionConfig::default()
                };
                let r = simulate(w, &c).expect("a mission");
                if r.truth_plan_length.is_some() {
                    solvable.extend(r.replan_ms.iter().copied());
                }
                in_missions.extend(r.replan_ms);
            }
        }
    }
    report(
        "re-plan latency in the missions (every policy, 3 runs; map update and plan)",
        &mut in_missions,
    );
    report("  of them in worlds whose truth has a path", &mut solvable);
    let problems: Vec<(Scene, Vector)> = worlds.iter().flat_map(|w| replans(w, &cfg)).collect();
    // As the missions plan them: on the coarser graph, the full one if that has no clear class.
    let coarse = |scene: &Scene| cfg.replan_resolution(scene);
    eprintln!(
        "{} re-plan events from {} worlds",
        problems.len(),
        worlds.len()
    );
    // Where the time of the slowest re-plans goes: each event's fastest of 5 runs, with the
    // planner's own stage timings and each class's evaluations, via-points and time.
    let mut slowest: Vec<(f64, String)> = problems
        .iter()
        .enumerate()
        .map(|(i, (scene, heading))| {
            let pc = cfg.replan_config(*heading);
            let runs: Vec<(f64, homospline_optim::Plan)> = (0..5)
                .map(|_| {
                    let t = Instant::now();
                    let p = replan_scene(scene, &pc, coarse(scene)).expect("a plan");
                    (t.elapsed().as_secs_f64() * 1e3, p)
                })
                .collect();
            let (ms, p) = runs
                .into_iter()
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .expect("5 runs");
            let classes: Vec<String> = p
                .classes
                .iter()
                .map(|c| format!("{} evals, {} points, {:.1} ms", c.evaluations, c.via_points.len(), c.time_ms))
                .collect();
            let line = format!(
                "event {i} ({}): {ms:.2} ms = graph {:.2} + classes {:.2} + optimisation {:.2} [{}]",
                scene.name,
                p.timing.voronoi,
                p.timing.classes,
                p.timing.optimize,
                classes.join("; ")
            );
            (ms, line)
        })
        .collect();
    slowest.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (_, line) in slowest.iter().take(5) {
        eprintln!("{line}");
    }
    let mut g = c.benchmark_group("mission");
    let mut times: Vec<f64> = Vec::new();
    g.bench_function("replan", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for i in 0..iters as usize {
                let (scene, heading) = &problems[i % problems.len()];
                let pc = cfg.replan_config(*heading);
                let t = Instant::now();
                let p = replan_scene(scene, &pc, coarse(scene)).expect("a plan");
                let dt = t.elapsed();
                std::hint::black_box(p);
                times.push(dt.as_secs_f64() * 1e3);
                total += dt;
            }
            total
        })
    });
    g.finish();
    report("replayed re-plan latency", &mut times);
}

/// Prints the count, p50, p99 and maximum of `times` (ms), sorting them.
fn report(what: &str, times: &mut [f64]) {
    if times.is_empty() {
        // Its bench was filtered out (`cargo bench ... -- NAME`).
        return;
    }
    times.sort_by(f64::total_cmp);
    eprintln!(
        "{what}: {} re-plans, p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
        times.len(),
        percentile(times, 0.5),
        percentile(times, 0.99),
        times.last().copied().unwrap_or(f64::NAN)
    );
}

fn bench_map(c: &mut Criterion) {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/worlds/maps/16room-blocked.yaml");
    let world = match homospline_mission::world::load_any(&path, |p| std::fs::read(p)) {
        Ok(homospline_mission::AnyWorld::Map(w)) => w,
        _ => panic!("{}: a map world", path.display()),
    };
    let (mut replan, mut field, mut graph, mut model, mut local) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), 0);
    // Each policy's re-plans (the offline plan is not one), over the three runs.
    let mut by_policy: Vec<(&str, Vec<f64>)> = Policy::all()
        .iter()
        .map(|p| (p.name(), Vec::new()))
        .collect();
    for _ in 0..3 {
        for (k, &policy) in Policy::all().iter().enumerate() {
            let cfg = MissionConfig {
                policy,
                ..MissionConfig::for_maps()
            };
            let r = homospline_mission::simulate_map(&world, &cfg).expect("a mission");
            assert!(r.reached, "{}: not reached", policy.name());
            replan.extend(r.replan_ms.iter().copied());
            by_policy[k].1.extend(r.replan_ms.iter().copied());
            for u in &r.map_updates {
                field.push(u.field_ms);
                graph.push(u.graph_ms);
                model.push(u.model_ms);
                local += usize::from(u.local);
            }
        }
    }
    let n_updates = field.len();
    for v in [&mut replan, &mut field, &mut graph, &mut model] {
        v.sort_by(f64::total_cmp);
    }
    eprintln!(
        "512 x 512 map world: re-plan latency (map update and plan) over {} re-plans: p50 {:.1} ms, p99 {:.1} ms; map updates: {} ({} local), brushfire p50 {:.2} ms, graph rebuilt from the field p50 {:.1} ms, model p50 {:.1} ms",
        replan.len(),
        percentile(&replan, 0.5),
        percentile(&replan, 0.99),
        n_updates,
        local,
        percentile(&field, 0.5),
        percentile(&graph, 0.5),
        percentile(&model, 0.5),
    );
    for (name, mut times) in by_policy {
        report(&format!("512 x 512 map world, {name}"), &mut times);
    }
    let grid = world.truth.to_grid().expect("a grid");
    let built = homospline_voronoi::DistanceField::build(&grid);
    let mut g = c.benchmark_group("mission_map_512");
    g.bench_function("brushfire_rebuild", |b| {
        b.iter(|| homospline_voronoi::DistanceField::build(&grid))
    });
    // The local update of a blockage that joins one obstacle: the door's cell and the wall
    // cell beside it (joined to that wall alone), added to the prior's field.
    let prior = world.prior.to_grid().expect("a grid");
    let prior_field = homospline_voronoi::DistanceField::build(&prior);
    let (i, j) = (151 + 1, 192 + 1);
    let cells = [(i - 1, j - 1), (i - 1, j), (i - 1, j + 1)];
    assert!(
        prior_field
            .clone()
            .add_cells(&mut prior.clone(), &cells)
            .is_ok(),
        "the bench's blockage joins one obstacle"
    );
    g.bench_function("brushfire_local_update", |b| {
        b.iter_batched(
            || (prior.clone(), prior_field.clone()),
            |(mut gr, mut f)| f.add_cells(&mut gr, &cells).map(|_| f),
            criterion::BatchSize::LargeInput,
        )
    });
    g.bench_function("graph_from_field", |b| {
        b.iter(|| homospline_voronoi::MapGraph::build(&grid, &built))
    });
    g.finish();
}

/// A mission on the paper's narrow pass with 20,000 hidden obstacles in a corner no robot
/// comes near: every look of every robot scans the obstacles not yet found, so this is the
/// sensors' cost at scale (a name lookup in a list once made it quadratic; measured:
/// docs/performance.md, "Measurements behind the defaults").
fn bench_hidden(c: &mut Criterion) {
    let scene = homospline_testkit::fixture_scenes()
        .into_iter()
        .find(|s| s.name == "narrow-pass")
        .expect("the narrow-pass fixture");
    let hidden: Vec<Obstacle> = (0..20_000u32)
        .map(|k| Obstacle {
            name: format!("h{k}"),
            circles: vec![Circle::new(
                88.03 + 0.06 * f64::from(k / 100),
                -7.95 + 0.1 * f64::from(k % 100),
                0.02,
            )],
        })
        .collect();
    let team = homospline_testkit::team(&scene, 0);
    let world =
        MissionWorld::new("hidden-20000", scene, hidden, Vec::new(), team).expect("a valid world");
    let cfg = MissionConfig {
        policy: Policy::NONE,
        ..MissionConfig::default()
    };
    let mut g = c.benchmark_group("mission");
    g.sample_size(10);
    g.bench_function("hidden_20000", |b| {
        b.iter(|| simulate(&world, &cfg).expect("a mission").reached)
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(5));
    targets = bench, bench_map, bench_hidden
}
criterion_main!(benches);
