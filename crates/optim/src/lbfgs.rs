//! Limited-memory BFGS with a backtracking (Armijo) line search, for the analytic gradient
//! of the spline cost. A value of `+inf` (a step that leaves the homotopy class) makes the
//! line search back off.

use homospline_geom::Real;

use crate::solver::{self, SettingError, Solver, SolverState, Termination};

/// Limited-memory BFGS with validated settings.
///
/// # Examples
///
/// ```
/// use homospline_optim::Lbfgs;
/// use homospline_optim::solver::Termination;
///
/// let lbfgs = Lbfgs::default()
///     .with_gradient_tolerance(1e-10)
///     .unwrap()
///     .with_value_tolerance(0.0)
///     .unwrap()
///     .with_max_evaluations(2_000)
///     .unwrap();
/// // Rosenbrock's valley in two dimensions, from (-1.2, 1).
/// let mut f = |x: &[f64]| {
///     let (a, b) = (1.0 - x[0], x[1] - x[0] * x[0]);
///     (a * a + 100.0 * b * b, vec![-2.0 * a - 400.0 * x[0] * b, 200.0 * b])
/// };
/// let out = lbfgs.minimize(&mut f, &[-1.2, 1.0]);
/// assert!(out.value < 1e-12, "{out:?}");
/// assert_eq!(out.termination, Termination::GradientTolerance);
/// assert!(Lbfgs::default().with_memory(0).is_err());
/// ```
///
/// # See also
/// [`crate::solver::run`] to drive it one iteration at a time with an observer,
/// [`crate::NelderMead`], the paper's derivative-free method.
#[derive(Clone, Debug, PartialEq)]
pub struct Lbfgs {
    memory: usize,
    gradient_tolerance: Real,
    value_tolerance: Real,
    max_evaluations: usize,
}

impl Default for Lbfgs {
    /// History 6, gradient tolerance 1e-8, value tolerance 1e-10, 500 evaluations.
    fn default() -> Self {
        Self {
            memory: 6,
            gradient_tolerance: 1e-8,
            value_tolerance: 1e-10,
            max_evaluations: 500,
        }
    }
}

impl Lbfgs {
    /// Sets how many past steps shape the search direction (at least 1).
    pub fn with_memory(mut self, memory: usize) -> Result<Self, SettingError> {
        if memory == 0 {
            return Err(SettingError("L-BFGS memory must be at least 1".into()));
        }
        self.memory = memory;
        Ok(self)
    }

    /// Sets the gradient tolerance: stop when the gradient's largest entry is at or below
    /// it (finite, >= 0).
    pub fn with_gradient_tolerance(mut self, tolerance: Real) -> Result<Self, SettingError> {
        self.gradient_tolerance = check_tolerance("gradient", tolerance)?;
        Ok(self)
    }

    /// Sets the value tolerance: stop when an iteration improves the value by at most this,
    /// relatively (finite, >= 0).
    pub fn with_value_tolerance(mut self, tolerance: Real) -> Result<Self, SettingError> {
        self.value_tolerance = check_tolerance("value", tolerance)?;
        Ok(self)
    }

    /// Sets the evaluation budget (value and gradient together count one; at least 1).
    pub fn with_max_evaluations(mut self, n: usize) -> Result<Self, SettingError> {
        if n == 0 {
            return Err(SettingError("the L-BFGS budget must be at least 1".into()));
        }
        self.max_evaluations = n;
        Ok(self)
    }
}

/// Result of [`Lbfgs::minimize`].
#[derive(Clone, Debug, PartialEq)]
pub struct LbfgsOutcome {
    /// Best point.
    pub x: Vec<Real>,
    /// Its value.
    pub value: Real,
    /// Why it stopped.
    pub termination: Termination,
    /// Evaluations.
    pub evaluations: usize,
    /// Iterations.
    pub iterations: usize,
}

/// An objective returning its value and gradient.
pub type ValueAndGradient<'a> = dyn FnMut(&[Real]) -> (Real, Vec<Real>) + 'a;

/// The L-BFGS state: the current point, its value and gradient, and the step history.
#[derive(Clone, Debug, PartialEq)]
pub struct LbfgsState {
    /// The current (best) point.
    pub x: Vec<Real>,
    /// Its value.
    pub value: Real,
    /// Its gradient.
    pub gradient: Vec<Real>,
    /// Evaluations so far.
    pub evaluations: usize,
    /// Iterations so far.
    pub iterations: usize,
    s_history: Vec<Vec<Real>>,
    y_history: Vec<Vec<Real>>,
    stopped: Option<Termination>,
}

impl SolverState for LbfgsState {
    fn best(&self) -> (&[Real], Real) {
        (&self.x, self.value)
    }

    fn evaluations(&self) -> usize {
        self.evaluations
    }

    fn iterations(&self) -> usize {
        self.iterations
    }
}

fn check_tolerance(name: &str, tolerance: Real) -> Result<Real, SettingError> {
    if tolerance.is_finite() && tolerance >= 0.0 {
        Ok(tolerance)
    } else {
        Err(SettingError(format!(
            "the L-BFGS {name} tolerance must be finite and >= 0, got {tolerance}"
        )))
    }
}

fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Lbfgs {
    /// Minimises `f`, which returns the value and the gradient, from `x0`.
    pub fn minimize(&self, f: &mut ValueAndGradient<'_>, x0: &[Real]) -> LbfgsOutcome {
        let (s, termination) = solver::run(self, f, x0, &mut ());
        LbfgsOutcome {
            x: s.x,
            value: s.value,
            termination,
            evaluations: s.evaluations,
            iterations: s.iterations,
        }
    }

    /// The direction `-H g` by the two-loop recursion over the history, or the unit
    /// steepest descent when the history is empty or gives no descent (which clears it).
    fn direction(&self, s: &mut LbfgsState) -> (Vec<Real>, Real) {
        let g = &s.gradient;
        let mut q = g.clone();
        let k = s.s_history.len();
        let mut alpha = vec![0.0; k];
        for i in (0..k).rev() {
            let (si, yi) = (&s.s_history[i], &s.y_history[i]);
            let rho = 1.0 / dot(yi, si);
            alpha[i] = rho * dot(si, &q);
            for (qj, yj) in q.iter_mut().zip(yi) {
                *qj -= alpha[i] * yj;
            }
        }
        if k > 0 {
            let gamma = dot(&s.s_history[k - 1], &s.y_history[k - 1])
                / dot(&s.y_history[k - 1], &s.y_history[k - 1]);
            q.iter_mut().for_each(|v| *v *= gamma);
        } else {
            // First step: a unit-length move along the steepest descent.
            let norm = dot(g, g).sqrt().max(1e-300);
            q.iter_mut().for_each(|v| *v /= norm);
        }
        for ((si, yi), ai) in s.s_history.iter().zip(&s.y_history).zip(&alpha) {
            let rho = 1.0 / dot(yi, si);
            let beta = rho * dot(yi, &q);
            for (qj, sj) in q.iter_mut().zip(si) {
                *qj += sj * (ai - beta);
            }
        }
        let mut d: Vec<Real> = q.iter().map(|v| -v).collect();
        let mut slope = dot(g, &d);
        if slope >= 0.0 {
            // Not a descent direction: restart from steepest descent.
            s.s_history.clear();
            s.y_history.clear();
            let norm = dot(g, g).sqrt().max(1e-300);
            d = g.iter().map(|v| -v / norm).collect();
            slope = dot(g, &d);
        }
        (d, slope)
    }
}

impl Solver for Lbfgs {
    type Objective<'a> = ValueAndGradient<'a>;
    type State = LbfgsState;

    fn init(&self, f: &mut ValueAndGradient<'_>, x0: &[Real]) -> LbfgsState {
        let x = x0.to_vec();
        let (value, gradient) = f(&x);
        LbfgsState {
            x,
            value,
            gradient,
            evaluations: 1,
            iterations: 0,
            s_history: Vec::new(),
            y_history: Vec::new(),
            stopped: None,
        }
    }

    /// One iteration: a search direction, a backtracking (Armijo, c = 1e-4) line search
    /// along it, and the history updated with the step when its curvature is positive.
    fn step(&self, f: &mut ValueAndGradient<'_>, s: &mut LbfgsState) {
        let (d, slope) = self.direction(s);
        let mut t = 1.0;
        let mut accepted = None;
        while s.evaluations < self.max_evaluations && t > 1e-12 {
            let xn: Vec<Real> = s.x.iter().zip(&d).map(|(a, b)| a + t * b).collect();
            let (fn_, gn) = f(&xn);
            s.evaluations += 1;
            if fn_.is_finite() && fn_ <= s.value + 1e-4 * t * slope {
                accepted = Some((xn, fn_, gn));
                break;
            }
            t *= 0.5;
        }
        let Some((xn, fnew, gn)) = accepted else {
            s.stopped = Some(if s.evaluations >= self.max_evaluations {
                Termination::MaxEvaluations
            } else {
                Termination::LineSearchFailed
            });
            return;
        };
        s.iterations += 1;
        let step: Vec<Real> = xn.iter().zip(&s.x).map(|(a, b)| a - b).collect();
        let change: Vec<Real> = gn.iter().zip(&s.gradient).map(|(a, b)| a - b).collect();
        let old = s.value;
        let improvement = old - fnew;
        s.x = xn;
        s.gradient = gn;
        s.value = fnew;
        if dot(&step, &change) > 1e-12 {
            s.s_history.push(step);
            s.y_history.push(change);
            if s.s_history.len() > self.memory {
                s.s_history.remove(0);
                s.y_history.remove(0);
            }
        }
        if improvement <= self.value_tolerance * (1.0 + old.abs()) {
            s.stopped = Some(Termination::ValueTolerance);
        }
    }

    fn terminate(&self, s: &LbfgsState) -> Option<Termination> {
        if let Some(why) = s.stopped {
            return Some(why);
        }
        if !s.value.is_finite() {
            return Some(Termination::NonFiniteStart);
        }
        if s.evaluations >= self.max_evaluations {
            return Some(Termination::MaxEvaluations);
        }
        let largest = s.gradient.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
        (largest <= self.gradient_tolerance).then_some(Termination::GradientTolerance)
    }
}
