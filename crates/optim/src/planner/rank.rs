//! Comparing and picking classes: the plan's rank order and the chosen class, the successive
//! halving that stops classes that cannot win after their first round, the limited-overlap
//! selection of diverse classes, the overlap of each class with the chosen one, and the
//! Pareto set.

use homospline_geom::Real;

use super::config::PlanConfig;
use super::report::ClassPlan;

/// The order of the plan's ranking: collision-free and safe first, then collision-free,
/// then the rest; within each by cost, then by signature.
pub(super) fn rank_order(a: &ClassPlan, b: &ClassPlan) -> std::cmp::Ordering {
    let group = |c: &ClassPlan| match (c.collision_free, c.safe) {
        (true, true) => 0,
        (true, false) => 1,
        _ => 2,
    };
    group(a)
        .cmp(&group(b))
        .then(a.cost.total.total_cmp(&b.cost.total))
        .then(a.signature.cmp(&b.signature))
}

/// Whether the plan may choose the class: collision-free and certified at least as clear as
/// the floor. The chosen class is the first such in [`rank_order`].
pub(super) fn choosable(c: &ClassPlan, cfg: &PlanConfig) -> bool {
    c.collision_free && c.certified_clearance >= cfg.clearance_floor
}

/// The classes of `done` (by seed index) in rank order ([`rank_order`]), each numbered
/// from 1, and the rank of the chosen class: the first [`choosable`] one.
pub(super) fn rank(
    mut done: Vec<(usize, ClassPlan)>,
    cfg: &PlanConfig,
) -> (Vec<ClassPlan>, Option<usize>) {
    done.sort_by_key(|(i, _)| *i);
    let mut classes: Vec<ClassPlan> = done.into_iter().map(|(_, c)| c).collect();
    // Rank: collision-free and safe first, then collision-free, then the rest; within each,
    // by cost; ties by signature for determinism.
    classes.sort_by(rank_order);
    let first = classes.iter().position(|c| choosable(c, cfg));
    if let Some(first) = first {
        let chosen = cfg
            .detour
            .map_or(first, |d| without_detour(&classes, first, d, cfg));
        if chosen != first {
            // The class chosen instead ranks just before the one it replaced.
            let c = classes.remove(chosen);
            classes.insert(first, c);
        }
    }
    for (i, c) in classes.iter_mut().enumerate() {
        c.rank = i + 1;
    }
    (classes, first.map(|f| f + 1))
}

/// [`PlanConfig::detour`]: from the class at `from` (choosable), the class that replaces it,
/// step by step, while a choosable class is more than `d.length_ratio` times shorter and
/// keeps `d.clearance_share` of its clearance (the first such in rank order at each step).
fn without_detour(
    classes: &[ClassPlan],
    from: usize,
    d: super::config::Detour,
    cfg: &PlanConfig,
) -> usize {
    let mut chosen = from;
    loop {
        let c = &classes[chosen];
        let shorter = classes.iter().position(|o| {
            choosable(o, cfg)
                && o.length * d.length_ratio < c.length
                && o.min_clearance >= d.clearance_share * c.min_clearance
        });
        match shorter {
            Some(o) => chosen = o,
            None => return chosen,
        }
    }
}

/// Ranks of the Pareto-optimal classes over (length, roughness, minimum clearance).
pub(super) fn pareto(classes: &[ClassPlan]) -> Vec<usize> {
    classes
        .iter()
        .filter(|a| {
            !classes.iter().any(|b| {
                let no_worse = b.length <= a.length
                    && b.cost.roughness <= a.cost.roughness
                    && b.min_clearance >= a.min_clearance;
                let better = b.length < a.length
                    || b.cost.roughness < a.cost.roughness
                    || b.min_clearance > a.min_clearance;
                no_worse && better
            })
        })
        .map(|c| c.rank)
        .collect()
}

/// A class after its first round, as [`outclassed`] weighs it.
#[derive(Clone, Copy)]
pub(super) struct Score {
    /// The class's index among the seeds (ties).
    pub(super) class: usize,
    /// The outer guard's value of its curve: short of the target ranks after every class
    /// that keeps it.
    pub(super) standing: Real,
    /// Its weighted cost.
    pub(super) total: Real,
    /// It can be the reference: its curve keeps the dm rule's target, the target is `dm`
    /// itself, and it is certified clear.
    pub(super) reference: bool,
    /// Its loop ended with its first round (nothing to stop).
    pub(super) done: bool,
}

/// The classes stopped after their first round ([`outclassed`]) and the cost that stopped
/// them.
pub(super) struct Pruning {
    /// One flag per class, in the order of the scores: stopped.
    pub(super) stop: Vec<bool>,
    /// The reference class's weighted cost after its first round.
    pub(super) reference_cost: Real,
}

/// Which classes cannot win after their first round, by the ratio `ratio` ([`PlanConfig::
/// prune`]). The reference is the class that ranks first now among those sure to rank in
/// the first group at the end (collision-free and safe): its curve keeps the dm rule's
/// target, and the target is `dm` itself (not a narrow passage's share of it), it meets the
/// floor, and it is certified clear. Its cost only falls in later rounds (the growth loop
/// returns its best curve), and it stays in the first group (its curves keep the target), so
/// a class whose cost exceeds `ratio` times the reference's would have to lower its own by
/// more than the ratio in the rounds it skips to overtake it. `None` when no class
/// qualifies (no dm rule, or no class at `dm` yet) or none would be stopped.
pub(super) fn outclassed(scores: &[Option<Score>], ratio: Real) -> Option<Pruning> {
    let r = scores
        .iter()
        .enumerate()
        .filter_map(|(pos, s)| s.filter(|s| s.reference).map(|s| (pos, s)))
        .min_by(|(_, a), (_, b)| {
            a.standing
                .total_cmp(&b.standing)
                .then(a.class.cmp(&b.class))
        })?;
    let (reference, reference_cost) = (r.0, r.1.total);
    let bar = ratio * reference_cost;
    let stop: Vec<bool> = scores
        .iter()
        .enumerate()
        .map(|(pos, s)| pos != reference && s.is_some_and(|s| !s.done && s.total > bar))
        .collect();
    stop.contains(&true).then_some(Pruning {
        stop,
        reference_cost,
    })
}

/// Relative slack between a class's cost as the optimiser evaluates it (far circles'
/// potential truncated within `1e-6` of the total) and as it is reported (nothing left out),
/// when the planner checks that a class run to its end came in under the reference cost of
/// a pruning.
const PRUNE_SLACK: Real = 1e-5;

/// Whether the stop held: the pruning assumed that a class run to its end would rank first
/// at no more than the reference's first-round cost; it held if one of `classes` not
/// stopped is collision-free, safe, at the floor and within [`PRUNE_SLACK`] of that cost.
pub(super) fn pruning_holds<'a>(
    pruning: &Pruning,
    classes: impl IntoIterator<Item = &'a ClassPlan>,
    cfg: &PlanConfig,
) -> bool {
    let bar = pruning.reference_cost * (1.0 + PRUNE_SLACK);
    classes.into_iter().any(|c| {
        !c.pruned
            && c.collision_free
            && c.safe
            && c.certified_clearance >= cfg.clearance_floor
            && c.cost.total <= bar
    })
}

/// The length of a class path on each graph edge it uses.
pub(super) type EdgeLengths = Vec<(usize, Real)>;

/// Greedy limited-overlap selection: classes in cost order, each kept if what it shares with
/// every class kept before it is at most `limit` of either's length, until `k` are kept. (The
/// shared length of two graph paths is the length of their common edges: symmetric.)
pub(super) fn limited_overlap(
    paths: &[EdgeLengths],
    lengths: &[Real],
    limit: Real,
    k: usize,
) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::new();
    for i in 0..paths.len() {
        if kept.len() == k {
            break;
        }
        if kept
            .iter()
            .all(|&j| shared_length(&paths[i], &paths[j]) <= limit * lengths[i].min(lengths[j]))
        {
            kept.push(i);
        }
    }
    kept
}

/// The length of `a` on edges that `b` uses too.
fn shared_length(a: &EdgeLengths, b: &EdgeLengths) -> Real {
    a.iter()
        .filter(|(e, _)| b.iter().any(|(f, _)| f == e))
        .map(|(_, l)| l)
        .sum()
}

/// Sets each class's overlap with the chosen class (rank `best`), by graph edges: `edges`
/// holds each seed's graph path by edge, in the order of `signatures` (the seeds' classes).
pub(super) fn set_overlaps(
    classes: &mut [ClassPlan],
    best: Option<usize>,
    signatures: &[String],
    edges: &[EdgeLengths],
) {
    let edges_of = |sig: &str| {
        signatures
            .iter()
            .position(|s| s == sig)
            .and_then(|i| edges.get(i))
    };
    if let Some(chosen) = best
        .and_then(|b| edges_of(&classes[b - 1].signature))
        .cloned()
    {
        for c in classes.iter_mut() {
            if let Some(own) = edges_of(&c.signature) {
                let total: Real = own.iter().map(|(_, l)| l).sum();
                if total > 0.0 {
                    c.overlap = shared_length(own, &chosen) / total;
                }
            }
        }
    }
}
