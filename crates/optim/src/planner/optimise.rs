//! Optimising the classes once the search has ended (a scene's; a map's under limited
//! overlap): every class on the board with successive halving, the repairs, the pruning's
//! check, the chosen class's polish or finish, and the dense retry when no class came out
//! clear.

use homospline_geom::Real;
use rayon::prelude::*;

use super::board;
use super::class::{ClassRun, ClassTask};
use super::config::PlanConfig;
use super::finish::{polish_chosen, repair_contenders};
use super::pool::in_pool;
use super::rank::pruning_holds;
use super::report::ClassPlan;
use super::seed::SeedPath;
use super::world::World;
#[cfg(doc)]
use crate::growth::Growth;

/// The classes of `seeds` optimised and reported, by seed index; with `raw`, each seed is
/// first made from its class path on that cell.
pub(super) fn optimise_classes(
    world: &World<'_>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    seeds: &[SeedPath],
    raw: Option<Real>,
    graph_cell: Option<Real>,
) -> Vec<(usize, ClassPlan)> {
    let order = longest_first(seeds);
    // Successive halving (`cfg.prune`, with either optimiser: its doc says why): every class
    // runs its first round (and is scored in its own job), then the classes that cannot win
    // stop ([`outclassed`](super::rank::outclassed)) and the others run their rounds left.
    // The decision depends on the first rounds only, not on the threads: the board
    // ([`board`]) runs rounds ahead of it only on a core that would otherwise wait, and
    // undoes them for a class it stops. (Without a decision point, the tasks ran to their
    // ends one after the other on each thread, and the decision came after the classes to be
    // stopped had run every round, which made plans much slower; measured:
    // docs/performance.md, "Measurements behind the defaults".)
    let board::Ran {
        mut tasks,
        mut runs,
        pruning,
    } = in_pool(pool, || {
        board::run_classes(world, cfg, seeds, raw, graph_cell, &order)
    });
    if cfg.interrupt.is_raised() {
        return Vec::new();
    }
    // A class whose loop ended on a curve that its cost's `m(C)` (searched around the
    // worst quadrature node) took to keep its target, but that is not proven to, was
    // optimised against a constraint it did not see ([`Growth::needs_repair`]). If it
    // could rank first (it costs less than every class reported certified safe), it
    // runs one more round searching every stretch between nodes, and is reported
    // again. A class that cannot rank first is reported as it is: its certificate
    // says how clear it is (convex's class `e`: a repair would cost the plan half its
    // time for an alternative).
    repair_contenders(world, cfg, pool, &mut tasks, &mut runs);
    // The stop assumed that a class run to its end would rank first at no more than
    // the reference's first-round cost. If none does (its certification found it
    // less clear than its cost evaluations did), the stopped classes run on after
    // all.
    if let Some(p) = &pruning
        && !pruning_holds(p, runs.iter().map(|(_, (c, _))| c), cfg)
    {
        runs = run_on(world, cfg, pool, &mut tasks);
        repair_contenders(world, cfg, pool, &mut tasks, &mut runs);
    }
    polish_chosen(world, cfg, &mut tasks, &mut runs);
    if cfg.interrupt.is_raised() {
        return Vec::new();
    }
    retry_dense(world, cfg, pool, graph_cell, &mut tasks, runs)
}

/// Seed indices, longest seed first (a scene's class paths, its seeds still to be made):
/// the classes' times differ by up to 3x, and a long class started last would run alone at
/// the end. Each class is independent, so the order changes no result.
fn longest_first(seeds: &[SeedPath]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..seeds.len()).collect();
    let seed_length = |i: usize| -> Real { super::polyline_length(&seeds[i].0) };
    order.sort_by(|&a, &b| seed_length(b).total_cmp(&seed_length(a)).then(a.cmp(&b)));
    order
}

/// Every class stopped by the pruning runs on after all: the rounds left of every class,
/// and each reported again.
fn run_on(
    world: &World<'_>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    tasks: &mut [(usize, ClassTask<'_>)],
) -> Vec<(usize, ClassRun)> {
    let model = world.model;
    for (_, task) in tasks.iter_mut() {
        task.pruned = false;
    }
    in_pool(pool, || {
        tasks
            .par_iter_mut()
            .with_max_len(1)
            .filter(|(_, task)| !task.pruned)
            .for_each(|(_, task)| task.run(model));
    });
    in_pool(pool, || {
        tasks
            .par_iter_mut()
            .with_max_len(1)
            .map(|(i, task)| (*i, task.report(world, cfg)))
            .collect()
    })
}

/// The classes of `runs` as reported, unless no class came out clear: then those that could
/// not start from a clear seed are tried again with dense via-points (a winding passage too
/// narrow for a spline through `max_via_points` via-points may be the only way). Only then:
/// dense seeds cost several times a class's usual time, and re-plans on the move wait for
/// them. The second pass starts from the dense seed; the first pass's curve stands unless
/// the dense one comes out clear. (The straight seed has no class to follow: it is never
/// marked.)
fn retry_dense(
    world: &World<'_>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    graph_cell: Option<Real>,
    tasks: &mut [(usize, ClassTask<'_>)],
    runs: Vec<(usize, ClassRun)>,
) -> Vec<(usize, ClassPlan)> {
    let again: Vec<usize> = runs
        .iter()
        .filter(|(_, (_, retry))| *retry)
        .map(|(i, _)| *i)
        .collect();
    let mut done: Vec<(usize, ClassPlan)> = runs.into_iter().map(|(i, (c, _))| (i, c)).collect();
    if !again.is_empty() && !done.iter().any(|(_, c)| c.collision_free) {
        let firsts = &done;
        let retried: Vec<(usize, ClassPlan)> = in_pool(pool, || {
            tasks
                .par_iter_mut()
                .with_max_len(1)
                .filter(|(i, _)| again.contains(i))
                .filter_map(|(i, task)| {
                    let first = &firsts.iter().find(|(j, _)| j == i)?.1;
                    task.dense(world, cfg, graph_cell, first).map(|c| (*i, c))
                })
                .collect()
        });
        for (i, c) in retried {
            if let Some(slot) = done.iter_mut().find(|(j, _)| *j == i) {
                slot.1 = c;
            }
        }
    }
    done
}
