//! A circle cover of simple polygons, so that buildings drawn as polygons become circle sets.
//!
//! [`cover_polygon`] returns circles whose union contains the polygon and stays within a
//! stated distance `tol` of it (every point of the union is at most `tol` from the polygon).
//! It subdivides a square quadtree over the polygon's box: a cell whose circumscribed circle
//! (centre `c`, radius `h / sqrt 2`) satisfies `sd(c) + h / sqrt 2 <= tol`, with `sd` the
//! signed distance to the polygon (negative inside), is kept as a circle; a cell whose circle
//! misses the polygon is dropped; any other cell is split in four. Every point of the polygon
//! lies in a kept or a split cell, so the union covers it; a kept circle's points are within
//! `max(0, sd(c) + r) <= tol` of the polygon. Cells on the boundary are kept once
//! `h * sqrt 2 <= tol`, so the subdivision ends.

use thiserror::Error;

use crate::math::{Point, Real};
use crate::shape::Circle;

/// A simple polygon (no self-intersections), vertices in either orientation.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// The vertices; the last connects back to the first.
    pub vertices: Vec<Point>,
}

/// Why a polygon cannot be covered.
#[derive(Debug, Error, PartialEq)]
pub enum CoverError {
    /// Fewer than three vertices.
    #[error("a polygon needs at least 3 vertices, got {0}")]
    TooFewVertices(usize),
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {0} is not a finite point")]
    NonFinite(usize),
    /// The tolerance is not a positive finite number.
    #[error("tolerance must be positive and finite, got {0}")]
    BadTolerance(Real),
    /// The polygon has zero area.
    #[error("the polygon has zero area")]
    Degenerate,
    /// The cover would need more circles than the caller allowed.
    #[error("covering needs more than {0} circles: raise the tolerance")]
    TooManyCircles(usize),
}

impl Polygon {
    /// A polygon from its vertices.
    pub fn new(vertices: Vec<Point>) -> Self {
        Self { vertices }
    }

    /// An axis-aligned rectangle.
    pub fn rectangle(min: Point, max: Point) -> Self {
        Self::new(vec![
            min,
            Point::new(max.x, min.y),
            max,
            Point::new(min.x, max.y),
        ])
    }

    /// Twice the signed area (positive when counter-clockwise).
    fn area2(&self) -> Real {
        let v = &self.vertices;
        (0..v.len())
            .map(|i| {
                let (a, b) = (v[i], v[(i + 1) % v.len()]);
                a.x * b.y - b.x * a.y
            })
            .sum()
    }

    /// Whether `p` is inside (even-odd rule; points on the boundary may go either way).
    pub fn contains(&self, p: &Point) -> bool {
        let v = &self.vertices;
        let mut inside = false;
        let mut j = v.len() - 1;
        for i in 0..v.len() {
            let (a, b) = (v[i], v[j]);
            if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
                inside = !inside;
            }
            j = i;
        }
        inside
    }

    /// Distance from `p` to the polygon's boundary.
    pub fn distance_to_boundary(&self, p: &Point) -> Real {
        let v = &self.vertices;
        (0..v.len())
            .map(|i| crate::math::distance_point_segment(p, &v[i], &v[(i + 1) % v.len()]))
            .fold(Real::INFINITY, Real::min)
    }

    /// Signed distance: negative inside, positive outside.
    pub fn signed_distance(&self, p: &Point) -> Real {
        let d = self.distance_to_boundary(p);
        if self.contains(p) { -d } else { d }
    }
}

/// Circles whose union contains `polygon` and lies within `tol` of it; at most `max_circles`.
pub fn cover_polygon(
    polygon: &Polygon,
    tol: Real,
    max_circles: usize,
) -> Result<Vec<Circle>, CoverError> {
    let v = &polygon.vertices;
    if v.len() < 3 {
        return Err(CoverError::TooFewVertices(v.len()));
    }
    if let Some(i) = v.iter().position(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return Err(CoverError::NonFinite(i));
    }
    if !(tol.is_finite() && tol > 0.0) {
        return Err(CoverError::BadTolerance(tol));
    }
    if polygon.area2() == 0.0 {
        return Err(CoverError::Degenerate);
    }
    let (mut lo, mut hi) = (v[0], v[0]);
    for p in v {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let side = (hi.x - lo.x).max(hi.y - lo.y);
    let mut stack = vec![(Point::new(lo.x + side / 2.0, lo.y + side / 2.0), side)];
    let mut out = Vec::new();
    // Depth-first in a fixed order: the output is deterministic.
    while let Some((c, h)) = stack.pop() {
        let r = h * std::f64::consts::FRAC_1_SQRT_2;
        let sd = polygon.signed_distance(&c);
        if sd > r {
            continue; // the circumscribed circle, hence the cell, misses the polygon
        }
        if sd + r <= tol {
            if out.len() == max_circles {
                return Err(CoverError::TooManyCircles(max_circles));
            }
            out.push(Circle {
                center: c,
                radius: r,
            });
            continue;
        }
        let q = h / 4.0;
        for (dx, dy) in [(q, q), (-q, q), (-q, -q), (q, -q)] {
            stack.push((Point::new(c.x + dx, c.y + dy), h / 2.0));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_cover_is_finite_and_tight() {
        let poly = Polygon::rectangle(Point::new(0.0, 0.0), Point::new(20.0, 8.0));
        let circles = cover_polygon(&poly, 0.5, 10_000).unwrap();
        assert!(!circles.is_empty());
        for c in &circles {
            // The circle's farthest point from the polygon is within tol.
            assert!(poly.signed_distance(&c.center) + c.radius <= 0.5 + 1e-12);
        }
    }

    #[test]
    fn rejects_bad_input() {
        let tri = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0)]);
        assert_eq!(
            cover_polygon(&tri, 0.1, 10),
            Err(CoverError::TooFewVertices(2))
        );
        let line = Polygon::new(vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
        ]);
        assert_eq!(cover_polygon(&line, 0.1, 10), Err(CoverError::Degenerate));
        let sq = Polygon::rectangle(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
        assert_eq!(
            cover_polygon(&sq, 0.0, 10),
            Err(CoverError::BadTolerance(0.0))
        );
        assert_eq!(
            cover_polygon(&sq, 1e-3, 10),
            Err(CoverError::TooManyCircles(10))
        );
    }
}
