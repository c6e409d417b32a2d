//! The analytic gradient of the cost against central finite differences, with the safety
//! term at the least clearance (7) and integrated along the curve (`safety_along`, maps).

use homospline_geom::{Circle, Point, Real};
use homospline_spline::{
    CircleModel, CostConfig, EndCondition, Parametrization, RoughnessForm, Spline, evaluate,
    gradient,
};
use proptest::prelude::*;

fn cfg() -> CostConfig {
    let mut cfg = CostConfig::paper_voronoi();
    cfg.w_max_clearance = 0.1;
    cfg.d_max = 6.0;
    cfg.w_danger = 0.3;
    cfg.w_critical = 0.3;
    cfg.w_passing_time = 0.2;
    cfg.danger_points = vec![(Point::new(30.0, 30.0), 10.0)];
    cfg.critical_points = vec![(Point::new(30.0, 30.0), 15.0)];
    cfg
}

fn check(
    pts: &[Point],
    end: EndCondition,
    model: &CircleModel,
    cfg: &CostConfig,
) -> Result<(), TestCaseError> {
    let s = Spline::new(pts, Parametrization::Uniform, end).unwrap();
    let (terms, g) = gradient(&s, model, cfg);
    prop_assert!((terms.total - evaluate(&s, model, cfg).total).abs() <= 1e-12 * terms.total.abs());
    let h = 1e-6;
    for j in 1..pts.len() - 1 {
        for axis in 0..2 {
            let at = |d: Real| {
                let mut p = pts.to_vec();
                p[j][axis] += d;
                evaluate(
                    &Spline::new(&p, Parametrization::Uniform, end).unwrap(),
                    model,
                    cfg,
                )
                .total
            };
            let fd = (at(h) - at(-h)) / (2.0 * h);
            let an = g[j - 1][axis];
            // Relative tolerance 1e-4 on the net value, plus 1e-5 of the safety term's own
            // scale `w4 D ln(omega)`: its gradient goes through the minimiser t* of the
            // clearance, which the golden-section search places to about 1e-6 relative
            // (measured: 2.3e-6 relative disagreement on a path 1.8 deep in a circle,
            // where D = 2e6 and the net gradient is a small difference of large terms).
            let safety_scale = cfg.w_safety * terms.safety * cfg.omega.ln();
            let tol = 1e-4 * (1.0 + fd.abs().max(an.abs())) + 1e-5 * safety_scale;
            prop_assert!(
                (fd - an).abs() <= tol,
                "point {} axis {}: fd {} analytic {} tol {}",
                j,
                axis,
                fd,
                an,
                tol
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn analytic_gradient_matches_finite_differences(
        inner in prop::collection::vec((5.0..55.0, 5.0..55.0), 1..6),
        circles in prop::collection::vec((0.0..60.0, 0.0..60.0, 1.0..5.0), 1..12),
        ends in 0..3usize,
        form in prop::sample::select(RoughnessForm::ALL.to_vec()),
        safety_along in any::<bool>(),
    ) {
        let mut pts = vec![Point::new(2.0, 30.0)];
        pts.extend(inner.into_iter().map(|(x, y)| Point::new(x, y)));
        pts.push(Point::new(58.0, 30.0));
        let circles: Vec<Circle> = circles.into_iter().map(|(x, y, r)| Circle::new(x, y, r)).collect();
        let end = match ends {
            0 => EndCondition::Natural,
            1 => EndCondition::Clamped { start: homospline_geom::Vector::new(20.0, 5.0), end: homospline_geom::Vector::new(10.0, -8.0) },
            _ => EndCondition::ClampedStart { start: homospline_geom::Vector::new(30.0, -4.0) },
        };
        // The clearance `|q - c| - r` has a kink at a circle's centre. A curve that passes
        // within `rho` of one has a minimiser t* of the clearance so sharp that Brent's
        // placement of it (to 1e-10 in t) turns the safety gradient's direction by about
        // |q'| 1e-10 / rho: on a case the CI drew (rho = 2e-4, D = 1.6e5) the gradient was
        // off by 0.3 % while the finite differences agreed to 1e-6 at every step from 1e-3
        // to 1e-8. Such curves (deep inside a circle, where no planner stays) are left out:
        // from 0.1 on, the error is below 1e-6 of the safety term's scale. 10,000 samples
        // over-estimate `rho` by at most half their spacing (< 0.02 here).
        let spline = Spline::new(&pts, Parametrization::Uniform, end).unwrap();
        let rho = spline
            .sample_uniform(10_000)
            .iter()
            .flat_map(|q| circles.iter().map(move |c| (q - c.center).norm()))
            .fold(Real::INFINITY, Real::min);
        prop_assume!(rho > 0.12);
        let model = CircleModel::new(circles);
        check(&pts, end, &model, &CostConfig { roughness: form, safety_along, ..cfg() })?;
    }
}

/// A long curve (a map path: 52 points, far from any circle at its ends) has the same
/// gradient by reverse mode as by central differences, at both ends and in the middle.
#[test]
fn long_curves_have_the_exact_gradient() {
    let n = 52;
    let pts: Vec<Point> = (0..n)
        .map(|k| {
            let x = k as Real * 2.0;
            Point::new(x, 20.0 + 3.0 * (x * 0.3).sin())
        })
        .collect();
    let model = CircleModel::new(
        (0..12)
            .map(|k| Circle::new(7.0 * k as Real + 3.0, 13.0 + (k % 3) as Real, 2.0))
            .collect(),
    );
    // No truncation of far circles (it is noise to finite differences).
    let cfg = CostConfig {
        tolerance: 0.0,
        ..CostConfig::paper_voronoi()
    };
    let s = Spline::new(&pts, Parametrization::Uniform, EndCondition::Natural).unwrap();
    let (terms, g) = gradient(&s, &model, &cfg);
    // The same allowance as above for the safety term's minimiser.
    let safety_scale = cfg.w_safety * terms.safety * cfg.omega.ln();
    let h = 1e-6;
    for j in [1, n / 2, n - 2] {
        for axis in 0..2 {
            let at = |d: Real| {
                let mut p = pts.clone();
                p[j][axis] += d;
                let sp = Spline::new(&p, Parametrization::Uniform, EndCondition::Natural).unwrap();
                evaluate(&sp, &model, &cfg).total
            };
            let fd = (at(h) - at(-h)) / (2.0 * h);
            let an = g[j - 1][axis];
            assert!(
                (fd - an).abs() <= 1e-4 * fd.abs().max(1.0) + 1e-5 * safety_scale,
                "point {j} axis {axis}: analytic {an}, differences {fd}"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Reverse mode through the spline (`pull_back`, O(n)) equals the forward sum over the
    /// cardinal basis (`basis`, O(n^2)) for any function of the segments' coefficients: here
    /// a random linear one, on random points, knots and end conditions.
    #[test]
    fn pull_back_matches_the_cardinal_basis(
        pts in prop::collection::vec((-50.0..50.0, -50.0..50.0), 2..40),
        weights in prop::collection::vec((-3.0..3.0, -3.0..3.0), 160),
        chord in any::<bool>(),
        ends in 0..3usize,
    ) {
        use homospline_geom::Vector;
        let pts: Vec<Point> = pts.into_iter().map(|(x, y)| Point::new(x, y)).collect();
        // Chord-length knots need distinct consecutive points.
        prop_assume!(!chord || pts.windows(2).all(|w| (w[1] - w[0]).norm() > 1e-3));
        let end = match ends {
            0 => EndCondition::Natural,
            1 => EndCondition::Clamped { start: Vector::new(3.0, -1.0), end: Vector::new(-2.0, 4.0) },
            _ => EndCondition::ClampedStart { start: Vector::new(-5.0, 2.0) },
        };
        let param = if chord { Parametrization::ChordLength } else { Parametrization::Uniform };
        let s = Spline::new(&pts, param, end).unwrap();
        let w = |k: usize| Vector::new(weights[k % 160].0, weights[k % 160].1);
        let grads: Vec<[Vector; 4]> =
            (0..s.segments()).map(|i| [w(4 * i), w(4 * i + 1), w(4 * i + 2), w(4 * i + 3)]).collect();
        let reverse = s.pull_back(&grads);
        // Forward: the coefficients of basis spline j are d(coef)/d(P_j) for either axis.
        let basis = s.basis();
        for (j, b) in basis.iter().enumerate() {
            let mut forward = Vector::zeros();
            for (i, g) in grads.iter().enumerate() {
                // Recover the basis segment's coefficients from its position and derivatives
                // at s = 0: a = q, b = q', c = q''/2, d from q'' at the segment's end.
                let h = b.knots()[i + 1] - b.knots()[i];
                let (q0, v0, a0) = b.eval_segment(i, 0.0);
                let (_, _, a1) = b.eval_segment(i, h);
                let coef = [q0.x, v0.x, a0.x / 2.0, (a1.x - a0.x) / (6.0 * h)];
                for k in 0..4 {
                    forward += g[k] * coef[k];
                }
            }
            let scale = 1.0 + forward.norm() + reverse[j].norm();
            prop_assert!(
                (forward - reverse[j]).norm() <= 1e-9 * scale,
                "point {} of {}: forward {:?} reverse {:?}", j, pts.len(), forward, reverse[j]
            );
        }
    }
}
