//! Certified minimum clearance along a spline, for the collision-free verdict.
//!
//! On a parameter interval `[s0, s1]` of one cubic segment the curve stays within
//! `e = (s1 - s0)^2 / 8 * max |q''|` of its chord (the linear-interpolation error bound;
//! `q''` is linear on a segment, so its maximum is at an end). Hence the clearance on the
//! interval is at least `segment_clearance(chord) - e`, and at most the clearance of either
//! end. Intervals are split until every lower bound is within `tol` of the best upper bound
//! found; the result brackets the true minimum: `lower <= min clearance <= upper`,
//! `upper - lower <= tol`. Clearance here is the model's
//! [`ClearanceModel::exact_clearance`], the function its `segment_clearance` bounds.

use homospline_geom::{Point, Real};

use crate::clearance_model::ClearanceModel;
use crate::curve::Spline;

/// A bracket of the minimum clearance along a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CertifiedClearance {
    /// Proven lower bound of the minimum clearance.
    pub lower: Real,
    /// Clearance attained at a point of the curve (an upper bound of the minimum).
    pub upper: Real,
    /// Parameter `t` where `upper` is attained.
    pub at: Real,
    /// Where `upper` is attained.
    pub point: Point,
    /// Chord checks done.
    pub checks: usize,
}

impl CertifiedClearance {
    /// Proven collision-free: the lower bound is positive.
    pub fn collision_free(&self) -> bool {
        self.lower > 0.0
    }
}

/// An interval of a segment to check: `(segment, s0, s1, depth, clearance at s0, at s1)`.
type Interval = (usize, Real, Real, u32, Real, Real);

/// Eight intervals per segment, in the order they are popped (start of the curve first).
fn initial_intervals(spline: &Spline, model: &dyn ClearanceModel) -> Vec<Interval> {
    let mut stack = Vec::with_capacity(8 * spline.segments());
    for seg in (0..spline.segments()).rev() {
        push_segment(spline, model, seg, &mut stack);
    }
    stack
}

/// Pushes the eight initial intervals of segment `seg`, last first.
fn push_segment(
    spline: &Spline,
    model: &dyn ClearanceModel,
    seg: usize,
    stack: &mut Vec<Interval>,
) {
    let knots = spline.knots();
    let h = knots[seg + 1] - knots[seg];
    let n = 8;
    let ends: Vec<(Real, Real)> = (0..=n)
        .map(|k| {
            let s = h * k as Real / n as Real;
            (s, model.exact_clearance(&spline.eval_segment(seg, s).0))
        })
        .collect();
    for k in (0..n).rev() {
        stack.push((seg, ends[k].0, ends[k + 1].0, 0, ends[k].1, ends[k + 1].1));
    }
}

/// Most chord checks per initial interval (eight a segment) that a proof or a bracket may
/// spend in all. A curve whose clearance runs within `delta` of the margin along a stretch of
/// length `L` needs about `L / delta` intervals to prove: along a corridor of nearly constant
/// clearance (a robot of just under half its width) that ran for minutes. Past the budget a
/// proof fails (unproven, never a false "clear"), and a bracket settles for a lower bound
/// within [`SETTLE_SHARE`] of its upper one (sound, wider than `tol`: an aisle of constant
/// clearance `c` needs about `L / tol` intervals for `tol`, `L / (0.1 c)` for a tenth);
/// past [`HARD_BUDGET`] times the budget it takes each open interval's lower bound as it is.
pub const CHECKS_PER_INTERVAL: usize = 64;

/// Past this many times its budget, a bracket stops splitting (see [`CHECKS_PER_INTERVAL`]).
pub const HARD_BUDGET: usize = 16;

/// Past its budget, a bracket takes an interval whose lower bound is at least this share of
/// the least clearance found (see [`CHECKS_PER_INTERVAL`]).
pub const SETTLE_SHARE: Real = 0.9;

/// Proves the intervals on `stack` more than `above` clear, as [`is_collision_free`] does
/// with 0; unproven past [`CHECKS_PER_INTERVAL`] times the intervals it starts with.
fn prove(
    spline: &Spline,
    model: &dyn ClearanceModel,
    stack: &mut Vec<Interval>,
    above: Real,
) -> bool {
    let mut budget = CHECKS_PER_INTERVAL * stack.len().max(1);
    while let Some((seg, s0, s1, depth, d0, d1)) = stack.pop() {
        if d0 <= above || d1 <= above || budget == 0 {
            return false;
        }
        budget -= 1;
        let (p0, _, a0) = spline.eval_segment(seg, s0);
        let (p1, _, a1) = spline.eval_segment(seg, s1);
        let e = (s1 - s0).powi(2) / 8.0 * a0.norm().max(a1.norm());
        if model.segment_clearance_between(&p0, &p1, d0, d1) - e > above {
            continue;
        }
        if depth >= 60 {
            return false;
        }
        let m = 0.5 * (s0 + s1);
        let dm = model.exact_clearance(&spline.eval_segment(seg, m).0);
        stack.push((seg, m, s1, depth + 1, dm, d1));
        stack.push((seg, s0, m, depth + 1, d0, dm));
    }
    true
}

/// The segments of `spline` (between consecutive via-points) that are not proven
/// collision-free by the intervals and bounds of [`is_collision_free`], in order: where a
/// seed needs more via-points.
pub fn uncertified_segments(spline: &Spline, model: &dyn ClearanceModel) -> Vec<usize> {
    let mut stack = Vec::new();
    (0..spline.segments())
        .filter(|&seg| {
            stack.clear();
            push_segment(spline, model, seg, &mut stack);
            !prove(spline, model, &mut stack, 0.0)
        })
        .collect()
}

/// Whether `spline` is proven collision-free: the same intervals and bounds as
/// [`min_clearance`], subdivided only until each interval's lower bound is positive, and
/// stopped at the first point found in collision (or an interval that cannot be proven
/// after 60 halvings). Cheaper than a bracket when only the answer matters; it can prove
/// a curve free that `min_clearance` with a coarse `tol` leaves unproven within `tol` of 0.
pub fn is_collision_free(spline: &Spline, model: &dyn ClearanceModel) -> bool {
    is_clear_by(spline, model, 0.0)
}

/// Whether `spline` is proven more than `margin` clear of every obstacle: the test of
/// [`is_collision_free`] (which is this with 0) against `margin`. `false` at the first point
/// found within `margin`, or an interval that cannot be proven after 60 halvings (a curve
/// whose least clearance is `margin` exactly).
pub fn is_clear_by(spline: &Spline, model: &dyn ClearanceModel, margin: Real) -> bool {
    let mut stack = initial_intervals(spline, model);
    prove(spline, model, &mut stack, margin)
}

/// Brackets the minimum clearance of `spline` to within `tol` (> 0).
pub fn min_clearance(spline: &Spline, model: &dyn ClearanceModel, tol: Real) -> CertifiedClearance {
    let tol = if tol > 0.0 && tol.is_finite() {
        tol
    } else {
        1e-6
    };
    let knots = spline.knots();
    let first = spline.points()[0];
    let mut best = CertifiedClearance {
        lower: Real::INFINITY,
        upper: model.exact_clearance(&first),
        at: 0.0,
        point: first,
        checks: 0,
    };
    // Intervals carry the clearance at their ends, so each subdivision asks for one new
    // point; the ends are still noted when an interval is popped, as before.
    let mut stack = initial_intervals(spline, model);
    let budget = CHECKS_PER_INTERVAL * stack.len().max(1);
    while let Some((seg, s0, s1, depth, d0, d1)) = stack.pop() {
        let (p0, _, a0) = spline.eval_segment(seg, s0);
        let (p1, _, a1) = spline.eval_segment(seg, s1);
        for (s, p, d) in [(s0, p0, d0), (s1, p1, d1)] {
            if d < best.upper {
                best.upper = d;
                best.at = knots[seg] + s;
                best.point = p;
            }
        }
        let e = (s1 - s0).powi(2) / 8.0 * a0.norm().max(a1.norm());
        let lower = model.segment_clearance_between(&p0, &p1, d0, d1) - e;
        best.checks += 1;
        let settle = best.checks >= HARD_BUDGET * budget
            || (best.checks >= budget && lower >= SETTLE_SHARE * best.upper);
        if lower >= best.upper - tol || depth >= 60 || settle {
            best.lower = best.lower.min(lower);
            continue;
        }
        let m = 0.5 * (s0 + s1);
        let dm = model.exact_clearance(&spline.eval_segment(seg, m).0);
        stack.push((seg, m, s1, depth + 1, dm, d1));
        stack.push((seg, s0, m, depth + 1, d0, dm));
    }
    best.lower = best.lower.min(best.upper);
    best
}
