//! Limited-memory BFGS with a backtracking (Armijo) line search, for the analytic gradient
//! of the spline cost. A value of `+inf` (a step that leaves the homotopy class) makes the
//! line search back off.

use homospline_geom::Real;

/// Settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Lbfgs {
    /// History length.
    pub memory: usize,
    /// Stop when the gradient's largest entry is below this.
    pub gradient_tolerance: Real,
    /// Stop when an iteration improves the value by less than this, relatively.
    pub value_tolerance: Real,
    /// Evaluation budget (value and gradient together count one).
    pub max_evaluations: usize,
}

impl Default for Lbfgs {
    fn default() -> Self {
        Self {
            memory: 6,
            gradient_tolerance: 1e-8,
            value_tolerance: 1e-10,
            max_evaluations: 500,
        }
    }
}

/// Result of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct LbfgsOutcome {
    /// Best point.
    pub x: Vec<Real>,
    /// Its value.
    pub value: Real,
    /// Evaluations.
    pub evaluations: usize,
    /// Iterations.
    pub iterations: usize,
}

/// An objective returning its value and gradient.
pub type ValueAndGradient<'a> = dyn FnMut(&[Real]) -> (Real, Vec<Real>) + 'a;

fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Lbfgs {
    /// Minimises `f`, which returns the value and the gradient.
    pub fn minimize(&self, f: &mut ValueAndGradient<'_>, x0: &[Real]) -> LbfgsOutcome {
        let n = x0.len();
        let mut x = x0.to_vec();
        let (mut fx, mut g) = f(&x);
        let mut evaluations = 1;
        let mut iterations = 0;
        let mut s_hist: Vec<Vec<Real>> = Vec::new();
        let mut y_hist: Vec<Vec<Real>> = Vec::new();
        if !fx.is_finite() {
            return LbfgsOutcome {
                x,
                value: fx,
                evaluations,
                iterations,
            };
        }
        while evaluations < self.max_evaluations {
            if g.iter().fold(0.0, |m: Real, v| m.max(v.abs())) <= self.gradient_tolerance {
                break;
            }
            // Two-loop recursion: d = -H g.
            let mut q = g.clone();
            let k = s_hist.len();
            let mut alpha = vec![0.0; k];
            for i in (0..k).rev() {
                let rho = 1.0 / dot(&y_hist[i], &s_hist[i]);
                alpha[i] = rho * dot(&s_hist[i], &q);
                for j in 0..n {
                    q[j] -= alpha[i] * y_hist[i][j];
                }
            }
            if k > 0 {
                let gamma =
                    dot(&s_hist[k - 1], &y_hist[k - 1]) / dot(&y_hist[k - 1], &y_hist[k - 1]);
                q.iter_mut().for_each(|v| *v *= gamma);
            } else {
                // First step: a unit-length move along the steepest descent.
                let norm = dot(&g, &g).sqrt().max(1e-300);
                q.iter_mut().for_each(|v| *v /= norm);
            }
            for i in 0..k {
                let rho = 1.0 / dot(&y_hist[i], &s_hist[i]);
                let beta = rho * dot(&y_hist[i], &q);
                for j in 0..n {
                    q[j] += s_hist[i][j] * (alpha[i] - beta);
                }
            }
            let mut d: Vec<Real> = q.iter().map(|v| -v).collect();
            let mut slope = dot(&g, &d);
            if slope >= 0.0 {
                // Not a descent direction: restart from steepest descent.
                s_hist.clear();
                y_hist.clear();
                let norm = dot(&g, &g).sqrt().max(1e-300);
                d = g.iter().map(|v| -v / norm).collect();
                slope = dot(&g, &d);
            }
            // Backtracking line search (Armijo, c = 1e-4).
            let mut t = 1.0;
            let mut accepted = None;
            while evaluations < self.max_evaluations && t > 1e-12 {
                let xn: Vec<Real> = x.iter().zip(&d).map(|(a, b)| a + t * b).collect();
                let (fn_, gn) = f(&xn);
                evaluations += 1;
                if fn_.is_finite() && fn_ <= fx + 1e-4 * t * slope {
                    accepted = Some((xn, fn_, gn));
                    break;
                }
                t *= 0.5;
            }
            let Some((xn, fnew, gn)) = accepted else {
                break;
            };
            iterations += 1;
            let s: Vec<Real> = xn.iter().zip(&x).map(|(a, b)| a - b).collect();
            let y: Vec<Real> = gn.iter().zip(&g).map(|(a, b)| a - b).collect();
            let improvement = fx - fnew;
            x = xn;
            g = gn;
            let old = fx;
            fx = fnew;
            if dot(&s, &y) > 1e-12 {
                s_hist.push(s);
                y_hist.push(y);
                if s_hist.len() > self.memory {
                    s_hist.remove(0);
                    y_hist.remove(0);
                }
            }
            if improvement <= self.value_tolerance * (1.0 + old.abs()) {
                break;
            }
        }
        LbfgsOutcome {
            x,
            value: fx,
            evaluations,
            iterations,
        }
    }
}
