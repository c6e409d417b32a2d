//! The paper's iterative optimisation (method.md section 4): optimise the inner via-points,
//! add one via-point, warm-started from the current curve, and repeat until the round limit
//! or a round that fails to improve.
//!
//! [`grow`] runs the loop, a [`Growth`], to its end. Its parts:
//!
//! - `config`: [`GrowthConfig`] and [`Optimizer`].
//! - `guard`: [`Guard`], what keeps candidates in their class, in bounds and clear.
//! - `state`: [`Growth`]'s state, its best curve and its result ([`Grown`], [`Round`]).
//! - `round`: one round ([`Growth::step`]): the optimiser, the acceptance, the growth.
//! - `insert`: the via-point added after a round.
//! - `finish`: the interior-point finish of a polish round.
//! - `polish`: rounds after the loop's end: repair, polish, finish.

use homospline_geom::Point;
use homospline_spline::{ClearanceModel, SplineError};

mod config;
mod finish;
mod guard;
mod insert;
mod polish;
mod round;
mod state;

pub use config::{GrowthConfig, Optimizer};
pub use finish::{FINISH_SAMPLES, FINISH_WEIGHTS, MIN_FINISH_EVALUATIONS};
pub use guard::{
    DIRECT_SIGNATURE_RAYS, Guard, LOCAL_PROOF_RAYS, MAX_REPORT_SAMPLES, SHORT_OF_TARGET,
    STRICT_SLACK, Tube, admissible, in_class_beside, report_spacing, stays_in_bounds,
};
pub use state::{Grown, Growth, Round};

/// Runs the growth loop from `seed` (`S`, initial via-points, `T`) to its end, and its
/// repair round if it needs one ([`Growth::repair`]).
pub fn grow(
    seed: &[Point],
    model: &dyn ClearanceModel,
    cfg: &GrowthConfig,
    guard: &Guard<'_>,
) -> Result<Grown, SplineError> {
    let mut g = Growth::new(seed, model, cfg, guard)?;
    while g.step(model, cfg, guard) {}
    g.repair(model, cfg, guard);
    Ok(g.result(model, cfg, guard))
}

#[cfg(test)]
mod tests;
