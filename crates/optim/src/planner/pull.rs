//! String pulling on a map's class path ([`pull_taut`]): chords that keep a margin from the
//! walls replace the ridge of free space, corners are cut, and the class is kept.

use homospline_geom::{Point, Real};
use homospline_homotopy::{Rays, Signature};
use homospline_spline::ClearanceModel;

use super::clearance::{clear_at_least, clearances_of};

/// String pulling on a map's class path, which runs along the ridge of free space: through
/// the middle of every room and round every bend at the bend's full clearance, so the curve
/// seeded by it is up to a fifth longer than the octile path, and an optimiser with a budget
/// that follows the path's length does not pull it straight.
///
/// Each point of the ridge gets a margin: its clearance less half a cell, at least half of
/// it (as at the ends), at most [`PULL_MARGIN`] cells and at least [`MIN_PULL_MARGIN`]. A pass ([`pull_pass`]) puts a
/// point every cell along the path and replaces it by chords between its points that keep
/// the least margin of the stretch they replace. A chord's corners lie on the path it
/// replaced (the ridge, at first), and once every chord touches its margin no chord can
/// move them; so before each further pass every corner is cut ([`cut_corners`]), and passes
/// go on, the points carrying their chord's margin, until the length falls by less than
/// 0.1 % (at most [`PULL_PASSES`]): the corners move in towards the walls, to the margin.
///
/// Every chord and cut is proven to keep the class (its loop with the stretch it replaces
/// encloses no obstacle), so the result needs no signature unless [`push_clear`] moved a
/// point; if that left the class, the ridge path is kept. (Passes that ran unchecked, the
/// class tested once on the result, left the class on both long paths of a random
/// 4096 x 4096 map, which then ran them again checked.) The cost then decides how far from
/// walls the curve ends up. On the MovingAI maps this brought the median length down to
/// about the octile optimum (measured: docs/performance.md, "Measurements behind the
/// defaults").
pub(super) fn pull_taut(
    poly: &[Point],
    model: &dyn ClearanceModel,
    rays: &Rays,
    cell: Real,
    signature: &Signature,
) -> Vec<Point> {
    if poly.len() < 3 {
        return poly.to_vec();
    }
    // A ridge point closer than the robot's radius (a corner of a staircase the disc rounds
    // only off the ridge: `homospline_maps::footprint`) asks its chords for the least margin,
    // so that the chord the disc can take replaces it.
    let margin = |c: Real| {
        (c - 0.5 * cell)
            .max(0.5 * c)
            .min(PULL_MARGIN * cell)
            .max(MIN_PULL_MARGIN * cell)
    };
    let margins: Vec<Real> = clearances_of(model, poly).into_iter().map(margin).collect();
    // A vertex's margin applies to both its segments.
    let path: Vec<(Point, Real)> = poly
        .iter()
        .enumerate()
        .map(|(i, &p)| (p, margins[i].min(margins[i.saturating_sub(1)])))
        .collect();
    let length =
        |p: &[(Point, Real)]| -> Real { p.windows(2).map(|w| (w[1].0 - w[0].0).norm()).sum() };
    let mut path = path;
    for pass in 0..PULL_PASSES {
        let cut = if pass == 0 {
            path.clone()
        } else {
            cut_corners(&path, model, rays, cell)
        };
        let next = pull_pass(&cut, model, rays, cell);
        let (before, after) = (length(&path), length(&next));
        path = next;
        if after > before * (1.0 - 1e-3) {
            break;
        }
    }
    let taut: Vec<Point> = path.into_iter().map(|(p, _)| p).collect();
    let pulled = push_clear(taut.clone(), model, cell);
    // Every chord and cut was proven to keep the class; only a point that `push_clear`
    // moved asks for the signature.
    if pulled == taut || rays.signature(&pulled) == *signature {
        return pulled;
    }
    poly.to_vec()
}

/// The path with every vertex in collision moved out of it and every segment that dips into
/// collision split, its middle moved out too (at most [`PUSH_DEPTH`] halvings), so that
/// the via-points seeded from it can converge onto a clear polyline. A robot's lattice keeps
/// a diagonal join by freeing the clearer of its two common neighbours, whose centre can be
/// closer than the radius: the ridge, and chords ending on it, can pass there. A vertex is
/// moved along the clearance's gradient until it keeps [`MIN_PULL_MARGIN`] cells; one that
/// cannot be is left, and the class check and the seed's certification decide.
fn push_clear(path: Vec<Point>, model: &dyn ClearanceModel, cell: Real) -> Vec<Point> {
    let floor = MIN_PULL_MARGIN * cell;
    if path.len() < 2 || path.iter().all(|p| model.exact_clearance(p) >= floor) {
        // The segments between vertices that keep the floor were certified by their chords.
        return path;
    }
    let push = |p: Point| -> Point {
        let mut q = p;
        for _ in 0..PUSH_STEPS {
            let d = model.exact_clearance(&q);
            if d >= floor {
                return q;
            }
            let g = model.clearance(&q).1;
            let n = g.norm();
            if n.is_nan() || n <= 0.0 {
                break;
            }
            q += g / n * (floor - d + 0.25 * floor);
        }
        if model.exact_clearance(&q) >= floor {
            q
        } else {
            p
        }
    };
    let last = path.len() - 1;
    let mut out = vec![path[0]];
    for (k, &p) in path.iter().enumerate().skip(1) {
        let b = if k < last { push(p) } else { p };
        fill(&mut out, b, PUSH_DEPTH, &push, model, 0.5 * floor, cell);
    }
    out
}

/// Appends `b` to `out`, first splitting the segment from `out`'s last point at its middle
/// (moved out by `push`) while it does not keep `target`, up to `depth` times.
fn fill(
    out: &mut Vec<Point>,
    b: Point,
    depth: usize,
    push: &dyn Fn(Point) -> Point,
    model: &dyn ClearanceModel,
    target: Real,
    cell: Real,
) {
    let a = out[out.len() - 1];
    if depth > 0 && !clear_at_least(model, a, b, target, cell) {
        let m = push(Point::from((a.coords + b.coords) * 0.5));
        fill(out, m, depth - 1, push, model, target, cell);
        fill(out, b, depth - 1, push, model, target, cell);
    } else {
        out.push(b);
    }
}

/// Most gradient steps of [`push_clear`] for one point.
const PUSH_STEPS: usize = 8;

/// Most halvings of a segment by [`push_clear`].
const PUSH_DEPTH: usize = 4;

/// Cuts each corner `V` of `path` (between `A` and `B`) by the chord between `V + s (A - V)`
/// and `V + s (B - V)`, for the largest `s` of a halving search whose chord keeps the margin
/// of both segments and whose cut triangle holds no obstacle. A chord's corners lie on the
/// path it replaced; cutting moves them in towards the walls, which a pass of chords alone
/// cannot do once every chord touches its margin.
fn cut_corners(
    path: &[(Point, Real)],
    model: &dyn ClearanceModel,
    rays: &Rays,
    cell: Real,
) -> Vec<(Point, Real)> {
    let mut out = vec![path[0]];
    for k in 1..path.len() - 1 {
        let (a, v, b) = (out[out.len() - 1].0, path[k].0, path[k + 1].0);
        let (ta, tb) = (path[k].1, path[k + 1].1);
        let target = ta.min(tb);
        let cut_at = |s: Real| {
            let (w1, w2) = (v + (a - v) * s, v + (b - v) * s);
            let ok = target > 0.0
                && clear_at_least(model, w1, w2, target, cell)
                && rays.sweep_is_clear(
                    &[w1, v, w2],
                    &[w1, Point::from((w1.coords + w2.coords) * 0.5), w2],
                );
            ok.then_some((w1, w2))
        };
        let mut best = None;
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..CUT_STEPS {
            let s = 0.5 * (lo + hi);
            match cut_at(s) {
                Some(w) => {
                    best = Some(w);
                    lo = s;
                }
                None => hi = s,
            }
        }
        match best {
            Some((w1, w2)) if (w1 - v).norm() > 0.05 * cell && (w2 - v).norm() > 0.05 * cell => {
                out.push((w1, ta));
                out.push((w2, target));
            }
            _ => out.push(path[k]),
        }
    }
    out.push(path[path.len() - 1]);
    out
}

/// Halving steps of [`cut_corners`]' search.
const CUT_STEPS: usize = 6;

/// One pass of [`pull_taut`] over `path`, whose points carry the margin of the segment that
/// ends at them. Each chord must also enclose no obstacle with the stretch it replaces
/// (their loop's word is empty), which proves that the pass keeps the class: the farthest
/// chord that keeps its margin is checked, and only if it fails are the chords of the
/// search checked one by one.
fn pull_pass(
    path: &[(Point, Real)],
    model: &dyn ClearanceModel,
    rays: &Rays,
    cell: Real,
) -> Vec<(Point, Real)> {
    // A point every cell, each with the least margin of the segments it is on.
    let mut dense = vec![path[0].0];
    let mut margin = vec![path.get(1).map_or(0.0, |p| p.1)];
    for (k, w) in path.windows(2).enumerate() {
        let n = ((w[1].0 - w[0].0).norm() / cell).ceil().max(1.0) as usize;
        let next = path.get(k + 2).map_or(w[1].1, |p| p.1.min(w[1].1));
        for j in 1..n {
            dense.push(w[0].0 + (w[1].0 - w[0].0) * (j as Real / n as Real));
            margin.push(w[1].1);
        }
        // The vertex itself, exactly (the goal stays the goal).
        dense.push(w[1].0);
        margin.push(next);
    }
    let target = |i: usize, j: usize| {
        margin[i..=j]
            .iter()
            .copied()
            .fold(Real::INFINITY, Real::min)
    };
    // The chord keeps the stretch's class when the straight-line homotopy from the stretch
    // to the chord (point k to the chord's point k) meets no obstacle's representative, or
    // the loop where it does has the empty word ([`Rays::same_class`], the obstacles near
    // it); else the whole signature of the stretch decides (most of a 4096^2 map's string
    // pulling went to it).
    let loop_is_trivial = |i: usize, j: usize| {
        let (a, b) = (dense[i], dense[j]);
        let n = (j - i) as Real;
        // Exactly `a` and `b` at the ends, as the sweep asks.
        let chord: Vec<Point> = (0..=j - i)
            .map(|k| {
                if k == j - i {
                    b
                } else {
                    a + (b - a) * (k as Real / n)
                }
            })
            .collect();
        rays.same_class(&dense[i..=j], &chord)
            .unwrap_or_else(|| rays.chord_keeps_class(&dense[i..=j]))
    };
    let clear = |i: usize, j: usize| {
        j == i + 1 || {
            let t = target(i, j);
            t > 0.0 && clear_at_least(model, dense[i], dense[j], t, cell)
        }
    };
    let last = dense.len() - 1;
    let mut out = vec![(dense[0], 0.0)];
    let mut i = 0;
    while i < last {
        // The farthest chord that keeps its margin; if its loop with the stretch is not
        // trivial (rare: a chord that jumps a small obstacle), the search again with every
        // chord tried held to the class too.
        let mut good = farthest(i, last, &clear);
        if good > i + 1 && !loop_is_trivial(i, good) {
            good = farthest(i, last, &|i, j| {
                clear(i, j) && (j == i + 1 || loop_is_trivial(i, j))
            });
        }
        out.push((dense[good], target(i, good).max(0.0)));
        i = good;
    }
    out
}

/// The farthest `j` in `(i, last]` that `ok(i, j)` admits by doubling the step while it
/// does, then halving between the last admitted and the first refused (`ok(i, i + 1)` is
/// taken as true).
fn farthest(i: usize, last: usize, ok: &dyn Fn(usize, usize) -> bool) -> usize {
    let (mut good, mut step, mut bad) = (i + 1, 2, None);
    while good < last {
        let j = (i + step).min(last);
        if ok(i, j) {
            good = j;
            step *= 2;
        } else {
            bad = Some(j);
            break;
        }
    }
    if let Some(mut hi) = bad {
        while hi - good > 1 {
            let mid = good + (hi - good) / 2;
            if ok(i, mid) {
                good = mid;
            } else {
                hi = mid;
            }
        }
    }
    good
}

/// Most passes of [`pull_taut`].
const PULL_PASSES: usize = 6;

/// The most clearance, in cells, a pulled chord must keep (less where the stretch it
/// replaces keeps less).
const PULL_MARGIN: Real = 1.0;

/// The least margin a chord keeps, cells: a ridge point in collision asks for it.
const MIN_PULL_MARGIN: Real = 0.01;
