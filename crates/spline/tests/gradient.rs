//! The analytic gradient of the cost against central finite differences.

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
    ) {
        let mut pts = vec![Point::new(2.0, 30.0)];
        pts.extend(inner.into_iter().map(|(x, y)| Point::new(x, y)));
        pts.push(Point::new(58.0, 30.0));
        let model = CircleModel::new(circles.into_iter().map(|(x, y, r)| Circle::new(x, y, r)).collect());
        let end = match ends {
            0 => EndCondition::Natural,
            1 => EndCondition::Clamped { start: homospline_geom::Vector::new(20.0, 5.0), end: homospline_geom::Vector::new(10.0, -8.0) },
            _ => EndCondition::ClampedStart { start: homospline_geom::Vector::new(30.0, -4.0) },
        };
        check(&pts, end, &model, &CostConfig { roughness: form, ..cfg() })?;
    }
}

/// A curve longer than `2 * BASIS_WINDOW + 2` points takes the windowed bases (linear cost):
/// its gradient still agrees with central differences.
#[test]
fn long_curves_take_the_windowed_gradient() {
    let n = 2 * homospline_spline::cost::BASIS_WINDOW + 12;
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
