//! After the classes' rounds: the repair round of each class that could rank first, and the
//! chosen class's polish ([`PlanConfig::polish`]) or its finish within the plan's work budget
//! ([`PlanConfig::finish_within`]), each kept only if the class still stands where it did.

use homospline_geom::Real;
use rayon::prelude::*;

use super::class::{ClassRun, ClassTask};
use super::config::PlanConfig;
use super::pool::in_pool;
use super::rank::{choosable, rank_order};
use super::world::World;
#[cfg(doc)]
use crate::growth::Growth;

/// The repair round of every class that could rank first ([`ClassTask::repair`]): one whose
/// loop ended on a curve that its cost's `m(C)` took to keep the target but that is not
/// proven to, and that costs less than every class reported certified safe (at the
/// clearance floor). Each is reported again in its place in `runs`.
pub(super) fn repair_contenders(
    world: &World<'_>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    tasks: &mut [(usize, ClassTask<'_>)],
    runs: &mut [(usize, ClassRun)],
) {
    let best_safe = runs
        .iter()
        .filter(|(_, (c, _))| {
            c.collision_free && c.safe && c.certified_clearance >= cfg.clearance_floor
        })
        .map(|(_, (c, _))| c.cost.total)
        .fold(Real::INFINITY, Real::min);
    let contenders: Vec<usize> = runs
        .iter()
        .filter(|(_, (c, _))| c.collision_free && c.cost.total < best_safe)
        .map(|(i, _)| *i)
        .collect();
    if contenders.is_empty() {
        return;
    }
    let model = world.model;
    let repaired: Vec<(usize, ClassRun)> = in_pool(pool, || {
        tasks
            .par_iter_mut()
            .with_max_len(1)
            .filter(|(i, _)| contenders.contains(i))
            .filter_map(|(i, task)| task.repair(model).then(|| (*i, task.report(world, cfg))))
            .collect()
    });
    for (i, run) in repaired {
        if let Some(slot) = runs.iter_mut().find(|(j, _)| *j == i) {
            slot.1 = run;
        }
    }
}

/// [`PlanConfig::polish`]: the class the plan will choose (first in [`rank_order`] among
/// the [`choosable`] classes) runs its polish
/// rounds and is reported again in its place in `runs`. The polish is kept only if the
/// class's new report still stands where the old one did: the same class, collision-free,
/// at least as clear as the floor, safe if it was, and no dearer (so it stays first);
/// otherwise its curve is put back, its rounds and evaluations still counted. (Without a
/// finite clearance target, under `--soft-dm` or from a straight seed, the rounds have
/// nothing else to hold them.) A class stopped by the pruning is not polished.
/// Without polish rounds, [`PlanConfig::finish_within`]: if the classes' evaluations so far
/// are fewer, the chosen class gets the finish alone ([`Growth::finish`]) with what is left,
/// kept or put back the same way.
pub(super) fn polish_chosen(
    world: &World<'_>,
    cfg: &PlanConfig,
    tasks: &mut [(usize, ClassTask<'_>)],
    runs: &mut [(usize, ClassRun)],
) {
    if world.grid_is_exact {
        // Scenes only: a map's classes are optimised while its search goes on.
        return;
    }
    let spent: usize = runs.iter().map(|(_, (c, _))| c.evaluations).sum();
    let finish_cap = cfg.finish_within.unwrap_or(0).saturating_sub(spent);
    if cfg.polish == 0 && finish_cap == 0 {
        return;
    }
    let Some((chosen, old)) = runs
        .iter()
        .filter(|(_, (c, _))| choosable(c, cfg))
        .min_by(|(_, (a, _)), (_, (b, _))| rank_order(a, b))
        .map(|(i, (c, _))| (*i, c.clone()))
    else {
        return;
    };
    let Some((_, task)) = tasks.iter_mut().find(|(i, _)| *i == chosen) else {
        return;
    };
    let saved = task.state.clone();
    let ran = if cfg.polish > 0 {
        task.polish(world.model, cfg.polish)
    } else {
        task.finish(world.model, finish_cap)
    };
    if !ran {
        return;
    }
    let mut run = task.report(world, cfg);
    let new = &run.0;
    let stands = new.signature == old.signature
        && choosable(new, cfg)
        && (new.safe || !old.safe)
        && new.cost.total <= old.cost.total;
    if !stands {
        if let (Some(g), Some(earlier)) = (task.state.as_mut(), saved) {
            g.undo_to(earlier);
        }
        run = task.report(world, cfg);
    }
    if let Some(slot) = runs.iter_mut().find(|(i, _)| *i == chosen) {
        slot.1 = run;
    }
}
