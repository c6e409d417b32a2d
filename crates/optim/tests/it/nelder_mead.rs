//! Nelder-Mead and L-BFGS on standard test functions with known minima.

use homospline_optim::nelder_mead::State;
use homospline_optim::solver::SolverState;
use homospline_optim::{Coefficients, Lbfgs, NelderMead, Termination};

fn rosenbrock(x: &[f64]) -> f64 {
    x.windows(2)
        .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
        .sum()
}

fn rosenbrock_grad(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut g = vec![0.0; n];
    for i in 0..n - 1 {
        g[i] += -400.0 * x[i] * (x[i + 1] - x[i] * x[i]) - 2.0 * (1.0 - x[i]);
        g[i + 1] += 200.0 * (x[i + 1] - x[i] * x[i]);
    }
    g
}

#[test]
fn adaptive_nelder_mead_finds_the_rosenbrock_minimum_in_2_to_10_dimensions() {
    for n in 2..=10 {
        let nm = NelderMead::new(n)
            .with_tolerances(1e-14, 1e-12)
            .unwrap()
            .with_max_evaluations(400_000)
            .unwrap()
            .with_initial_step(vec![0.5; n])
            .unwrap()
            .with_restarts(5);
        let x0 = vec![-1.2; n];
        let out = nm.minimize(&mut |x: &[f64]| rosenbrock(x), &x0, &mut ());
        let err = out.x.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
        assert!(
            out.value < 1e-8 && err < 1e-3,
            "n = {n}: f = {:e}, |x - 1| = {err:e}, {:?}",
            out.value,
            out.termination
        );
    }
}

#[test]
fn standard_coefficients_solve_small_problems() {
    let nm = NelderMead::new(2)
        .with_coefficients(Coefficients::standard())
        .unwrap()
        .with_tolerances(1e-14, 1e-12)
        .unwrap();
    // Booth: minimum 0 at (1, 3).
    let out = nm.minimize(
        &mut |x: &[f64]| (x[0] + 2.0 * x[1] - 7.0).powi(2) + (2.0 * x[0] + x[1] - 5.0).powi(2),
        &[0.0, 0.0],
        &mut (),
    );
    assert!(
        (out.x[0] - 1.0).abs() < 1e-5 && (out.x[1] - 3.0).abs() < 1e-5,
        "{:?}",
        out.x
    );
    // Beale: minimum 0 at (3, 0.5).
    let beale = |x: &[f64]| {
        (1.5 - x[0] + x[0] * x[1]).powi(2)
            + (2.25 - x[0] + x[0] * x[1] * x[1]).powi(2)
            + (2.625 - x[0] + x[0] * x[1].powi(3)).powi(2)
    };
    let out = nm.minimize(&mut |x: &[f64]| beale(x), &[1.0, 1.0], &mut ());
    assert!(
        (out.x[0] - 3.0).abs() < 1e-4 && (out.x[1] - 0.5).abs() < 1e-4,
        "{:?}",
        out.x
    );
    // Sphere in 8 dimensions, adaptive.
    let nm = NelderMead::new(8)
        .with_tolerances(1e-16, 1e-12)
        .unwrap()
        .with_max_evaluations(100_000)
        .unwrap();
    let out = nm.minimize(
        &mut |x: &[f64]| x.iter().map(|v| (v - 2.0).powi(2)).sum(),
        &[0.0; 8],
        &mut (),
    );
    assert!(out.value < 1e-10, "{}", out.value);
}

#[test]
fn termination_reasons_and_budget() {
    let nm = NelderMead::new(4).with_max_evaluations(50).unwrap();
    let out = nm.minimize(&mut |x: &[f64]| rosenbrock(x), &[-1.2; 4], &mut ());
    assert_eq!(out.termination, Termination::MaxEvaluations);
    assert!(out.evaluations <= 50 + 4, "{}", out.evaluations);
    let nm = NelderMead::new(2).with_tolerances(1e-3, 0.0).unwrap();
    let out = nm.minimize(
        &mut |x: &[f64]| x[0] * x[0] + x[1] * x[1],
        &[1.0, 1.0],
        &mut (),
    );
    assert_eq!(out.termination, Termination::ValueTolerance);
}

#[test]
fn setters_validate() {
    assert!(
        NelderMead::new(2)
            .with_coefficients(Coefficients {
                reflection: 1.0,
                expansion: 0.5,
                contraction: 0.5,
                shrink: 0.5
            })
            .is_err()
    );
    assert!(NelderMead::new(2).with_initial_step(vec![1.0]).is_err());
    assert!(
        NelderMead::new(2)
            .with_initial_step(vec![1.0, 0.0])
            .is_err()
    );
    assert!(NelderMead::new(2).with_tolerances(-1.0, 0.0).is_err());
    assert!(NelderMead::new(2).with_max_evaluations(3).is_err());
    let a = Coefficients::adaptive(10);
    assert!(
        (a.expansion - 1.2).abs() < 1e-15
            && (a.contraction - 0.7).abs() < 1e-15
            && (a.shrink - 0.9).abs() < 1e-15
    );
}

#[test]
fn the_observer_sees_every_iteration_and_values_never_increase() {
    let nm = NelderMead::new(3).with_max_evaluations(2000).unwrap();
    let mut trace: Vec<(usize, f64)> = Vec::new();
    let mut obs = |s: &State| trace.push((s.iterations, s.best().1));
    let out = nm.minimize(&mut |x: &[f64]| rosenbrock(x), &[0.0; 3], &mut obs);
    assert_eq!(trace.len(), out.iterations + 1);
    assert!(trace.windows(2).all(|w| w[1].1 <= w[0].1));
}

#[test]
fn lbfgs_finds_the_rosenbrock_minimum() {
    for n in [2, 5, 10] {
        let lb = Lbfgs::default()
            .with_max_evaluations(20_000)
            .unwrap()
            .with_gradient_tolerance(1e-10)
            .unwrap()
            .with_value_tolerance(0.0)
            .unwrap();
        let out = lb.minimize(
            &mut |x: &[f64]| (rosenbrock(x), rosenbrock_grad(x)),
            &vec![-1.2; n],
        );
        assert!(out.value < 1e-12, "n = {n}: {}", out.value);
    }
}

#[test]
fn a_bounded_objective_gives_the_exact_objectives_path() {
    // At or above its bound the objective may answer anything at or above it: here the
    // bound plus a large, varying amount (a cost stopped early returns its lower bound).
    // The solver must take every step as with the exact values.
    for n in [2, 5, 8] {
        let nm = NelderMead::new(n)
            .with_max_evaluations(60 * n)
            .unwrap()
            .with_initial_step(vec![0.3; n])
            .unwrap();
        let x0: Vec<f64> = (0..n).map(|i| -1.2 + 0.1 * i as f64).collect();
        let mut exact_trace = Vec::new();
        let exact = nm.minimize(&mut |x: &[f64]| rosenbrock(x), &x0, &mut |s: &State| {
            exact_trace.push(s.clone())
        });
        let (mut calls, mut answered_above) = (0usize, 0usize);
        let mut bounded_trace = Vec::new();
        let bounded = nm.minimize_bounded(
            &mut |x: &[f64], bound: f64| {
                calls += 1;
                let v = rosenbrock(x);
                if v >= bound {
                    answered_above += 1;
                    bound + 1e6 * (calls % 7) as f64
                } else {
                    v
                }
            },
            &x0,
            &mut |s: &State| bounded_trace.push(s.clone()),
        );
        assert_eq!(exact, bounded, "n = {n}");
        assert_eq!(exact_trace, bounded_trace, "n = {n}");
        // The test means something only if many answers were the stand-ins.
        assert!(
            answered_above * 5 > calls,
            "n = {n}: {answered_above} of {calls}"
        );
    }
}

#[test]
fn lbfgs_says_why_it_stopped() {
    let f = |x: &[f64]| (rosenbrock(x), rosenbrock_grad(x));
    let small = Lbfgs::default().with_max_evaluations(5).unwrap();
    let out = small.minimize(&mut |x: &[f64]| f(x), &[-1.2, 1.0]);
    assert_eq!(out.termination, Termination::MaxEvaluations);
    assert_eq!(out.evaluations, 5);
    // A start outside the domain: nothing can be judged.
    let out = Lbfgs::default().minimize(&mut |_: &[f64]| (f64::INFINITY, vec![0.0; 2]), &[0.0; 2]);
    assert_eq!(
        (out.termination, out.evaluations, out.iterations),
        (Termination::NonFiniteStart, 1, 0)
    );
    // A wall just past the start in every direction: the line search backs off to nothing.
    let walled = |x: &[f64]| {
        if x[0].abs() + x[1].abs() > 1e-13 {
            (f64::INFINITY, vec![0.0; 2])
        } else {
            (x[0] + x[1], vec![1.0, 1.0])
        }
    };
    let out = Lbfgs::default().minimize(&mut |x: &[f64]| walled(x), &[0.0; 2]);
    assert_eq!(out.termination, Termination::LineSearchFailed);
    assert_eq!(out.x, vec![0.0, 0.0]);
    // Settings are checked where they are set.
    assert!(Lbfgs::default().with_memory(0).is_err());
    assert!(Lbfgs::default().with_gradient_tolerance(f64::NAN).is_err());
    assert!(Lbfgs::default().with_value_tolerance(-1.0).is_err());
    assert!(Lbfgs::default().with_max_evaluations(0).is_err());
}

#[test]
fn both_solvers_run_through_one_driver_and_the_observer_sees_each_step() {
    use homospline_optim::solver::{Solver, Termination, run};
    /// The best value after `init` and after each step, and how the run ended.
    fn trace<S: Solver>(
        solver: &S,
        f: &mut S::Objective<'_>,
        x0: &[f64],
    ) -> (Vec<f64>, S::State, Termination) {
        let mut values = Vec::new();
        let (state, why) = run(solver, f, x0, &mut |s: &S::State| values.push(s.best().1));
        (values, state, why)
    }
    // Nelder-Mead counts every step, and its budget binds: a step spends at most n + 2
    // evaluations, so the run ends within n + 1 of the budget.
    let nm = NelderMead::new(3).with_max_evaluations(60).unwrap();
    let (values, state, why) = trace(&nm, &mut |x: &[f64], _: f64| rosenbrock(x), &[0.0; 3]);
    assert_eq!(why, Termination::MaxEvaluations);
    assert_eq!(values.len(), state.iterations() + 1);
    assert!(
        (60..=60 + 4).contains(&state.evaluations()),
        "{}",
        state.evaluations()
    );
    assert!(values.windows(2).all(|w| w[1] <= w[0]));
    // L-BFGS: Armijo steps only go down, and a step whose line search finds nothing better
    // ends the run without counting as an iteration.
    let lb = Lbfgs::default().with_max_evaluations(400).unwrap();
    let mut fg = |x: &[f64]| (rosenbrock(x), rosenbrock_grad(x));
    let (values, state, why) = trace(&lb, &mut fg, &[0.0; 3]);
    let moved = values.len() - 1 - usize::from(why == Termination::LineSearchFailed);
    assert_eq!(moved, state.iterations(), "{why:?}");
    assert!(
        values[..=moved].windows(2).all(|w| w[1] < w[0]),
        "{values:?}"
    );
    assert!(state.best().1 < 1e-10, "{why:?}: {}", state.best().1);
    // A budget that runs out inside a line search ends with the budget's reason.
    let small = Lbfgs::default().with_max_evaluations(7).unwrap();
    let (_, state, why) = trace(&small, &mut fg, &[0.0; 3]);
    assert_eq!((why, state.evaluations()), (Termination::MaxEvaluations, 7));
}
