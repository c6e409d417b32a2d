//! The one scalar and the point and vector types every homospline crate uses.

/// The scalar of all geometry: map units, `f64`.
pub type Real = f64;
/// A point in the plane.
pub type Point = nalgebra::Point2<Real>;
/// A displacement in the plane.
pub type Vector = nalgebra::Vector2<Real>;

/// A number as messages print it: as written (`0.05`, `4096`) at ordinary magnitudes, in
/// scientific notation (`1e308`, `1e-200`) beyond them, where Rust's `{}` would print
/// hundreds of digits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub Real);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-6..1e16).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// A measured value for a message: three decimals where that says something (`-2.500`),
/// else three significant digits in scientific notation (`-5.000e-170`, not `-0.000`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Short(pub Real);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-3..1e6).contains(&a) {
            write!(f, "{:.3}", self.0)
        } else {
            write!(f, "{:.3e}", self.0)
        }
    }
}

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

/// Douglas-Peucker simplification of a polyline, keeping both ends: every dropped point is
/// within `tol` of the segment that replaces it. At most `max_points` are kept (splits stop
/// once that many are; `usize::MAX` for no cap). The workspace's one implementation.
pub fn douglas_peucker(pts: &[Point], tol: Real, max_points: usize) -> Vec<Point> {
    if pts.len() <= 2 {
        return pts.to_vec();
    }
    let mut keep = vec![false; pts.len()];
    keep[0] = true;
    keep[pts.len() - 1] = true;
    let mut kept = 2usize;
    let mut stack = vec![(0, pts.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        let mut best = (0.0, 0);
        for (k, p) in pts.iter().enumerate().take(b).skip(a + 1) {
            let d = distance_point_segment(p, &pts[a], &pts[b]);
            if d > best.0 {
                best = (d, k);
            }
        }
        if best.0 > tol && kept < max_points {
            keep[best.1] = true;
            kept += 1;
            stack.push((a, best.1));
            stack.push((best.1, b));
        }
    }
    pts.iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::Num;

    #[test]
    fn numbers_print_short_at_every_magnitude() {
        for (x, text) in [
            (0.05, "0.05"),
            (4096.0, "4096"),
            (-2.5, "-2.5"),
            (0.0, "0"),
            (1e308, "1e308"),
            (-1e300, "-1e300"),
            (1e-200, "1e-200"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
        ] {
            assert_eq!(Num(x).to_string(), text);
        }
    }
}
