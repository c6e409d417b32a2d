//! The cost of a path: every criterion of the method as a separate weighted term.
//!
//! Integrals are taken with Gauss-Legendre quadrature on each spline segment, split into
//! [`CostConfig::pieces`] equal pieces of [`CostConfig::nodes`] nodes. The minimal clearance
//! `m(C)` of the safety term is the smallest node clearance refined by Brent's method
//! around it. Terms (method.md section 3):
//!
//! | term | value |
//! |---|---|
//! | topology `T` (2) | `sum_c integral U_c(q) dl`, `U_c = 1 + tanh(alpha (r_c - d_c))` |
//! | roughness `R` (4) | `integral |q''|^2 dt` |
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

use homospline_geom::{Point, Real, Scene, Vector};
use thiserror::Error;

use crate::curve::{Parametrization, Spline};
use crate::field::{ClearanceModel, FieldSample};
use crate::quad::gauss_legendre_cached;

/// Weights and parameters of the cost.
#[derive(Clone, Debug, PartialEq)]
pub struct CostConfig {
    /// `g1`: topology (collision) term.
    pub w_topology: Real,
    /// `g2`: roughness.
    pub w_roughness: Real,
    /// `g3`: length.
    pub w_length: Real,
    /// `g4`: safety.
    pub w_safety: Real,
    /// Maximal-clearance term.
    pub w_max_clearance: Real,
    /// Start visibility.
    pub w_start_visibility: Real,
    /// Goal visibility.
    pub w_goal_visibility: Real,
    /// Danger points.
    pub w_danger: Real,
    /// Critical points.
    pub w_critical: Real,
    /// Sheltered share.
    pub w_sheltered: Real,
    /// Passing time.
    pub w_passing_time: Real,
    /// `alpha` of the potential (1).
    pub alpha: Real,
    /// Required clearance `dm` of the safety term.
    pub dm: Real,
    /// Base `omega` of the safety term.
    pub omega: Real,
    /// `d_max` of the maximal-clearance term.
    pub d_max: Real,
    /// Speed limit on straight parts (passing time).
    pub v_max: Real,
    /// Lateral acceleration limit (passing time): `v <= sqrt(a_lat / kappa)`.
    pub lateral_accel: Real,
    /// Gauss-Legendre nodes per piece (2 to 64).
    pub nodes: usize,
    /// Pieces per spline segment.
    pub pieces: usize,
    /// Relative truncation allowed in the topology term: the potential of far circles may be
    /// left out as long as what is left out is at most `tolerance * (g2 R + g3 L)`, a lower
    /// bound of the total times `tolerance`. 0 keeps every circle whose potential exceeds
    /// `2 exp(-30)` per unit length; reports use 0.
    pub tolerance: Real,
    /// Danger points `(at, min_distance)`.
    pub danger_points: Vec<(Point, Real)>,
    /// Critical points `(at, max_distance)`.
    pub critical_points: Vec<(Point, Real)>,
    /// Hazard sources.
    pub hazards: Vec<Point>,
}

/// Why a cost configuration is unusable.
#[derive(Debug, Error, PartialEq)]
pub enum CostConfigError {
    /// A weight is negative, NaN or infinite.
    #[error("weight {0} must be finite and >= 0, got {1}")]
    Weight(&'static str, Real),
    /// A parameter is out of its range.
    #[error("parameter {0} {1}, got {2}")]
    Parameter(&'static str, &'static str, Real),
}

impl Default for CostConfig {
    fn default() -> Self {
        Self::paper_voronoi()
    }
}

impl CostConfig {
    /// The paper's original cost (9): `F = T + R + 0.5 L`, `alpha = 0.5`.
    pub fn paper_original() -> Self {
        Self {
            w_topology: 1.0,
            w_roughness: 1.0,
            w_length: 0.5,
            w_safety: 0.0,
            w_max_clearance: 0.0,
            w_start_visibility: 0.0,
            w_goal_visibility: 0.0,
            w_danger: 0.0,
            w_critical: 0.0,
            w_sheltered: 0.0,
            w_passing_time: 0.0,
            alpha: 0.5,
            dm: 3.0,
            omega: 20.0,
            d_max: 10.0,
            v_max: 1.0,
            lateral_accel: 0.5,
            nodes: 5,
            pieces: 2,
            tolerance: 1e-7,
            danger_points: Vec::new(),
            critical_points: Vec::new(),
            hazards: Vec::new(),
        }
    }

    /// The cost used with the Voronoi seeds (10): `F = T + R + 0.5 L + D`, `dm = 3`,
    /// `omega = 20`.
    pub fn paper_voronoi() -> Self {
        Self {
            w_safety: 1.0,
            ..Self::paper_original()
        }
    }

    /// A named preset: `paper-original` (9) or `paper-voronoi` (10).
    pub fn preset(name: &str) -> Option<Self> {
        match name {
            "paper-original" | "original" => Some(Self::paper_original()),
            "paper-voronoi" | "voronoi" | "paper" => Some(Self::paper_voronoi()),
            _ => None,
        }
    }

    /// Takes the scene's danger points, critical points and hazards.
    pub fn with_scene_points(mut self, scene: &Scene) -> Self {
        self.danger_points = scene
            .danger_points
            .iter()
            .map(|d| (d.at, d.min_distance))
            .collect();
        self.critical_points = scene
            .critical_points
            .iter()
            .map(|d| (d.at, d.max_distance))
            .collect();
        self.hazards = scene.hazards.clone();
        self
    }

    /// Sets a weight by its name (`topology`, `roughness`, `length`, `safety`,
    /// `max_clearance`, `start_visibility`, `goal_visibility`, `danger`, `critical`,
    /// `sheltered`, `passing_time`) or a parameter (`alpha`, `dm`, `omega`, `d_max`, `v_max`,
    /// `lateral_accel`); validated.
    pub fn set(&mut self, name: &str, value: Real) -> Result<(), String> {
        let slot = self
            .slot(name)
            .ok_or_else(|| format!("unknown weight or parameter '{name}'"))?;
        let old = std::mem::replace(slot, value);
        self.validate().map_err(|e| {
            if let Some(slot) = self.slot(name) {
                *slot = old;
            }
            e.to_string()
        })
    }

    /// The weight or parameter called `name`.
    fn slot(&mut self, name: &str) -> Option<&mut Real> {
        Some(match name {
            "topology" | "g1" => &mut self.w_topology,
            "roughness" | "g2" => &mut self.w_roughness,
            "length" | "g3" => &mut self.w_length,
            "safety" | "g4" => &mut self.w_safety,
            "max_clearance" => &mut self.w_max_clearance,
            "start_visibility" => &mut self.w_start_visibility,
            "goal_visibility" => &mut self.w_goal_visibility,
            "danger" => &mut self.w_danger,
            "critical" => &mut self.w_critical,
            "sheltered" => &mut self.w_sheltered,
            "passing_time" => &mut self.w_passing_time,
            "alpha" => &mut self.alpha,
            "dm" => &mut self.dm,
            "omega" => &mut self.omega,
            "d_max" => &mut self.d_max,
            "v_max" => &mut self.v_max,
            "lateral_accel" => &mut self.lateral_accel,
            _ => return None,
        })
    }

    /// Checks every weight and parameter.
    pub fn validate(&self) -> Result<(), CostConfigError> {
        for (name, w) in [
            ("topology", self.w_topology),
            ("roughness", self.w_roughness),
            ("length", self.w_length),
            ("safety", self.w_safety),
            ("max_clearance", self.w_max_clearance),
            ("start_visibility", self.w_start_visibility),
            ("goal_visibility", self.w_goal_visibility),
            ("danger", self.w_danger),
            ("critical", self.w_critical),
            ("sheltered", self.w_sheltered),
            ("passing_time", self.w_passing_time),
        ] {
            if !(w.is_finite() && w >= 0.0) {
                return Err(CostConfigError::Weight(name, w));
            }
        }
        for (name, v) in [
            ("alpha", self.alpha),
            ("omega", self.omega),
            ("v_max", self.v_max),
            ("lateral_accel", self.lateral_accel),
            ("d_max", self.d_max),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(CostConfigError::Parameter(
                    name,
                    "must be finite and > 0",
                    v,
                ));
            }
        }
        if !(0.0..=1e-3).contains(&self.tolerance) {
            return Err(CostConfigError::Parameter(
                "tolerance",
                "must be in [0, 1e-3]",
                self.tolerance,
            ));
        }
        if !self.dm.is_finite() {
            return Err(CostConfigError::Parameter("dm", "must be finite", self.dm));
        }
        if !(2..=64).contains(&self.nodes) {
            return Err(CostConfigError::Parameter(
                "nodes",
                "must be in 2..=64",
                self.nodes as Real,
            ));
        }
        if !(1..=64).contains(&self.pieces) {
            return Err(CostConfigError::Parameter(
                "pieces",
                "must be in 1..=64",
                self.pieces as Real,
            ));
        }
        Ok(())
    }

    /// The weighted sum of `t`.
    pub fn total(&self, t: &CostTerms) -> Real {
        self.w_topology * t.topology
            + self.w_roughness * t.roughness
            + self.w_length * t.length
            + self.w_safety * t.safety
            + self.w_max_clearance * t.max_clearance
            + self.w_start_visibility * t.start_visibility
            + self.w_goal_visibility * t.goal_visibility
            + self.w_danger * t.danger
            + self.w_critical * t.critical
            + self.w_sheltered * t.sheltered
            + self.w_passing_time * t.passing_time
    }
}

/// Every term of the cost, unweighted, and the weighted total.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CostTerms {
    /// Weighted sum.
    pub total: Real,
    /// `T`.
    pub topology: Real,
    /// `R`.
    pub roughness: Real,
    /// `L`.
    pub length: Real,
    /// `D`.
    pub safety: Real,
    /// Maximal-clearance excess.
    pub max_clearance: Real,
    /// `1 - visible share` from the start.
    pub start_visibility: Real,
    /// `1 - visible share` from the goal.
    pub goal_visibility: Real,
    /// Danger-point violation.
    pub danger: Real,
    /// Critical-point violation.
    pub critical: Real,
    /// `1 - sheltered share`.
    pub sheltered: Real,
    /// Passing time.
    pub passing_time: Real,
    /// `m(C)`: minimal clearance found (nodes, refined near the minimum).
    pub min_clearance: Real,
}

/// Partial derivatives of the integrand at one node, already multiplied by its weight:
/// with respect to `q`, `q'`, `q''`.
struct NodePartial {
    seg: usize,
    s: Real,
    gq: Vector,
    gv: Vector,
    ga: Vector,
}

/// Segments on each side of a via-point over which its influence is taken in [`gradient`]
/// on long curves (more than `2 * BASIS_WINDOW + 2` points).
pub const BASIS_WINDOW: usize = 20;

/// The cost of `spline` against `model`.
pub fn evaluate(spline: &Spline, model: &dyn ClearanceModel, cfg: &CostConfig) -> CostTerms {
    run(spline, model, cfg, None)
}

/// The cost and its gradient with respect to the inner via-points (`points[1..n-1]`).
///
/// Analytic for uniform parameters (the spline is then linear in its points); with
/// chord-length parameters the knots move with the points, and the gradient is taken by
/// central differences (step `1e-6` times the scene scale).
pub fn gradient(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
) -> (CostTerms, Vec<Vector>) {
    let n = spline.points().len();
    if spline.parametrization() == Parametrization::ChordLength {
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
    let terms = run(spline, model, cfg, Some(&mut partials));
    let mut g = vec![Vector::zeros(); n.saturating_sub(2)];
    if n > 2 * BASIS_WINDOW + 2 {
        // Long curves (maps): each via-point's basis on its window of segments only, so the
        // gradient costs O(n) rather than O(n^2) (see `Spline::local_basis`).
        let local: Vec<(usize, Spline)> = (1..n - 1)
            .map(|j| spline.local_basis(j, BASIS_WINDOW))
            .collect();
        for p in &partials {
            let lo = (p.seg + 1).saturating_sub(BASIS_WINDOW).max(1);
            let hi = (p.seg + BASIS_WINDOW).min(n - 2);
            for j in lo..=hi {
                let (first, b) = &local[j - 1];
                if p.seg < *first || p.seg - first >= b.segments() {
                    continue;
                }
                let (b0, b1, b2) = b.eval_segment(p.seg - first, p.s);
                g[j - 1] += p.gq * b0.x + p.gv * b1.x + p.ga * b2.x;
            }
        }
        return (terms, g);
    }
    let basis = spline.basis();
    for p in &partials {
        for (j, gj) in g.iter_mut().enumerate() {
            let (b, b1, b2) = basis[j + 1].eval_segment(p.seg, p.s);
            *gj += p.gq * b.x + p.gv * b1.x + p.ga * b2.x;
        }
    }
    (terms, g)
}

/// Brent's minimisation of `f` on `[a, b]` from `x` (with `fx = f(x)`): parabolic steps where
/// they are safe, golden-section steps otherwise, until the bracket is `2 tol` wide in `t`
/// (at most 64 evaluations). Superlinear on a smooth minimum; a kink (a path through a
/// circle's centre) falls back to golden-section's linear rate.
fn brent_min(
    f: impl Fn(Real) -> Real,
    (a, b): (Real, Real),
    (x, fx): (Real, Real),
    tol: Real,
) -> (Real, Real) {
    const GOLD: Real = 0.381_966_011_250_105_1; // (3 - sqrt 5) / 2
    let (mut a, mut b) = (a, b);
    let (mut x, mut w, mut v) = (x, x, x);
    let (mut fx, mut fw, mut fv) = (fx, fx, fx);
    let (mut d, mut e): (Real, Real) = (0.0, 0.0);
    for _ in 0..64 {
        let m = 0.5 * (a + b);
        if (x - m).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol {
            // Parabola through (v, fv), (w, fw), (x, fx).
            let r = (x - w) * (fx - fv);
            let q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            let mut q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < 2.0 * tol || b - u < 2.0 * tol {
                    d = if x < m { tol } else { -tol };
                }
                golden = false;
            }
        }
        if golden {
            e = if x < m { b - x } else { a - x };
            d = GOLD * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else {
            x + tol.copysign(d)
        };
        let fu = f(u);
        if fu <= fx {
            if u < x {
                b = x;
            } else {
                a = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
}

fn unit(v: &Vector) -> Vector {
    let n = v.norm();
    if n > 0.0 { v / n } else { Vector::zeros() }
}

fn run(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
    mut grad: Option<&mut Vec<NodePartial>>,
) -> CostTerms {
    let (gx, gw) = gauss_legendre_cached(cfg.nodes.clamp(2, 64));
    let pieces = cfg.pieces.max(1);
    let mut t = CostTerms {
        min_clearance: Real::INFINITY,
        ..CostTerms::default()
    };
    let need_field =
        cfg.w_topology > 0.0 || cfg.w_safety > 0.0 || cfg.w_max_clearance > 0.0 || grad.is_none();
    let need_clearance = cfg.w_safety > 0.0 || cfg.w_max_clearance > 0.0 || grad.is_none();
    let knots = spline.knots();
    let nodes = gx.len();
    // All quadrature nodes of the curve first, then one field query for all of them.
    let mut pts = Vec::with_capacity(spline.segments() * pieces * nodes);
    let mut meta = Vec::with_capacity(pts.capacity()); // (segment, s, weight, v, a, |v|)
    // Length and roughness first: they bound the total from below, which sets how much of
    // the far circles' potential may be left out.
    let (mut length, mut roughness) = (0.0, 0.0);
    for seg in 0..spline.segments() {
        let h = (knots[seg + 1] - knots[seg]) / pieces as Real;
        for piece in 0..pieces {
            let base = h * piece as Real;
            for k in 0..nodes {
                let s = base + h * gx[k];
                let (p, v, a) = spline.eval_segment(seg, s);
                let speed = v.norm();
                length += gw[k] * h * speed;
                roughness += gw[k] * h * a.norm_squared();
                pts.push(p);
                meta.push((seg, s, gw[k] * h, v, a, speed));
            }
        }
    }
    (t.length, t.roughness) = (length, roughness);
    let mut field = vec![FieldSample::default(); pts.len()];
    if need_field {
        // Left-out potential per unit length <= allowance, so the topology term loses at
        // most allowance * L = tolerance * (g2 R + g3 L) <= tolerance * total.
        let allowance = if cfg.w_topology > 0.0 && length > 0.0 {
            cfg.tolerance * (cfg.w_roughness * roughness + cfg.w_length * length)
                / (cfg.w_topology * length)
        } else {
            0.0
        };
        model.field_batch(&pts, cfg.alpha, allowance, &mut field);
    }
    // Node with the smallest clearance: (clearance, segment, s, node index).
    let mut worst = (Real::INFINITY, 0usize, 0.0, 0usize);
    // (segment, s, length weight, point) of each node, in order, for the line-of-sight shares.
    let mut trail: Vec<(usize, Real, Real, Point)> = Vec::new();
    let need_trail = cfg.w_start_visibility > 0.0
        || cfg.w_goal_visibility > 0.0
        || (cfg.w_sheltered > 0.0 && !cfg.hazards.is_empty());
    {
        {
            for (idx, &(seg, s, wq, v, a, speed)) in meta.iter().enumerate() {
                let p = pts[idx];
                let vhat = if speed > 0.0 {
                    v / speed
                } else {
                    Vector::zeros()
                };
                let (u, du) = (field[idx].potential, field[idx].potential_grad);
                t.topology += wq * u * speed;
                let mut gq = Vector::zeros();
                let mut gv = vhat * (cfg.w_length + cfg.w_topology * u) * wq;
                let mut ga = a * (2.0 * cfg.w_roughness * wq);
                gq += du * (cfg.w_topology * wq * speed);
                if need_clearance {
                    let (d, dd) = (field[idx].clearance, field[idx].clearance_grad);
                    if d < worst.0 {
                        worst = (d, seg, s, idx);
                    }
                    if d > cfg.d_max {
                        t.max_clearance += wq * (d - cfg.d_max) * speed;
                        gq += dd * (cfg.w_max_clearance * wq * speed);
                        gv += vhat * (cfg.w_max_clearance * wq * (d - cfg.d_max));
                    }
                }
                for &(at, dmin) in &cfg.danger_points {
                    let r = p - at;
                    let dist = r.norm();
                    let e = dmin - dist;
                    if e > 0.0 {
                        t.danger += wq * e * e * speed;
                        gq -= unit(&r) * (cfg.w_danger * wq * speed * 2.0 * e);
                        gv += vhat * (cfg.w_danger * wq * e * e);
                    }
                }
                for &(at, dmax) in &cfg.critical_points {
                    let r = p - at;
                    let e = r.norm() - dmax;
                    if e > 0.0 {
                        t.critical += wq * e * e * speed;
                        gq += unit(&r) * (cfg.w_critical * wq * speed * 2.0 * e);
                        gv += vhat * (cfg.w_critical * wq * e * e);
                    }
                }
                if cfg.w_passing_time > 0.0 || grad.is_none() {
                    let c = v.x * a.y - v.y * a.x;
                    // The curvature limit binds when sqrt(|c| / (a_lat speed^3)) > 1 / v_max,
                    // that is |c| v_max^2 > a_lat speed^3: no root or division to decide.
                    let curvy =
                        c.abs() * cfg.v_max * cfg.v_max > cfg.lateral_accel * speed * speed * speed;
                    if !curvy || speed == 0.0 || c == 0.0 {
                        t.passing_time += wq * speed / cfg.v_max;
                        gv += vhat * (cfg.w_passing_time * wq / cfg.v_max);
                    } else {
                        // f = sqrt(|c| / a_lat) speed^(-1/2).
                        let k0 = 1.0 / cfg.lateral_accel.sqrt();
                        t.passing_time += wq * k0 * c.abs().sqrt() / speed.sqrt();
                        let dc = c.signum() / (2.0 * c.abs().sqrt());
                        let w = cfg.w_passing_time * wq * k0;
                        gv += (Vector::new(a.y, -a.x) * (dc / speed.sqrt())
                            - v * (0.5 * c.abs().sqrt() * speed.powf(-2.5)))
                            * w;
                        ga += Vector::new(-v.y, v.x) * (dc / speed.sqrt() * w);
                    }
                }
                if need_trail {
                    trail.push((seg, s, wq * speed, p));
                }
                if let Some(g) = grad.as_deref_mut() {
                    g.push(NodePartial { seg, s, gq, gv, ga });
                }
            }
        }
    }
    let total_len = t.length.max(Real::MIN_POSITIVE);
    if need_clearance && worst.0.is_finite() {
        // Brent's refinement of m(C) between the worst node's neighbours (where a local
        // minimum next to the smallest sample lies), in global `t` so that a minimum across
        // a knot is found too.
        let (_, seg, s0, idx) = worst;
        let t0 = knots[seg] + s0;
        let t_of = |i: usize| knots[meta[i].0] + meta[i].1;
        let ta = if idx > 0 { t_of(idx - 1) } else { 0.0 };
        let tz = if idx + 1 < meta.len() {
            t_of(idx + 1)
        } else {
            1.0
        };
        // The bracket's stretch of curve lies in the box of its Bezier control points (per
        // segment it touches); only circles that can come nearer than the worst node's
        // clearance there matter.
        let (sa, sz) = (spline.locate(ta).0, spline.locate(tz).0);
        let (mut lo, mut hi) = (spline.position(ta), spline.position(ta));
        for k in sa..=sz {
            let s0 = (ta - knots[k]).max(0.0);
            let s1 = (tz - knots[k]).min(knots[k + 1] - knots[k]);
            let ((p0, v0, _), (p3, v3, _)) =
                (spline.eval_segment(k, s0), spline.eval_segment(k, s1));
            let third = (s1 - s0) / 3.0;
            for p in [p0, p0 + v0 * third, p3 - v3 * third, p3] {
                lo = lo.inf(&p);
                hi = hi.sup(&p);
            }
        }
        let local = model.restricted(&lo, &hi, worst.0);
        let near: &dyn ClearanceModel = local.as_deref().unwrap_or(model);
        let f = |t: Real| near.clearance(&spline.position(t)).0;
        let (tb, fb) = brent_min(f, (ta, tz), (t0, worst.0), 1e-10);
        // Brent searches the open bracket; a minimum at one of its ends (the start or the
        // goal inside an obstacle's reach) is taken there exactly.
        let (tb, fb) = [(ta, f(ta)), (tz, f(tz))]
            .into_iter()
            .fold((tb, fb), |best, e| if e.1 < best.1 { e } else { best });
        let (tm, m) = if fb < worst.0 {
            (tb, fb)
        } else {
            (t0, worst.0)
        };
        let (seg, sm) = spline.locate(tm);
        t.min_clearance = m;
        t.safety = cfg.omega.powf(cfg.dm - m);
        if let Some(g) = grad {
            let (_, dd) = model.clearance(&spline.eval_segment(seg, sm).0);
            let coef = -cfg.w_safety * t.safety * cfg.omega.ln();
            g.push(NodePartial {
                seg,
                s: sm,
                gq: dd * coef,
                gv: Vector::zeros(),
                ga: Vector::zeros(),
            });
        }
    }
    if need_trail {
        let start = spline.points()[0];
        let goal = *spline.points().last().unwrap_or(&start);
        let visible_prefix =
            |from: &Point, order: &mut dyn Iterator<Item = &(usize, Real, Real, Point)>| {
                let mut len = 0.0;
                for (_, _, dl, p) in order {
                    if !model.line_of_sight(from, p) {
                        break;
                    }
                    len += dl;
                }
                len
            };
        if cfg.w_start_visibility > 0.0 {
            t.start_visibility = 1.0 - visible_prefix(&start, &mut trail.iter()) / total_len;
        }
        if cfg.w_goal_visibility > 0.0 {
            t.goal_visibility = 1.0 - visible_prefix(&goal, &mut trail.iter().rev()) / total_len;
        }
        if cfg.w_sheltered > 0.0 && !cfg.hazards.is_empty() {
            let hidden: Real = trail
                .iter()
                .filter(|(_, _, _, p)| cfg.hazards.iter().all(|h| !model.line_of_sight(h, p)))
                .map(|(_, _, dl, _)| dl)
                .sum();
            t.sheltered = 1.0 - hidden / total_len;
        }
    }
    t.total = cfg.total(&t);
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_validates_and_keeps_the_old_value_on_error() {
        let mut c = CostConfig::paper_voronoi();
        c.set("safety", 2.5).unwrap();
        assert_eq!(c.w_safety, 2.5);
        c.set("g3", 1.0).unwrap();
        assert_eq!(c.w_length, 1.0);
        assert_eq!(
            c.set("safty", 1.0).unwrap_err(),
            "unknown weight or parameter 'safty'"
        );
        assert!(c.set("alpha", -1.0).is_err());
        assert_eq!(c.alpha, 0.5);
        assert!(c.set("roughness", Real::NAN).is_err());
        assert_eq!(c.w_roughness, 1.0);
    }
}
