//! The individual terms at the quadrature nodes: the integrals (topology, maximal clearance,
//! danger, critical, passing time) with their partial derivatives, the safety term integrated
//! along the curve, and the line-of-sight shares.

use homospline_geom::{Point, Real, Vector};

use super::config::CostConfig;
use super::quadrature::Samples;
use super::terms::CostTerms;
use crate::clearance_model::{ClearanceModel, FieldSample};
use crate::curve::Spline;

/// Partial derivatives of the integrand at one node, already multiplied by its weight:
/// with respect to `q`, `q'`, `q''`.
pub(super) struct NodePartial {
    pub(super) seg: usize,
    pub(super) s: Real,
    pub(super) gq: Vector,
    pub(super) gv: Vector,
    pub(super) ga: Vector,
}

/// The node of least clearance.
#[derive(Clone, Copy)]
pub(super) struct Worst {
    pub(super) clearance: Real,
    pub(super) index: usize,
}

/// What [`run`](super::pipeline::run) must compute beyond what the weights need.
#[derive(Clone, Copy)]
pub(super) struct Needs {
    /// Every term's value (a report needs them all; an optimiser only what it weighs). The
    /// field and `m(C)` are always computed: the optimiser's guard rejects candidates by
    /// `m(C)`, whatever the weights.
    pub(super) all: bool,
    pub(super) line_of_sight: bool,
}

impl Needs {
    pub(super) fn of(cfg: &CostConfig, all: bool) -> Self {
        Self {
            all,
            line_of_sight: cfg.w_start_visibility > 0.0
                || cfg.w_goal_visibility > 0.0
                || (cfg.w_sheltered > 0.0 && !cfg.hazards.is_empty()),
        }
    }
}

/// Which point terms [`integrate_nodes`] computes.
pub(super) struct Weighs {
    danger: bool,
    critical: bool,
}

/// Step 3: the integrals over the nodes `range` (topology, maximal clearance, danger,
/// critical, passing time) added to `t` and, with `GRAD`, each node's partial derivatives;
/// returns the node of least clearance among `worst` (the nodes before) and these. The loop
/// is compiled twice, with and without the partials, so that a value alone does not pay for
/// them.
#[allow(clippy::too_many_arguments)]
pub(super) fn integrate_nodes<const GRAD: bool>(
    samples: &Samples,
    field: &[FieldSample],
    range: std::ops::Range<usize>,
    cfg: &CostConfig,
    needs: Needs,
    t: &mut CostTerms,
    mut grad: Option<&mut Vec<NodePartial>>,
    mut worst: Option<Worst>,
) -> Option<Worst> {
    // Terms of weight 0 are left out unless every term is asked for.
    let weighs = Weighs {
        danger: needs.all || cfg.w_danger > 0.0,
        critical: needs.all || cfg.w_critical > 0.0,
    };
    for (idx, n) in samples
        .nodes
        .iter()
        .enumerate()
        .take(range.end)
        .skip(range.start)
    {
        let (p, wq, v, a, speed) = (samples.points[idx], n.dt, n.v, n.a, n.speed);
        let vhat = if GRAD && speed > 0.0 {
            v / speed
        } else {
            Vector::zeros()
        };
        let (u, du) = (field[idx].potential, field[idx].potential_grad);
        t.topology += wq * u * speed;
        let (mut gq, mut gv, mut ga) = (Vector::zeros(), Vector::zeros(), Vector::zeros());
        if GRAD {
            gq = du * (cfg.w_topology * wq * speed);
            gv = vhat * (cfg.w_length + cfg.w_topology * u) * wq;
        }
        let (d, dd) = (field[idx].clearance, field[idx].clearance_grad);
        if worst.is_none_or(|w| d < w.clearance) {
            worst = Some(Worst {
                clearance: d,
                index: idx,
            });
        }
        if d > cfg.d_max && (needs.all || cfg.w_max_clearance > 0.0) {
            t.max_clearance += wq * (d - cfg.d_max) * speed;
            if GRAD {
                gq += dd * (cfg.w_max_clearance * wq * speed);
                gv += vhat * (cfg.w_max_clearance * wq * (d - cfg.d_max));
            }
        }
        for &(at, dmin) in cfg.danger_points.iter().filter(|_| weighs.danger) {
            let r = p - at;
            let e = dmin - r.norm();
            if e > 0.0 {
                t.danger += wq * e * e * speed;
                if GRAD {
                    gq -= unit(&r) * (cfg.w_danger * wq * speed * 2.0 * e);
                    gv += vhat * (cfg.w_danger * wq * e * e);
                }
            }
        }
        for &(at, dmax) in cfg.critical_points.iter().filter(|_| weighs.critical) {
            let r = p - at;
            let e = r.norm() - dmax;
            if e > 0.0 {
                t.critical += wq * e * e * speed;
                if GRAD {
                    gq += unit(&r) * (cfg.w_critical * wq * speed * 2.0 * e);
                    gv += vhat * (cfg.w_critical * wq * e * e);
                }
            }
        }
        if cfg.w_passing_time > 0.0 || needs.all {
            let c = v.x * a.y - v.y * a.x;
            // The curvature limit binds when sqrt(|c| / (a_lat speed^3)) > 1 / v_max, that
            // is |c| v_max^2 > a_lat speed^3: no root or division to decide.
            let curvy = c.abs() * cfg.v_max * cfg.v_max > cfg.lateral_accel * speed * speed * speed;
            if !curvy || speed == 0.0 || c == 0.0 {
                t.passing_time += wq * speed / cfg.v_max;
                if GRAD {
                    gv += vhat * (cfg.w_passing_time * wq / cfg.v_max);
                }
            } else {
                // f = sqrt(|c| / a_lat) speed^(-1/2).
                let k0 = 1.0 / cfg.lateral_accel.sqrt();
                t.passing_time += wq * k0 * c.abs().sqrt() / speed.sqrt();
                if GRAD {
                    let dc = c.signum() / (2.0 * c.abs().sqrt());
                    let w = cfg.w_passing_time * wq * k0;
                    gv += (Vector::new(a.y, -a.x) * (dc / speed.sqrt())
                        - v * (0.5 * c.abs().sqrt() * speed.powf(-2.5)))
                        * w;
                    ga += Vector::new(-v.y, v.x) * (dc / speed.sqrt() * w);
                }
            }
        }
        if GRAD && let Some(g) = grad.as_deref_mut() {
            g.push(NodePartial {
                seg: n.seg,
                s: n.s,
                gq,
                gv,
                ga,
            });
        }
    }
    worst
}

/// [`CostConfig::safety_along`]: `D = I / scale`, `I = integral omega^(dm - d(q)) dl` over
/// the quadrature nodes, into `t.safety`, and with `grad` each node's partials:
/// `dD/dq = -ln(omega) e |q'| dt grad d / scale` and `dD/dq' = e dt q' / (|q'| scale)`, where
/// `e = omega^(dm - d)`.
pub(super) fn safety_along(
    samples: &Samples,
    field: &[FieldSample],
    cfg: &CostConfig,
    scale: Real,
    t: &mut CostTerms,
    grad: Option<&mut Vec<NodePartial>>,
) {
    // omega^(dm - d) as exp((dm - d) ln omega): one exp a node where powf took two logs' work.
    let ln_omega = cfg.omega.ln();
    // One pass: each node's exponential serves the integral and its partials. The sum
    // starts at -0.0, as `Iterator::sum` of floats does.
    let mut integral: Real = -0.0;
    let mut grad = grad;
    for (n, f) in samples.nodes.iter().zip(field) {
        let ei = ((cfg.dm - f.clearance) * ln_omega).exp();
        integral += ei * n.speed * n.dt;
        if let Some(g) = grad.as_deref_mut() {
            let w = cfg.w_safety * n.dt * ei / scale;
            g.push(NodePartial {
                seg: n.seg,
                s: n.s,
                gq: f.clearance_grad * (-ln_omega * n.speed * w),
                gv: unit(&n.v) * w,
                ga: Vector::zeros(),
            });
        }
    }
    t.safety = integral / scale;
}

/// Step 5: the line-of-sight shares (start and goal visibility, shelter from hazards).
pub(super) fn line_of_sight_shares(
    spline: &Spline,
    model: &dyn ClearanceModel,
    samples: &Samples,
    cfg: &CostConfig,
    t: &mut CostTerms,
) {
    let total_len = samples.length.max(Real::MIN_POSITIVE);
    let dl = |i: usize| samples.nodes[i].dt * samples.nodes[i].speed;
    let start = spline.points()[0];
    let goal = *spline.points().last().unwrap_or(&start);
    let visible_prefix = |from: &Point, order: &mut dyn Iterator<Item = usize>| {
        let mut len = 0.0;
        for i in order {
            if !model.line_of_sight(from, &samples.points[i]) {
                break;
            }
            len += dl(i);
        }
        len
    };
    let count = samples.points.len();
    if cfg.w_start_visibility > 0.0 {
        t.start_visibility = 1.0 - visible_prefix(&start, &mut (0..count)) / total_len;
    }
    if cfg.w_goal_visibility > 0.0 {
        t.goal_visibility = 1.0 - visible_prefix(&goal, &mut (0..count).rev()) / total_len;
    }
    if cfg.w_sheltered > 0.0 && !cfg.hazards.is_empty() {
        let hidden: Real = (0..count)
            .filter(|&i| {
                cfg.hazards
                    .iter()
                    .all(|h| !model.line_of_sight(h, &samples.points[i]))
            })
            .map(dl)
            .sum();
        t.sheltered = 1.0 - hidden / total_len;
    }
}

fn unit(v: &Vector) -> Vector {
    let n = v.norm();
    if n > 0.0 { v / n } else { Vector::zeros() }
}
