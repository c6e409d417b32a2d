//! The classes' rounds as jobs on a shared board, so that no core idles while there is work:
//! first rounds first, rounds ahead of the pruning decision on a free core, then the rounds
//! left (the class with the most work left first) and the reports, one job at a time.
//!
//! A class's rounds depend only on the class (its seed, settings and guard), and the decision
//! on the first rounds' scores only, so the plan does not depend on which thread ran what or
//! when: a round run ahead for a class that the decision stops is undone (it is called off
//! part-way if still running), and the class reports its first round's curve, as it would
//! have without running ahead.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use homospline_geom::Real;

use super::class::{ClassRun, ClassTask, start_class};
use super::config::PlanConfig;
use super::rank::{Pruning, Score, outclassed};
use super::seed::{SeedPath, class_seed};
use super::world::World;
use crate::growth::Growth;

/// A class's place on the board between jobs.
struct Slot<'w> {
    /// The class's index among the seeds.
    class: usize,
    /// `None` before its first job and while a job has it.
    task: Option<ClassTask<'w>>,
    /// Its first round has run (and, with pruning, it has been scored).
    started: bool,
    /// A job has it.
    running: bool,
    /// Its loop has rounds left.
    more: bool,
    score: Option<Score>,
    /// The loop and its time after the first round, kept while rounds run ahead of the
    /// decision.
    snapshot: Option<(Option<Growth>, Real)>,
    /// Stopped by the decision.
    pruned: bool,
    run: Option<ClassRun>,
}

/// What a worker does next.
enum Job<'w> {
    /// Set the class (its seed index) up and run its first round.
    Start(usize),
    /// Run one more round (`ahead`: before the decision).
    Round { task: ClassTask<'w>, ahead: bool },
    /// The class's plan.
    Report(ClassTask<'w>),
}

/// What a job gives back, besides the class's task.
enum Done {
    /// Rounds left, and the class's score (with pruning).
    Start(bool, Option<Score>),
    /// Rounds left; `None`: called off.
    Round(Option<bool>),
    Report(Box<ClassRun>),
}

/// The classes run to their ends: tasks and runs in the order given, and the decision.
pub(super) struct Ran<'w> {
    pub tasks: Vec<(usize, ClassTask<'w>)>,
    pub runs: Vec<(usize, ClassRun)>,
    pub pruning: Option<Pruning>,
}

struct Board<'w> {
    slots: Vec<Slot<'w>>,
    /// The decision is taken (at once without pruning).
    decided: bool,
    pruning: Option<Pruning>,
    /// Workers at work.
    active: usize,
}

/// Everything a worker reads.
struct Shop<'w> {
    world: &'w World<'w>,
    cfg: &'w PlanConfig,
    seeds: &'w [SeedPath],
    /// The seeds are class paths, made into seeds on this cell in their first jobs.
    raw: Option<Real>,
    graph_cell: Option<Real>,
    threads: usize,
    board: Mutex<Board<'w>>,
    /// One per slot: a round run ahead is not wanted.
    stops: Vec<AtomicBool>,
}

/// The classes `order` (seed indices, longest first) run to their ends and reported, on the
/// current thread pool, stopped after their first rounds by `cfg.prune`; with `raw`, each
/// seed is first made from its class path ([`class_seed`]) in the class's first job.
pub(super) fn run_classes<'w>(
    world: &'w World<'w>,
    cfg: &'w PlanConfig,
    seeds: &'w [SeedPath],
    raw: Option<Real>,
    graph_cell: Option<Real>,
    order: &[usize],
) -> Ran<'w> {
    let slots = order
        .iter()
        .map(|&class| Slot {
            class,
            task: None,
            started: false,
            running: false,
            more: false,
            score: None,
            snapshot: None,
            pruned: false,
            run: None,
        })
        .collect();
    let shop = Shop {
        world,
        cfg,
        seeds,
        raw,
        graph_cell,
        threads: rayon::current_num_threads().max(1),
        board: Mutex::new(Board {
            slots,
            decided: cfg.prune.is_none(),
            pruning: None,
            active: 0,
        }),
        stops: order.iter().map(|_| AtomicBool::new(false)).collect(),
    };
    if !order.is_empty() {
        lock(&shop.board).active = 1;
        rayon::scope(|s| s.spawn(|s| work(s, &shop)));
    }
    let board = shop.board.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut tasks = Vec::with_capacity(board.slots.len());
    let mut runs = Vec::with_capacity(board.slots.len());
    for slot in board.slots {
        // Every slot is reported before the last worker leaves (a job that panicked has
        // re-raised its panic from the scope).
        debug_assert!(
            slot.run.is_some() || cfg.interrupt.is_raised(),
            "class {} not reported",
            slot.class
        );
        if cfg.interrupt.is_raised() {
            continue;
        }
        if let Some(task) = slot.task {
            let run = slot.run.unwrap_or_else(|| task.report(world, cfg));
            tasks.push((slot.class, task));
            runs.push((slot.class, run));
        }
    }
    Ran {
        tasks,
        runs,
        pruning: board.pruning,
    }
}

fn lock<'m, 'w>(m: &'m Mutex<Board<'w>>) -> std::sync::MutexGuard<'m, Board<'w>> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A worker: takes jobs until none is left to take, and calls in the pool's idle threads
/// when it took one and work may be left for them (a worker called in for nothing leaves at
/// once). It never waits on another.
fn work<'s, 'w: 's>(s: &rayon::Scope<'s>, shop: &'s Shop<'w>) {
    let mut b = lock(&shop.board);
    loop {
        // Interrupted: no further job; the plan returns `Interrupted`.
        let job = (!shop.cfg.interrupt.is_raised())
            .then(|| pick(&mut b))
            .flatten();
        let Some((pos, job)) = job else {
            b.active -= 1;
            return;
        };
        let idle = shop.threads.saturating_sub(b.active);
        for _ in 0..idle {
            b.active += 1;
            s.spawn(|s| work(s, shop));
        }
        drop(b);
        let done = execute(shop, pos, job);
        b = lock(&shop.board);
        finish(&mut b, shop, pos, done);
    }
}

/// Takes the slot's task for a job (`None` when a job has it).
fn take<'w>(slot: &mut Slot<'w>) -> Option<ClassTask<'w>> {
    let task = slot.task.take()?;
    slot.running = true;
    Some(task)
}

/// The next job, marked as taken: a first round; after the decision, a round of the class
/// with the most work left, else a report; before it, a round ahead for the class that
/// stands best.
fn pick<'w>(b: &mut Board<'w>) -> Option<(usize, Job<'w>)> {
    if (!ahead_first() || b.decided || !b.slots.iter().any(|s| s.started))
        && let Some(job) = start_next(b)
    {
        return Some(job);
    }
    if b.decided {
        let free = |s: &Slot<'_>| s.started && s.task.is_some();
        // The class with the most work left first (its rounds form a chain: started last,
        // it would run alone at the end); ties in the given order.
        if let Some((pos, _)) = b
            .slots
            .iter()
            .enumerate()
            .filter(|(_, s)| free(s) && !s.pruned && s.more)
            .map(|(pos, s)| (pos, s.task.as_ref().map_or(0, ClassTask::budget_left)))
            .min_by_key(|&(pos, left)| (std::cmp::Reverse(left), pos))
        {
            let task = take(&mut b.slots[pos])?;
            return Some((pos, Job::Round { task, ahead: false }));
        }
        let pos = b
            .slots
            .iter()
            .position(|s| free(s) && s.run.is_none() && (s.pruned || !s.more))?;
        return Some((pos, Job::Report(take(&mut b.slots[pos])?)));
    }
    // Before the decision (only with pruning: without, it is taken at once).
    let ahead = b
        .slots
        .iter()
        .enumerate()
        .filter(|(_, s)| s.started && s.more && s.task.is_some())
        .min_by(|(_, a), (_, c)| {
            let standing = |s: &Slot<'_>| s.score.map_or(Real::INFINITY, |s| s.standing);
            standing(a)
                .total_cmp(&standing(c))
                .then(a.class.cmp(&c.class))
        })
        .map(|(pos, _)| pos);
    let Some(pos) = ahead else {
        // First rounds left: reached only in the test's order, once nothing runs ahead.
        return start_next(b);
    };
    let slot = &mut b.slots[pos];
    let task = take(slot)?;
    if slot.snapshot.is_none() {
        slot.snapshot = Some((task.state.clone(), task.time_ms));
    }
    Some((pos, Job::Round { task, ahead: true }))
}

/// The first round of the next class not started, marked as taken.
fn start_next<'w>(b: &mut Board<'w>) -> Option<(usize, Job<'w>)> {
    let pos = b.slots.iter().position(|s| !s.started && !s.running)?;
    b.slots[pos].running = true;
    Some((pos, Job::Start(b.slots[pos].class)))
}

/// Tests only: run rounds ahead before any other first round, so that a single thread runs
/// (and undoes) them in a known order. Plans must not change with it.
#[cfg(test)]
pub(super) static AHEAD_FIRST: AtomicBool = AtomicBool::new(false);

/// Tests only: stopped classes put back to their first round's loop.
#[cfg(test)]
pub(super) static UNDONE: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

#[cfg(test)]
fn ahead_first() -> bool {
    AHEAD_FIRST.load(Ordering::Relaxed)
}

#[cfg(not(test))]
fn ahead_first() -> bool {
    false
}

/// Runs a job, outside the lock.
fn execute<'w>(shop: &Shop<'w>, pos: usize, job: Job<'w>) -> (ClassTask<'w>, Done) {
    let model = shop.world.model;
    match job {
        Job::Start(class) => {
            let (poly, sig, gcost) = &shop.seeds[class];
            let made;
            let poly = match (shop.raw, sig) {
                (Some(cell), Some(sig)) => {
                    made = class_seed(shop.world, cell, poly, sig);
                    &made
                }
                _ => poly,
            };
            let mut task = start_class(
                shop.world,
                shop.cfg,
                poly,
                sig.as_ref(),
                *gcost,
                shop.graph_cell,
            );
            let more = task
                .step_unless(model, &|| shop.cfg.interrupt.is_raised())
                .unwrap_or(false);
            let score = shop.cfg.prune.map(|_| task.score(class, model));
            (task, Done::Start(more, score))
        }
        Job::Round { mut task, ahead } => {
            // An interrupt calls the round off part-way (the class ends where it is; the plan
            // returns `Interrupted`); a round ahead is also called off by the decision.
            let interrupt = &shop.cfg.interrupt;
            let more = if ahead {
                let stop = &shop.stops[pos];
                task.step_unless(model, &|| {
                    stop.load(Ordering::Relaxed) || interrupt.is_raised()
                })
            } else {
                Some(
                    task.step_unless(model, &|| interrupt.is_raised())
                        .unwrap_or(false),
                )
            };
            (task, Done::Round(more))
        }
        Job::Report(task) => {
            let run = task.report(shop.world, shop.cfg);
            (task, Done::Report(Box::new(run)))
        }
    }
}

/// Puts a finished job's class back, and takes the decision once every class is scored.
fn finish<'w>(b: &mut Board<'w>, shop: &Shop<'w>, pos: usize, (task, done): (ClassTask<'w>, Done)) {
    let slot = &mut b.slots[pos];
    slot.running = false;
    slot.task = Some(task);
    match done {
        Done::Start(more, score) => {
            slot.started = true;
            slot.more = more;
            slot.score = score;
        }
        // Called off (`None`): the loop is as it was before the round.
        Done::Round(more) => slot.more = more.unwrap_or(slot.more),
        Done::Report(run) => slot.run = Some(*run),
    }
    if !b.decided && b.slots.iter().all(|s| s.started) {
        let scores: Vec<Option<Score>> = b.slots.iter().map(|s| s.score).collect();
        b.pruning = shop.cfg.prune.and_then(|ratio| outclassed(&scores, ratio));
        if let Some(p) = &b.pruning {
            for ((slot, &stop), flag) in b.slots.iter_mut().zip(&p.stop).zip(&shop.stops) {
                slot.pruned = stop;
                if stop {
                    flag.store(true, Ordering::Relaxed);
                }
            }
        }
        b.decided = true;
    }
    if b.decided {
        // A stopped class goes back to its first round's loop; a kept one no longer needs it.
        for slot in b.slots.iter_mut().filter(|s| !s.running) {
            if let Some(task) = slot.task.as_mut() {
                task.pruned = slot.pruned;
                if let Some((state, time_ms)) = slot.snapshot.take()
                    && slot.pruned
                {
                    task.state = state;
                    task.time_ms = time_ms;
                    #[cfg(test)]
                    UNDONE.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
    }
}
