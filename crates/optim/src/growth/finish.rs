//! A polish round's interior-point finish ([`interior_finish`]): L-BFGS on the cost plus a
//! log barrier on the clearance, in stages of falling weight, and the guarded gradient it
//! (and an L-BFGS round) descends.

use homospline_geom::{Point, Real, Vector};
use homospline_spline::{
    ClearanceModel, CostTerms, EndCondition, Parametrization, Spline, gradient,
};

use super::config::GrowthConfig;
use super::guard::{Guard, SHORT_OF_TARGET, admissible, proven_at};
use super::state::{build, to_points};
#[cfg(doc)]
use super::{guard::STRICT_SLACK, state::Growth};
use crate::barrier::Barrier;
#[cfg(doc)]
use homospline_spline::is_clear_by;

/// The barrier weights of the interior-point finish's stages, as fractions of the cost it
/// starts from: each stage runs L-BFGS on the cost plus the barrier from where the last
/// stopped, so the curve comes closer to the clearance it must keep as the weight falls.
pub const FINISH_WEIGHTS: [Real; 3] = [1e-2, 1e-3, 1e-4];

/// What a round does after (or instead of) its optimiser: [`interior_finish`] or not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Finish {
    /// The optimiser alone (the loop's rounds, a repair).
    No,
    /// The optimiser, then the finish with the round's budget (a polish round).
    After,
    /// The finish alone, with half the round's budget, at most `cap` evaluations.
    Only { cap: usize },
}

/// The least budget [`Growth::finish`] runs with: two evaluations for each of the finish's
/// stages.
pub const MIN_FINISH_EVALUATIONS: usize = 2 * FINISH_WEIGHTS.len();

/// Barrier samples per segment in the finish.
pub const FINISH_SAMPLES: usize = 16;

/// The cost of a candidate that the round's guard admits and its gradient with respect to
/// the inner via-points (x, y interleaved), else `+inf` (a gradient optimiser's line search
/// backs off): out of the class or the bounds, rejected, or below the clearance target or
/// the round's starting clearance, whichever is less (a ratchet).
pub(super) fn guarded_gradient(
    sp: &Spline,
    model: &dyn ClearanceModel,
    cfg: &GrowthConfig,
    guard: &Guard<'_>,
    current: Real,
) -> (Real, Vec<Real>) {
    if !admissible(sp, guard, cfg.guard_samples) {
        let inner = 2 * sp.points().len().saturating_sub(2);
        return (Real::INFINITY, vec![0.0; inner]);
    }
    let (terms, g) = gradient(sp, model, &cfg.cost);
    guarded_value(terms, &g, guard, current)
}

/// [`guarded_gradient`] of an admissible candidate from its cost terms and gradient `g`
/// (one vector per inner via-point).
fn guarded_value(
    terms: CostTerms,
    g: &[Vector],
    guard: &Guard<'_>,
    current: Real,
) -> (Real, Vec<Real>) {
    let m = terms.min_clearance;
    if guard.rejects(m) || m < guard.clearance_target.min(current) {
        (Real::INFINITY, vec![0.0; 2 * g.len()])
    } else {
        (terms.total, g.iter().flat_map(|v| [v.x, v.y]).collect())
    }
}

/// A polish round's finish ([`Growth::polish`]): from the round's result `x0` (of value
/// `value0`), L-BFGS on the cost plus a [`Barrier`] on the clearance at the round's
/// clearance to keep (the target, or the round's starting clearance if less, or the floor,
/// or 0 for a collision-free guard), in the stages of [`FINISH_WEIGHTS`], each with a third
/// of the round's `budget` (a value with its gradient counts one evaluation). Nelder-Mead at
/// a round's budget stops far from the best curve of its via-points where the constraint
/// `m(C) >= target` binds; L-BFGS against the guard's rejection alone
/// stalls on that constraint, while the barrier lets it slide along it. A stage's curve is
/// kept only if it is certified collision-free (for a collision-free guard) and inside the
/// bounds, and proven at the target and the floor ([`is_clear_by`] less [`STRICT_SLACK`],
/// on models that bound how the clearance bends), and the stages stop at the first that is
/// not: L-BFGS presses against the constraint, and the cost's search of `m(C)` can miss a
/// dip that it found. Returns the last kept stage's point and its guard value if that is
/// below `value0`, else `x0` and `value0`, with the evaluations spent (a value with its
/// gradient counts one, though it costs more than a value; measured: docs/performance.md,
/// "Measurements behind the defaults"). Only for
/// uniform parameters (the spline is then linear in its points); otherwise it returns `x0`
/// at once.
#[allow(clippy::too_many_arguments)]
pub(super) fn interior_finish(
    model: &dyn ClearanceModel,
    cfg: &GrowthConfig,
    guard: &Guard<'_>,
    (s, t, end): (Point, Point, EndCondition),
    x0: Vec<Real>,
    value0: Real,
    budget: usize,
    current: Real,
) -> (Vec<Real>, Real, usize) {
    let keep = guard
        .clearance_target
        .min(current)
        .max(guard.clearance_floor)
        .max(if guard.collision_free {
            0.0
        } else {
            Real::NEG_INFINITY
        });
    if cfg.parametrization != Parametrization::Uniform
        || x0.is_empty()
        || value0.is_nan()
        || value0 >= SHORT_OF_TARGET
        || !keep.is_finite()
    {
        return (x0, value0, 0);
    }
    let width = if cfg.cost.dm > 0.0 {
        cfg.cost.dm / 6.0
    } else {
        0.5
    };
    // What the round's acceptance and the polish will ask of the curve, asked of each
    // stage's: certified collision-free and inside the bounds, proven at the floor and at
    // the target (where the model bounds how the clearance bends). Without it a stage's
    // curve that failed later would cost the round the simplex's result too.
    let certifiable = model.bend_radius().is_some();
    let proven = |x: &[Real]| {
        build(&to_points(s, t, x), end, cfg).is_some_and(|sp| {
            guard.certifies(&sp, model)
                && (!certifiable
                    || (proven_at(&sp, model, guard.clearance_target)
                        && proven_at(&sp, model, guard.clearance_floor)))
        })
    };
    let mut spent = 0usize;
    let mut x = x0.clone();
    for fraction in FINISH_WEIGHTS {
        let barrier = Barrier {
            at: keep,
            width,
            weight: fraction * value0.abs().max(1.0),
            samples_per_segment: FINISH_SAMPLES,
        };
        let mut fg = |y: &[Real]| -> (Real, Vec<Real>) {
            spent += 1;
            let Some(sp) = build(&to_points(s, t, y), end, cfg) else {
                return (Real::INFINITY, vec![0.0; y.len()]);
            };
            // [`guarded_gradient`], then the barrier (only for a finite value), on this
            // thread. Worked out on the other core (`rayon::join`, once an evaluation), it
            // saved 5 to 11 % of a plan where the machine woke the other thread quickly and
            // cost 23 to 43 % where it did not (docs/performance.md, *plan*).
            if !admissible(&sp, guard, cfg.guard_samples) {
                return (Real::INFINITY, vec![0.0; y.len()]);
            }
            let (terms, grad) = gradient(&sp, model, &cfg.cost);
            let (v, mut g) = guarded_value(terms, &grad, guard, current);
            if !v.is_finite() {
                return (v, g);
            }
            match barrier.value_and_gradient(&sp, model) {
                Some((b, bg)) => {
                    for (gi, bv) in g.chunks_exact_mut(2).zip(&bg) {
                        gi[0] += bv.x;
                        gi[1] += bv.y;
                    }
                    (v + b, g)
                }
                None => (Real::INFINITY, g),
            }
        };
        let lb = super::round::lbfgs_for(
            cfg.lbfgs_value_tolerance,
            (budget / FINISH_WEIGHTS.len()).max(2),
        );
        let out = lb.minimize(&mut fg, &x);
        if !out.value.is_finite() || !proven(&out.x) {
            break;
        }
        x = out.x;
    }
    let value = build(&to_points(s, t, &x), end, cfg)
        .map_or(Real::INFINITY, |sp| guard.cost(&sp, model, cfg));
    if value < value0 {
        (x, value, spent)
    } else {
        (x0, value0, spent)
    }
}
