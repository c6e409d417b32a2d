//! The exact shortest path between two points that keeps a given clearance from a set of
//! circles: the geometric optimum that no curve of that clearance can beat.
//!
//! A curve whose clearance is at least `c` stays out of every open disc of radius `r + c`
//! around the circles, so its length is at least that of the shortest path in the plane
//! minus those discs. That path is made of straight segments tangent to the grown discs and
//! arcs of their boundaries (it never touches a point where two grown boundaries cross: the
//! union of the discs fills more than a half-plane around such a point). It is found exactly
//! on the *tangent graph*: its nodes are the start, the goal and every tangent point (from
//! the two points and between every pair of circles, outer and inner), its edges the tangent
//! segments that enter no disc and the arcs between consecutive nodes of one circle that
//! enter no other disc; Dijkstra's algorithm finds the shortest route. The pairs of circles
//! whose tangents are tested are only those a free tangent ray of one can reach (`Reach`),
//! a number that stays flat as a field of given density grows, so the graph is built in
//! near-linear time; each candidate segment is tested against the discs of the buckets it
//! crosses (`DiscIndex`), not against every disc. Meant for checking plans, not for
//! planning.
//!
//! The tests use it as an oracle: no reported curve may be shorter than the optimum at its
//! certified clearance. The robot's bounds are not taken in, so the result is a lower bound
//! for a robot that must stay inside them too.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::f64::consts::TAU;

use thiserror::Error;

use crate::math::{Point, Real, Vector};
use crate::shape::Circle;

mod index;
mod reach;

use index::DiscIndex;
use reach::{Pairs, Reach, at, wrap};

/// An input the query cannot take.
#[derive(Debug, Error, PartialEq)]
pub enum ShortestPathError {
    /// The clearance is negative or not finite.
    #[error("clearance must be finite and >= 0, got {0}")]
    Clearance(Real),
    /// A point is not finite.
    #[error("the {0} is not a finite point")]
    Point(&'static str),
    /// The length bound is not a number.
    #[error("the length bound must be a number, got {0}")]
    Bound(Real),
    /// A circle has a non-finite centre or a radius that is not finite and positive.
    #[error("circle {index} is invalid (centre and radius must be finite, radius > 0)")]
    Circle {
        /// Its index in the input.
        index: usize,
    },
}

/// One piece of a shortest path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    /// A straight segment.
    Segment {
        /// Where it starts.
        from: Point,
        /// Where it ends.
        to: Point,
    },
    /// An arc of a grown circle, from angle `from` to angle `to` (radians; counter-clockwise
    /// when `to > from`).
    Arc {
        /// The grown circle.
        circle: Circle,
        /// Start angle.
        from: Real,
        /// End angle.
        to: Real,
    },
}

impl Piece {
    /// The point at fraction `u` in `[0, 1]` of the piece.
    pub fn point(&self, u: Real) -> Point {
        match *self {
            Piece::Segment { from, to } => from + (to - from) * u,
            Piece::Arc { circle, from, to } => {
                circle.center + at(from + (to - from) * u) * circle.radius
            }
        }
    }

    /// Points along it from its start to its end: a segment's two ends; an arc's at equal
    /// angles at most `max_angle` radians apart (both ends included).
    pub fn points(&self, max_angle: Real) -> Vec<Point> {
        let n = match *self {
            Piece::Segment { .. } => 1,
            Piece::Arc { from, to, .. } => (((to - from).abs() / max_angle).ceil() as usize).max(1),
        };
        (0..=n).map(|k| self.point(k as Real / n as Real)).collect()
    }

    /// Its length.
    pub fn length(&self) -> Real {
        match *self {
            Piece::Segment { from, to } => (to - from).norm(),
            Piece::Arc { circle, from, to } => circle.radius * (to - from).abs(),
        }
    }
}

/// A shortest path: its length and its pieces from the start to the goal.
#[derive(Clone, Debug, PartialEq)]
pub struct ShortestPath {
    /// The length (the pieces' sum).
    pub length: Real,
    /// Segments and arcs, in order.
    pub pieces: Vec<Piece>,
}

/// Relative slack of the feasibility tests: a tangent segment touches its own discs, and
/// rounding puts it a few ulps inside. Allowing that much (1e-9 of the radius) can only
/// shorten the result, so it stays a lower bound (where two discs overlap by less than the
/// slack, a path may slip between them: still a lower bound, though not a tight one).
pub(crate) const SLACK: Real = 1e-9;

/// The length of the shortest path from `start` to `goal` that keeps at least `clearance`
/// from every circle (no bounds), or `None` when there is none: `start` or `goal` is less
/// than `clearance` from a circle, or the grown discs wall one off from the other.
///
/// ```
/// use homospline_geom::{Circle, Point, shortest::shortest_path_length};
///
/// // Around a unit circle grown by 1 between points 4 apart on each side of it.
/// let (s, t) = (Point::new(-4.0, 0.0), Point::new(4.0, 0.0));
/// let len = shortest_path_length(&s, &t, &[Circle::new(0.0, 0.0, 1.0)], 1.0).unwrap().unwrap();
/// // Two tangents of length sqrt(16 - 4) and the arc between them.
/// let exact = 2.0 * 12f64.sqrt() + 2.0 * (std::f64::consts::PI - 2.0 * (0.5f64).acos());
/// assert!((len - exact).abs() < 1e-9);
/// ```
pub fn shortest_path_length(
    start: &Point,
    goal: &Point,
    circles: &[Circle],
    clearance: Real,
) -> Result<Option<Real>, ShortestPathError> {
    Ok(shortest_path(start, goal, circles, clearance)?.map(|p| p.length))
}

/// [`shortest_path_length`] with the path itself.
pub fn shortest_path(
    start: &Point,
    goal: &Point,
    circles: &[Circle],
    clearance: Real,
) -> Result<Option<ShortestPath>, ShortestPathError> {
    Ok(TangentGraph::build(start, goal, circles, clearance)?.and_then(|g| g.shortest()))
}

/// The inputs' checks.
fn validate(
    start: &Point,
    goal: &Point,
    circles: &[Circle],
    clearance: Real,
) -> Result<(), ShortestPathError> {
    if !(clearance.is_finite() && clearance >= 0.0) {
        return Err(ShortestPathError::Clearance(clearance));
    }
    for (name, p) in [("start", start), ("goal", goal)] {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(ShortestPathError::Point(name));
        }
    }
    for (index, c) in circles.iter().enumerate() {
        if !(c.center.x.is_finite()
            && c.center.y.is_finite()
            && c.radius.is_finite()
            && c.radius > 0.0)
        {
            return Err(ShortestPathError::Circle { index });
        }
    }
    Ok(())
}

/// Whether `p` is in the open disc, past the slack.
pub(crate) fn inside(d: &Circle, p: &Point) -> bool {
    (p - d.center).norm() < d.radius * (1.0 - SLACK)
}

/// Whether the segment `[a, b]` enters the open disc `d`, past the slack.
pub(crate) fn enters(d: &Circle, a: &Point, b: &Point) -> bool {
    crate::math::distance_point_segment(&d.center, a, b) < d.radius * (1.0 - SLACK)
}

/// The tangent graph of the module doc, for searches of one's own (a homotopy class's
/// shortest path searches it with each edge's ray crossings). Node [`TangentGraph::START`]
/// is the start, [`TangentGraph::GOAL`] the goal; every edge is a piece of free space (up to
/// the slack) and is listed from both of its ends, oriented away from the node.
#[derive(Clone, Debug)]
pub struct TangentGraph {
    discs: Vec<Circle>,
    /// The discs bucketed, for the feasibility tests.
    index: DiscIndex,
    nodes: Vec<Point>,
    /// Per disc, its nodes' angles and indices.
    on_disc: Vec<Vec<(Real, usize)>>,
    edges: Vec<Vec<Edge>>,
}

/// An edge of the tangent graph, from the node whose list holds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The node it leads to.
    pub to: usize,
    /// The segment or arc, oriented from the node whose list holds it to `to`.
    pub piece: Piece,
}

impl TangentGraph {
    /// The start's node.
    pub const START: usize = 0;
    /// The goal's node.
    pub const GOAL: usize = 1;

    /// The graph of the paths from `start` to `goal` that keep `clearance` from `circles`;
    /// `None` when `start` or `goal` is less than `clearance` from a circle.
    pub fn build(
        start: &Point,
        goal: &Point,
        circles: &[Circle],
        clearance: Real,
    ) -> Result<Option<Self>, ShortestPathError> {
        Self::build_within(start, goal, circles, clearance, Real::INFINITY)
    }

    /// [`TangentGraph::build`] keeping only the pieces of the routes from `start` to `goal`
    /// no longer than `bound`: a disc no such route can touch gets no node (it still
    /// blocks), and a tangent whose ends cannot both lie on such a route is not tested.
    /// Every route of length at most `bound` is in the graph with its length, so its
    /// shortest route and a class's are those of the whole graph whenever they are no
    /// longer than `bound`; longer routes may be missing. With a curve's length as the
    /// bound, the candidate tangents fall to those in the ellipse of foci `start` and
    /// `goal` through the curve's length, several times fewer on random fields for curves
    /// near the straight line (docs/performance.md). An infinite bound keeps everything.
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_geom::{Circle, Point, shortest::TangentGraph};
    ///
    /// let (s, t) = (Point::new(-4.0, 0.0), Point::new(4.0, 0.0));
    /// let circles = [Circle::new(0.0, 0.0, 1.0), Circle::new(0.0, 30.0, 1.0)];
    /// let all = TangentGraph::build(&s, &t, &circles, 0.5).unwrap().unwrap();
    /// let near = TangentGraph::build_within(&s, &t, &circles, 0.5, 10.0).unwrap().unwrap();
    /// // The far circle gets no node, and the shortest route is the same.
    /// assert!(near.nodes().len() < all.nodes().len());
    /// assert_eq!(near.shortest().unwrap().length, all.shortest().unwrap().length);
    /// ```
    pub fn build_within(
        start: &Point,
        goal: &Point,
        circles: &[Circle],
        clearance: Real,
        bound: Real,
    ) -> Result<Option<Self>, ShortestPathError> {
        validate(start, goal, circles, clearance)?;
        if bound.is_nan() {
            return Err(ShortestPathError::Bound(bound));
        }
        let discs: Vec<Circle> = circles.iter().map(|c| c.inflated(clearance)).collect();
        if [start, goal]
            .iter()
            .any(|p| discs.iter().any(|d| inside(d, p)))
        {
            return Ok(None);
        }
        Ok(Some(Self::new(start, goal, discs, bound, Pairs::Visible)))
    }

    /// The nodes' points.
    pub fn nodes(&self) -> &[Point] {
        &self.nodes
    }

    /// The edges leaving `node`.
    pub fn edges(&self, node: usize) -> &[Edge] {
        &self.edges[node]
    }

    fn new(start: &Point, goal: &Point, discs: Vec<Circle>, bound: Real, pairs: Pairs) -> Self {
        let mut g = Self {
            on_disc: vec![Vec::new(); discs.len()],
            index: DiscIndex::new(&discs),
            discs: discs.clone(),
            nodes: vec![*start, *goal],
            edges: vec![Vec::new(); 2],
        };
        // A route through points p and q (in either order) is at least as long as
        // `through(p, q)`; through a point of disc i, at least `reach[i]`.
        let (s, t) = (*start, *goal);
        let through = |p: &Point, q: &Point| {
            (p - q).norm() + ((s - p).norm() + (q - t).norm()).min((s - q).norm() + (p - t).norm())
        };
        let to_s: Vec<Real> = discs.iter().map(|d| (d.center - s).norm()).collect();
        let to_t: Vec<Real> = discs.iter().map(|d| (d.center - t).norm()).collect();
        let kept: Vec<usize> = (0..discs.len())
            .filter(|&i| to_s[i] + to_t[i] - 2.0 * discs[i].radius <= bound)
            .collect();
        if (s - t).norm() <= bound {
            g.segment(None, None, s, t);
        }
        let mut is_kept = vec![false; discs.len()];
        for &i in &kept {
            is_kept[i] = true;
        }
        let mut reach = Reach::new(discs.len());
        let mut partners = Vec::new();
        for &i in &kept {
            let d = &discs[i];
            // Tangents from each end point.
            for (node, p) in [(0usize, *start), (1, *goal)] {
                let v = p - d.center;
                let dist = v.norm();
                let base = v.y.atan2(v.x);
                if dist <= d.radius {
                    // On the grown circle (within the slack: it is not inside): the point is
                    // a node of the circle itself, and the path may start along its arc.
                    g.on_disc[i].push((wrap(base), node));
                    continue;
                }
                let half = (d.radius / dist).clamp(-1.0, 1.0).acos();
                for a in [base + half, base - half] {
                    let q = d.center + at(a) * d.radius;
                    if through(&p, &q) <= bound {
                        g.segment(Some(node), Some((i, a)), p, q);
                    }
                }
            }
            // Outer and inner tangents to every later disc a route within the bound may
            // pass along with this one, among those a tangent of this one can reach.
            match pairs {
                Pairs::Visible => reach.partners(&g.discs, &g.index, i, &mut partners),
                #[cfg(test)]
                Pairs::All => partners = (0..discs.len()).collect(),
            }
            for &j in partners.iter().filter(|&&j| j > i && is_kept[j]) {
                let e = &discs[j];
                let v = e.center - d.center;
                let dist = v.norm();
                let (near_s, near_t) = (to_s[i] + to_t[j], to_s[j] + to_t[i]);
                if dist == 0.0 || dist + near_s.min(near_t) - 2.0 * (d.radius + e.radius) > bound {
                    continue;
                }
                let base = v.y.atan2(v.x);
                // Outer: the normal n has n . v / |v| = (r_i - r_j) / d, both points at +n.
                let cos_outer = (d.radius - e.radius) / dist;
                if cos_outer.abs() < 1.0 {
                    let half = cos_outer.acos();
                    for a in [base + half, base - half] {
                        let (p, q) = (d.center + at(a) * d.radius, e.center + at(a) * e.radius);
                        if through(&p, &q) <= bound {
                            g.bitangent((i, a), (j, a), p, q);
                        }
                    }
                }
                // Inner: n . v / |v| = (r_i + r_j) / d, the point on j at -n.
                let cos_inner = (d.radius + e.radius) / dist;
                // `<=`: discs that touch have a zero-length inner tangent through the contact.
                if cos_inner <= 1.0 {
                    let half = cos_inner.acos();
                    for a in [base + half, base - half] {
                        let b = a + std::f64::consts::PI;
                        let (p, q) = (d.center + at(a) * d.radius, e.center + at(b) * e.radius);
                        if through(&p, &q) <= bound {
                            g.bitangent((i, a), (j, b), p, q);
                        }
                    }
                }
            }
        }
        g.arcs();
        g
    }

    /// A node at angle `a` on disc `i`, unless another disc covers it.
    fn node_on(&mut self, (i, a): (usize, Real), p: Point) -> Option<usize> {
        if self
            .index
            .near_point(&p)
            .any(|k| k != i && inside(&self.discs[k], &p))
        {
            return None;
        }
        let n = self.nodes.len();
        self.nodes.push(p);
        self.edges.push(Vec::new());
        self.on_disc[i].push((wrap(a), n));
        Some(n)
    }

    /// An edge both ways: a segment (`arc: None`) or the arc of disc `i` from angle `a0`
    /// to `a1` counter-clockwise (from `u` to `v`).
    fn link(&mut self, u: usize, v: usize, arc: Option<(usize, Real, Real)>) {
        let (forth, back) = match arc {
            None => {
                let (a, b) = (self.nodes[u], self.nodes[v]);
                (
                    Piece::Segment { from: a, to: b },
                    Piece::Segment { from: b, to: a },
                )
            }
            Some((i, a0, a1)) => {
                let circle = self.discs[i];
                (
                    Piece::Arc {
                        circle,
                        from: a0,
                        to: a1,
                    },
                    Piece::Arc {
                        circle,
                        from: a1,
                        to: a0,
                    },
                )
            }
        };
        self.edges[u].push(Edge {
            to: v,
            piece: forth,
        });
        self.edges[v].push(Edge { to: u, piece: back });
    }

    /// The segment from the end point `from` (or `None`: the start) to a tangent point, or
    /// the start-goal segment, if it enters no disc.
    fn segment(&mut self, from: Option<usize>, to: Option<(usize, Real)>, p: Point, q: Point) {
        if self.index.blocked(&self.discs, &p, &q) {
            return;
        }
        match (from, to) {
            (Some(u), Some(t)) => {
                if let Some(v) = self.node_on(t, q) {
                    self.link(u, v, None);
                }
            }
            _ => self.link(0, 1, None),
        }
    }

    fn bitangent(&mut self, a: (usize, Real), b: (usize, Real), p: Point, q: Point) {
        if self.index.blocked(&self.discs, &p, &q) {
            return;
        }
        if let Some(u) = self.node_on(a, p)
            && let Some(v) = self.node_on(b, q)
        {
            self.link(u, v, None);
        }
    }

    /// The arcs between consecutive nodes of each disc that enter no other disc.
    fn arcs(&mut self) {
        for i in 0..self.discs.len() {
            let mut list = std::mem::take(&mut self.on_disc[i]);
            list.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            let n = list.len();
            if n >= 2 {
                for k in 0..n {
                    let (a0, u) = list[k];
                    let (mut a1, v) = list[(k + 1) % n];
                    if k + 1 == n {
                        a1 += TAU;
                    }
                    if !self.arc_is_free(i, a0, a1) {
                        continue;
                    }
                    self.link(u, v, Some((i, a0, a1)));
                }
            }
            self.on_disc[i] = list;
        }
    }

    /// Whether the arc of disc `i` from angle `a0` to `a1` (counter-clockwise, `a1 >= a0`,
    /// `a0` in `[0, 2 pi)`) stays out of every other open disc.
    fn arc_is_free(&self, i: usize, a0: Real, a1: Real) -> bool {
        let d = self.discs[i];
        let r = Vector::new(d.radius, d.radius);
        self.index
            .near_box(&(d.center - r), &(d.center + r))
            .all(|k| {
                let e = self.discs[k];
                if k == i {
                    return true;
                }
                let v = e.center - d.center;
                let dist = v.norm();
                let (ri, rk) = (d.radius, e.radius * (1.0 - SLACK));
                if dist >= ri + rk || dist + rk <= ri {
                    // Apart, or disc k inside disc i: circle i never enters it.
                    return true;
                }
                if dist + ri <= rk {
                    // Circle i lies inside disc k (its nodes were dropped already).
                    return false;
                }
                // Circle i is inside disc k on the open interval (phi - h, phi + h).
                let phi = v.y.atan2(v.x);
                let h = ((ri * ri + dist * dist - rk * rk) / (2.0 * ri * dist))
                    .clamp(-1.0, 1.0)
                    .acos();
                let lo = wrap(phi - h);
                // The forbidden interval [lo, lo + 2h] against the arc [a0, a1], both taken
                // modulo 2 pi: they overlap if the forbidden one starts inside the arc or the
                // arc starts inside the forbidden one.
                let start_in_arc = (lo - a0).rem_euclid(TAU) < a1 - a0;
                let arc_in_forbidden = (a0 - lo).rem_euclid(TAU) < 2.0 * h;
                !(start_in_arc || arc_in_forbidden)
            })
    }

    /// Each node's distance to `node` (every edge is listed from both ends, so it is the
    /// distance from it too): for a search's heuristic.
    pub fn distances_to(&self, node: usize) -> Vec<Real> {
        self.dijkstra(node, None).0
    }

    /// The shortest path from the start to the goal (Dijkstra), `None` when the grown
    /// circles wall one off from the other.
    pub fn shortest(&self) -> Option<ShortestPath> {
        let (dist, came) = self.dijkstra(Self::START, Some(Self::GOAL));
        if !dist[Self::GOAL].is_finite() {
            return None;
        }
        let mut pieces = Vec::new();
        let mut v = Self::GOAL;
        while let Some((u, e)) = came[v] {
            pieces.push(e.piece);
            v = u;
        }
        pieces.reverse();
        Some(ShortestPath {
            length: dist[Self::GOAL],
            pieces,
        })
    }

    /// Dijkstra from `source`, stopping once `target` is settled: each node's distance, and
    /// the node and edge it was reached by.
    fn dijkstra(
        &self,
        source: usize,
        target: Option<usize>,
    ) -> (Vec<Real>, Vec<Option<(usize, Edge)>>) {
        let mut dist = vec![Real::INFINITY; self.nodes.len()];
        let mut came: Vec<Option<(usize, Edge)>> = vec![None; self.nodes.len()];
        dist[source] = 0.0;
        // Entries (distance's bits, node): non-negative floats order as their bits.
        let mut heap = BinaryHeap::from([Reverse((0u64, source))]);
        while let Some(Reverse((bits, u))) = heap.pop() {
            let du = Real::from_bits(bits);
            if Some(u) == target {
                break;
            }
            if du > dist[u] {
                continue;
            }
            for e in &self.edges[u] {
                let dv = du + e.piece.length();
                if dv < dist[e.to] {
                    dist[e.to] = dv;
                    came[e.to] = Some((u, *e));
                    heap.push(Reverse((dv.to_bits(), e.to)));
                }
            }
        }
        (dist, came)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::FRAC_PI_2;

    proptest! {
        /// The bucketed tests answer as the tests of every disc did.
        #[test]
        fn the_disc_index_answers_as_testing_every_disc(
            discs in prop::collection::vec((-20.0..20.0f64, -20.0..20.0f64, 0.01..6.0f64), 1..60),
            segs in prop::collection::vec((-30.0..30.0f64, -30.0..30.0f64, -30.0..30.0f64, -30.0..30.0f64), 1..40),
        ) {
            let discs: Vec<Circle> = discs.iter().map(|&(x, y, r)| Circle::new(x, y, r)).collect();
            let index = DiscIndex::new(&discs);
            for &(ax, ay, bx, by) in &segs {
                let (a, b) = (Point::new(ax, ay), Point::new(bx, by));
                let brute = discs.iter().any(|d| enters(d, &a, &b));
                prop_assert_eq!(index.blocked(&discs, &a, &b), brute);
                prop_assert_eq!(index.blocked(&discs, &a, &a), discs.iter().any(|d| enters(d, &a, &a)));
                let near: Vec<usize> = index.near_point(&a).collect();
                for (k, d) in discs.iter().enumerate() {
                    if inside(d, &a) {
                        prop_assert!(near.contains(&k));
                    }
                }
                let (lo, hi) = (a.inf(&b), a.sup(&b));
                let near: Vec<usize> = index.near_box(&lo, &hi).collect();
                for (k, d) in discs.iter().enumerate() {
                    let c = d.center;
                    let meets = c.x + d.radius >= lo.x && c.x - d.radius <= hi.x
                        && c.y + d.radius >= lo.y && c.y - d.radius <= hi.y;
                    if meets {
                        prop_assert!(near.contains(&k));
                    }
                }
            }
        }
    }

    proptest! {
        /// A bounded graph's shortest route is the whole graph's whenever that is within the
        /// bound (to rounding), and no route it finds is shorter than the whole graph's.
        #[test]
        fn a_bounded_graph_keeps_every_route_within_its_bound(
            discs in prop::collection::vec((-20.0..20.0f64, -20.0..20.0f64, 0.2..4.0f64), 1..40),
            clearance in 0.0..1.0f64,
            slack in 1.0..1.6f64,
        ) {
            let discs: Vec<Circle> = discs.iter().map(|&(x, y, r)| Circle::new(x, y, r)).collect();
            let (s, t) = (Point::new(-25.0, -3.0), Point::new(25.0, 4.0));
            let Some(all) = TangentGraph::build(&s, &t, &discs, clearance).unwrap() else {
                return Ok(());
            };
            let Some(best) = all.shortest() else { return Ok(()) };
            for bound in [best.length * slack, best.length * (1.0 + 1e-9), best.length * 0.99] {
                let some = TangentGraph::build_within(&s, &t, &discs, clearance, bound)
                    .unwrap()
                    .unwrap();
                prop_assert!(some.nodes().len() <= all.nodes().len());
                match some.shortest() {
                    // The same route, its pieces summed in another order: equal to 1e-12.
                    Some(p) if bound >= best.length => {
                        prop_assert!((p.length - best.length).abs() <= 1e-12 * best.length)
                    }
                    Some(p) => prop_assert!(p.length >= best.length * (1.0 - 1e-12)),
                    None => prop_assert!(bound < best.length),
                }
            }
        }
    }

    /// The graph built from the visible pairs and from every pair, on grown discs.
    fn both(
        s: Point,
        t: Point,
        discs: &[Circle],
        clearance: Real,
    ) -> Option<(TangentGraph, TangentGraph)> {
        let grown: Vec<Circle> = discs.iter().map(|c| c.inflated(clearance)).collect();
        if grown.iter().any(|d| inside(d, &s) || inside(d, &t)) {
            return None;
        }
        let visible = TangentGraph::new(&s, &t, grown.clone(), Real::INFINITY, Pairs::Visible);
        let all = TangentGraph::new(&s, &t, grown, Real::INFINITY, Pairs::All);
        Some((visible, all))
    }

    proptest! {
        /// The pairs left out are those whose every tangent is blocked: the graph is the
        /// same, node for node and edge for edge, in sparse fields, dense fields and
        /// clusters of overlapping discs.
        #[test]
        fn the_visible_pairs_give_the_graph_of_every_pair(
            discs in prop::collection::vec((-15.0..15.0f64, -15.0..15.0f64, 0.05..3.0f64), 1..120),
            clearance in 0.0..0.8f64,
        ) {
            let discs: Vec<Circle> = discs.iter().map(|&(x, y, r)| Circle::new(x, y, r)).collect();
            let (s, t) = (Point::new(-16.0, -16.0), Point::new(16.0, 15.5));
            let Some((visible, all)) = both(s, t, &discs, clearance) else { return Ok(()) };
            prop_assert_eq!(&visible.nodes, &all.nodes);
            prop_assert_eq!(&visible.edges, &all.edges);
        }
    }

    /// `n` discs uniform in a square of side `sqrt(n)`, radius 0.3 to 0.45: a third of the
    /// area covered, whatever `n`.
    fn field(n: usize, seed: u64) -> Vec<Circle> {
        let mut seed = seed;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as Real / (1u64 << 53) as Real
        };
        let side = (n as Real).sqrt();
        (0..n)
            .map(|_| Circle::new(side * next(), side * next(), 0.3 + 0.15 * next()))
            .collect()
    }

    /// The mean number of partners of the discs within 5 of the middle of a field.
    fn mean_partners(discs: &[Circle]) -> Real {
        let grown: Vec<Circle> = discs.iter().map(|c| c.inflated(0.05)).collect();
        let index = DiscIndex::new(&grown);
        let middle = Point::new(1.0, 1.0) * (discs.len() as Real).sqrt() / 2.0;
        let mut reach = Reach::new(grown.len());
        let (mut sum, mut count, mut out) = (0, 0, Vec::new());
        for (i, d) in grown.iter().enumerate() {
            if (d.center - middle).norm() < 5.0 {
                reach.partners(&grown, &index, i, &mut out);
                sum += out.len();
                count += 1;
            }
        }
        sum as Real / count as Real
    }

    /// A disc's partners are the discs its free rays can reach, as many in a field four
    /// times as large of the same density: the pair tests grow as the discs, not their
    /// square. The graph is still that of every pair.
    #[test]
    fn partners_do_not_grow_with_the_field() {
        let (small, large) = (field(900, 7), field(3600, 7));
        let (p_small, p_large) = (mean_partners(&small), mean_partners(&large));
        assert!(p_small < 900.0 / 3.0, "{p_small} partners of 900");
        assert!(
            p_large < 1.5 * p_small,
            "{p_large} partners of 3600 against {p_small} of 900"
        );
        let (s, t) = (Point::new(-1.0, -1.0), Point::new(30.5, 30.5));
        let (visible, all) = both(s, t, &small, 0.05).unwrap();
        assert_eq!(visible.nodes, all.nodes);
        assert_eq!(visible.edges, all.edges);
        assert!(visible.shortest().is_some());
    }

    #[test]
    fn a_clear_segment_is_its_own_shortest_path() {
        let c = [Circle::new(0.0, 5.0, 1.0)];
        let (s, t) = (Point::new(-3.0, 0.0), Point::new(3.0, 0.0));
        assert_eq!(shortest_path_length(&s, &t, &c, 1.0), Ok(Some(6.0)));
    }

    #[test]
    fn ends_on_a_grown_circle_go_round_its_arc() {
        // Both ends exactly at the clearance from a unit circle: half the grown circle.
        let c = [Circle::new(0.0, 0.0, 1.0)];
        let (s, t) = (Point::new(-2.0, 0.0), Point::new(2.0, 0.0));
        let len = shortest_path_length(&s, &t, &c, 1.0).unwrap().unwrap();
        assert!((len - 2.0 * std::f64::consts::PI).abs() < 1e-12, "{len}");
    }

    #[test]
    fn ends_too_close_or_walled_off_have_no_path() {
        let s = Point::new(0.0, 0.0);
        let t = Point::new(10.0, 0.0);
        let near = [Circle::new(1.0, 0.0, 0.5)];
        assert_eq!(shortest_path_length(&s, &t, &near, 1.0), Ok(None));
        // A ring of touching circles around the goal.
        let ring: Vec<Circle> = (0..12)
            .map(|k| {
                let a = TAU * k as Real / 12.0;
                Circle::new(10.0 + 3.0 * a.cos(), 3.0 * a.sin(), 0.9)
            })
            .collect();
        assert_eq!(shortest_path_length(&s, &t, &ring, 0.0), Ok(None));
        assert!(shortest_path_length(&s, &t, &ring, -1.0).is_err());
        assert!(shortest_path_length(&s, &t, &[Circle::new(0.0, 9.0, 0.0)], 0.0).is_err());
    }

    #[test]
    fn an_arc_through_another_disc_is_not_free() {
        // Circle 0 at the origin, radius 3; circle 1 covers its arc within 38.9 degrees of
        // the positive x axis (cos h = (9 + 9 - 4) / 18).
        let discs = [Circle::new(0.0, 0.0, 3.0), Circle::new(3.0, 0.0, 2.0)];
        let g = TangentGraph::new(
            &Point::new(-9.0, 0.0),
            &Point::new(9.0, 9.0),
            discs.to_vec(),
            Real::INFINITY,
            Pairs::Visible,
        );
        let h = (14.0 / 18.0 as Real).acos();
        assert!(!g.arc_is_free(0, TAU - 1.0, TAU + 1.0));
        assert!(!g.arc_is_free(0, 0.5 * h, 0.6 * h));
        assert!(!g.arc_is_free(0, 0.9 * h, 2.0));
        assert!(g.arc_is_free(0, 1.01 * h, 3.0));
        assert!(g.arc_is_free(0, 3.0, TAU - 1.01 * h));
        // Circle 1 inside circle 0's disc over its left part: its right arcs are free.
        assert!(g.arc_is_free(1, TAU - 1.0, TAU + 1.0));
        assert!(!g.arc_is_free(1, 3.0, 3.2));
    }

    #[test]
    fn two_overlapping_circles_are_passed_round_their_outer_arcs() {
        // Two unit circles overlapping into a peanut across the line; the path goes round
        // above or below (symmetric), over the two outer arcs.
        let c = [Circle::new(-0.5, 0.0, 1.0), Circle::new(0.5, 0.0, 1.0)];
        let (s, t) = (Point::new(-5.0, 0.0), Point::new(5.0, 0.0));
        let len = shortest_path_length(&s, &t, &c, 0.0).unwrap().unwrap();
        // Tangent from (-5, 0) to the left circle (distance 4.5 from its centre), the outer
        // tangent along y = 1 (length 1), the same on the right.
        let d: Real = 4.5;
        let tangent = (d * d - 1.0).sqrt();
        let arc = FRAC_PI_2 - (1.0 / d).acos();
        let exact = 2.0 * (tangent + arc) + 1.0;
        assert!((len - exact).abs() < 1e-9, "{len} vs {exact}");
    }
}
