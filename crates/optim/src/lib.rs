//! Nelder-Mead, the via-point growth loop, and the homotopy-seeded planner (method.md
//! sections 4 and 5).
//!
//! - [`solver`]: the [`solver::Solver`] trait both optimisers implement, in argmin's shape
//!   (`init`, `step`, `terminate`, a [`Termination`] reason, an [`solver::Observer`]), and
//!   [`solver::run`], which drives any of them.
//! - [`nelder_mead`]: [`NelderMead`], standard and dimension-adaptive (Gao and Han 2012),
//!   with validating setters and restarts.
//! - [`lbfgs`]: [`Lbfgs`], for the analytic gradient (an option; Nelder-Mead stays default),
//!   with validating setters.
//! - [`barrier`]: [`barrier::Barrier`], a log barrier on the clearance with its gradient, for
//!   the interior-point finish of a polish round and of the chosen class's finish within
//!   its work budget (`PlanConfig::finish_within`).
//! - [`growth`]: [`grow`], the paper's loop: optimise, add a via-point, repeat.
//! - [`planner`]: [`plan`], scene to ranked plan. It is the only module that touches every
//!   lower crate (voronoi, homotopy, spline), and it holds no algorithm of its own beyond
//!   seeding and ranking.

pub mod barrier;
pub mod growth;
pub mod lbfgs;
pub mod names;
pub mod nelder_mead;
pub mod planner;
pub mod solver;

pub use growth::{Grown, Growth, GrowthConfig, Guard, Optimizer, Round, grow};
pub use lbfgs::Lbfgs;
pub use nelder_mead::{Coefficients, NelderMead, Outcome};
pub use planner::{
    ClassPlan, Deadline, Detour, Interrupt, Plan, PlanConfig, PlanError, PlanGraph, Seed, Timing,
    World, default_resolution, graph_misfit, plan, plan_with_graph, plan_world,
};
pub use solver::{Solver, Termination};
