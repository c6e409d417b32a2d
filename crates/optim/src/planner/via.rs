//! Via-points for a class's seed: a scene's first admissible Douglas-Peucker or evenly
//! spaced set ([`seed_points`]), or a map's certified subdivision of its path
//! ([`subdivided_seed`]).

use homospline_geom::{Point, Real};
use homospline_spline::{ClearanceModel, Spline, is_collision_free};

use crate::growth::{GrowthConfig, Guard};

/// Via-points for a seed polyline: Douglas-Peucker vertices, the tolerance halved until the
/// spline through them is admissible (in the class, inside the bounds, clear of obstacles and
/// of the guard's floor); then evenly spaced points, more and more of them. The first
/// admissible set wins; `None` if none is.
pub(super) fn seed_points(
    poly: &[Point],
    model: &dyn ClearanceModel,
    guard: &Guard<'_>,
    cfg: &GrowthConfig,
) -> Option<Vec<Point>> {
    let ok = |pts: &[Point]| {
        Spline::new(pts, cfg.parametrization, cfg.end).is_ok_and(|sp| {
            guard.cost(&sp, model, cfg).is_finite() && is_collision_free(&sp, model)
        })
    };
    let len = super::polyline_length(poly);
    let mut tol = len / 8.0;
    let limit = cfg.max_via_points + 2;
    for _ in 0..16 {
        let pts = homospline_geom::math::douglas_peucker(poly, tol, limit);
        if ok(&pts) {
            return Some(pts);
        }
        if pts.len() >= limit {
            break;
        }
        tol *= 0.5;
    }
    (1..=cfg.max_via_points)
        .map(|inner| resample(poly, inner))
        .find(|pts| ok(pts))
}

/// The densest evenly spaced via-points, when no set is admissible: the class is optimised
/// and reported as it ends up.
pub(super) fn last_resort(poly: &[Point], cfg: &GrowthConfig) -> Vec<Point> {
    resample(poly, cfg.max_via_points)
}

/// Via-points for a seed polyline that runs through free cells (a map's ridge), by certified
/// subdivision: the Douglas-Peucker vertices at one cell, with no gap longer than
/// [`SEED_MAX_GAP`] cells, then a via-point added at the middle (by arc length along the
/// seed) of every spline segment that is not certified collision-free, until all are. As
/// via-points close in, the spline tends to the polyline, which has positive clearance, so
/// this ends; it is also stopped at one via-point per quarter cell of path. The count follows
/// the path: a long winding path gets many via-points, a straight one few. If the spline is
/// certified but leaves its class or the bounds, every segment is halved. With `max_points`,
/// `None` once the points would be more than that (always `Some` without).
pub(super) fn subdivided_seed(
    poly: &[Point],
    model: &dyn ClearanceModel,
    guard: &Guard<'_>,
    cfg: &GrowthConfig,
    cell: Real,
    max_points: Option<usize>,
) -> Option<Vec<Point>> {
    let mut cum = Vec::with_capacity(poly.len());
    let mut acc = 0.0;
    cum.push(0.0);
    for w in poly.windows(2) {
        acc += (w[1] - w[0]).norm();
        cum.push(acc);
    }
    let total = acc;
    let at = |s: Real| -> Point {
        let i = cum.partition_point(|&c| c < s).clamp(1, poly.len() - 1);
        let seg = cum[i] - cum[i - 1];
        let f = if seg > 0.0 {
            ((s - cum[i - 1]) / seg).clamp(0.0, 1.0)
        } else {
            0.0
        };
        poly[i - 1] + (poly[i] - poly[i - 1]) * f
    };
    // Arc-length positions of the Douglas-Peucker vertices (a subsequence of the polyline).
    let kept = homospline_geom::math::douglas_peucker(poly, cell, usize::MAX);
    let mut params = Vec::with_capacity(kept.len());
    let mut k = 0;
    for (i, p) in poly.iter().enumerate() {
        if k < kept.len() && *p == kept[k] {
            params.push(cum[i]);
            k += 1;
        }
    }
    let max_gap = SEED_MAX_GAP * cell;
    let mut filled = vec![params[0]];
    for w in params.windows(2) {
        let n = ((w[1] - w[0]) / max_gap).ceil().max(1.0) as usize;
        for j in 1..=n {
            filled.push(w[0] + (w[1] - w[0]) * j as Real / n as Real);
        }
    }
    let mut params = filled;
    params.dedup();
    grade(&mut params);
    let cap = ((total / (0.25 * cell)).ceil() as usize).max(3);
    let cap = max_points.map_or(cap, |m| cap.min(m));
    loop {
        let pts: Vec<Point> = params.iter().map(|&s| at(s)).collect();
        if max_points.is_some_and(|m| pts.len() > m) {
            return None;
        }
        let Ok(sp) = Spline::new(&pts, cfg.parametrization, cfg.end) else {
            return Some(pts);
        };
        let mut bad = homospline_spline::certify::uncertified_segments(&sp, model);
        if bad.is_empty() {
            if guard.cost(&sp, model, cfg).is_finite() {
                return Some(pts);
            }
            bad = (0..sp.segments()).collect();
        }
        if params.len() + bad.len() > cap {
            return Some(pts);
        }
        let mut next = Vec::with_capacity(params.len() + bad.len());
        let mut b = bad.iter().peekable();
        for (i, &s) in params.iter().enumerate() {
            next.push(s);
            if b.peek() == Some(&&i) {
                b.next();
                next.push(0.5 * (s + params[i + 1]));
            }
        }
        params = next;
        grade(&mut params);
    }
}

/// Splits every gap longer than twice a neighbouring one, until none is: with uniform
/// parameters a spline through unevenly spaced via-points overshoots, and graded spacing
/// keeps it close to its polyline.
fn grade(params: &mut Vec<Real>) {
    loop {
        let gaps: Vec<Real> = params.windows(2).map(|w| w[1] - w[0]).collect();
        let split: Vec<bool> = (0..gaps.len())
            .map(|i| {
                let left = if i > 0 { gaps[i - 1] } else { Real::INFINITY };
                let right = gaps.get(i + 1).copied().unwrap_or(Real::INFINITY);
                gaps[i] > 2.0 * left.min(right)
            })
            .collect();
        if !split.iter().any(|&b| b) {
            return;
        }
        let mut next = Vec::with_capacity(params.len() * 2);
        for (i, &s) in params.iter().enumerate() {
            next.push(s);
            if split.get(i).copied().unwrap_or(false) {
                next.push(0.5 * (s + params[i + 1]));
            }
        }
        *params = next;
    }
}

/// Longest gap between a map seed's first via-points, cells.
pub const SEED_MAX_GAP: Real = 16.0;

pub(super) fn resample(poly: &[Point], inner: usize) -> Vec<Point> {
    if poly.len() < 2 {
        // A class path of one point (start and goal at one node): nothing to spread.
        return poly.to_vec();
    }
    let cum: Vec<Real> = std::iter::once(0.0)
        .chain(poly.windows(2).scan(0.0, |acc, w| {
            *acc += (w[1] - w[0]).norm();
            Some(*acc)
        }))
        .collect();
    let total = *cum.last().unwrap_or(&0.0);
    let mut out = vec![poly[0]];
    for k in 1..=inner {
        let target = total * k as Real / (inner + 1) as Real;
        let i = cum
            .partition_point(|&c| c < target)
            .clamp(1, poly.len() - 1);
        let seg = cum[i] - cum[i - 1];
        let f = if seg > 0.0 {
            (target - cum[i - 1]) / seg
        } else {
            0.0
        };
        out.push(poly[i - 1] + (poly[i] - poly[i - 1]) * f);
    }
    out.push(poly[poly.len() - 1]);
    out.dedup();
    out
}
