//! The terms of the cost: [`TERMS`] (names, weights, values) and [`PARAMETERS`], which drive
//! setting a weight or parameter by name, validation and the weighted total; [`CostTerms`],
//! the values of one evaluation; and the terms that bound an unfinished evaluation's.

use homospline_geom::Real;
use homospline_geom::math::Num;
use thiserror::Error;

use super::config::CostConfig;

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
    #[error("weight {0} must be finite and >= 0, got {value}", value = Num(*.1))]
    Weight(&'static str, Real),
    /// A parameter is out of its range.
    #[error("parameter {0} {1}, got {value}", value = Num(*.2))]
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

impl CostConfig {
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

/// Terms bounding those of the finished evaluation from the terms `t` computed so far and
/// an upper bound `m_up` of `m(C)`: `min_clearance = m_up`, safety `omega^(dm - m_up)` (with
/// `omega >= 1` the power falls as `m` rises; else 0), the line-of-sight shares 0 (they come
/// last), the other terms as they are, and the total of these. Every term and weight is
/// `>= 0` and the total is their sum in a fixed order, so lowering some terms lowers it
/// (rounding is monotone); the margin of `1e-9` on safety and the total covers the power's
/// last bit. `None` when a weight is negative (`validate` refuses that; a configuration
/// built by hand may have it) or the total is not finite.
pub(super) fn bounding_terms(t: &CostTerms, m_up: Real, cfg: &CostConfig) -> Option<CostTerms> {
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
