//! Clearance, segment distance, intersection, line of sight and ray casts against circles.
//!
//! Queries on one circle are free functions named `[operation]_[shape]_[shape]`
//! ([`distance_point_circle`], [`distance_segment_circle`], [`cast_ray_circle`]); the
//! [`CircleSet`] entry point answers them for a whole set, with a plain loop for small sets
//! and parry's BVH for large ones ([`QueryBackend`]).
//!
//! The clearance of a point is equation (6) of the method: `min_c (|p - c| - r_c)`. It is the
//! exact Euclidean distance to the union of the discs whenever it is non-negative; inside
//! the union it is negative, and its magnitude is the depth inside the nearest single disc.

use parry2d_f64::bounding_volume::Aabb;
use parry2d_f64::math::Vector as PVector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhNode};
use parry2d_f64::query::Ray;

use crate::math::{Point, Real, Vector, closest_on_segment, distance_point_segment};
use crate::shape::Circle;

/// Signed distance from `p` to the circle's boundary (negative inside).
#[inline]
pub fn distance_point_circle(p: &Point, c: &Circle) -> Real {
    c.signed_distance(p)
}

/// Signed distance from the segment `[a, b]` to the circle: the distance from the centre to
/// the segment minus the radius. Exact; negative when the segment enters the disc.
#[inline]
pub fn distance_segment_circle(a: &Point, b: &Point, c: &Circle) -> Real {
    distance_point_segment(&c.center, a, b) - c.radius
}

/// Whether the segment `[a, b]` meets the closed disc.
#[inline]
pub fn intersects_segment_circle(a: &Point, b: &Point, c: &Circle) -> bool {
    distance_segment_circle(a, b, c) <= 0.0
}

/// First time `t` in `[0, max_toi]` at which `origin + t * dir` is in the closed disc.
/// A ray that starts inside hits at `t = 0` (the disc is solid).
pub fn cast_ray_circle(origin: &Point, dir: &Vector, c: &Circle, max_toi: Real) -> Option<Real> {
    let m = origin - c.center;
    let cc = m.norm_squared() - c.radius * c.radius;
    if cc <= 0.0 {
        return Some(0.0);
    }
    let a = dir.norm_squared();
    if a == 0.0 {
        return None;
    }
    let b = m.dot(dir);
    if b >= 0.0 {
        return None; // moving away from an outside start
    }
    let disc = b * b - a * cc;
    if disc < 0.0 {
        return None;
    }
    // Numerically stable smaller root: t = cc / (-b + sqrt(disc)).
    let t = cc / (-b + disc.sqrt());
    (t <= max_toi).then_some(t)
}

/// Distance from the segment `[a, b]` to the closed axis-aligned box `[mins, maxs]`; 0 when
/// they meet (Liang-Barsky clipping, else the least of the ends' distances to the box and
/// the corners' to the segment: two disjoint convex sets are nearest at a vertex of one).
///
/// # Examples
/// ```
/// use homospline_geom::Point;
/// use homospline_geom::query::distance_segment_aabb;
///
/// let (lo, hi) = (Point::new(1.0, -1.0), Point::new(2.0, 0.0));
/// // Round the box's corner (1, 0): the segment passes it at sqrt(2) / 4.
/// let d = distance_segment_aabb(&Point::new(0.5, 0.0), &Point::new(1.0, 0.5), &lo, &hi);
/// assert!((d - 2f64.sqrt() / 4.0).abs() < 1e-12);
/// ```
pub fn distance_segment_aabb(a: &Point, b: &Point, mins: &Point, maxs: &Point) -> Real {
    // Liang-Barsky clip: does the segment enter the box?
    let d = b - a;
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    let mut meets = true;
    for (p, q) in [
        (-d.x, a.x - mins.x),
        (d.x, maxs.x - a.x),
        (-d.y, a.y - mins.y),
        (d.y, maxs.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                meets = false;
                break;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
            if t0 > t1 {
                meets = false;
                break;
            }
        }
    }
    if meets {
        return 0.0;
    }
    // Disjoint convex sets in the plane: the closest pair involves a vertex of one of them.
    let box_dist = |p: &Point| {
        let dx = (mins.x - p.x).max(p.x - maxs.x).max(0.0);
        let dy = (mins.y - p.y).max(p.y - maxs.y).max(0.0);
        (dx * dx + dy * dy).sqrt()
    };
    let corners = [
        Point::new(mins.x, mins.y),
        Point::new(maxs.x, mins.y),
        Point::new(maxs.x, maxs.y),
        Point::new(mins.x, maxs.y),
    ];
    let mut best = box_dist(a).min(box_dist(b));
    for c in &corners {
        best = best.min(distance_point_segment(c, a, b));
    }
    best
}

fn node_distance_point(node: &BvhNode, p: &Point) -> Real {
    let (mins, maxs) = (node.mins(), node.maxs());
    let dx = (mins.x - p.x).max(p.x - maxs.x).max(0.0);
    let dy = (mins.y - p.y).max(p.y - maxs.y).max(0.0);
    (dx * dx + dy * dy).sqrt()
}

/// A BVH lower bound is only valid for outside distances: a node the query touches may hold a
/// disc the query is deep inside, so such nodes are always visited.
#[inline]
fn prune_cost(d: Real) -> Real {
    if d > 0.0 { d } else { Real::NEG_INFINITY }
}

/// How a [`CircleSet`] answers its queries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueryBackend {
    /// Pick by size: [`QueryBackend::Linear`] below [`CircleSet::BVH_THRESHOLD`] circles.
    Auto,
    /// A plain loop over every circle.
    Linear,
    /// parry's bounding-volume hierarchy over the circles' boxes.
    Bvh,
}

/// Clearance of a point: equation (6) of the method, with its witness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearance {
    /// `min_c (|p - c| - r_c)`: negative inside an obstacle.
    pub distance: Real,
    /// Index of the circle that attains it.
    pub nearest: usize,
    /// Gradient of the clearance: the unit vector from the nearest centre to `p`
    /// (zero when `p` is that centre, where it is undefined).
    pub gradient: Vector,
}

/// Where a ray first meets a set of circles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Time of impact, in multiples of the ray's direction vector.
    pub toi: Real,
    /// Index of the circle hit.
    pub circle: usize,
    /// The point of impact.
    pub point: Point,
    /// Outward unit normal of the circle at the point (zero when the ray starts at a centre).
    pub normal: Vector,
}

/// A set of circles ready for queries.
#[derive(Clone)]
pub struct CircleSet {
    circles: Vec<Circle>,
    bvh: Option<Bvh>,
}

impl std::fmt::Debug for CircleSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CircleSet")
            .field("circles", &self.circles.len())
            .field("backend", &self.backend())
            .finish()
    }
}

impl CircleSet {
    /// Size from which [`QueryBackend::Auto`] builds a BVH. Chosen from the `clearance`
    /// criterion bench (README, performance table): at 30 circles the loop wins every query
    /// (clearance 62 ns against 76 ns); at 128 the BVH wins point clearance (111 against
    /// 241 ns) and ray casts (174 against 432 ns), the hot queries, while the loop still wins
    /// short segments (378 against 473 ns); at 5,000 the BVH wins all by 2x to 30x.
    pub const BVH_THRESHOLD: usize = 64;

    /// A set with the backend picked by size.
    pub fn new(circles: Vec<Circle>) -> Self {
        Self::with_backend(circles, QueryBackend::Auto)
    }

    /// A set with a chosen backend.
    pub fn with_backend(circles: Vec<Circle>, backend: QueryBackend) -> Self {
        let use_bvh = match backend {
            QueryBackend::Auto => circles.len() >= Self::BVH_THRESHOLD,
            QueryBackend::Linear => false,
            QueryBackend::Bvh => !circles.is_empty(),
        };
        let bvh = use_bvh.then(|| {
            let leaves: Vec<Aabb> = circles
                .iter()
                .map(|c| {
                    Aabb::new(
                        PVector::new(c.center.x - c.radius, c.center.y - c.radius),
                        PVector::new(c.center.x + c.radius, c.center.y + c.radius),
                    )
                })
                .collect();
            Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves)
        });
        Self { circles, bvh }
    }

    /// The backend in use ([`QueryBackend::Linear`] or [`QueryBackend::Bvh`]).
    pub fn backend(&self) -> QueryBackend {
        if self.bvh.is_some() {
            QueryBackend::Bvh
        } else {
            QueryBackend::Linear
        }
    }

    /// The circles, in the order given.
    pub fn circles(&self) -> &[Circle] {
        &self.circles
    }

    /// Number of circles.
    pub fn len(&self) -> usize {
        self.circles.len()
    }

    /// Whether there are no circles.
    pub fn is_empty(&self) -> bool {
        self.circles.is_empty()
    }

    /// The same set with every radius grown by `by`, same backend choice.
    pub fn inflated(&self, by: Real) -> Self {
        let backend = self.backend();
        Self::with_backend(
            self.circles.iter().map(|c| c.inflated(by)).collect(),
            backend,
        )
    }

    /// Clearance of `p` (equation 6) with the nearest circle and the gradient; `None` for an
    /// empty set. Ties go to the lowest index with the linear backend.
    pub fn clearance(&self, p: &Point) -> Option<Clearance> {
        let (nearest, distance) = match &self.bvh {
            None => {
                let mut best = (usize::MAX, Real::INFINITY);
                for (i, c) in self.circles.iter().enumerate() {
                    // |v| - r < best needs |v|^2 < (best + r)^2: most circles stop at the
                    // square (with a margin, so that rounding never skips a nearer circle).
                    let reach = best.1 + c.radius;
                    let v2 = (p - c.center).norm_squared();
                    if reach <= 0.0 || v2 > reach * reach * (1.0 + 1e-12) {
                        continue;
                    }
                    let d = c.signed_distance(p);
                    if d < best.1 {
                        best = (i, d);
                    }
                }
                (best.0 != usize::MAX).then_some(best)?
            }
            Some(bvh) => {
                let circles = &self.circles;
                let (i, d) = bvh.find_best(
                    Real::INFINITY,
                    |node: &BvhNode, _| prune_cost(node_distance_point(node, p)),
                    |leaf, _| Some(circles[leaf as usize].signed_distance(p)),
                )?;
                (i as usize, d)
            }
        };
        let v = p - self.circles[nearest].center;
        let n = v.norm();
        let gradient = if n > 0.0 { v / n } else { Vector::zeros() };
        Some(Clearance {
            distance,
            nearest,
            gradient,
        })
    }

    /// Exact signed distance from the segment `[a, b]` to the set, `min_c (dist(c, ab) - r_c)`,
    /// with the circle that attains it; `None` for an empty set.
    pub fn distance_to_segment(&self, a: &Point, b: &Point) -> Option<(Real, usize)> {
        match &self.bvh {
            None => {
                let mut best = (Real::INFINITY, usize::MAX);
                for (i, c) in self.circles.iter().enumerate() {
                    let d = distance_segment_circle(a, b, c);
                    if d < best.0 {
                        best = (d, i);
                    }
                }
                (best.1 != usize::MAX).then_some(best)
            }
            Some(bvh) => {
                let circles = &self.circles;
                let (i, d) = bvh.find_best(
                    Real::INFINITY,
                    |node: &BvhNode, _| {
                        let (mins, maxs) = (node.mins(), node.maxs());
                        prune_cost(distance_segment_aabb(
                            a,
                            b,
                            &Point::new(mins.x, mins.y),
                            &Point::new(maxs.x, maxs.y),
                        ))
                    },
                    |leaf, _| Some(distance_segment_circle(a, b, &circles[leaf as usize])),
                )?;
                Some((d, i as usize))
            }
        }
    }

    /// Whether the segment `[a, b]` meets any closed disc of the set.
    pub fn intersects_segment(&self, a: &Point, b: &Point) -> bool {
        match &self.bvh {
            None => self
                .circles
                .iter()
                .any(|c| intersects_segment_circle(a, b, c)),
            Some(bvh) => {
                // Depth-first over the boxes the segment meets; stops at the first disc hit.
                let mut leaves = bvh.leaves(|node: &BvhNode| {
                    let (mins, maxs) = (node.mins(), node.maxs());
                    distance_segment_aabb(
                        a,
                        b,
                        &Point::new(mins.x, mins.y),
                        &Point::new(maxs.x, maxs.y),
                    ) <= 0.0
                });
                leaves.any(|leaf| intersects_segment_circle(a, b, &self.circles[leaf as usize]))
            }
        }
    }

    /// Whether `a` sees `b`: no disc of the set meets the segment between them (a segment
    /// that only grazes a disc is blocked).
    pub fn line_of_sight(&self, a: &Point, b: &Point) -> bool {
        !self.intersects_segment(a, b)
    }

    /// First hit of the ray `origin + t * dir`, `t` in `[0, max_toi]`.
    pub fn cast_ray(&self, origin: &Point, dir: &Vector, max_toi: Real) -> Option<RayHit> {
        let (circle, toi) = match &self.bvh {
            None => {
                let mut best: Option<(usize, Real)> = None;
                for (i, c) in self.circles.iter().enumerate() {
                    let limit = best.map_or(max_toi, |b| b.1);
                    if let Some(t) = cast_ray_circle(origin, dir, c, limit)
                        && best.is_none_or(|b| t < b.1)
                    {
                        best = Some((i, t));
                    }
                }
                best?
            }
            Some(bvh) => {
                let ray = Ray::new(PVector::new(origin.x, origin.y), PVector::new(dir.x, dir.y));
                let circles = &self.circles;
                let (i, t) = bvh.cast_ray(&ray, max_toi, |leaf, best| {
                    cast_ray_circle(origin, dir, &circles[leaf as usize], best)
                })?;
                (i as usize, t)
            }
        };
        let point = origin + dir * toi;
        let v = point - self.circles[circle].center;
        let n = v.norm();
        let normal = if n > 0.0 { v / n } else { Vector::zeros() };
        Some(RayHit {
            toi,
            circle,
            point,
            normal,
        })
    }

    /// Closest point of the segment `[a, b]` to circle `i`'s centre, for callers that need the
    /// witness of [`CircleSet::distance_to_segment`].
    pub fn closest_on_segment_to(&self, i: usize, a: &Point, b: &Point) -> Point {
        closest_on_segment(a, b, &self.circles[i].center).0
    }
}
