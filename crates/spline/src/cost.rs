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

use homospline_geom::{Point, Real, Scene, Vector};
use thiserror::Error;

use crate::curve::{EndCondition, Parametrization, Spline};
use crate::field::{ClearanceModel, FIELD_BLOCK, FieldSample};
use crate::quad::gauss_legendre_cached;
pub use crate::roughness::RoughnessForm;
use crate::roughness::roughness;

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
    /// The form of roughness (4).
    pub roughness: RoughnessForm,
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
    /// left out as long as what is left out is at most `tolerance * (g2 R + g3 L + g4 D_knots)`
    /// (`D_knots`: `D` at the least knot clearance, at most `D`), a lower
    /// bound of the total times `tolerance`. 0 keeps every circle whose potential exceeds
    /// `2 exp(-30)` per unit length; reports use 0.
    pub tolerance: Real,
    /// Danger points `(at, min_distance)`.
    pub danger_points: Vec<(Point, Real)>,
    /// Critical points `(at, max_distance)`.
    pub critical_points: Vec<(Point, Real)>,
    /// Hazard sources.
    pub hazards: Vec<Point>,
    /// Where `m(C)` is searched between the quadrature nodes.
    pub clearance_search: ClearanceSearch,
    /// The safety term integrated along the curve, `D = (1 / |S T|) integral omega^(dm - d(q))
    /// dl`, instead of (7)'s `omega^(dm - m(C))` at the least clearance only (maps). On a
    /// straight path of constant clearance it is (7); it sees every stretch that comes near
    /// an obstacle (each pulls with its own share), and a start or goal next to a wall
    /// weighs only over the stretch near it: with (7) the least clearance of a map path is
    /// usually its start's or a one-cell door's, `D` is then the same for every curve, and
    /// the rest of the path grazed corners. The scale is the fixed `|S T|` (1 when `S = T`),
    /// not the curve's length: divided by its own length, `D` paid a detour through open
    /// space (it lowered the mean), and paths on small cluttered maps came out twice as long.
    pub safety_along: bool,
}

/// Where the cost looks for `m(C)` between its quadrature nodes, which can be several units
/// apart on a long segment: a curve passing a small circle between two nodes dips below
/// both (by up to `a^2 / 8 rho` for nodes `a` apart passing a centre at `rho`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ClearanceSearch {
    /// Brent's method between the worst node's two neighbours: the optimiser's default. It
    /// misses a dip between two other nodes (on 320 scenes, 181 of 1,266 classes whose
    /// `m(C)` kept `dm` were certified below it). The planner gives a class whose final
    /// curve has such a dip, and that could rank first, one more round with `EveryStretch`
    /// (`homospline_optim::Growth::repair`).
    #[default]
    WorstNode,
    /// As `WorstNode`, then every stretch between two consecutive nodes (and from each end
    /// to its nearest node) whose bound lets the clearance dip below the least value found
    /// is halved, the lowest bound first, until no bound is more than `1e-5` below it. The
    /// bound is the larger of the Lipschitz one and one from how sharply the clearance can
    /// bend ([`ClearanceModel::bend_radius`]); the worst node's two stretches are searched
    /// too (Brent's method follows one valley, and a second dip beside it escapes it). An
    /// evaluation costs 1.6 times as much on the cost bench: a curve held near `dm` has
    /// many stretches close to it. A model without the bend bound gets `WorstNode` (a map's
    /// grid has it: the distance to a square bends as a disc of radius 0's).
    EveryStretch,
}

impl ClearanceSearch {
    /// Both, in order.
    pub const ALL: [Self; 2] = [Self::WorstNode, Self::EveryStretch];

    /// `worst-node` or `every-stretch`, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::WorstNode => "worst-node",
            Self::EveryStretch => "every-stretch",
        }
    }

    /// The search called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// One weighted term of the cost: its names, its weight and its value.
pub struct Term {
    /// Name for `--weight NAME=VALUE` and [`CostConfig::set`].
    pub name: &'static str,
    /// The paper's name of the weight (`g1` .. `g4`), if it has one.
    pub alias: Option<&'static str>,
    /// The weight in a configuration.
    pub weight: fn(&CostConfig) -> Real,
    weight_mut: fn(&mut CostConfig) -> &mut Real,
    /// The unweighted value in a set of terms.
    pub value: fn(&CostTerms) -> Real,
}

/// Every weighted term, in the order of the total.
pub const TERMS: [Term; 11] = [
    Term {
        name: "topology",
        alias: Some("g1"),
        weight: |c| c.w_topology,
        weight_mut: |c| &mut c.w_topology,
        value: |t| t.topology,
    },
    Term {
        name: "roughness",
        alias: Some("g2"),
        weight: |c| c.w_roughness,
        weight_mut: |c| &mut c.w_roughness,
        value: |t| t.roughness,
    },
    Term {
        name: "length",
        alias: Some("g3"),
        weight: |c| c.w_length,
        weight_mut: |c| &mut c.w_length,
        value: |t| t.length,
    },
    Term {
        name: "safety",
        alias: Some("g4"),
        weight: |c| c.w_safety,
        weight_mut: |c| &mut c.w_safety,
        value: |t| t.safety,
    },
    Term {
        name: "max_clearance",
        alias: None,
        weight: |c| c.w_max_clearance,
        weight_mut: |c| &mut c.w_max_clearance,
        value: |t| t.max_clearance,
    },
    Term {
        name: "start_visibility",
        alias: None,
        weight: |c| c.w_start_visibility,
        weight_mut: |c| &mut c.w_start_visibility,
        value: |t| t.start_visibility,
    },
    Term {
        name: "goal_visibility",
        alias: None,
        weight: |c| c.w_goal_visibility,
        weight_mut: |c| &mut c.w_goal_visibility,
        value: |t| t.goal_visibility,
    },
    Term {
        name: "danger",
        alias: None,
        weight: |c| c.w_danger,
        weight_mut: |c| &mut c.w_danger,
        value: |t| t.danger,
    },
    Term {
        name: "critical",
        alias: None,
        weight: |c| c.w_critical,
        weight_mut: |c| &mut c.w_critical,
        value: |t| t.critical,
    },
    Term {
        name: "sheltered",
        alias: None,
        weight: |c| c.w_sheltered,
        weight_mut: |c| &mut c.w_sheltered,
        value: |t| t.sheltered,
    },
    Term {
        name: "passing_time",
        alias: None,
        weight: |c| c.w_passing_time,
        weight_mut: |c| &mut c.w_passing_time,
        value: |t| t.passing_time,
    },
];

/// What a parameter must satisfy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// Finite and `> 0`.
    Positive,
    /// Finite and `>= 0` (a negative `dm` marked colliding classes safe).
    NonNegative,
}

/// One real parameter of the cost that [`CostConfig::set`] can change.
pub struct Parameter {
    /// Name for `--weight NAME=VALUE` and [`CostConfig::set`].
    pub name: &'static str,
    /// What it must satisfy.
    pub rule: Rule,
    /// Its value in a configuration.
    pub get: fn(&CostConfig) -> Real,
    get_mut: fn(&mut CostConfig) -> &mut Real,
}

/// Every settable parameter.
pub const PARAMETERS: [Parameter; 6] = [
    Parameter {
        name: "alpha",
        rule: Rule::Positive,
        get: |c| c.alpha,
        get_mut: |c| &mut c.alpha,
    },
    Parameter {
        name: "dm",
        rule: Rule::NonNegative,
        get: |c| c.dm,
        get_mut: |c| &mut c.dm,
    },
    Parameter {
        name: "omega",
        rule: Rule::Positive,
        get: |c| c.omega,
        get_mut: |c| &mut c.omega,
    },
    Parameter {
        name: "d_max",
        rule: Rule::Positive,
        get: |c| c.d_max,
        get_mut: |c| &mut c.d_max,
    },
    Parameter {
        name: "v_max",
        rule: Rule::Positive,
        get: |c| c.v_max,
        get_mut: |c| &mut c.v_max,
    },
    Parameter {
        name: "lateral_accel",
        rule: Rule::Positive,
        get: |c| c.lateral_accel,
        get_mut: |c| &mut c.lateral_accel,
    },
];

/// Why a cost configuration is unusable.
#[derive(Debug, Error, PartialEq)]
pub enum CostConfigError {
    /// No weight or parameter has this name.
    #[error("unknown weight or parameter '{0}' (weights: {weights}; parameters: {params})", weights = term_names(), params = parameter_names())]
    Unknown(String),
    /// A weight is negative, NaN or infinite.
    #[error("weight {0} must be finite and >= 0, got {1}")]
    Weight(&'static str, Real),
    /// A parameter is out of its range.
    #[error("parameter {0} {1}, got {2}")]
    Parameter(&'static str, &'static str, Real),
}

/// The weights' names, comma-separated.
pub fn term_names() -> String {
    TERMS.iter().map(|t| t.name).collect::<Vec<_>>().join(", ")
}

/// The settable parameters' names, comma-separated.
pub fn parameter_names() -> String {
    PARAMETERS
        .iter()
        .map(|p| p.name)
        .collect::<Vec<_>>()
        .join(", ")
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
            roughness: RoughnessForm::Paper,
            alpha: 0.5,
            dm: 3.0,
            omega: 20.0,
            d_max: 10.0,
            v_max: 1.0,
            lateral_accel: 0.5,
            nodes: 5,
            pieces: 2,
            tolerance: 1e-6,
            danger_points: Vec::new(),
            critical_points: Vec::new(),
            hazards: Vec::new(),
            clearance_search: ClearanceSearch::WorstNode,
            safety_along: false,
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

    /// Sets a weight by its name in [`TERMS`] (or the paper's `g1` .. `g4`) or a parameter
    /// of [`PARAMETERS`]; validated, and on error the old value stays.
    pub fn set(&mut self, name: &str, value: Real) -> Result<(), CostConfigError> {
        let slot = self
            .slot(name)
            .ok_or_else(|| CostConfigError::Unknown(name.to_string()))?;
        let old = std::mem::replace(slot, value);
        self.validate().inspect_err(|_| {
            if let Some(slot) = self.slot(name) {
                *slot = old;
            }
        })
    }

    /// The weight or parameter called `name`.
    fn slot(&mut self, name: &str) -> Option<&mut Real> {
        if let Some(t) = TERMS
            .iter()
            .find(|t| t.name == name || t.alias == Some(name))
        {
            return Some((t.weight_mut)(self));
        }
        PARAMETERS
            .iter()
            .find(|p| p.name == name)
            .map(|p| (p.get_mut)(self))
    }

    /// Checks every weight and parameter.
    pub fn validate(&self) -> Result<(), CostConfigError> {
        for t in &TERMS {
            let w = (t.weight)(self);
            if !(w.is_finite() && w >= 0.0) {
                return Err(CostConfigError::Weight(t.name, w));
            }
        }
        for p in &PARAMETERS {
            let v = (p.get)(self);
            match p.rule {
                Rule::Positive if !(v.is_finite() && v > 0.0) => {
                    return Err(CostConfigError::Parameter(
                        p.name,
                        "must be finite and > 0",
                        v,
                    ));
                }
                Rule::NonNegative if !(v.is_finite() && v >= 0.0) => {
                    return Err(CostConfigError::Parameter(
                        p.name,
                        "must be finite and >= 0",
                        v,
                    ));
                }
                _ => {}
            }
        }
        if !(0.0..=1e-3).contains(&self.tolerance) {
            return Err(CostConfigError::Parameter(
                "tolerance",
                "must be in [0, 1e-3]",
                self.tolerance,
            ));
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

    /// The weighted sum of `t`, term by term in the order of [`TERMS`].
    pub fn total(&self, t: &CostTerms) -> Real {
        let sum = TERMS
            .iter()
            .fold(0.0, |acc, term| acc + (term.weight)(self) * (term.value)(t));
        if !sum.is_nan() {
            return sum;
        }
        // A term of weight 0 does not count, even where it is unbounded: with no obstacle
        // the maximal-clearance excess is infinite, and 0 * inf made the total NaN. (Summed
        // again only then: a test per term in every evaluation cost 230 instructions.)
        TERMS
            .iter()
            .fold(0.0, |acc, term| match (term.weight)(self) {
                0.0 => acc,
                w => acc + w * (term.value)(t),
            })
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

/// The cost of `spline` against `model`: every term, weighted or not.
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

/// The cost and its gradient with respect to the inner via-points (`points[1..n-1]`).
///
/// Analytic for uniform parameters (the spline is then linear in its points), in `O(n)` by
/// reverse mode through the spline ([`Spline::pull_back`]); with
/// chord-length parameters the knots move with the points, and with a start heading the
/// start slope does, so there the gradient is taken by central differences (step `1e-6`
/// times the scene scale).
pub fn gradient(
    spline: &Spline,
    model: &dyn ClearanceModel,
    cfg: &CostConfig,
) -> (CostTerms, Vec<Vector>) {
    let n = spline.points().len();
    if spline.parametrization() == Parametrization::ChordLength
        || matches!(spline.end_condition(), EndCondition::StartHeading { .. })
    {
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
    let terms = run(spline, model, cfg, Some(&mut partials), false);
    // dC/d(a, b, c, d) per segment, then reverse mode through the spline (O(n), exact).
    let mut coef = vec![[Vector::zeros(); 4]; spline.segments()];
    for p in &partials {
        let (s, s2) = (p.s, p.s * p.s);
        let c = &mut coef[p.seg];
        c[0] += p.gq;
        c[1] += p.gq * s + p.gv;
        c[2] += p.gq * s2 + p.gv * (2.0 * s) + p.ga * 2.0;
        c[3] += p.gq * (s2 * s) + p.gv * (3.0 * s2) + p.ga * (6.0 * s);
    }
    let mut g = spline.pull_back(&coef);
    g.pop();
    g.remove(0);
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

/// One quadrature node of the curve.
#[derive(Clone, Copy)]
struct Node {
    /// Spline segment.
    seg: usize,
    /// Parameter within the segment.
    s: Real,
    /// Quadrature weight times the piece's parameter length (`dt`).
    dt: Real,
    /// `q'`.
    v: Vector,
    /// `q''`.
    a: Vector,
    /// `|q'|`.
    speed: Real,
}

/// The curve at its quadrature nodes, with its length.
#[derive(Default)]
struct Samples {
    points: Vec<Point>,
    nodes: Vec<Node>,
    length: Real,
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

/// Step 1: every quadrature node of the curve, and its length, into `out`.
fn sample(spline: &Spline, cfg: &CostConfig, out: &mut Samples) {
    let (gx, gw) = gauss_legendre_cached(cfg.nodes.clamp(2, 64));
    let pieces = cfg.pieces.max(1);
    let knots = spline.knots();
    out.points.clear();
    out.nodes.clear();
    // Summed in a local, in the same order (the same bits), then stored.
    let mut length = 0.0;
    for seg in 0..spline.segments() {
        let h = (knots[seg + 1] - knots[seg]) / pieces as Real;
        for piece in 0..pieces {
            let base = h * piece as Real;
            for (&x, &w) in gx.iter().zip(gw.iter()) {
                let s = base + h * x;
                let (p, v, a) = spline.eval_segment(seg, s);
                let speed = v.norm();
                let dt = w * h;
                length += dt * speed;
                out.points.push(p);
                out.nodes.push(Node {
                    seg,
                    s,
                    dt,
                    v,
                    a,
                    speed,
                });
            }
        }
    }
    out.length = length;
}

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
fn field_and_integrals(
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

/// The node of least clearance.
#[derive(Clone, Copy)]
struct Worst {
    clearance: Real,
    index: usize,
}

/// What [`run`] must compute beyond what the weights need.
#[derive(Clone, Copy)]
struct Needs {
    /// Every term's value (a report needs them all; an optimiser only what it weighs). The
    /// field and `m(C)` are always computed: the optimiser's guard rejects candidates by
    /// `m(C)`, whatever the weights.
    all: bool,
    line_of_sight: bool,
}

impl Needs {
    fn of(cfg: &CostConfig, all: bool) -> Self {
        Self {
            all,
            line_of_sight: cfg.w_start_visibility > 0.0
                || cfg.w_goal_visibility > 0.0
                || (cfg.w_sheltered > 0.0 && !cfg.hazards.is_empty()),
        }
    }
}

/// Which point terms [`integrate`] computes.
struct Weighs {
    danger: bool,
    critical: bool,
}

/// Step 3: the integrals over the nodes `range` (topology, maximal clearance, danger,
/// critical, passing time) added to `t` and, with `GRAD`, each node's partial derivatives;
/// returns the node of least clearance among `worst` (the nodes before) and these. The loop
/// is compiled twice, with and without the partials, so that a value alone does not pay for
/// them.
#[allow(clippy::too_many_arguments)]
fn integrate_nodes<const GRAD: bool>(
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

/// Step 4: `m(C)`, the worst node's clearance refined by Brent's method between its
/// neighbours (where a local minimum next to the smallest sample lies), in global `t` so that
/// a minimum across a knot is found too; then, where the model bounds how sharply the
/// clearance bends ([`ClearanceModel::bend_radius`]), every stretch between two nodes whose
/// bound ([`least_on`]) lets it dip below the least value found so far is halved, the
/// lowest bound first. Returns `(t, m)`.
fn refine_min_clearance(
    spline: &Spline,
    model: &dyn ClearanceModel,
    samples: &Samples,
    field: &[FieldSample],
    worst: Worst,
    knot_clear: &[(Real, Real)],
    search: ClearanceSearch,
) -> (Real, Real) {
    let knots = spline.knots();
    let t_of = |i: usize| knots[samples.nodes[i].seg] + samples.nodes[i].s;
    let n = samples.nodes.len();
    let idx = worst.index;
    let t0 = t_of(idx);
    let ta = if idx > 0 { t_of(idx - 1) } else { 0.0 };
    let tz = if idx + 1 < n { t_of(idx + 1) } else { 1.0 };
    let (tb, fb) = refine_bracket(spline, model, (ta, tz), (t0, worst.clearance));
    // `m(C)` is the least clearance over all of `[0, 1]`: the knots are taken in (all of
    // them where the safety term weighs and the model truncates, else the ends). The
    // quadrature nodes do not reach the ends, and a curve that leaves a start next to a wall
    // quickly (a long curve, its parameter spread thin) put its first node farther from the
    // wall than a short curve's: `D` favoured long detours from such a start. The ends are
    // fixed, so where one of them is the least clear, `D` is the same for every curve. With
    // the knots in, `m(C)` is at most the least knot clearance, which the truncation's
    // allowance counts on.
    let mut best = knot_clear
        .iter()
        .copied()
        .fold((tb, fb), |best, e| if e.1 < best.1 { e } else { best });
    let Some(radius) = model
        .bend_radius()
        .filter(|_| search == ClearanceSearch::EveryStretch)
    else {
        return best;
    };
    // Every stretch between consecutive nodes, the worst node's two included (a second dip
    // there escapes Brent's method, which follows one valley), and from the start to the
    // first node and from the last node to the goal, whose clearances are known.
    let last = spline.segments() - 1;
    let end = |t: Real| {
        let (seg, s) = if t == 0.0 {
            (0, 0.0)
        } else {
            (last, knots[last + 1] - knots[last])
        };
        let (p, v, a) = spline.eval_segment(seg, s);
        let c = knot_clear
            .iter()
            .find(|k| k.0 == t)
            .map_or_else(|| model.clearance_value(&p), |k| k.1);
        Probe::new(t, c, seg, v, a)
    };
    let node = |i: usize| {
        let nd = &samples.nodes[i];
        Probe {
            t: t_of(i),
            clearance: field[i].clearance,
            seg: nd.seg,
            speed: nd.speed,
            accel: nd.a.norm(),
        }
    };
    // Best first: the stretch whose bound lets it fall lowest is halved first, so that the
    // least clearance is found early and the other stretches are dropped by it.
    let mut heap = std::collections::BinaryHeap::new();
    let push =
        |heap: &mut std::collections::BinaryHeap<Stretch>, a: Probe, b: Probe, best: Real| {
            let bound = least_on(spline, radius, &a, &b);
            if bound < best - STRETCH_TOLERANCE {
                heap.push(Stretch { bound, a, b });
            }
        };
    for i in 0..=n {
        let (a, b) = match (i.checked_sub(1), i < n) {
            (None, true) => (end(0.0), node(0)),
            (Some(j), true) => (node(j), node(i)),
            (Some(j), false) => (node(j), end(1.0)),
            (None, false) => continue,
        };
        push(&mut heap, a, b, best.1);
    }
    // A cap on the probes, for curves through a disc's centre (there only the Lipschitz
    // bound holds): the search then stops with the least value so far.
    let mut probes_left = STRETCH_PROBES * (n + 1);
    while let Some(Stretch { bound, a, b }) = heap.pop() {
        if bound >= best.1 - STRETCH_TOLERANCE || probes_left == 0 {
            break;
        }
        probes_left -= 1;
        let tm = 0.5 * (a.t + b.t);
        if tm <= a.t || tm >= b.t {
            continue;
        }
        let (seg, s) = spline.locate(tm);
        let (p, v, acc) = spline.eval_segment(seg, s);
        let m = Probe::new(tm, model.clearance_value(&p), seg, v, acc);
        if m.clearance < best.1 {
            best = (m.t, m.clearance);
        }
        push(&mut heap, a, m, best.1);
        push(&mut heap, m, b, best.1);
    }
    best
}

/// A stretch of the curve between two probes, and the least its clearance can be there
/// ([`least_on`]); ordered so that a `BinaryHeap` gives the least bound first.
struct Stretch {
    bound: Real,
    a: Probe,
    b: Probe,
}

impl PartialEq for Stretch {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for Stretch {}

impl PartialOrd for Stretch {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Stretch {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        // The least bound first; ties by position, so that the order is the same every run.
        other
            .bound
            .total_cmp(&self.bound)
            .then(other.a.t.total_cmp(&self.a.t))
    }
}

/// A point of the curve for [`least_on`]: its `t`, clearance, segment, `|q'|` and `|q''|`.
#[derive(Clone, Copy)]
struct Probe {
    t: Real,
    clearance: Real,
    seg: usize,
    speed: Real,
    accel: Real,
}

impl Probe {
    fn new(t: Real, clearance: Real, seg: usize, v: Vector, a: Vector) -> Self {
        Self {
            t,
            clearance,
            seg,
            speed: v.norm(),
            accel: a.norm(),
        }
    }
}

/// How far below the least clearance of the curve [`ClearanceSearch::EveryStretch`] may
/// leave `m(C)`: a stretch is halved until its bound ([`least_on`]) keeps it within this of
/// the least value found.
const STRETCH_TOLERANCE: Real = 1e-5;

/// The most probes [`ClearanceSearch::EveryStretch`] takes per stretch, on average over the
/// curve's stretches (a collision-free curve takes a fraction of one).
const STRETCH_PROBES: usize = 64;

/// A lower bound of the clearance between two points of the curve, `a` and `b`. It moves
/// at most `|q'|` per unit of `t`, so it stays above the lesser end's value less `V dt / 2`,
/// `V` the largest `|q'|` on the stretch (at most an end's plus `A` times half the stretch,
/// `A` the largest `|q''|`: `q''` is linear on each segment, so that is at an end or a
/// knot). And the distance `rho` to a disc's centre has `rho'' <= V^2 / rho + A`; with
/// `rho` at least the first bound plus the least radius `r`
/// ([`ClearanceModel::bend_radius`]), where that is positive, each disc's clearance, and so
/// their least, stays above the chord between the ends less `M dt^2 / 8`, `M` that bound.
/// The larger of the two.
fn least_on(spline: &Spline, radius: Real, a: &Probe, b: &Probe) -> Real {
    let dt = b.t - a.t;
    let low = a.clearance.min(b.clearance);
    if dt <= 0.0 || !low.is_finite() {
        return low;
    }
    let mut accel = a.accel.max(b.accel);
    // The knots inside the stretch, where `q''` may be largest.
    for k in a.seg + 1..=b.seg {
        accel = accel.max(spline.eval_segment(k, 0.0).2.norm());
    }
    let speed = a.speed.max(b.speed) + 0.5 * accel * dt;
    let lipschitz = low - 0.5 * speed * dt;
    let floor = lipschitz + radius;
    if floor <= 0.0 {
        return lipschitz;
    }
    let bend = speed * speed / floor + accel;
    lipschitz.max(low - 0.125 * bend * dt * dt)
}

/// Brent's search of `[ta, tz]` from `(t0, d0)`, `d0` the clearance at `t0`, with the model
/// restricted to the circles that can come nearer than `d0` there; the ends of the bracket
/// are taken in exactly. Returns `(t, m)` with `m <= d0`.
fn refine_bracket(
    spline: &Spline,
    model: &dyn ClearanceModel,
    (ta, tz): (Real, Real),
    (t0, d0): (Real, Real),
) -> (Real, Real) {
    let knots = spline.knots();
    // The bracket's stretch of curve lies in the box of its Bezier control points (per
    // segment it touches); only circles that can come nearer than `d0` there matter.
    let (sa, sz) = (spline.locate(ta).0, spline.locate(tz).0);
    let (mut lo, mut hi) = (spline.position(ta), spline.position(ta));
    for k in sa..=sz {
        let s0 = (ta - knots[k]).max(0.0);
        let s1 = (tz - knots[k]).min(knots[k + 1] - knots[k]);
        let ((p0, v0, _), (p3, v3, _)) = (spline.eval_segment(k, s0), spline.eval_segment(k, s1));
        let third = (s1 - s0) / 3.0;
        for p in [p0, p0 + v0 * third, p3 - v3 * third, p3] {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    }
    let local = model.restricted(&lo, &hi, d0);
    let near: &dyn ClearanceModel = local.as_deref().unwrap_or(model);
    let f = |t: Real| near.clearance_value(&spline.position(t));
    let (tb, fb) = brent_min(f, (ta, tz), (t0, d0), 1e-10);
    // Brent searches the open bracket; a minimum at one of its ends (the start or the goal
    // inside an obstacle's reach) is taken there exactly.
    let (tb, fb) = [(ta, f(ta)), (tz, f(tz))]
        .into_iter()
        .fold((tb, fb), |best, e| if e.1 < best.1 { e } else { best });
    if fb < d0 { (tb, fb) } else { (t0, d0) }
}

/// Each knot's parameter and clearance, into `out` (`d` is a buffer).
fn knot_clearances(
    spline: &Spline,
    model: &dyn ClearanceModel,
    d: &mut Vec<Real>,
    out: &mut Vec<(Real, Real)>,
) {
    d.clear();
    d.resize(spline.points().len(), 0.0);
    model.clearances(spline.points(), d);
    out.clear();
    out.extend(spline.knots().iter().copied().zip(d.iter().copied()));
}

/// Step 5: the line-of-sight shares (start and goal visibility, shelter from hazards).
fn line_of_sight_shares(
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

/// The terms of the cost (every one with `all`, else those weighed), and with `grad` the
/// partial derivatives of the weighted total at each node (the safety term's at the point of
/// least clearance).
fn run(
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

/// [`run`] on the buffers of `scratch`.
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
        // Roughness depends on q'' at the knots only.
        let knots = spline.knots();
        let last = spline.segments() - 1;
        for (i, d) in rough.knot_partials.iter().enumerate() {
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
    // Every knot's clearance where the safety term weighs and the model truncates (the
    // allowance counts on them); else only the ends', which `m(C)` always takes in.
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
    let least_knot = knots.iter().map(|k| k.1).fold(Real::INFINITY, Real::min);
    // The stops below bound `D` by `m(C)`, which holds for (7) only.
    let enough = enough.filter(|_| !cfg.safety_along);
    // First stop: roughness, length and the knots' clearances (`m(C)` is at most theirs).
    if let Some(enough) = enough
        && let Some(low) = bounding_terms(&t, least_knot, cfg)
        && enough(&low)
    {
        return Err(low);
    }
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
    if let Some(enough) = enough
        && let Some(w) = worst
        && let Some(low) = bounding_terms(&t, w.clearance.min(least_knot), cfg)
        && enough(&low)
    {
        return Err(low);
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
            t.safety = cfg.omega.powf(cfg.dm - m);
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
    }
    if needs.line_of_sight {
        line_of_sight_shares(spline, model, samples, cfg, &mut t);
    }
    t.total = cfg.total(&t);
    Ok(t)
}

/// [`CostConfig::safety_along`]: `D = I / scale`, `I = integral omega^(dm - d(q)) dl` over
/// the quadrature nodes, into `t.safety`, and with `grad` each node's partials:
/// `dD/dq = -ln(omega) e |q'| dt grad d / scale` and `dD/dq' = e dt q' / (|q'| scale)`, where
/// `e = omega^(dm - d)`.
fn safety_along(
    samples: &Samples,
    field: &[FieldSample],
    cfg: &CostConfig,
    scale: Real,
    t: &mut CostTerms,
    grad: Option<&mut Vec<NodePartial>>,
) {
    let e = |d: Real| cfg.omega.powf(cfg.dm - d);
    let integral: Real = samples
        .nodes
        .iter()
        .zip(field)
        .map(|(n, f)| e(f.clearance) * n.speed * n.dt)
        .sum();
    t.safety = integral / scale;
    let Some(g) = grad else { return };
    let ln_omega = cfg.omega.ln();
    for (n, f) in samples.nodes.iter().zip(field) {
        let ei = e(f.clearance);
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

/// Terms bounding those of the finished evaluation from the terms `t` computed so far and
/// an upper bound `m_up` of `m(C)`: `min_clearance = m_up`, safety `omega^(dm - m_up)` (with
/// `omega >= 1` the power falls as `m` rises; else 0), the line-of-sight shares 0 (they come
/// last), the other terms as they are, and the total of these. Every term and weight is
/// `>= 0` and the total is their sum in a fixed order, so lowering some terms lowers it
/// (rounding is monotone); the margin of `1e-9` on safety and the total covers the power's
/// last bit. `None` when a weight is negative (`validate` refuses that; a configuration
/// built by hand may have it) or the total is not finite.
fn bounding_terms(t: &CostTerms, m_up: Real, cfg: &CostConfig) -> Option<CostTerms> {
    if !TERMS.iter().all(|term| (term.weight)(cfg) >= 0.0) {
        return None;
    }
    const MARGIN: Real = 1.0 - 1e-9;
    let safety = if cfg.omega >= 1.0 && m_up.is_finite() {
        cfg.omega.powf(cfg.dm - m_up) * MARGIN
    } else {
        0.0
    };
    let mut low = CostTerms {
        min_clearance: m_up,
        safety,
        start_visibility: 0.0,
        goal_visibility: 0.0,
        sheltered: 0.0,
        ..*t
    };
    low.total = cfg.total(&low) * MARGIN;
    low.total.is_finite().then_some(low)
}

#[cfg(test)]
mod tests {
    use super::*;

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
