//! The cost of a path: every criterion of the method as a separate weighted term.
//!
//! Integrals are taken with Gauss-Legendre quadrature on each spline segment, split into
//! [`CostConfig::pieces`] equal pieces of [`CostConfig::nodes`] nodes. The minimal clearance
//! `m(C)` of the safety term is the smallest node clearance refined by Brent's method
//! around it. The terms (`docs/method.md`, section 3) are listed once, in [`TERMS`], which
//! drives their names, their validation and the weighted total:
//!
//! | term | value |
//! |---|---|
//! | topology `T` (2) | `sum_c integral U_c(q) dl`, `U_c = 1 + tanh(alpha (r_c - d_c))` |
//! | roughness `R` (4) | `integral |q''| dt` (paper, default); `integral |q''|^2 dt` (energy); `sqrt(integral |q''|^2 dt)` (authors) |
//! | length `L` (5) | `integral dl` |
//! | safety `D` (7) | `omega^(dm - m(C))` |
//! | maximal clearance | `integral max(0, d(q) - d_max) dl` |
//! | start / goal visibility (8) | `1 - visible length / L`, from the start / from the end |
//! | danger points | `sum_i integral max(0, dmin_i - |q - a_i|)^2 dl` |
//! | critical points | `sum_i integral max(0, |q - a_i| - dmax_i)^2 dl` |
//! | sheltered | `1 - (length hidden from every hazard) / L` |
//! | passing time | `integral dl / v`, `v = min(v_max, sqrt(a_lat / kappa))` |
//!
//! The analytic [`gradient`] covers every term but the three line-of-sight shares
//! (visibility and shelter), which are piecewise constant in the node positions of the
//! quadrature; their weight enters the gradient as zero (say so to a gradient optimiser).
//! Roughness is exact, segment by segment ([`crate::roughness`]), and so is its gradient.
//!
//! Files, from the bottom up: `config` ([`CostConfig`] and its presets), `terms` ([`TERMS`],
//! [`PARAMETERS`], [`CostTerms`]), then one per step of an evaluation: `quadrature` (the
//! nodes), `integrand` (the individual terms at the nodes), `integrate` (the field and the
//! integrals), `clearance` (`m(C)`, with `brent`); `pipeline` runs the steps ([`evaluate`])
//! and `derivatives` takes the [`gradient`].

mod brent;
mod clearance;
mod config;
mod derivatives;
mod integrand;
mod integrate;
mod pipeline;
mod quadrature;
mod terms;

pub use crate::roughness::RoughnessForm;
pub use config::{ClearanceSearch, CostConfig};
pub use derivatives::gradient;
pub use pipeline::{evaluate, evaluate_weighted, evaluate_weighted_unless};
pub use terms::{
    CostConfigError, CostTerms, PARAMETERS, Parameter, Rule, TERMS, Term, parameter_names,
    term_names,
};

#[cfg(test)]
mod tests {
    use homospline_geom::{Point, Real};

    use super::*;
    use crate::curve::Spline;

    #[test]
    fn the_least_clearance_includes_the_ends_of_the_curve() {
        // A long curve leaving a start 0.5 from a circle: its first quadrature node is far
        // from the start, where the circle is farther; m(C) is still the start's 0.5, and D
        // is the same as a short curve's from that start.
        let model = crate::CircleModel::new(vec![homospline_geom::Circle::new(0.0, 0.0, 1.0)]);
        let start = Point::new(1.5, 0.0);
        let cfg = CostConfig::paper_voronoi();
        for far in [5.0, 50.0, 500.0] {
            let sp = Spline::natural(&[
                start,
                Point::new(1.5 + far / 2.0, 0.0),
                Point::new(1.5 + far, 0.0),
            ])
            .unwrap();
            let t = evaluate(&sp, &model, &cfg);
            assert!(
                (t.min_clearance - 0.5).abs() < 1e-12,
                "{far}: {}",
                t.min_clearance
            );
            assert!((t.safety - cfg.omega.powf(cfg.dm - 0.5)).abs() < 1e-9);
        }
    }

    #[test]
    fn set_validates_and_keeps_the_old_value_on_error() {
        let mut c = CostConfig::paper_voronoi();
        c.set("safety", 2.5).unwrap();
        assert_eq!(c.w_safety, 2.5);
        c.set("g3", 1.0).unwrap();
        assert_eq!(c.w_length, 1.0);
        assert_eq!(
            c.set("safty", 1.0).unwrap_err(),
            CostConfigError::Unknown("safty".into())
        );
        assert!(
            c.set("safty", 1.0)
                .unwrap_err()
                .to_string()
                .starts_with("unknown weight or parameter 'safty' (weights: topology, roughness")
        );
        assert_eq!(
            c.set("alpha", -1.0).unwrap_err(),
            CostConfigError::Parameter("alpha", "must be finite and > 0", -1.0)
        );
        assert_eq!(c.alpha, 0.5);
        assert!(matches!(
            c.set("roughness", Real::NAN),
            Err(CostConfigError::Weight("roughness", _))
        ));
        assert_eq!(c.w_roughness, 1.0);
    }
}
