//! Clearance queries on the world's model that the seeding asks: the clearances of points
//! in one batch, a path's least vertex clearance, and whether a segment keeps a clearance.

use homospline_geom::{Point, Real};
use homospline_spline::ClearanceModel;

/// The clearance at each of `pts`, without gradients, in one batch
/// ([`ClearanceModel::clearances`]).
pub(super) fn clearances_of(model: &dyn ClearanceModel, pts: &[Point]) -> Vec<Real> {
    let mut out = vec![0.0; pts.len()];
    model.clearances(pts, &mut out);
    out
}

/// The least clearance of a class's graph path (at its vertices).
pub(super) fn bottleneck(poly: &[Point], model: &dyn ClearanceModel) -> Real {
    clearances_of(model, poly)
        .into_iter()
        .fold(Real::INFINITY, Real::min)
}

/// Whether the segment `ab` keeps at least `target` clearance. First the model's bound on
/// the whole segment; else a march from `a`: the clearance is 1-Lipschitz, so from a point
/// `d` clear every point within `d - target` further on is at least `target` clear, and the
/// march steps that far (at least an eighth of a cell, the step then certified by the
/// model's bound on it) until it comes within `d(b) - target` of `b`. Each point's exact
/// clearance is computed once. `false` when a point, or an eighth-of-a-cell step, is not
/// certified.
pub(super) fn clear_at_least(
    model: &dyn ClearanceModel,
    a: Point,
    b: Point,
    target: Real,
    cell: Real,
) -> bool {
    let (da, db) = (model.exact_clearance(&a), model.exact_clearance(&b));
    if da < target || db < target {
        return false;
    }
    if model.segment_clearance_between(&a, &b, da, db) >= target {
        return true;
    }
    let len = (b - a).norm();
    let dir = (b - a) / len;
    let end = len - (db - target);
    let min_step = 0.125 * cell;
    let (mut s, mut p, mut d) = (0.0, a, da);
    loop {
        if s + (d - target) >= end {
            return true;
        }
        if d - target >= min_step {
            s += d - target;
            p = a + dir * s;
            d = model.exact_clearance(&p);
            if d < target {
                return false;
            }
        } else {
            let next = (s + min_step).min(len);
            let q = a + dir * next;
            let dq = model.exact_clearance(&q);
            if dq < target || model.segment_clearance_between(&p, &q, d, dq) < target {
                return false;
            }
            (s, p, d) = (next, q, dq);
        }
    }
}
