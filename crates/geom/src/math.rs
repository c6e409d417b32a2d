//! The one scalar and the point and vector types every homospline crate uses.

/// The scalar of all geometry: map units, `f64`.
pub type Real = f64;
/// A point in the plane.
pub type Point = nalgebra::Point2<Real>;
/// A displacement in the plane.
pub type Vector = nalgebra::Vector2<Real>;

/// 2-D cross product (the z component of `a x b`).
#[inline]
pub fn cross(a: &Vector, b: &Vector) -> Real {
    a.x * b.y - a.y * b.x
}

/// Closest point to `p` on the segment `[a, b]`, and its parameter in `[0, 1]`.
#[inline]
pub fn closest_on_segment(a: &Point, b: &Point, p: &Point) -> (Point, Real) {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 == 0.0 {
        return (*a, 0.0);
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    (a + ab * t, t)
}

/// Euclidean distance from `p` to the segment `[a, b]`.
#[inline]
pub fn distance_point_segment(p: &Point, a: &Point, b: &Point) -> Real {
    let (q, _) = closest_on_segment(a, b, p);
    (p - q).norm()
}
