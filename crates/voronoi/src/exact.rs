//! The graph of a scene against its exact circles: the raster a scene's graph is built on
//! marks a cell by its centre, so a ridge can run up to half a cell inside a circle, and
//! through a gap between two circles narrower than a cell. This step pushes every polyline
//! point out of the circles and drops an edge that still cannot keep out of them.

use homospline_geom::{CircleSet, Point, Real};

use crate::graph::{NodeKind, VoronoiGraph};

/// Pushes `p` out of the circles until its clearance is at least `margin` (along the
/// clearance gradient, a few steps for points between circles), with that clearance; `None`
/// if it cannot.
fn push_out(p: Point, circles: &CircleSet, margin: Real) -> Option<(Point, Real)> {
    let mut p = p;
    for _ in 0..16 {
        let c = match circles.clearance(&p) {
            None => return Some((p, Real::INFINITY)),
            Some(c) => c,
        };
        if c.distance >= margin {
            return Some((p, c.distance));
        }
        if c.gradient == homospline_geom::Vector::zeros() {
            return None;
        }
        // Aimed past the margin by half of it: aimed at the margin itself, a step could
        // land a rounding error short of it, and every later step too (a point 0.011 inside
        // a circle came out at clearance 0.002 - 2e-15 against a margin of 0.002, sixteen
        // times, and its edge was kept on the raster, inside the circle).
        p += c.gradient * (1.5 * margin - c.distance);
    }
    None
}

/// The exact clearance of the segment `ab`.
fn segment_clearance(a: &Point, b: &Point, circles: &CircleSet) -> Real {
    circles
        .distance_to_segment(a, b)
        .map_or(Real::INFINITY, |(d, _)| d)
}

/// The clearance of `p`.
fn clearance_of(p: &Point, circles: &CircleSet) -> Real {
    circles.clearance(p).map_or(Real::INFINITY, |c| c.distance)
}

/// How many times [`refine`] may halve one polyline segment. Only the pieces that cut a
/// circle are halved, so the work is a few pieces per halving; what ends the halving is
/// the piece's length reaching the margin (a thousandth of a cell), which a segment across
/// a 4096-cell grid reaches after 22 halvings. A fixed depth of 6 failed on a long straight
/// edge that grazed a circle: its first halvings were spent far from the circle, and the
/// edge kept its raster polyline 0.012 inside it.
const MAX_HALVINGS: u32 = 40;

/// A segment and its ends' clearances.
struct Piece {
    a: Point,
    da: Real,
    b: Point,
    db: Real,
}

/// Appends the points after `a` up to `b` to `out`, halving `ab` (pushed out) until every
/// piece keeps out of the circles; `false` if that fails within `depth` halvings or once a
/// piece that still cuts a circle is no longer than `margin`. `least`
/// takes in the clearance of every piece appended whose clearance could be below `floor`:
/// a piece whose ends' clearances `da`, `db` prove it clear by at least `floor` (the
/// clearance is 1-Lipschitz, so it is at least `(da + db - |ab|) / 2` along the piece) is
/// appended without its exact clearance.
fn refine(
    piece: Piece,
    circles: &CircleSet,
    (margin, floor): (Real, Real),
    depth: u32,
    out: &mut Vec<Point>,
    least: &mut Real,
) -> bool {
    let Piece { a, da, b, db } = piece;
    let lower = 0.5 * (da + db - (b - a).norm());
    if lower > 0.0 && lower > floor + 1e-9 * (1.0 + floor.abs()) {
        out.push(b);
        return true;
    }
    let d = segment_clearance(&a, &b, circles);
    if d >= 0.0 {
        out.push(b);
        *least = least.min(d);
        return true;
    }
    if depth == 0 || (b - a).norm() <= margin {
        return false;
    }
    let Some((m, dm)) = push_out(Point::from((a.coords + b.coords) * 0.5), circles, margin) else {
        return false;
    };
    let (first, second) = (
        Piece {
            a,
            da,
            b: m,
            db: dm,
        },
        Piece {
            a: m,
            da: dm,
            b,
            db,
        },
    );
    refine(first, circles, (margin, floor), depth - 1, out, least)
        && refine(second, circles, (margin, floor), depth - 1, out, least)
}

/// Makes every edge of `graph` keep out of `circles` (`margin` is the clearance a moved
/// point gets): nodes other than start and goal are pushed out, then each polyline's points,
/// with points inserted where a segment still cuts a circle. An edge that cannot (it runs
/// through a gap the circles close, or narrower than the raster could see) is dropped, unless
/// it joins the start or the goal, which stays as it is (its clearance says so). Each edge's
/// length and clearances are recomputed from its new polyline and the circles.
pub(crate) fn keep_out_of_circles(graph: &mut VoronoiGraph, circles: &CircleSet, margin: Real) {
    if circles.is_empty() {
        return;
    }
    for node in &mut graph.nodes {
        if matches!(node.kind, NodeKind::Start | NodeKind::Goal) {
            continue;
        }
        if let Some((p, _)) = push_out(Point::new(node.at[0], node.at[1]), circles, margin) {
            node.at = [p.x, p.y];
        }
    }
    let nodes = graph.nodes.clone();
    let (start, goal) = (graph.start, graph.goal);
    graph.edges.retain_mut(|e| {
        let connector = [Some(e.from), Some(e.to)]
            .iter()
            .any(|n| n.is_some() && (*n == start || *n == goal));
        let from = Point::new(nodes[e.from].at[0], nodes[e.from].at[1]);
        let to = Point::new(nodes[e.to].at[0], nodes[e.to].at[1]);
        let n = e.polyline.len();
        let mut pts = vec![from];
        // The least clearance of the segments of `pts` that could bring the edge's below
        // the raster's, each appended by `refine`.
        let mut exact = Real::INFINITY;
        let floor = e.min_clearance;
        let mut ok = true;
        let mut last = clearance_of(&from, circles);
        for (k, q) in e.polyline.iter().enumerate().skip(1) {
            let q = if k + 1 == n {
                Some((to, clearance_of(&to, circles)))
            } else {
                push_out(Point::new(q[0], q[1]), circles, margin)
            };
            let Some((q, dq)) = q else {
                ok = false;
                break;
            };
            let a = *pts.last().expect("the first point");
            let piece = Piece {
                a,
                da: last,
                b: q,
                db: dq,
            };
            ok &= refine(
                piece,
                circles,
                (margin, floor),
                MAX_HALVINGS,
                &mut pts,
                &mut exact,
            );
            last = dq;
            if !ok {
                break;
            }
        }
        if !ok {
            // The edge keeps its raster polyline only when it joins the start or the goal.
            if connector {
                let poly: Vec<Point> = e.polyline.iter().map(|q| Point::new(q[0], q[1])).collect();
                e.min_clearance = poly
                    .windows(2)
                    .map(|w| segment_clearance(&w[0], &w[1], circles))
                    .fold(e.min_clearance, Real::min);
                e.mean_clearance = e.mean_clearance.max(e.min_clearance);
            }
            return connector;
        }
        e.polyline = pts.iter().map(|p| [p.x, p.y]).collect();
        e.length = pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        e.min_clearance = e.min_clearance.min(exact);
        e.mean_clearance = e.mean_clearance.max(e.min_clearance);
        true
    });
}
