//! [`gradient`]: the cost's gradient with respect to the inner via-points.

use homospline_geom::{Real, Vector};

use super::config::CostConfig;
use super::pipeline::{evaluate, run};
use super::terms::CostTerms;
use crate::clearance_model::ClearanceModel;
use crate::curve::{EndCondition, Parametrization, Spline};

/// The cost and its gradient with respect to the inner via-points (`points[1..n-1]`).
///
/// Analytic for uniform parameters (the spline is then linear in its points), in `O(n)` by
/// reverse mode through the spline ([`Spline::pull_back`]); with
/// chord-length parameters the knots move with the points, and with a start heading the
/// start slope does, so there the gradient is taken by central differences (step `1e-6`
/// times the scene scale).
pub fn gradient(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
) -> (CostTerms, Vec<Vector>) {
    let n = spline.points().len();
    if spline.parametrization() == Parametrization::ChordLength
        || matches!(spline.end_condition(), EndCondition::StartHeading { .. })
    {
        let terms = evaluate(spline, model, cfg);
        let scale = spline
            .points()
            .iter()
            .map(|p| p.coords.amax())
            .fold(1.0, Real::max);
        let h = 1e-6 * scale;
        let mut g = vec![Vector::zeros(); n.saturating_sub(2)];
        for (j, gj) in g.iter_mut().enumerate() {
            for axis in 0..2 {
                let at = |delta: Real| {
                    let mut pts = spline.points().to_vec();
                    pts[j + 1][axis] += delta;
                    Spline::new(&pts, spline.parametrization(), spline.end_condition())
                        .map_or(Real::NAN, |s| evaluate(&s, model, cfg).total)
                };
                gj[axis] = (at(h) - at(-h)) / (2.0 * h);
            }
        }
        return (terms, g);
    }
    let mut partials = Vec::new();
    let terms = run(spline, model, cfg, Some(&mut partials), false);
    // dC/d(a, b, c, d) per segment, then reverse mode through the spline (O(n), exact).
    let mut coef = vec![[Vector::zeros(); 4]; spline.segments()];
    for p in &partials {
        let (s, s2) = (p.s, p.s * p.s);
        let c = &mut coef[p.seg];
        c[0] += p.gq;
        c[1] += p.gq * s + p.gv;
        c[2] += p.gq * s2 + p.gv * (2.0 * s) + p.ga * 2.0;
        c[3] += p.gq * (s2 * s) + p.gv * (3.0 * s2) + p.ga * (6.0 * s);
    }
    let mut g = spline.pull_back(&coef);
    g.pop();
    g.remove(0);
    (terms, g)
}
