//! `Reach`: the discs a free tangent ray of a disc can reach, which keeps the tangent
//! graph's pair tests near-linear in the discs.

use std::f64::consts::{FRAC_PI_2, TAU};

use super::{DiscIndex, SLACK};
use crate::math::{Point, Real, Vector};
use crate::shape::Circle;

/// How [`TangentGraph`] chooses the pairs of discs whose common tangents it tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Pairs {
    /// Every pair: the tests' oracle.
    #[cfg(test)]
    All,
    /// The pairs that [`Reach::partners`] finds.
    Visible,
}

/// The discs a free tangent segment of a disc can reach: what keeps the tangent graph's
/// pair tests near-linear in the discs.
///
/// Every common tangent of discs `i` and `j` leaves disc `i` along one of its tangent rays:
/// from the point at angle `a`, `c_i + r_i u(a)`, in the direction `+u'(a)` or `-u'(a)`
/// (`u(a) = (cos a, sin a)`, `u'` its quarter turn). A disc `k` at distance `d` and bearing
/// `phi` blocks the `+` ray at `a` when the ray's line passes within `r_k` of its centre
/// and the centre projects ahead of the tangent point: with `theta = a - phi`, when
/// `|d cos theta - r_i| < r_k` and `theta` lies in `[-pi, 0]` (`[0, pi]` for `-`). It
/// blocks the ray before the ray has gone `d + r_i` along. It also removes the tangent
/// point outright where it covers it (`|c_i + r_i u(a) - c_k| < r_k`): no node, no segment.
/// Both are arcs of angles `a` in closed form.
///
/// The discs are taken ring of buckets by ring outward from disc `i`'s centre; after ring
/// `R`, every disc not yet taken lies at least `R` buckets' sides away, so a tangent point
/// on it is at least `R side - r_i` along its ray. Once the blocking arcs of discs with
/// `d + 2 r_i < R side` cover every angle for both directions, no tangent ray of disc `i`
/// reaches any disc further out, and the search stops: the discs taken so far are disc
/// `i`'s partners. Two things keep the rings few and thin:
/// - once some rays are blocked, a bucket of the later rings is taken only if a ray still
///   open can pass through it (its heading within the bucket's angular width of the bucket's
///   bearing), so the search follows the open rays outward in narrow cones;
/// - a ray that leaves the discs' box before it leaves the rings taken meets no further disc
///   (see [`Reach::leave_the_box`]), so a disc at the field's edge stops as one inside it.
///
/// In a field of given density the partners then stay as many whatever its size, and the
/// pair tests fall from `n^2` to about `n` times the discs within a ray's longest free run.
/// The skipped pairs' tangents are all blocked, so the graph is the same as with every
/// pair (a test compares them node for node).
///
/// Margins keep every arc inside its exact one: blockers are shrunk by 1e-4 of their
/// radius and arcs by 1e-6 radians at each end, which can only take in more partners.
#[derive(Clone, Debug)]
pub(super) struct Reach {
    /// Disc `k` was taken in the search for disc `i` when `seen[k] == i + 1`.
    pub(super) seen: Vec<usize>,
    /// Per direction (`+`, `-`), the blocking arcs `(from, to, reach)` within `[0, 2 pi]`
    /// (an arc across angle 0 is split there), sorted by `from`: usable against the discs
    /// of ring `R` when `reach + 2 r_i < R side`.
    pub(super) arcs: [Vec<(Real, Real, Real)>; 2],
    /// Per direction, the arcs of the ring being taken, merged into `arcs` at its end.
    pub(super) fresh: [Vec<(Real, Real, Real)>; 2],
    /// The headings `(from, to)` of the rays no arc blocks yet (both directions).
    pub(super) open: Vec<(Real, Real)>,
    pub(super) merged_open: Vec<(Real, Real)>,
    pub(super) merged: Vec<(Real, Real, Real)>,
}

impl Reach {
    /// Angles within this of an arc's exact ends are not counted as blocked.
    pub(super) const ANGLE_MARGIN: Real = 1e-6;
    /// A blocker counts as this fraction of its radius.
    pub(super) const SHRINK: Real = 1.0 - 1e-4;

    pub(super) fn new(n: usize) -> Self {
        Self {
            seen: vec![0; n],
            arcs: [Vec::new(), Vec::new()],
            fresh: [Vec::new(), Vec::new()],
            open: Vec::new(),
            merged_open: Vec::new(),
            merged: Vec::new(),
        }
    }

    /// The discs (other than `i`, ascending) that a tangent ray of disc `i` may reach
    /// before another disc blocks it: a superset of the partners of its free tangents.
    pub(super) fn partners(
        &mut self,
        discs: &[Circle],
        index: &DiscIndex,
        i: usize,
        out: &mut Vec<usize>,
    ) {
        out.clear();
        for list in self.arcs.iter_mut().chain(&mut self.fresh) {
            list.clear();
        }
        self.open.clear();
        let c = discs[i].center;
        let r = discs[i].radius;
        let ((bx, _), (by, _)) = index.range(&c, &c);
        let (bx, by) = (bx as isize, by as isize);
        let (nx, ny) = (index.nx as isize, index.ny as isize);
        let last = bx.max(nx - 1 - bx).max(by).max(ny - 1 - by);
        // Half a bucket's diagonal, widened for rounding.
        let half = index.side * (0.5 * std::f64::consts::SQRT_2 + 1e-9);
        // Whether the rays leave every bucket of the coming rings but those in `open`.
        let mut narrowed = false;
        for ring in 0..=last {
            let mut take = |x: isize, y: isize| {
                if x < 0 || y < 0 || x >= nx || y >= ny {
                    return;
                }
                if narrowed {
                    // A ray from within r of c passes within `half` of the bucket's centre
                    // only if its direction is within `w` of the centre's bearing.
                    let m =
                        index.lo + Vector::new(x as Real + 0.5, y as Real + 0.5) * index.side - c;
                    let dist = m.norm();
                    if dist > r + half {
                        let w = (half / (dist - r)).min(1.0).asin() + (r / dist).min(1.0).asin();
                        let from = m.y.atan2(m.x) - w - Self::ANGLE_MARGIN;
                        let len = 2.0 * (w + Self::ANGLE_MARGIN);
                        if !self.open.iter().any(|&(a, b)| overlap(from, len, a, b - a)) {
                            return;
                        }
                    }
                }
                for &k in index.bucket(x as usize, y as usize) {
                    let k = k as usize;
                    if k == i || self.seen[k] == i + 1 {
                        continue;
                    }
                    self.seen[k] = i + 1;
                    out.push(k);
                    Self::blocking_arcs(&mut self.fresh, c, r, &discs[k]);
                }
            };
            if ring == 0 {
                take(bx, by);
            } else {
                for x in bx - ring..=bx + ring {
                    take(x, by - ring);
                    take(x, by + ring);
                }
                for y in by - ring + 1..by + ring {
                    take(bx - ring, y);
                    take(bx + ring, y);
                }
            }
            if ring == last {
                break;
            }
            for dir in 0..2 {
                self.merge(dir);
            }
            let limit = ring as Real * index.side * (1.0 - 1e-9) - 2.0 * r;
            if limit > 0.0 {
                // The directions of the rays not yet blocked: the `+` ray at angle a heads
                // at a + pi/2, the `-` ray at a - pi/2.
                self.open.clear();
                for (dir, turn) in [(0, FRAC_PI_2), (1, -FRAC_PI_2)] {
                    Self::gaps(&self.arcs[dir], limit, turn, &mut self.open);
                }
                if !self.open.is_empty() {
                    self.leave_the_box(index, c, r, ring);
                }
                if self.open.is_empty() {
                    break;
                }
                narrowed = true;
            }
        }
        out.sort_unstable();
    }

    /// Removes from the open headings those of the rays that leave the discs' box before
    /// they leave the rings taken so far (up to `ring` round the bucket of `c`): past the
    /// box there is no disc, and a ray never comes back into a convex box.
    ///
    /// The part of the rings inside the box, `Q`, is a rectangle. A ray from a point `p`
    /// inside it leaves through a side `K1 K2` (counter-clockwise) when its heading lies
    /// between the bearings of `K1` and `K2` from `p`; for every `p` within `r` of `c` when
    /// it lies between those from `c` narrowed by `asin(r / |K - c|)` at each end. Only the
    /// sides of `Q` on the box's boundary count.
    pub(super) fn leave_the_box(&mut self, index: &DiscIndex, c: Point, r: Real, ring: isize) {
        let ((bx, _), (by, _)) = index.range(&c, &c);
        let (bx, by) = (bx as isize, by as isize);
        let edge = |b: isize| index.side * b as Real;
        let (x0, x1) = (
            index.lo.x + edge(bx - ring),
            index.lo.x + edge(bx + ring + 1),
        );
        let (y0, y1) = (
            index.lo.y + edge(by - ring),
            index.lo.y + edge(by + ring + 1),
        );
        // Which sides of the rings reach the box's (bottom, right, top, left).
        let out = [
            y0 <= index.lo.y,
            x1 >= index.hi.x,
            y1 >= index.hi.y,
            x0 <= index.lo.x,
        ];
        let (x0, x1) = (x0.max(index.lo.x), x1.min(index.hi.x));
        let (y0, y1) = (y0.max(index.lo.y), y1.min(index.hi.y));
        let corners = [
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ];
        for side in 0..4 {
            if !out[side] {
                continue;
            }
            let (k1, k2) = (corners[side] - c, corners[(side + 1) % 4] - c);
            let (d1, d2) = (k1.norm(), k2.norm());
            if d1 <= r || d2 <= r {
                continue;
            }
            let from = k1.y.atan2(k1.x) + (r / d1).asin() + Self::ANGLE_MARGIN;
            let len = (k2.y.atan2(k2.x) - k1.y.atan2(k1.x)).rem_euclid(TAU)
                - (r / d1).asin()
                - (r / d2).asin()
                - 2.0 * Self::ANGLE_MARGIN;
            if len > 0.0 {
                cut(&mut self.open, &mut self.merged_open, from, from + len);
            }
        }
    }

    /// Merges direction `dir`'s fresh arcs into its sorted arcs.
    pub(super) fn merge(&mut self, dir: usize) {
        let fresh = &mut self.fresh[dir];
        if fresh.is_empty() {
            return;
        }
        fresh.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let old = &self.arcs[dir];
        self.merged.clear();
        let (mut a, mut b) = (0, 0);
        while a < old.len() || b < fresh.len() {
            if b == fresh.len() || (a < old.len() && old[a].0 <= fresh[b].0) {
                self.merged.push(old[a]);
                a += 1;
            } else {
                self.merged.push(fresh[b]);
                b += 1;
            }
        }
        fresh.clear();
        std::mem::swap(&mut self.arcs[dir], &mut self.merged);
    }

    /// Records the arcs of angles at which disc `k` blocks a tangent ray of the disc of
    /// centre `c` and radius `r` (see the type's doc).
    pub(super) fn blocking_arcs(
        arcs: &mut [Vec<(Real, Real, Real)>; 2],
        c: Point,
        r: Real,
        k: &Circle,
    ) {
        let v = k.center - c;
        let d = v.norm();
        let rho = k.radius * (1.0 - SLACK) * Self::SHRINK;
        if d == 0.0 || !(d.is_finite() && rho > 0.0) {
            return;
        }
        let phi = v.y.atan2(v.x);
        let mut push = |dir: usize, reach: Real, from: Real, to: Real| {
            let (from, to) = (from + Self::ANGLE_MARGIN, to - Self::ANGLE_MARGIN);
            if to > from {
                let start = wrap(phi + from);
                let end = start + (to - from);
                if end > TAU {
                    arcs[dir].push((start, TAU, reach));
                    arcs[dir].push((0.0, end - TAU, reach));
                } else {
                    arcs[dir].push((start, end, reach));
                }
            }
        };
        // The tangent point inside disc k: cos theta > x. Blocks both directions at once.
        let x = (d * d + r * r - rho * rho) / (2.0 * d * r);
        if x <= -1.0 {
            for list in arcs.iter_mut() {
                list.push((0.0, TAU, 0.0));
            }
            return;
        }
        if x < 1.0 {
            let h = x.acos();
            push(0, 0.0, -h, h);
            push(1, 0.0, -h, h);
        }
        // The ray's line within rho of the centre, the centre ahead: cos theta in (lo, hi).
        let (lo, hi) = ((r - rho) / d, (r + rho) / d);
        if lo < 1.0 {
            let (near, far) = (hi.min(1.0).acos(), lo.max(-1.0).acos());
            push(0, d, -far, -near);
            push(1, d, near, far);
        }
    }

    /// Appends to `out` the angles the sorted arcs usable within `limit` leave uncovered
    /// (as `(from, to)`, `from < to`), each turned by `turn`.
    pub(super) fn gaps(
        arcs: &[(Real, Real, Real)],
        limit: Real,
        turn: Real,
        out: &mut Vec<(Real, Real)>,
    ) {
        let mut upto: Real = 0.0;
        for &(from, to, reach) in arcs {
            if reach >= limit {
                continue;
            }
            if from > upto {
                out.push((upto + turn, from + turn));
            }
            upto = upto.max(to);
            if upto >= TAU {
                return;
            }
        }
        out.push((upto + turn, TAU + turn));
    }
}

/// Removes the angles of `[from, to]` (`to - from` in `[0, 2 pi]`, taken modulo 2 pi)
/// from the arcs `(a, b)` of `arcs` (`b - a` in `[0, 2 pi]`).
pub(super) fn cut(
    arcs: &mut Vec<(Real, Real)>,
    scratch: &mut Vec<(Real, Real)>,
    from: Real,
    to: Real,
) {
    scratch.clear();
    for &(a, b) in arcs.iter() {
        // The cut moved by whole turns to start at or after a.
        let start = a + (from - a).rem_euclid(TAU);
        let end = start + (to - from);
        // The cut's turn before this one may still cover the arc's start.
        let (prev_start, prev_end) = (start - TAU, end - TAU);
        let mut lo = a;
        if prev_end > lo && prev_start <= lo {
            lo = prev_end;
        }
        if lo >= b {
            continue;
        }
        if start >= b {
            scratch.push((lo, b));
        } else {
            if start > lo {
                scratch.push((lo, start));
            }
            if end < b {
                scratch.push((end, b));
            }
        }
    }
    std::mem::swap(arcs, scratch);
}

/// Whether the arc of angles from `a` of length `la` meets the arc from `b` of length `lb`
/// (closed; lengths in `[0, 2 pi]`).
pub(super) fn overlap(a: Real, la: Real, b: Real, lb: Real) -> bool {
    (b - a).rem_euclid(TAU) <= la || (a - b).rem_euclid(TAU) <= lb
}

/// The unit vector at angle `a`.
pub(super) fn at(a: Real) -> Vector {
    Vector::new(a.cos(), a.sin())
}

/// `a` in `[0, 2 pi)`.
pub(super) fn wrap(a: Real) -> Real {
    let w = a.rem_euclid(TAU);
    if w >= TAU { 0.0 } else { w }
}
