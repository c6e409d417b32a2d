//! Step 4 of an evaluation: `m(C)`, the least clearance of the curve, refined from the worst
//! quadrature node by Brent's method and, with [`ClearanceSearch::EveryStretch`], by halving
//! every stretch whose bound lets the clearance dip below the least value found.

use homospline_geom::{Real, Vector};

use super::brent::brent_min;
use super::config::ClearanceSearch;
use super::integrand::Worst;
use super::quadrature::Samples;
use crate::clearance_model::{ClearanceModel, FieldSample};
use crate::curve::Spline;

/// Step 4: `m(C)`, the worst node's clearance refined by Brent's method between its
/// neighbours (where a local minimum next to the smallest sample lies), in global `t` so that
/// a minimum across a knot is found too; then, where the model bounds how sharply the
/// clearance bends ([`ClearanceModel::bend_radius`]), every stretch between two nodes whose
/// bound ([`least_on`]) lets it dip below the least value found so far is halved, the
/// lowest bound first. Returns `(t, m)`.
pub(super) fn refine_min_clearance(
    spline: &Spline,
    model: &dyn ClearanceModel,
    samples: &Samples,
    field: &[FieldSample],
    worst: Worst,
    knot_clear: &[(Real, Real)],
    search: ClearanceSearch,
) -> (Real, Real) {
    let knots = spline.knots();
    let t_of = |i: usize| knots[samples.nodes[i].seg] + samples.nodes[i].s;
    let n = samples.nodes.len();
    let idx = worst.index;
    let t0 = t_of(idx);
    let ta = if idx > 0 { t_of(idx - 1) } else { 0.0 };
    let tz = if idx + 1 < n { t_of(idx + 1) } else { 1.0 };
    let (tb, fb) = refine_bracket(spline, model, (ta, tz), (t0, worst.clearance));
    // `m(C)` is the least clearance over all of `[0, 1]`: the knots are taken in (all of
    // them where the safety term weighs and the model truncates, else the ends). The
    // quadrature nodes do not reach the ends, and a curve that leaves a start next to a wall
    // quickly (a long curve, its parameter spread thin) put its first node farther from the
    // wall than a short curve's: `D` favoured long detours from such a start. The ends are
    // fixed, so where one of them is the least clear, `D` is the same for every curve. With
    // the knots in, `m(C)` is at most the least knot clearance, which the truncation's
    // allowance counts on.
    let best = knot_clear
        .iter()
        .copied()
        .fold((tb, fb), |best, e| if e.1 < best.1 { e } else { best });
    let Some(radius) = model
        .bend_radius()
        .filter(|_| search == ClearanceSearch::EveryStretch)
    else {
        return best;
    };
    search_every_stretch(spline, model, samples, field, knot_clear, radius, best)
}

/// [`ClearanceSearch::EveryStretch`] from `best`, the least clearance found so far as
/// `(t, m)`, with `radius` the model's bend bound: every stretch between two probes whose
/// bound ([`least_on`]) lets the clearance dip more than [`STRETCH_TOLERANCE`] below the
/// least value is halved, the lowest bound first. Returns the least `(t, m)` found.
fn search_every_stretch(
    spline: &Spline,
    model: &dyn ClearanceModel,
    samples: &Samples,
    field: &[FieldSample],
    knot_clear: &[(Real, Real)],
    radius: Real,
    mut best: (Real, Real),
) -> (Real, Real) {
    let knots = spline.knots();
    let t_of = |i: usize| knots[samples.nodes[i].seg] + samples.nodes[i].s;
    let n = samples.nodes.len();
    // Every stretch between consecutive nodes, the worst node's two included (a second dip
    // there escapes Brent's method, which follows one valley), and from the start to the
    // first node and from the last node to the goal, whose clearances are known.
    let last = spline.segments() - 1;
    let end = |t: Real| {
        let (seg, s) = if t == 0.0 {
            (0, 0.0)
        } else {
            (last, knots[last + 1] - knots[last])
        };
        let (p, v, a) = spline.eval_segment(seg, s);
        let c = knot_clear
            .iter()
            .find(|k| k.0 == t)
            .map_or_else(|| model.clearance_value(&p), |k| k.1);
        Probe::new(t, c, seg, v, a)
    };
    let node = |i: usize| {
        let nd = &samples.nodes[i];
        Probe {
            t: t_of(i),
            clearance: field[i].clearance,
            seg: nd.seg,
            speed: nd.speed,
            accel: nd.a.norm(),
        }
    };
    // Best first: the stretch whose bound lets it fall lowest is halved first, so that the
    // least clearance is found early and the other stretches are dropped by it.
    let mut heap = std::collections::BinaryHeap::new();
    let push =
        |heap: &mut std::collections::BinaryHeap<Stretch>, a: Probe, b: Probe, best: Real| {
            let bound = least_on(spline, radius, &a, &b);
            if bound < best - STRETCH_TOLERANCE {
                heap.push(Stretch { bound, a, b });
            }
        };
    for i in 0..=n {
        let (a, b) = match (i.checked_sub(1), i < n) {
            (None, true) => (end(0.0), node(0)),
            (Some(j), true) => (node(j), node(i)),
            (Some(j), false) => (node(j), end(1.0)),
            (None, false) => continue,
        };
        push(&mut heap, a, b, best.1);
    }
    // A cap on the probes, for curves through a disc's centre (there only the Lipschitz
    // bound holds): the search then stops with the least value so far.
    let mut probes_left = STRETCH_PROBES * (n + 1);
    while let Some(Stretch { bound, a, b }) = heap.pop() {
        if bound >= best.1 - STRETCH_TOLERANCE || probes_left == 0 {
            break;
        }
        probes_left -= 1;
        let tm = 0.5 * (a.t + b.t);
        if tm <= a.t || tm >= b.t {
            continue;
        }
        let (seg, s) = spline.locate(tm);
        let (p, v, acc) = spline.eval_segment(seg, s);
        let m = Probe::new(tm, model.clearance_value(&p), seg, v, acc);
        if m.clearance < best.1 {
            best = (m.t, m.clearance);
        }
        push(&mut heap, a, m, best.1);
        push(&mut heap, m, b, best.1);
    }
    best
}

/// A stretch of the curve between two probes, and the least its clearance can be there
/// ([`least_on`]); ordered so that a `BinaryHeap` gives the least bound first.
struct Stretch {
    bound: Real,
    a: Probe,
    b: Probe,
}

impl PartialEq for Stretch {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for Stretch {}

impl PartialOrd for Stretch {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Stretch {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        // The least bound first; ties by position, so that the order is the same every run.
        other
            .bound
            .total_cmp(&self.bound)
            .then(other.a.t.total_cmp(&self.a.t))
    }
}

/// A point of the curve for [`least_on`]: its `t`, clearance, segment, `|q'|` and `|q''|`.
#[derive(Clone, Copy)]
struct Probe {
    t: Real,
    clearance: Real,
    seg: usize,
    speed: Real,
    accel: Real,
}

impl Probe {
    fn new(t: Real, clearance: Real, seg: usize, v: Vector, a: Vector) -> Self {
        Self {
            t,
            clearance,
            seg,
            speed: v.norm(),
            accel: a.norm(),
        }
    }
}

/// How far below the least clearance of the curve [`ClearanceSearch::EveryStretch`] may
/// leave `m(C)`: a stretch is halved until its bound ([`least_on`]) keeps it within this of
/// the least value found.
const STRETCH_TOLERANCE: Real = 1e-5;

/// The most probes [`ClearanceSearch::EveryStretch`] takes per stretch, on average over the
/// curve's stretches (a collision-free curve takes a fraction of one).
const STRETCH_PROBES: usize = 64;

/// A lower bound of the clearance between two points of the curve, `a` and `b`. It moves
/// at most `|q'|` per unit of `t`, so it stays above the lesser end's value less `V dt / 2`,
/// `V` the largest `|q'|` on the stretch (at most an end's plus `A` times half the stretch,
/// `A` the largest `|q''|`: `q''` is linear on each segment, so that is at an end or a
/// knot). And the distance `rho` to a disc's centre has `rho'' <= V^2 / rho + A`; with
/// `rho` at least the first bound plus the least radius `r`
/// ([`ClearanceModel::bend_radius`]), where that is positive, each disc's clearance, and so
/// their least, stays above the chord between the ends less `M dt^2 / 8`, `M` that bound.
/// The larger of the two.
fn least_on(spline: &Spline, radius: Real, a: &Probe, b: &Probe) -> Real {
    let dt = b.t - a.t;
    let low = a.clearance.min(b.clearance);
    if dt <= 0.0 || !low.is_finite() {
        return low;
    }
    let mut accel = a.accel.max(b.accel);
    // The knots inside the stretch, where `q''` may be largest.
    for k in a.seg + 1..=b.seg {
        accel = accel.max(spline.eval_segment(k, 0.0).2.norm());
    }
    let speed = a.speed.max(b.speed) + 0.5 * accel * dt;
    let lipschitz = low - 0.5 * speed * dt;
    let floor = lipschitz + radius;
    if floor <= 0.0 {
        return lipschitz;
    }
    let bend = speed * speed / floor + accel;
    lipschitz.max(low - 0.125 * bend * dt * dt)
}

/// Brent's search of `[ta, tz]` from `(t0, d0)`, `d0` the clearance at `t0`, with the model
/// restricted to the circles that can come nearer than `d0` there; the ends of the bracket
/// are taken in exactly. Returns `(t, m)` with `m <= d0`.
fn refine_bracket(
    spline: &Spline,
    model: &dyn ClearanceModel,
    (ta, tz): (Real, Real),
    (t0, d0): (Real, Real),
) -> (Real, Real) {
    let knots = spline.knots();
    // The bracket's stretch of curve lies in the box of its Bezier control points (per
    // segment it touches); only circles that can come nearer than `d0` there matter.
    let (sa, sz) = (spline.locate(ta).0, spline.locate(tz).0);
    let (mut lo, mut hi) = (spline.position(ta), spline.position(ta));
    for k in sa..=sz {
        let s0 = (ta - knots[k]).max(0.0);
        let s1 = (tz - knots[k]).min(knots[k + 1] - knots[k]);
        let ((p0, v0, _), (p3, v3, _)) = (spline.eval_segment(k, s0), spline.eval_segment(k, s1));
        let third = (s1 - s0) / 3.0;
        for p in [p0, p0 + v0 * third, p3 - v3 * third, p3] {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    }
    let local = model.restricted(&lo, &hi, d0);
    let near: &dyn ClearanceModel = local.as_deref().unwrap_or(model);
    let f = |t: Real| near.clearance_value(&spline.position(t));
    let (tb, fb) = brent_min(f, (ta, tz), (t0, d0), 1e-10);
    // Brent searches the open bracket; a minimum at one of its ends (the start or the goal
    // inside an obstacle's reach) is taken there exactly.
    let (tb, fb) = [(ta, f(ta)), (tz, f(tz))]
        .into_iter()
        .fold((tb, fb), |best, e| if e.1 < best.1 { e } else { best });
    if fb < d0 { (tb, fb) } else { (t0, d0) }
}

/// Each knot's parameter and clearance, into `out` (`d` is a buffer).
pub(super) fn knot_clearances(
    spline: &Spline,
    model: &dyn ClearanceModel,
    d: &mut Vec<Real>,
    out: &mut Vec<(Real, Real)>,
) {
    d.clear();
    d.resize(spline.points().len(), 0.0);
    model.clearances(spline.points(), d);
    out.clear();
    out.extend(spline.knots().iter().copied().zip(d.iter().copied()));
}
