//! One evaluation of the cost, step by step ([`evaluate`], [`evaluate_weighted`],
//! [`evaluate_weighted_unless`]), on buffers kept per thread.

use homospline_geom::{Real, Vector};

use super::clearance::{knot_clearances, refine_min_clearance};
use super::config::CostConfig;
use super::integrand::{Needs, NodePartial, line_of_sight_shares, safety_along};
use super::integrate::field_and_integrals;
use super::quadrature::{Samples, sample};
use super::terms::{CostTerms, bounding_terms};
use crate::clearance_model::{ClearanceModel, FieldSample};
use crate::curve::Spline;
use crate::roughness::roughness;

/// The cost of `spline` against `model`: every term, weighted or not.
///
/// # Examples
///
/// ```
/// use homospline_geom::{Circle, Point};
/// use homospline_spline::{CircleModel, CostConfig, Spline, evaluate};
///
/// let model = CircleModel::new(vec![Circle::new(5.0, 0.0, 1.0)]);
/// let straight = Spline::natural(&[Point::new(0.0, 0.0), Point::new(10.0, 0.0)])?;
/// let round = Spline::natural(&[Point::new(0.0, 0.0), Point::new(5.0, 4.0), Point::new(10.0, 0.0)])?;
/// let cfg = CostConfig::default();
/// let (a, b) = (evaluate(&straight, &model, &cfg), evaluate(&round, &model, &cfg));
/// // Through the disc the potential term dominates: going round is cheaper.
/// assert!(b.total < a.total);
/// assert!(b.length > a.length);
/// # Ok::<(), homospline_spline::SplineError>(())
/// ```
///
/// See also [`CostConfig`] (weights, `dm`, presets), [`ClearanceModel`].
pub fn evaluate(spline: &Spline, model: &dyn ClearanceModel, cfg: &CostConfig) -> CostTerms {
    run(spline, model, cfg, None, true)
}

/// [`evaluate_weighted`] for an optimiser that may not need the exact value: `enough` is
/// asked with terms that bound the exact ones (every term and the total at most the exact
/// ones, `min_clearance` at least the exact `m(C)`), once the roughness, the length and the
/// knots' clearances are known and again once the integrals are; if it answers `true`, the
/// evaluation stops there and returns those terms as `Err`. Else `Ok` with the same terms as
/// [`evaluate_weighted`]. What is skipped: the field and the integrals at the first stop,
/// the refinement of `m(C)` at the second.
pub fn evaluate_weighted_unless(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
    enough: &dyn Fn(&CostTerms) -> bool,
) -> Result<CostTerms, CostTerms> {
    run_unless(spline, model, cfg, None, false, Some(enough))
}

/// The cost of `spline` as an optimiser needs it: the same `total` and `min_clearance` as
/// [`evaluate`], but the terms whose weight is 0 are not computed (they read 0).
pub fn evaluate_weighted(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
) -> CostTerms {
    run(spline, model, cfg, None, false)
}

/// The buffers of one evaluation, kept per thread between evaluations: an optimiser evaluates
/// thousands of curves of the same size, and allocation was a tenth of a plan's time (these
/// buffers and the spline's own were most of it).
#[derive(Default)]
struct Scratch {
    samples: Samples,
    field: Vec<FieldSample>,
    knot_clearances: Vec<(Real, Real)>,
    distances: Vec<Real>,
}

thread_local! {
    /// Taken out for an evaluation and put back after it (a `Cell`, so that an evaluation
    /// nested in another, which does not happen, would only allocate its own).
    static SCRATCH: std::cell::Cell<Scratch> = std::cell::Cell::new(Scratch::default());
}

/// The terms of the cost (every one with `all`, else those weighed), and with `grad` the
/// partial derivatives of the weighted total at each node (the safety term's at the point of
/// least clearance).
pub(super) fn run(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
    grad: Option<&mut Vec<NodePartial>>,
    all: bool,
) -> CostTerms {
    // Without `enough` the run never stops early: both arms hold the full terms.
    run_unless(spline, model, cfg, grad, all, None).unwrap_or_else(|t| t)
}

/// [`run`], stopping early with `Err(bounding terms)` when `enough` says so
/// ([`evaluate_weighted_unless`]).
fn run_unless(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
    grad: Option<&mut Vec<NodePartial>>,
    all: bool,
    enough: Option<&dyn Fn(&CostTerms) -> bool>,
) -> Result<CostTerms, CostTerms> {
    // `try_with`: a thread tearing down its locals gets fresh buffers instead of a panic.
    let mut scratch = SCRATCH.try_with(|s| s.take()).unwrap_or_default();
    let t = run_in(spline, model, cfg, grad, all, enough, &mut scratch);
    let _ = SCRATCH.try_with(|s| s.set(scratch));
    t
}

/// [`run`] on the buffers of `scratch`: the steps in order, with the two places where
/// `enough` may stop the evaluation.
fn run_in(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
    mut grad: Option<&mut Vec<NodePartial>>,
    all: bool,
    enough: Option<&dyn Fn(&CostTerms) -> bool>,
    scratch: &mut Scratch,
) -> Result<CostTerms, CostTerms> {
    let needs = Needs::of(cfg, all);
    let Scratch {
        samples,
        field,
        knot_clearances: knots,
        distances,
    } = scratch;
    sample(spline, cfg, samples);
    let samples = &*samples;
    let rough = roughness(spline, cfg.roughness, grad.is_some());
    let mut t = CostTerms {
        min_clearance: Real::INFINITY,
        length: samples.length,
        roughness: rough.value,
        ..CostTerms::default()
    };
    if let Some(g) = grad.as_deref_mut() {
        push_roughness_partials(spline, &rough.knot_partials, cfg, g);
    }
    end_clearances(spline, model, cfg, distances, knots);
    let least_knot = knots.iter().map(|k| k.1).fold(Real::INFINITY, Real::min);
    // The stops below bound `D` by `m(C)`, which holds for (7) only.
    let enough = enough.filter(|_| !cfg.safety_along);
    // First stop: roughness, length and the knots' clearances (`m(C)` is at most theirs).
    stop_if_enough(enough, &t, least_knot, cfg)?;
    let worst = field_and_integrals(
        model,
        samples,
        least_knot,
        cfg,
        needs,
        &mut t,
        grad.as_deref_mut(),
        field,
        enough,
    )?;
    // Second stop: every integral, and `m(C)` at most the least node's and knot's clearance
    // (the refinement below only lowers it).
    if let Some(w) = worst {
        stop_if_enough(enough, &t, w.clearance.min(least_knot), cfg)?;
    }
    if let Some(worst) = worst.filter(|w| w.clearance.is_finite()) {
        let (tm, m) = refine_min_clearance(
            spline,
            model,
            samples,
            field,
            worst,
            knots,
            cfg.clearance_search,
        );
        t.min_clearance = m;
        if cfg.safety_along {
            let span = (spline.position(1.0) - spline.position(0.0)).norm();
            let scale = if span > 0.0 { span } else { 1.0 };
            safety_along(samples, field, cfg, scale, &mut t, grad);
        } else {
            safety_at_least_clearance(spline, model, cfg, tm, &mut t, grad);
        }
    }
    if needs.line_of_sight {
        line_of_sight_shares(spline, model, samples, cfg, &mut t);
    }
    t.total = cfg.total(&t);
    Ok(t)
}

/// `Err(terms bounding the finished ones)` ([`bounding_terms`], `m_up` an upper bound of
/// `m(C)`) when `enough` answers `true` for them; else `Ok`.
fn stop_if_enough(
    enough: Option<&dyn Fn(&CostTerms) -> bool>,
    t: &CostTerms,
    m_up: Real,
    cfg: &CostConfig,
) -> Result<(), CostTerms> {
    if let Some(enough) = enough
        && let Some(low) = bounding_terms(t, m_up, cfg)
        && enough(&low)
    {
        return Err(low);
    }
    Ok(())
}

/// The roughness term's partials into `g`: it depends on `q''` at the knots only, taken at
/// the start of each segment and at the end of the last.
fn push_roughness_partials(
    spline: &Spline,
    knot_partials: &[Vector],
    cfg: &CostConfig,
    g: &mut Vec<NodePartial>,
) {
    let knots = spline.knots();
    let last = spline.segments() - 1;
    for (i, d) in knot_partials.iter().enumerate() {
        let (seg, s) = if i <= last {
            (i, 0.0)
        } else {
            (last, knots[last + 1] - knots[last])
        };
        g.push(NodePartial {
            seg,
            s,
            gq: Vector::zeros(),
            gv: Vector::zeros(),
            ga: d * cfg.w_roughness,
        });
    }
}

/// The clearances `m(C)` takes in besides the nodes', into `knots`: every knot's where the
/// safety term weighs and the model truncates (the allowance counts on them); else only the
/// ends' (`distances` is a buffer).
fn end_clearances(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
    distances: &mut Vec<Real>,
    knots: &mut Vec<(Real, Real)>,
) {
    if cfg.w_safety > 0.0 && model.truncates() {
        knot_clearances(spline, model, distances, knots);
    } else {
        knots.clear();
        knots.extend(
            [0.0, 1.0]
                .iter()
                .map(|&t| (t, model.clearance(&spline.position(t)).0)),
        );
    }
}

/// The safety term (7), `D = omega^(dm - m(C))`, from `t.min_clearance` into `t.safety`, and
/// with `grad` its partial at the point of least clearance, `tm`.
fn safety_at_least_clearance(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
    tm: Real,
    t: &mut CostTerms,
    grad: Option<&mut Vec<NodePartial>>,
) {
    t.safety = cfg.omega.powf(cfg.dm - t.min_clearance);
    if let Some(g) = grad {
        let (seg, s) = spline.locate(tm);
        let (_, dd) = model.clearance(&spline.eval_segment(seg, s).0);
        let coef = -cfg.w_safety * t.safety * cfg.omega.ln();
        g.push(NodePartial {
            seg,
            s,
            gq: dd * coef,
            gv: Vector::zeros(),
            ga: Vector::zeros(),
        });
    }
}
