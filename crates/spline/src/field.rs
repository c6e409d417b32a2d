//! The clearance model: how every obstacle term of the cost sees the obstacles.
//!
//! [`ClearanceModel`] answers "how far is this point from obstacles, and towards where" and
//! the repulsive potential of equation (1). [`CircleModel`] is exact for circle sets; a grid
//! distance field (occupancy maps) implements the same trait in a later crate.

use homospline_geom::{Circle, CircleSet, Point, Real, Vector};

/// Potential tails below `2 exp(-POTENTIAL_CUTOFF)` per unit length are dropped:
/// `U_c = 1 + tanh(alpha (r - d)) = 2 / (1 + exp(2 alpha (d - r)))`, so a circle whose
/// `2 alpha (d - r)` exceeds the cutoff over a whole region adds less than `1.9e-13` per unit
/// length there.
pub const POTENTIAL_CUTOFF: Real = 30.0;

/// Obstacles as the cost sees them.
pub trait ClearanceModel: Send + Sync {
    /// Clearance `d(q)` (equation 6; negative inside) and its gradient.
    fn clearance(&self, p: &Point) -> (Real, Vector);

    /// The repulsive potential and its gradient at each point of `pts`, written to `out`.
    /// For circles it is `sum_c U_c(q)` (equations 1-2); a distance field gives
    /// `1 + tanh(-alpha d(q))`. `region` is a box holding every point of `pts`: a model may
    /// skip obstacles whose potential is negligible (below [`POTENTIAL_CUTOFF`]) in all of it.
    fn potential_batch(
        &self,
        pts: &[Point],
        alpha: Real,
        region: (Point, Point),
        out: &mut [(Real, Vector)],
    );

    /// Whether the segment `[a, b]` is free of obstacles.
    fn line_of_sight(&self, a: &Point, b: &Point) -> bool;

    /// A lower bound of the clearance over the segment `[a, b]` (exact for circles).
    fn segment_clearance(&self, a: &Point, b: &Point) -> Real;
}

/// Exact model of a circle set (circles already inflated by the robot radius).
#[derive(Clone, Debug)]
pub struct CircleModel {
    set: CircleSet,
    xs: Vec<Real>,
    ys: Vec<Real>,
    rs: Vec<Real>,
}

impl CircleModel {
    /// A model over `circles`.
    pub fn new(circles: Vec<Circle>) -> Self {
        let xs = circles.iter().map(|c| c.center.x).collect();
        let ys = circles.iter().map(|c| c.center.y).collect();
        let rs = circles.iter().map(|c| c.radius).collect();
        Self {
            set: CircleSet::new(circles),
            xs,
            ys,
            rs,
        }
    }

    /// The underlying query set.
    pub fn set(&self) -> &CircleSet {
        &self.set
    }
}

impl ClearanceModel for CircleModel {
    fn clearance(&self, p: &Point) -> (Real, Vector) {
        match self.set.clearance(p) {
            Some(c) => (c.distance, c.gradient),
            None => (Real::INFINITY, Vector::zeros()),
        }
    }

    fn potential_batch(
        &self,
        pts: &[Point],
        alpha: Real,
        region: (Point, Point),
        out: &mut [(Real, Vector)],
    ) {
        out.iter_mut().for_each(|o| *o = (0.0, Vector::zeros()));
        let (lo, hi) = region;
        for k in 0..self.xs.len() {
            let (cx, cy, r) = (self.xs[k], self.ys[k], self.rs[k]);
            let dx = (lo.x - cx).max(cx - hi.x).max(0.0);
            let dy = (lo.y - cy).max(cy - hi.y).max(0.0);
            let dbox = (dx * dx + dy * dy).sqrt();
            if 2.0 * alpha * (dbox - r) > POTENTIAL_CUTOFF {
                continue;
            }
            for (p, o) in pts.iter().zip(out.iter_mut()) {
                let (vx, vy) = (p.x - cx, p.y - cy);
                let d = (vx * vx + vy * vy).sqrt();
                // U = 2 / (1 + e), e = exp(2 alpha (d - r)); dU/dd = -alpha (1 - tanh^2)
                //   = -alpha U (2 - U).
                let e = (2.0 * alpha * (d - r)).exp();
                let u = 2.0 / (1.0 + e);
                o.0 += u;
                if d > 0.0 {
                    let g = -alpha * u * (2.0 - u) / d;
                    o.1.x += g * vx;
                    o.1.y += g * vy;
                }
            }
        }
    }

    fn line_of_sight(&self, a: &Point, b: &Point) -> bool {
        self.set.line_of_sight(a, b)
    }

    fn segment_clearance(&self, a: &Point, b: &Point) -> Real {
        self.set
            .distance_to_segment(a, b)
            .map_or(Real::INFINITY, |d| d.0)
    }
}
