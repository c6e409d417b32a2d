//! Cubic splines through via-points and every cost criterion of the method (sections 2-3).
//!
//! - [`curve`]: [`Spline`], a parametric cubic spline `q(t)`, `t` in `[0, 1]`, through
//!   `S, p1 .. pk, T`; natural or clamped ends; uniform or chord-length parameters; built in
//!   `O(k)` with a tridiagonal (Thomas) solve; arc-length sampling.
//! - [`clearance_model`]: the [`ClearanceModel`] trait through which every obstacle term asks "how far
//!   is this point from obstacles, and towards where", with [`CircleModel`] (exact).
//! - [`cost`]: [`CostConfig`] (weights and parameters, the paper's presets), [`evaluate`]
//!   and [`gradient`] (analytic, with respect to the inner via-points).
//! - [`roughness`]: roughness (4) in closed form per segment, in the paper's, the energy
//!   and the authors' forms.
//! - [`certify`]: [`min_clearance`], a certified interval for the minimum clearance along the
//!   curve, refined where clearance is small.
//!
//! This crate knows nothing of grids or graphs; it depends on `geom` only.
//!
//! ```
//! use homospline_geom::{Circle, Point};
//! use homospline_spline::{CircleModel, CostConfig, Spline, evaluate, min_clearance};
//!
//! let model = CircleModel::new(vec![Circle::new(30.0, 30.0, 5.0)]);
//! let pts = [Point::new(5.0, 30.0), Point::new(30.0, 45.0), Point::new(55.0, 30.0)];
//! let spline = Spline::natural(&pts).unwrap();
//! let cost = evaluate(&spline, &model, &CostConfig::paper_voronoi()); // cost (10)
//! assert!(cost.total > cost.length * 0.5);
//! let clear = min_clearance(&spline, &model, 1e-6); // lower <= min <= upper
//! assert!(clear.collision_free());
//! ```

pub mod certify;
pub mod clearance_model;
pub mod cost;
pub mod curve;
pub mod names;
pub mod quad;
pub mod roughness;

pub use certify::{CertifiedClearance, is_clear_by, is_collision_free, min_clearance};
pub use clearance_model::{CircleModel, ClearanceModel, FIELD_BLOCK};
pub use cost::{
    ClearanceSearch, CostConfig, CostConfigError, CostTerms, RoughnessForm, evaluate,
    evaluate_weighted, evaluate_weighted_unless, gradient,
};
pub use curve::{EndCondition, Parametrization, Spline, SplineError};
pub use names::{Choice, Preset, UnknownName};
