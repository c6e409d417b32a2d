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

/// `exp(x)` without branches or library calls, so that loops over it vectorise: range
/// reduction `x = k ln 2 + r`, `|r| <= ln 2 / 2`, a degree-13 Taylor polynomial for `e^r`
/// (truncation below 2e-16 relative) and `2^k` assembled in the exponent bits. `x` is
/// clamped to `[-700, 700]` (the potential needs no more: `e^700` already makes `U` zero).
#[inline(always)]
pub fn exp_fast(x: Real) -> Real {
    const LOG2E: Real = std::f64::consts::LOG2_E;
    const LN2_HI: Real = Real::from_bits(0x3fe6_2e42_fee0_0000); // ln 2, upper bits
    const LN2_LO: Real = Real::from_bits(0x3dea_39ef_3579_3c76); // ln 2 - LN2_HI
    const SHIFTER: Real = 6_755_399_441_055_744.0; // 1.5 * 2^52: rounds to an integer
    let x = x.clamp(-700.0, 700.0);
    let shifted = x * LOG2E + SHIFTER;
    let kf = shifted - SHIFTER;
    let r = (x - kf * LN2_HI) - kf * LN2_LO;
    let mut p = 1.0 / 6_227_020_800.0;
    for c in [
        1.0 / 479_001_600.0,
        1.0 / 39_916_800.0,
        1.0 / 3_628_800.0,
        1.0 / 362_880.0,
        1.0 / 40_320.0,
        1.0 / 5_040.0,
        1.0 / 720.0,
        1.0 / 120.0,
        1.0 / 24.0,
        1.0 / 6.0,
        0.5,
        1.0,
        1.0,
    ] {
        p = p * r + c;
    }
    // k sits in the low mantissa bits of `shifted`: integer arithmetic only, so it vectorises.
    let k = shifted.to_bits().wrapping_sub(SHIFTER.to_bits());
    p * Real::from_bits(k.wrapping_add(1023) << 52)
}

/// What [`ClearanceModel::field_batch`] returns for one point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FieldSample {
    /// Repulsive potential.
    pub potential: Real,
    /// Its gradient.
    pub potential_grad: Vector,
    /// Clearance `d(q)`.
    pub clearance: Real,
    /// Its gradient.
    pub clearance_grad: Vector,
}

/// Obstacles as the cost sees them.
pub trait ClearanceModel: Send + Sync {
    /// Clearance `d(q)` (equation 6; negative inside) and its gradient.
    fn clearance(&self, p: &Point) -> (Real, Vector);

    /// The repulsive potential, the clearance and their gradients at each point of `pts`,
    /// written to `out`. For circles the potential is `sum_c U_c(q)` (equations 1-2); a
    /// distance field gives `1 + tanh(-alpha d(q))`. `region` is a box holding every point of
    /// `pts`: a model may skip obstacles whose potential is negligible (below
    /// [`POTENTIAL_CUTOFF`]) in all of it, but the clearance must stay exact.
    fn field_batch(
        &self,
        pts: &[Point],
        alpha: Real,
        region: (Point, Point),
        out: &mut [FieldSample],
    );

    /// Whether the segment `[a, b]` is free of obstacles.
    fn line_of_sight(&self, a: &Point, b: &Point) -> bool;

    /// A lower bound of the clearance over the segment `[a, b]` (exact for circles).
    fn segment_clearance(&self, a: &Point, b: &Point) -> Real;

    /// The clearance that collision checks trust, at one point: the same function that
    /// `segment_clearance` bounds from below. By default the cost's clearance.
    fn exact_clearance(&self, p: &Point) -> Real {
        self.clearance(p).0
    }
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

    fn field_batch(
        &self,
        pts: &[Point],
        alpha: Real,
        region: (Point, Point),
        out: &mut [FieldSample],
    ) {
        let n = pts.len().min(out.len());
        let px: Vec<Real> = pts[..n].iter().map(|p| p.x).collect();
        let py: Vec<Real> = pts[..n].iter().map(|p| p.y).collect();
        let mut u_sum = vec![0.0; n];
        let mut gx = vec![0.0; n];
        let mut gy = vec![0.0; n];
        let mut best = vec![Real::INFINITY; n];
        let mut best_k = vec![usize::MAX; n];
        let (lo, hi) = region;
        for k in 0..self.xs.len() {
            let (cx, cy, r) = (self.xs[k], self.ys[k], self.rs[k]);
            let dx = (lo.x - cx).max(cx - hi.x).max(0.0);
            let dy = (lo.y - cy).max(cy - hi.y).max(0.0);
            let dbox = (dx * dx + dy * dy).sqrt();
            if 2.0 * alpha * (dbox - r) > POTENTIAL_CUTOFF {
                continue;
            }
            // A branch-free loop over equal-length slices: it vectorises.
            let two_alpha = 2.0 * alpha;
            let lanes = px
                .iter()
                .zip(py.iter())
                .zip(u_sum.iter_mut())
                .zip(gx.iter_mut().zip(gy.iter_mut()))
                .zip(best.iter_mut().zip(best_k.iter_mut()));
            for ((((&x, &y), us), (gxi, gyi)), (bi, bki)) in lanes {
                let (vx, vy) = (x - cx, y - cy);
                let d = (vx * vx + vy * vy).sqrt();
                // U = 2 / (1 + e), e = exp(2 alpha (d - r)); dU/dd = -alpha (1 - tanh^2)
                //   = -alpha U (2 - U). At the centre the gradient is undefined: 0 there.
                let c = d - r;
                let u = 2.0 / (1.0 + exp_fast(two_alpha * c));
                *us += u;
                let inv_d = if d > 0.0 { 1.0 / d } else { 0.0 };
                let g = -alpha * u * (2.0 - u) * inv_d;
                *gxi += g * vx;
                *gyi += g * vy;
                let better = c < *bi;
                *bi = if better { c } else { *bi };
                *bki = if better { k } else { *bki };
            }
        }
        // Circles skipped above are farther than the cutoff from every point; where no kept
        // circle is nearer than that, ask the exact query.
        let cutoff_distance = POTENTIAL_CUTOFF / (2.0 * alpha);
        for i in 0..n {
            let p = pts[i];
            let (clearance, clearance_grad) = if best[i] <= cutoff_distance {
                let k = best_k[i];
                let v = Vector::new(p.x - self.xs[k], p.y - self.ys[k]);
                let d = v.norm();
                (best[i], if d > 0.0 { v / d } else { Vector::zeros() })
            } else {
                self.clearance(&p)
            };
            out[i] = FieldSample {
                potential: u_sum[i],
                potential_grad: Vector::new(gx[i], gy[i]),
                clearance,
                clearance_grad,
            };
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_fast_matches_the_library_exp() {
        let mut worst: Real = 0.0;
        let mut x = -700.0;
        while x <= 700.0 {
            let rel = (exp_fast(x) - x.exp()).abs() / x.exp();
            worst = worst.max(rel);
            x += 0.0137;
        }
        assert!(worst < 1e-14, "worst relative error {worst}");
    }
}
