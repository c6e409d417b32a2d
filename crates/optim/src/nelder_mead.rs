//! The Nelder-Mead simplex method, shaped like an argmin solver: `init`, `step`,
//! `terminate`, a termination reason, validating setters and an observer.

use homospline_geom::Real;

pub use crate::solver::{Observer, SettingError, Termination};
use crate::solver::{Solver, SolverState};

/// Reflection, expansion, contraction and shrink coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients {
    /// Reflection `alpha`.
    pub reflection: Real,
    /// Expansion `gamma`.
    pub expansion: Real,
    /// Contraction `rho`.
    pub contraction: Real,
    /// Shrink `sigma`.
    pub shrink: Real,
}

impl Coefficients {
    /// The standard values (1, 2, 1/2, 1/2).
    pub fn standard() -> Self {
        Self {
            reflection: 1.0,
            expansion: 2.0,
            contraction: 0.5,
            shrink: 0.5,
        }
    }

    /// Gao and Han's (2012) dimension-adaptive values: `1, 1 + 2/n, 3/4 - 1/(2n), 1 - 1/n`.
    pub fn adaptive(n: usize) -> Self {
        let n = n.max(1) as Real;
        Self {
            reflection: 1.0,
            expansion: 1.0 + 2.0 / n,
            contraction: 0.75 - 1.0 / (2.0 * n),
            shrink: if n > 1.0 { 1.0 - 1.0 / n } else { 0.5 },
        }
    }
}

/// The solver's state.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Vertices, sorted best first after each step.
    pub simplex: Vec<Vec<Real>>,
    /// Their values.
    pub values: Vec<Real>,
    /// Evaluations so far.
    pub evaluations: usize,
    /// Iterations so far.
    pub iterations: usize,
}

impl SolverState for State {
    fn best(&self) -> (&[Real], Real) {
        (&self.simplex[0], self.values[0])
    }

    fn evaluations(&self) -> usize {
        self.evaluations
    }

    fn iterations(&self) -> usize {
        self.iterations
    }
}

/// The result of [`NelderMead::minimize`].
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The best point.
    pub x: Vec<Real>,
    /// Its value.
    pub value: Real,
    /// Why it stopped (the last run's reason).
    pub termination: Termination,
    /// Evaluations, all runs.
    pub evaluations: usize,
    /// Iterations, all runs.
    pub iterations: usize,
    /// Restarts done.
    pub restarts: usize,
}

/// An objective that is told, with each point, the value from which on every value is as
/// good as any other to the solver (`+inf`: the value itself is needed). Below that bound it
/// must return the exact value; at or above it, the exact value or any value at or above
/// the bound. A costly objective can stop early once a lower bound of its value reaches the
/// bound: the solver's path is the same as with the exact values.
pub type BoundedObjective<'a> = dyn FnMut(&[Real], Real) -> Real + 'a;

/// Nelder-Mead with validated settings.
#[derive(Clone, Debug, PartialEq)]
pub struct NelderMead {
    coefficients: Coefficients,
    initial_step: Vec<Real>,
    value_tolerance: Real,
    size_tolerance: Real,
    max_evaluations: usize,
    restarts: usize,
}

impl NelderMead {
    /// A solver for `n` dimensions with adaptive coefficients, unit initial steps, value
    /// tolerance 1e-10, size tolerance 1e-10, 10,000 evaluations and no restarts.
    pub fn new(n: usize) -> Self {
        Self {
            coefficients: Coefficients::adaptive(n),
            initial_step: vec![1.0; n],
            value_tolerance: 1e-10,
            size_tolerance: 1e-10,
            max_evaluations: 10_000,
            restarts: 0,
        }
    }

    /// Sets the coefficients: `reflection > 0`, `expansion > max(1, reflection)`,
    /// `0 < contraction < 1`, `0 < shrink < 1`.
    pub fn with_coefficients(mut self, c: Coefficients) -> Result<Self, SettingError> {
        let ok = c.reflection > 0.0
            && c.expansion > 1.0
            && c.expansion > c.reflection
            && c.contraction > 0.0
            && c.contraction < 1.0
            && c.shrink > 0.0
            && c.shrink < 1.0;
        if !ok {
            return Err(SettingError(format!(
                "invalid Nelder-Mead coefficients {c:?}"
            )));
        }
        self.coefficients = c;
        Ok(self)
    }

    /// Sets the initial simplex: vertex `i` is `x0 + step[i] e_i`; scale it to the problem.
    pub fn with_initial_step(mut self, step: Vec<Real>) -> Result<Self, SettingError> {
        if step.len() != self.initial_step.len()
            || step.iter().any(|s| !(s.is_finite() && *s != 0.0))
        {
            return Err(SettingError(format!(
                "initial step needs {} finite non-zero entries",
                self.initial_step.len()
            )));
        }
        self.initial_step = step;
        Ok(self)
    }

    /// Sets the value and simplex-size tolerances (both >= 0, finite).
    pub fn with_tolerances(mut self, value: Real, size: Real) -> Result<Self, SettingError> {
        if !(value.is_finite() && value >= 0.0 && size.is_finite() && size >= 0.0) {
            return Err(SettingError(format!(
                "tolerances must be finite and >= 0, got {value}, {size}"
            )));
        }
        self.value_tolerance = value;
        self.size_tolerance = size;
        Ok(self)
    }

    /// Sets the evaluation budget (> n + 1).
    pub fn with_max_evaluations(mut self, n: usize) -> Result<Self, SettingError> {
        if n <= self.initial_step.len() + 1 {
            return Err(SettingError(format!(
                "the budget must exceed n + 1 = {}",
                self.initial_step.len() + 1
            )));
        }
        self.max_evaluations = n;
        Ok(self)
    }

    /// Sets how many times to restart from the best point with a fresh simplex.
    pub fn with_restarts(mut self, n: usize) -> Self {
        self.restarts = n;
        self
    }

    /// Runs to termination, then restarts from the best point while restarts remain and the
    /// last run improved.
    pub fn minimize(
        &self,
        f: &mut dyn FnMut(&[Real]) -> Real,
        x0: &[Real],
        observer: &mut dyn Observer<State>,
    ) -> Outcome {
        self.minimize_bounded(&mut |x: &[Real], _| f(x), x0, observer)
    }

    /// [`NelderMead::minimize`] on a [`BoundedObjective`]: the same path and result as with
    /// the exact values.
    pub fn minimize_bounded(
        &self,
        f: &mut BoundedObjective<'_>,
        x0: &[Real],
        observer: &mut dyn Observer<State>,
    ) -> Outcome {
        let mut x = x0.to_vec();
        let (mut evaluations, mut iterations, mut restarts) = (0, 0, 0);
        let mut best = Real::INFINITY;
        loop {
            // `solver::run`'s loop, with the budget counted across the runs: a run stops by
            // its own test first, then when the runs together have spent the budget.
            let mut s = self.init(f, &x);
            observer.observe(&s);
            let reason = loop {
                if let Some(r) = self.terminate(&s) {
                    break r;
                }
                if evaluations + s.evaluations >= self.max_evaluations {
                    break Termination::MaxEvaluations;
                }
                self.step(f, &mut s);
                observer.observe(&s);
            };
            evaluations += s.evaluations;
            iterations += s.iterations;
            let (bx, bv) = s.best();
            let improved = bv < best - self.value_tolerance * (1.0 + bv.abs());
            if bv < best {
                best = bv;
                x = bx.to_vec();
            }
            if restarts >= self.restarts || !improved || reason == Termination::MaxEvaluations {
                return Outcome {
                    x,
                    value: best,
                    termination: reason,
                    evaluations,
                    iterations,
                    restarts,
                };
            }
            restarts += 1;
        }
    }
}

impl Solver for NelderMead {
    type Objective<'a> = BoundedObjective<'a>;
    type State = State;

    /// The initial simplex around `x0` (every value is needed exactly).
    fn init(&self, f: &mut BoundedObjective<'_>, x0: &[Real]) -> State {
        let n = x0.len();
        let mut simplex = vec![x0.to_vec()];
        for i in 0..n {
            let mut v = x0.to_vec();
            v[i] += self.initial_step[i];
            simplex.push(v);
        }
        let values: Vec<Real> = simplex
            .iter()
            .map(|x| sanitize(f(x, Real::INFINITY)))
            .collect();
        let mut s = State {
            simplex,
            values,
            evaluations: n + 1,
            iterations: 0,
        };
        sort(&mut s);
        s
    }

    /// One iteration: reflect, expand, contract or shrink. Each trial point's bound is the
    /// value it must beat to be taken: the worst vertex for the reflection and the inside
    /// contraction, the reflection for the expansion and the outside contraction; a shrink
    /// needs every value.
    fn step(&self, f: &mut BoundedObjective<'_>, s: &mut State) {
        let n = s.simplex.len() - 1;
        let c = &self.coefficients;
        let centroid: Vec<Real> = (0..n)
            .map(|j| s.simplex[..n].iter().map(|v| v[j]).sum::<Real>() / n as Real)
            .collect();
        let worst = s.simplex[n].clone();
        let along = |t: Real| -> Vec<Real> {
            (0..n)
                .map(|j| centroid[j] + t * (centroid[j] - worst[j]))
                .collect()
        };
        let xr = along(c.reflection);
        let fr = sanitize(f(&xr, s.values[n]));
        s.evaluations += 1;
        if fr < s.values[0] {
            let xe = along(c.reflection * c.expansion);
            let fe = sanitize(f(&xe, fr));
            s.evaluations += 1;
            if fe < fr {
                s.simplex[n] = xe;
                s.values[n] = fe;
            } else {
                s.simplex[n] = xr;
                s.values[n] = fr;
            }
        } else if fr < s.values[n - 1] {
            s.simplex[n] = xr;
            s.values[n] = fr;
        } else {
            // Outside contraction if the reflection beat the worst, inside otherwise; either
            // is taken only below both.
            let bar = s.values[n].min(fr);
            let (xc, fc) = if fr < s.values[n] {
                let x = along(c.reflection * c.contraction);
                let v = sanitize(f(&x, bar));
                (x, v)
            } else {
                let x = along(-c.contraction);
                let v = sanitize(f(&x, bar));
                (x, v)
            };
            s.evaluations += 1;
            if fc < bar {
                s.simplex[n] = xc;
                s.values[n] = fc;
            } else {
                let best = s.simplex[0].clone();
                for i in 1..=n {
                    for (v, b) in s.simplex[i].iter_mut().zip(&best) {
                        *v = b + c.shrink * (*v - b);
                    }
                    s.values[i] = sanitize(f(&s.simplex[i], Real::INFINITY));
                }
                s.evaluations += n;
            }
        }
        s.iterations += 1;
        sort(s);
    }

    /// Why to stop now, if at all.
    fn terminate(&self, s: &State) -> Option<Termination> {
        if s.evaluations >= self.max_evaluations {
            return Some(Termination::MaxEvaluations);
        }
        let (lo, hi) = (s.values[0], s.values[s.values.len() - 1]);
        if lo.is_finite() && hi.is_finite() && hi - lo <= self.value_tolerance * (1.0 + lo.abs()) {
            return Some(Termination::ValueTolerance);
        }
        let size = s.simplex[1..]
            .iter()
            .map(|v| {
                v.iter()
                    .zip(&s.simplex[0])
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, Real::max)
            })
            .fold(0.0, Real::max);
        (size <= self.size_tolerance).then_some(Termination::SimplexSize)
    }
}

/// NaN is worse than anything.
fn sanitize(v: Real) -> Real {
    if v.is_nan() { Real::INFINITY } else { v }
}

fn sort(s: &mut State) {
    // Stable insertion sort of the vertices by value, moving rows rather than cloning them:
    // ties keep their order, so runs are reproducible. After a reflection, expansion or
    // contraction only the last vertex is out of place, so this is one pass.
    for i in 1..s.values.len() {
        let mut j = i;
        while j > 0 && s.values[j - 1].total_cmp(&s.values[j]).is_gt() {
            s.values.swap(j - 1, j);
            s.simplex.swap(j - 1, j);
            j -= 1;
        }
    }
}
