//! Roughness (4) of a cubic spline, exactly: `q''` is linear on each segment, so the
//! integrals of `|q''|` and `|q''|^2` have closed forms per segment, and so do their
//! derivatives with respect to the second derivatives at the knots.
//!
//! On a segment `q''(u) = a0 + u d` (`u` in `[0, 1]`, `d = a1 - a0`). The energy
//! `integral |q''|^2 du = |a0|^2 + a0.d + |d|^2 / 3` is a polynomial. The paper's
//! `integral |q''| du` is, in the frame of `d`, `|d| integral sqrt(w^2 + k^2) dw` with
//! `w = u + a0.d / |d|^2` and `k` the line's distance from the origin over `|d|`: closed form
//! with `asinh`. Where the line stays farther from the origin than `2 |d|` the integrand is
//! analytic well beyond the segment (twice its length) and 8-node Gauss-Legendre is exact to
//! rounding; nearer, the closed form is used, whose terms are then all of order one (no
//! cancellation).
//!
//! `|q''|` has no derivative where `q''` vanishes along a whole segment (a straight stretch):
//! there the gradient is taken as zero, the subgradient of least norm, so a straight curve is
//! stationary. Where `q''` only passes through zero at one point the integral is
//! differentiable and its derivative is the closed form's (the `k asinh(w / k)` terms tend
//! to zero with `k`).

use std::fmt;

use homospline_geom::{Real, Vector};

use crate::curve::Spline;
use crate::quad::gauss_legendre_cached;

/// The form of roughness (4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RoughnessForm {
    /// `integral_0^1 |q''(t)| dt`: the paper's (4), whose printed form lost its root sign
    /// like (3) and (6). Linear in the map's scale.
    #[default]
    Paper,
    /// `integral_0^1 |q''(t)|^2 dt`: the bending energy. Grows with the square of the
    /// scale and, at the paper's weights, swamps the safety term.
    Energy,
    /// `sqrt(integral_0^1 |q''(t)|^2 dt)`: what the authors' code computes.
    Authors,
}

impl RoughnessForm {
    /// Every form, in the order of the option's help.
    pub const ALL: [RoughnessForm; 3] = [Self::Paper, Self::Energy, Self::Authors];

    /// `paper`, `energy` or `authors`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Energy => "energy",
            Self::Authors => "authors",
        }
    }

    /// The form called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// How the form grows with the number `n` of spline segments when the parameter is
    /// uniform over `[0, 1]`: `q''` scales with `n^2` and `dt` with `1 / n`, so the paper's
    /// form grows like `n`, the energy like `n^3`, the authors' like `n^1.5`. Dividing the
    /// weight by `n^power` measures with one unit of parameter per segment.
    pub fn segment_power(self) -> Real {
        match self {
            Self::Paper => 1.0,
            Self::Energy => 3.0,
            Self::Authors => 1.5,
        }
    }
}

impl fmt::Display for RoughnessForm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The roughness of a curve and its derivative with respect to `q''` at each knot.
#[derive(Clone, Debug, PartialEq)]
pub struct Roughness {
    /// `R` in the chosen form.
    pub value: Real,
    /// `dR / dq''(t_i)` for each knot `t_i`, `i = 0 ..= segments`.
    pub knot_partials: Vec<Vector>,
}

/// Roughness (4) of `spline` in `form`; with `partials`, its derivative at every knot.
pub fn roughness(spline: &Spline, form: RoughnessForm, partials: bool) -> Roughness {
    let n = spline.segments();
    let knots = spline.knots();
    // q'' at every knot (continuous: a C2 spline), each computed once, as the loop reaches
    // it (no buffer: this runs at every evaluation).
    let acc = |i: usize| {
        if i < n {
            spline.eval_segment(i, 0.0).2
        } else {
            spline.eval_segment(n - 1, knots[n] - knots[n - 1]).2
        }
    };
    let mut next = acc(0);
    let mut value = 0.0;
    let mut knot_partials = if partials {
        vec![Vector::zeros(); n + 1]
    } else {
        Vec::new()
    };
    for i in 0..n {
        let h = knots[i + 1] - knots[i];
        let (a0, a1) = (next, acc(i + 1));
        next = a1;
        let (f, g0, g1) = match form {
            RoughnessForm::Paper if partials => bending::<true>(a0, a1),
            RoughnessForm::Paper => bending::<false>(a0, a1),
            RoughnessForm::Energy | RoughnessForm::Authors => energy(a0, a1),
        };
        value += h * f;
        if partials {
            knot_partials[i] += g0 * h;
            knot_partials[i + 1] += g1 * h;
        }
    }
    if form == RoughnessForm::Authors {
        // sqrt(E): dE / (2 sqrt(E)); zero at E = 0 (least-norm subgradient).
        let root = value.sqrt();
        let scale = if root > 0.0 { 0.5 / root } else { 0.0 };
        for g in &mut knot_partials {
            *g *= scale;
        }
        value = root;
    }
    Roughness {
        value,
        knot_partials,
    }
}

/// `integral_0^1 |a0 + u (a1 - a0)|^2 du` and its gradients with respect to `a0` and `a1`.
fn energy(a0: Vector, a1: Vector) -> (Real, Vector, Vector) {
    let d = a1 - a0;
    let f = a0.norm_squared() + a0.dot(&d) + d.norm_squared() / 3.0;
    // d/da0 = 2 integral a (1 - u) = 2 (a0 / 3 + a1 / 6); d/da1 = 2 (a0 / 6 + a1 / 3).
    (f, a0 * (2.0 / 3.0) + a1 / 3.0, a0 / 3.0 + a1 * (2.0 / 3.0))
}

/// `k asinh(w / k)`, which tends to 0 with `k`.
fn k_asinh(k: Real, w: Real) -> Real {
    let r = w / k;
    if k > 0.0 && r.is_finite() {
        k * r.asinh()
    } else {
        0.0
    }
}

/// `integral_0^1 |a(u)| du` with `a(u) = a0 + u (a1 - a0)`, and with `GRAD` its gradients
/// with respect to `a0` and `a1`: `integral â (1 - u) du` and `integral â u du`,
/// `â = a / |a|` (zero vectors without `GRAD`).
fn bending<const GRAD: bool>(a0: Vector, a1: Vector) -> (Real, Vector, Vector) {
    let d = a1 - a0;
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        let m = a0.norm();
        let unit = if GRAD && m > 0.0 {
            a0 / m
        } else {
            Vector::zeros()
        };
        return (m, unit * 0.5, unit * 0.5);
    }
    let u_star = (-a0.dot(&d) / len2).clamp(0.0, 1.0);
    let closest2 = (a0 + d * u_star).norm_squared();
    if closest2 > 4.0 * len2 {
        // |a| is analytic within twice the segment's length of it (in u: a disc of radius 2
        // around [0, 1]): 8-node Gauss-Legendre is exact to about 1e-15 relative.
        let (x, w) = gauss_legendre_cached(8);
        let (mut f, mut g0, mut g1) = (0.0, Vector::zeros(), Vector::zeros());
        for (&u, &wu) in x.iter().zip(w.iter()) {
            let a = a0 + d * u;
            let m = a.norm();
            f += wu * m;
            if GRAD {
                let unit = a * (wu / m);
                g0 += unit * (1.0 - u);
                g1 += unit * u;
            }
        }
        return (f, g0, g1);
    }
    // Frame of d: a(u) = len (w e + c n), w = w0 + u, |a| = len sqrt(w^2 + k^2), k = |c|.
    // Here the line passes within 2 len of the origin, so |w0| <= 3 and nothing cancels.
    let len = len2.sqrt();
    let e = d / len;
    let nrm = Vector::new(-e.y, e.x);
    let w0 = a0.dot(&e) / len;
    let c = a0.dot(&nrm) / len; // signed k
    let k = c.abs();
    let s = |w: Real| (w * w + k * k).sqrt();
    let (wa, wb) = (w0, w0 + 1.0);
    let (sa, sb) = (s(wa), s(wb));
    let kh = k_asinh(k, wb) - k_asinh(k, wa); // k [asinh(w / k)]
    let f = len * 0.5 * ((wb * sb - wa * sa) + k * kh);
    if !GRAD {
        return (f, Vector::zeros(), Vector::zeros());
    }
    // integral â dw = e [S] + sign(c) n [k asinh(w / k)].
    let j0 = e * (sb - sa) + nrm * (c.signum() * kh);
    // integral â w dw = e [(w S - k^2 asinh(w / k)) / 2] + c n [S] (c = signed k).
    let jw = e * (0.5 * ((wb * sb - wa * sa) - k * kh)) + nrm * (c * (sb - sa));
    let j1 = jw - j0 * w0; // integral â u du, u = w - w0
    (f, j0 - j1, j1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Simpson's rule on `n` (even) intervals of [0, 1].
    fn simpson(f: impl Fn(Real) -> Real, n: usize) -> Real {
        let h = 1.0 / n as Real;
        let mut acc = f(0.0) + f(1.0);
        for i in 1..n {
            acc += f(i as Real * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        acc * h / 3.0
    }

    #[test]
    fn bending_matches_simpson_and_its_gradient_matches_differences() {
        let cases = [
            (Vector::new(3.0, 1.0), Vector::new(-2.0, 0.5)), // passes near zero
            (Vector::new(3.0, 0.0), Vector::new(-2.0, 0.0)), // through zero
            (Vector::new(10.0, 4.0), Vector::new(11.0, 3.0)), // far from zero
            (Vector::new(0.0, 0.0), Vector::new(1.0, 2.0)),  // zero at an end
            (Vector::new(1e-3, 2.0), Vector::new(1e-3, -2.0)),
        ];
        for (a0, a1) in cases {
            let (f, g0, g1) = bending::<true>(a0, a1);
            assert_eq!(bending::<false>(a0, a1).0, f);
            let reference = simpson(|u| (a0 + (a1 - a0) * u).norm(), 400_000);
            assert!(
                (f - reference).abs() < 1e-9,
                "{a0:?} {a1:?}: {f} vs {reference}"
            );
            let h = 1e-6;
            for axis in 0..2 {
                let mut dv = Vector::zeros();
                dv[axis] = h;
                let b = |a0, a1| bending::<false>(a0, a1).0;
                let d0 = (b(a0 + dv, a1) - b(a0 - dv, a1)) / (2.0 * h);
                let d1 = (b(a0, a1 + dv) - b(a0, a1 - dv)) / (2.0 * h);
                assert!(
                    (d0 - g0[axis]).abs() < 1e-6,
                    "{a0:?} {a1:?}: {d0} vs {}",
                    g0[axis]
                );
                assert!(
                    (d1 - g1[axis]).abs() < 1e-6,
                    "{a0:?} {a1:?}: {d1} vs {}",
                    g1[axis]
                );
            }
        }
    }

    #[test]
    fn energy_matches_simpson() {
        let (a0, a1) = (Vector::new(3.0, 1.0), Vector::new(-2.0, 0.5));
        let reference = simpson(|u| (a0 + (a1 - a0) * u).norm_squared(), 1000);
        assert!((energy(a0, a1).0 - reference).abs() < 1e-12);
    }
}
