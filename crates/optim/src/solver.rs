//! The solver seam that Nelder-Mead and L-BFGS share, in argmin's shape: `init`, `step`,
//! `terminate`, a termination reason and an observer of every iteration.

use homospline_geom::Real;
use thiserror::Error;

/// A solver's setting out of range, in words naming it.
#[derive(Debug, Error, PartialEq)]
#[error("{0}")]
pub struct SettingError(pub String);

/// Why a solver stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The values agree within the value tolerance: the simplex's vertices (Nelder-Mead), or
    /// the last iteration's improvement (L-BFGS).
    ValueTolerance,
    /// The simplex is smaller than the size tolerance (Nelder-Mead).
    SimplexSize,
    /// The gradient's largest entry is within the gradient tolerance (L-BFGS).
    GradientTolerance,
    /// No step along the search direction decreased the value enough (L-BFGS).
    LineSearchFailed,
    /// The value at the starting point is not finite, so no step can be judged (L-BFGS).
    NonFiniteStart,
    /// The evaluation budget is spent.
    MaxEvaluations,
}

/// What every solver's state tells: its best point and how much work it took.
pub trait SolverState {
    /// The best point so far and its value.
    fn best(&self) -> (&[Real], Real);
    /// Evaluations of the objective so far.
    fn evaluations(&self) -> usize;
    /// Iterations completed so far: steps that moved the solver (an L-BFGS step whose line
    /// search found no better point is not counted; Nelder-Mead counts every step).
    fn iterations(&self) -> usize;
}

/// A minimiser over `R^n`, driven one iteration at a time.
///
/// [`run`] drives any solver: `init`, then `step` while `terminate` says go on, with the
/// observer told after `init` and after every step. A solver's settings are checked by its
/// setters, so `init` and `step` cannot fail.
///
/// # Examples
///
/// Both solvers run through the same driver:
///
/// ```
/// use homospline_optim::solver::{run, Solver, SolverState, Termination};
/// use homospline_optim::{Lbfgs, NelderMead};
///
/// // A bowl with its bottom at (1, -2).
/// let value = |x: &[f64]| (x[0] - 1.0).powi(2) + 3.0 * (x[1] + 2.0).powi(2);
///
/// let nm = NelderMead::new(2).with_tolerances(1e-14, 1e-10).unwrap();
/// let mut bounded = |x: &[f64], _bound: f64| value(x);
/// let (state, why) = run(&nm, &mut bounded, &[0.0, 0.0], &mut ());
/// assert!(state.best().1 < 1e-9);
/// assert!(matches!(why, Termination::ValueTolerance | Termination::SimplexSize));
///
/// let lbfgs = Lbfgs::default();
/// let mut with_gradient =
///     |x: &[f64]| (value(x), vec![2.0 * (x[0] - 1.0), 6.0 * (x[1] + 2.0)]);
/// let mut seen = 0;
/// let (state, why) = run(&lbfgs, &mut with_gradient, &[0.0, 0.0], &mut |_: &_| seen += 1);
/// let (x, v) = state.best();
/// assert!(v < 1e-12 && (x[0] - 1.0).abs() < 1e-6 && (x[1] + 2.0).abs() < 1e-6);
/// // The observer saw the start and every step; a last step that found nothing better is
/// // not an iteration.
/// assert!(seen == state.iterations() + 1 || why == Termination::LineSearchFailed);
/// ```
///
/// # See also
/// [`crate::NelderMead::minimize_bounded`] (restarts, with the budget counted across runs),
/// [`crate::Lbfgs::minimize`], [`crate::grow`] (which picks one per round).
pub trait Solver {
    /// The objective the solver calls: a bounded value for Nelder-Mead
    /// ([`crate::nelder_mead::BoundedObjective`]), value and gradient for L-BFGS
    /// ([`crate::lbfgs::ValueAndGradient`]).
    type Objective<'a>: ?Sized;
    /// Everything the solver carries from one iteration to the next.
    type State: SolverState;

    /// The state at `x0`, with the evaluations that needs.
    fn init(&self, f: &mut Self::Objective<'_>, x0: &[Real]) -> Self::State;

    /// One iteration.
    fn step(&self, f: &mut Self::Objective<'_>, state: &mut Self::State);

    /// Why to stop now, if at all.
    fn terminate(&self, state: &Self::State) -> Option<Termination>;
}

/// What an observer sees: the state after `init` and after every `step`.
pub trait Observer<S> {
    /// Called after `init` and after each `step`.
    fn observe(&mut self, state: &S);
}

impl<S> Observer<S> for () {
    fn observe(&mut self, _: &S) {}
}

impl<S, F: FnMut(&S)> Observer<S> for F {
    fn observe(&mut self, state: &S) {
        self(state)
    }
}

/// Runs `solver` from `x0` until it terminates: the final state and why it stopped.
///
/// See [`Solver`] for an example.
pub fn run<S: Solver>(
    solver: &S,
    f: &mut S::Objective<'_>,
    x0: &[Real],
    observer: &mut dyn Observer<S::State>,
) -> (S::State, Termination) {
    let mut state = solver.init(f, x0);
    observer.observe(&state);
    loop {
        if let Some(why) = solver.terminate(&state) {
            return (state, why);
        }
        solver.step(f, &mut state);
        observer.observe(&state);
    }
}
