//! Steps 2 and 3 of an evaluation: the field at every quadrature node and the integrals over
//! the nodes, in stretches where the evaluation may stop early.

use homospline_geom::Real;

use super::config::CostConfig;
use super::integrand::{Needs, NodePartial, Worst, integrate_nodes};
use super::quadrature::Samples;
use super::terms::{CostTerms, bounding_terms};
use crate::clearance_model::{ClearanceModel, FIELD_BLOCK, FieldSample};

/// The potential the field query may leave out per unit length: the topology term then
/// loses at most `allowance * L = tolerance * (g2 R + g3 L + g4 D_knots) <= tolerance *
/// total`, where `D_knots = omega^(dm - least knot clearance) <= D`, since `m(C)` is at most
/// the clearance at any knot (and `m(C)` takes in the knots).
fn field_allowance(
    samples: &Samples,
    roughness: Real,
    knot_clearance: Real,
    cfg: &CostConfig,
) -> Real {
    let length = samples.length;
    let safety_floor = if cfg.w_safety > 0.0 && knot_clearance.is_finite() {
        cfg.w_safety * cfg.omega.powf(cfg.dm - knot_clearance)
    } else {
        0.0
    };
    if cfg.w_topology > 0.0 && length > 0.0 {
        cfg.tolerance * (cfg.w_roughness * roughness + cfg.w_length * length + safety_floor)
            / (cfg.w_topology * length)
    } else {
        0.0
    }
}

/// Nodes per stretch when an evaluation may stop within the field pass: a multiple of
/// [`FIELD_BLOCK`], so that the field's values are those of one batch query, to the bit.
const STRETCH: usize = 4 * FIELD_BLOCK;

/// Steps 2 and 3: the field (potential and clearance) at every node, far circles' potential
/// left out within the configured tolerance ([`field_allowance`]), and the integrals over
/// the nodes ([`integrate_nodes`]); returns the node of least clearance. With the partials
/// (`grad`) in one batch query. Without, the field is asked for values only, and with
/// `enough` in stretches of [`STRETCH`] nodes: after each stretch but the last, `enough` is
/// asked with terms bounding the finished ones (every integral so far is a sum of
/// non-negative parts in node order, so at most its final value, and `m(C)` at most the
/// least clearance of the nodes so far and of the knots); `Err(those terms)` when it answers
/// `true`. A candidate that falls short of the dm rule's target stops at the first stretch
/// that shows it, and one whose cost already exceeds what it must beat soon after. The
/// values at the nodes and the sums are the same, to the bit, whether or not it stops.
#[allow(clippy::too_many_arguments)]
pub(super) fn field_and_integrals(
    model: &dyn ClearanceModel,
    samples: &Samples,
    least_knot: Real,
    cfg: &CostConfig,
    needs: Needs,
    t: &mut CostTerms,
    grad: Option<&mut Vec<NodePartial>>,
    field: &mut Vec<FieldSample>,
    enough: Option<&dyn Fn(&CostTerms) -> bool>,
) -> Result<Option<Worst>, CostTerms> {
    let allowance = field_allowance(samples, t.roughness, least_knot, cfg);
    let n = samples.points.len();
    // Every node's sample is written (by stretch) before it is read: the old ones are
    // not cleared.
    field.resize(n, FieldSample::default());
    if let Some(g) = grad {
        model.field_batch(&samples.points, cfg.alpha, allowance, field);
        return Ok(integrate_nodes::<true>(
            samples,
            field,
            0..n,
            cfg,
            needs,
            t,
            Some(g),
            None,
        ));
    }
    let stretch = if enough.is_some() { STRETCH } else { n.max(1) };
    let mut worst = None;
    let mut from = 0;
    while from < n {
        let to = (from + stretch).min(n);
        model.field_values(
            &samples.points[from..to],
            cfg.alpha,
            allowance,
            &mut field[from..to],
        );
        worst = integrate_nodes::<false>(samples, field, from..to, cfg, needs, t, None, worst);
        if to < n
            && let Some(enough) = enough
            && let Some(w) = worst
            && let Some(low) = bounding_terms(t, w.clearance.min(least_knot), cfg)
            && enough(&low)
        {
            return Err(low);
        }
        from = to;
    }
    Ok(worst)
}
