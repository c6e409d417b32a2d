//! A logarithmic barrier on the clearance along a spline, with its gradient with respect to
//! the inner via-points: what lets a gradient optimiser approach `m(C) = target` from inside
//! instead of stalling against a rejection ([`crate::growth::Growth::polish`]'s finish).

use homospline_geom::{Real, Vector};
use homospline_spline::{ClearanceModel, Spline};

/// `weight * (-ln(g / width) + g / width - 1)` for a sample whose clearance is `g` above
/// `at` and less than `width` above it, `0` from `width` on: continuous with its first
/// derivative at `width` (both zero there), and `+inf` as `g` falls to `0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Barrier {
    /// The clearance that samples must stay above.
    pub at: Real,
    /// How far above `at` the barrier reaches (> 0).
    pub width: Real,
    /// Its weight (> 0).
    pub weight: Real,
    /// Samples per segment, at the midpoints of equal steps of the segment's parameter.
    pub samples_per_segment: usize,
}

impl Barrier {
    /// The barrier's value over the samples of `spline` and its gradient with respect to
    /// the inner via-points (`points[1..n-1]`), or `None` when a sample's clearance is at or
    /// below `at`. The gradient is exact where the spline is linear in its points (uniform
    /// parameters, with the end slopes fixed: [`Spline::pull_back`]).
    pub fn value_and_gradient(
        &self,
        spline: &Spline,
        model: &dyn ClearanceModel,
    ) -> Option<(Real, Vec<Vector>)> {
        let k = self.samples_per_segment.max(1);
        let knots = spline.knots();
        let mut coef = vec![[Vector::zeros(); 4]; spline.segments()];
        let mut value = 0.0;
        for (seg, c) in coef.iter_mut().enumerate() {
            let h = knots[seg + 1] - knots[seg];
            for j in 0..k {
                let s = h * (j as Real + 0.5) / k as Real;
                let (q, _, _) = spline.eval_segment(seg, s);
                let (d, grad) = model.clearance(&q);
                let g = d - self.at;
                if g.is_nan() || g <= 0.0 {
                    return None;
                }
                if g < self.width {
                    let r = g / self.width;
                    value += self.weight * (-r.ln() + r - 1.0);
                    // d/dq of the term: weight (1/width - 1/g) grad d, into the segment's
                    // coefficients a + b s + c s^2 + d s^3.
                    let gq = grad * (self.weight * (1.0 / self.width - 1.0 / g));
                    c[0] += gq;
                    c[1] += gq * s;
                    c[2] += gq * (s * s);
                    c[3] += gq * (s * s * s);
                }
            }
        }
        let mut g = spline.pull_back(&coef);
        g.pop();
        g.remove(0);
        Some((value, g))
    }
}
