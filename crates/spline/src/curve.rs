//! A parametric cubic spline `q(t) = (x(t), y(t))`, `t` in `[0, 1]`, through via-points.

use homospline_geom::{Point, Real, Vector};
use thiserror::Error;

/// How the knots `t_i` are spread over `[0, 1]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parametrization {
    /// `t_i = i / (k + 1)`: the paper's form. Roughness `R = integral |q''|^2 dt` then
    /// depends on the number of via-points as well as the shape; the spline is linear in the
    /// via-points, which gives the analytic gradient.
    #[default]
    Uniform,
    /// `t_i` proportional to the cumulative chord length: follows the geometry better when
    /// via-points are unevenly spaced; `R` is closer to a bending energy.
    ChordLength,
}

/// End conditions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum EndCondition {
    /// `q'' = 0` at both ends.
    #[default]
    Natural,
    /// Given first derivatives `dq/dt` at the start and the end.
    Clamped {
        /// `q'(0)`.
        start: Vector,
        /// `q'(1)`.
        end: Vector,
    },
    /// A given first derivative at the start, `q'' = 0` at the end.
    ClampedStart {
        /// `q'(0)`.
        start: Vector,
    },
    /// The curve leaves the start along `direction` at the speed of its first chord
    /// (`|q'(0)| = |P1 - P0| / (t1 - t0)`), with `q'' = 0` at the end: a robot re-planning on
    /// the move keeps its heading. The slope depends on `P1`, so the analytic gradient does
    /// not apply (see `cost::gradient`).
    StartHeading {
        /// The direction to leave in (any length but zero).
        direction: Vector,
    },
}

impl EndCondition {
    /// The same kind of condition with zero slopes: the ends of the cardinal basis.
    fn with_zero_slopes(self) -> Self {
        match self {
            Self::Natural => Self::Natural,
            Self::Clamped { .. } => Self::Clamped {
                start: Vector::zeros(),
                end: Vector::zeros(),
            },
            Self::ClampedStart { .. } => Self::ClampedStart {
                start: Vector::zeros(),
            },
            Self::StartHeading { .. } => Self::Natural,
        }
    }
}

/// Why a spline cannot be built.
#[derive(Debug, Error, PartialEq)]
pub enum SplineError {
    /// Fewer than two points.
    #[error("a spline needs at least 2 points, got {0}")]
    TooFewPoints(usize),
    /// A coordinate is NaN or infinite.
    #[error("point {0} is not finite")]
    NonFinite(usize),
    /// Two consecutive points coincide under chord-length parameters.
    #[error("points {0} and {1} coincide: chord-length parameters need distinct points")]
    Coincident(usize, usize),
}

/// A cubic spline through `points`, stored per segment as `a + b s + c s^2 + d s^3`,
/// `s = t - t_i`.
///
/// # Examples
///
/// ```
/// use homospline_geom::Point;
/// use homospline_spline::Spline;
///
/// let pts = [Point::new(0.0, 0.0), Point::new(5.0, 3.0), Point::new(10.0, 0.0)];
/// let sp = Spline::natural(&pts)?;
/// // It passes through its points; its length is more than the chords'.
/// let (p, _, _) = sp.eval_segment(1, 0.0);
/// assert!((p - pts[1]).norm() < 1e-12);
/// assert!(sp.length() > 2.0 * 34f64.sqrt());
/// # Ok::<(), homospline_spline::SplineError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    knots: Vec<Real>,
    points: Vec<Point>,
    coef: Vec<[Vector; 4]>,
    param: Parametrization,
    end: EndCondition,
}

impl Spline {
    /// The natural spline with uniform parameters: the paper's curve.
    pub fn natural(points: &[Point]) -> Result<Self, SplineError> {
        Self::new(points, Parametrization::Uniform, EndCondition::Natural)
    }

    /// A spline through `points` (`S`, via-points, `T`).
    pub fn new(
        points: &[Point],
        param: Parametrization,
        end: EndCondition,
    ) -> Result<Self, SplineError> {
        let n = points.len();
        if n < 2 {
            return Err(SplineError::TooFewPoints(n));
        }
        if let Some(i) = points
            .iter()
            .position(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(SplineError::NonFinite(i));
        }
        let knots = match param {
            Parametrization::Uniform => (0..n).map(|i| i as Real / (n - 1) as Real).collect(),
            Parametrization::ChordLength => {
                let mut k = vec![0.0; n];
                for i in 1..n {
                    let d = (points[i] - points[i - 1]).norm();
                    if d == 0.0 {
                        return Err(SplineError::Coincident(i - 1, i));
                    }
                    k[i] = k[i - 1] + d;
                }
                let total = k[n - 1];
                k.iter_mut().for_each(|t| *t /= total);
                k[n - 1] = 1.0;
                k
            }
        };
        Ok(Self::with_knots(knots, points, param, end))
    }

    /// The spline through `points` at the given knots.
    fn with_knots(
        knots: Vec<Real>,
        points: &[Point],
        param: Parametrization,
        end: EndCondition,
    ) -> Self {
        let n = points.len();
        let m = second_derivatives(&knots, points, end);
        let coef = (0..n - 1)
            .map(|i| {
                let h = knots[i + 1] - knots[i];
                let (p0, p1) = (points[i].coords, points[i + 1].coords);
                let (m0, m1) = (m[i], m[i + 1]);
                [
                    p0,
                    (p1 - p0) / h - (m0 * 2.0 + m1) * (h / 6.0),
                    m0 / 2.0,
                    (m1 - m0) / (6.0 * h),
                ]
            })
            .collect();
        Self {
            knots,
            points: points.to_vec(),
            coef,
            param,
            end,
        }
    }

    /// The parametrization it was built with.
    pub fn parametrization(&self) -> Parametrization {
        self.param
    }

    /// The end conditions it was built with.
    pub fn end_condition(&self) -> EndCondition {
        self.end
    }

    /// The cardinal basis: for each point `j`, the scalar spline on the same knots through
    /// `1` at knot `j` and `0` elsewhere (end slopes zero when clamped), stored in `x`. With
    /// fixed knots the spline is `q(t) = sum_j B_j(t) P_j` plus a term of the clamped slopes,
    /// so `B_j` is the derivative of `q` with respect to `P_j`.
    pub fn basis(&self) -> Vec<Spline> {
        let n = self.points.len();
        let end = self.end.with_zero_slopes();
        (0..n)
            .map(|j| {
                let pts: Vec<Point> = (0..n)
                    .map(|i| Point::new(if i == j { 1.0 } else { 0.0 }, 0.0))
                    .collect();
                Self::with_knots(self.knots.clone(), &pts, self.param, end)
            })
            .collect()
    }

    /// The gradient with respect to the points of a function of the segments' coefficients
    /// (knots and clamped end slopes held fixed), by reverse mode through the spline's
    /// construction: `coef_grads[i]` holds the derivatives with respect to `a, b, c, d` of
    /// segment `i` (`a + b s + c s^2 + d s^3`). The second derivatives `M` solve `A M = r(P)`
    /// with `A` tridiagonal and fixed, so their adjoint is one solve with `A^T`: `O(n)`, and
    /// exact (the same as summing against [`Spline::basis`], which costs `O(n^2)`). A start
    /// heading's slope is held fixed too (it moves with `P_1`; `cost::gradient` takes that
    /// case by differences).
    ///
    /// # Panics
    /// When `coef_grads` does not hold one entry per segment (a caller's bug).
    pub fn pull_back(&self, coef_grads: &[[Vector; 4]]) -> Vec<Vector> {
        let n = self.points.len();
        assert_eq!(
            coef_grads.len(),
            n - 1,
            "one coefficient gradient per segment"
        );
        let t = &self.knots;
        let h: Vec<Real> = (0..n - 1).map(|i| t[i + 1] - t[i]).collect();
        let mut gp = vec![Vector::zeros(); n];
        let mut gm = vec![Vector::zeros(); n];
        let mut gslope = vec![Vector::zeros(); n - 1];
        for (i, [ga, gb, gc, gd]) in coef_grads.iter().enumerate() {
            // a = P_i, b = slope_i - (2 M_i + M_{i+1}) h / 6, c = M_i / 2,
            // d = (M_{i+1} - M_i) / (6 h).
            gp[i] += ga;
            gslope[i] += gb;
            gm[i] += gb * (-h[i] / 3.0) + gc * 0.5 - gd / (6.0 * h[i]);
            gm[i + 1] += gb * (-h[i] / 6.0) + gd / (6.0 * h[i]);
        }
        let natural_pair = n == 2 && self.end == EndCondition::Natural;
        if !natural_pair {
            let (sub, diag, sup) = system_matrix(&h, self.end);
            // Solve A^T lambda = gm: A^T has sub'[i] = sup[i-1] and sup'[i] = sub[i+1].
            let tsub: Vec<Real> = (0..n)
                .map(|i| if i == 0 { 0.0 } else { sup[i - 1] })
                .collect();
            let tsup: Vec<Real> = (0..n)
                .map(|i| if i + 1 == n { 0.0 } else { sub[i + 1] })
                .collect();
            let lambda = solve_tridiagonal(&tsub, diag, &tsup, gm);
            // r_i = 6 (slope_i - slope_{i-1}) inside, 6 slope_0 on a clamped start row,
            // -6 slope_{n-2} on a clamped end row (the given slopes are constants).
            for i in 1..n - 1 {
                gslope[i] += lambda[i] * 6.0;
                gslope[i - 1] -= lambda[i] * 6.0;
            }
            if !matches!(self.end, EndCondition::Natural) {
                gslope[0] += lambda[0] * 6.0;
            }
            if matches!(self.end, EndCondition::Clamped { .. }) {
                gslope[n - 2] -= lambda[n - 1] * 6.0;
            }
        }
        for (i, g) in gslope.iter().enumerate() {
            gp[i + 1] += g / h[i];
            gp[i] -= g / h[i];
        }
        gp
    }

    /// The points it passes through.
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// The knots `t_0 = 0 < ... < t_n = 1`.
    pub fn knots(&self) -> &[Real] {
        &self.knots
    }

    /// Number of cubic segments (points - 1).
    pub fn segments(&self) -> usize {
        self.coef.len()
    }

    /// The segment holding `t` (clamped to `[0, 1]`) and the local parameter `s`.
    #[inline]
    pub fn locate(&self, t: Real) -> (usize, Real) {
        let t = t.clamp(0.0, 1.0);
        let i = match self.knots.binary_search_by(|k| k.total_cmp(&t)) {
            Ok(i) => i.min(self.coef.len() - 1),
            Err(i) => (i.max(1) - 1).min(self.coef.len() - 1),
        };
        (i, t - self.knots[i])
    }

    /// Position, first and second derivative on segment `i` at local parameter `s`.
    #[inline]
    pub fn eval_segment(&self, i: usize, s: Real) -> (Point, Vector, Vector) {
        let [a, b, c, d] = &self.coef[i];
        let p = a + (b + (c + d * s) * s) * s;
        let d1 = b + (c * 2.0 + d * (3.0 * s)) * s;
        let d2 = c * 2.0 + d * (6.0 * s);
        (Point::from(p), d1, d2)
    }

    /// Position `q(t)`.
    pub fn position(&self, t: Real) -> Point {
        let (i, s) = self.locate(t);
        self.eval_segment(i, s).0
    }

    /// First derivative `q'(t)`.
    pub fn velocity(&self, t: Real) -> Vector {
        let (i, s) = self.locate(t);
        self.eval_segment(i, s).1
    }

    /// Second derivative `q''(t)`.
    pub fn acceleration(&self, t: Real) -> Vector {
        let (i, s) = self.locate(t);
        self.eval_segment(i, s).2
    }

    /// Length of segment `i` by 16-point Gauss-Legendre on 4 sub-intervals.
    pub fn segment_length(&self, i: usize) -> Real {
        self.arc_length(i, 0.0, self.knots[i + 1] - self.knots[i])
    }

    /// Arc length on segment `i` between local parameters `s0 < s1` (64 Gauss nodes).
    pub fn arc_length(&self, i: usize, s0: Real, s1: Real) -> Real {
        let (x, w) = crate::quad::gauss_legendre_cached(16);
        let pieces = 4;
        let h = (s1 - s0) / pieces as Real;
        let mut total = 0.0;
        for k in 0..pieces {
            let base = s0 + h * k as Real;
            for (x, w) in x.iter().zip(w) {
                total += w * h * self.eval_segment(i, base + h * x).1.norm();
            }
        }
        total
    }

    /// Total length.
    pub fn length(&self) -> Real {
        (0..self.segments()).map(|i| self.segment_length(i)).sum()
    }

    /// Samples the curve so that consecutive samples are at most `max_spacing` apart along
    /// the curve (measured arc length, not chord), start and goal included; each sample with
    /// its parameter `t`.
    pub fn sample_by_arc_length(&self, max_spacing: Real) -> Vec<(Real, Point)> {
        let mut out = vec![(0.0, self.points[0])];
        let spacing = if max_spacing.is_finite() && max_spacing > 0.0 {
            max_spacing
        } else {
            0.5
        };
        for i in 0..self.segments() {
            let h = self.knots[i + 1] - self.knots[i];
            let len = self.segment_length(i);
            let n = ((len / spacing).ceil() as usize).max(1);
            // Uniform in s first, then split any piece longer than the spacing.
            let mut stack: Vec<(Real, Real)> = (0..n)
                .rev()
                .map(|k| {
                    (
                        h * k as Real / n as Real,
                        if k + 1 == n {
                            h
                        } else {
                            h * (k + 1) as Real / n as Real
                        },
                    )
                })
                .collect();
            while let Some((a, b)) = stack.pop() {
                // The Bezier control polygon of the piece bounds its length from above and the
                // chord from below: the quadrature is needed only when the spacing lies
                // between them.
                let (pa, va, _) = self.eval_segment(i, a);
                let (pb, vb, _) = self.eval_segment(i, b);
                let third = (b - a) / 3.0;
                let (c1, c2) = (pa + va * third, pb - vb * third);
                let polygon = (c1 - pa).norm() + (c2 - c1).norm() + (pb - c2).norm();
                let longer = polygon > spacing
                    && ((pb - pa).norm() > spacing || self.arc_length(i, a, b) > spacing);
                if longer && b - a > 1e-12 {
                    let m = 0.5 * (a + b);
                    stack.push((m, b));
                    stack.push((a, m));
                } else {
                    let t = if b == h {
                        self.knots[i + 1]
                    } else {
                        self.knots[i] + b
                    };
                    let p = if b == h {
                        self.points[i + 1]
                    } else {
                        self.eval_segment(i, b).0
                    };
                    out.push((t, p));
                }
            }
        }
        out
    }

    /// `n + 1` points at equal parameter steps.
    pub fn sample_uniform(&self, n: usize) -> Vec<Point> {
        // The same points as `position(k / n)`, walking the segments instead of searching.
        let last = self.coef.len() - 1;
        let mut seg = 0;
        (0..=n)
            .map(|k| {
                let t = (k as Real / n.max(1) as Real).clamp(0.0, 1.0);
                while seg < last && t >= self.knots[seg + 1] {
                    seg += 1;
                }
                self.eval_segment(seg, t - self.knots[seg]).0
            })
            .collect()
    }

    /// A bound on how far apart this curve and `other` come at any one parameter,
    /// `max over t of |q(t) - other(t)|`, from the Bezier control points of their
    /// difference segment by segment (the difference of each segment lies in their convex
    /// hull); `None` unless both have the same knots. Never below the true largest gap, but
    /// for rounding (of the order of `1e-16` times the coefficients).
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_geom::Point;
    /// use homospline_spline::{EndCondition, Parametrization, Spline};
    ///
    /// let s = Point::new(0.0, 0.0);
    /// let t = Point::new(10.0, 0.0);
    /// let build = |y| {
    ///     Spline::new(&[s, Point::new(5.0, y), t], Parametrization::Uniform, EndCondition::Natural)
    ///         .unwrap()
    /// };
    /// let (a, b) = (build(2.0), build(2.5));
    /// let bound = a.deviation_bound(&b).unwrap();
    /// // The via-point moved by 0.5, the ends not at all: the bound is at least 0.5.
    /// assert!(bound >= 0.5 && bound < 1.0, "{bound}");
    /// assert!((a.position(0.5) - b.position(0.5)).norm() <= bound);
    /// ```
    ///
    /// # See also
    /// [`Spline::segment_box`], the same control points' box of one curve.
    pub fn deviation_bound(&self, other: &Spline) -> Option<Real> {
        if self.knots != other.knots {
            return None;
        }
        let mut bound: Real = 0.0;
        for (i, (p, q)) in self.coef.iter().zip(&other.coef).enumerate() {
            let h = self.knots[i + 1] - self.knots[i];
            let difference = [p[0] - q[0], p[1] - q[1], p[2] - q[2], p[3] - q[3]];
            for v in bezier(&difference, h) {
                bound = bound.max(v.norm());
            }
        }
        Some(bound)
    }

    /// The size of segment `i`'s terms on its parameter interval, `|a| + |b| h + |c| h^2 +
    /// |d| h^3` (largest coordinate of each): the scale of the rounding in a point computed
    /// on it.
    pub fn segment_size(&self, i: usize) -> Real {
        let h = self.knots[i + 1] - self.knots[i];
        let [a, b, c, d] = &self.coef[i];
        a.amax() + b.amax() * h + c.amax() * h * h + d.amax() * h * h * h
    }

    /// A control-polygon bound of segment `i`: the box of its Bezier control points, which
    /// contains the segment (convex hull property).
    pub fn segment_box(&self, i: usize) -> (Point, Point) {
        let h = self.knots[i + 1] - self.knots[i];
        let [p0, p1, p2, p3] = bezier(&self.coef[i], h);
        let mut lo = p0;
        let mut hi = p0;
        for p in [p1, p2, p3] {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
        (Point::from(lo), Point::from(hi))
    }
}

/// The Bezier control points of the cubic `a + b s + c s^2 + d s^3` for `s` in `[0, h]`
/// (power basis to Bezier): the cubic lies in their convex hull.
fn bezier([a, b, c, d]: &[Vector; 4], h: Real) -> [Vector; 4] {
    [
        *a,
        a + b * (h / 3.0),
        a + b * (2.0 * h / 3.0) + c * (h * h / 3.0),
        a + b * h + c * (h * h) + d * (h * h * h),
    ]
}

/// Second derivatives at the knots (the `M_i` of the classic formulation), by Thomas'
/// algorithm on the tridiagonal system; `O(n)`, two allocations (the result and the
/// eliminated diagonal): this runs once per optimiser evaluation. The operations are those of
/// [`system_matrix`] and [`solve_tridiagonal`], in the same order, so the result is the same
/// to the bit.
fn second_derivatives(t: &[Real], p: &[Point], end: EndCondition) -> Vec<Vector> {
    let n = p.len();
    if n == 2 && end == EndCondition::Natural {
        return vec![Vector::zeros(); n];
    }
    let h = |i: usize| t[i + 1] - t[i];
    let slope = |i: usize| (p[i + 1] - p[i]) / h(i);
    // The right-hand side, eliminated in place below.
    let mut m = vec![Vector::zeros(); n];
    for (i, r) in m.iter_mut().enumerate().take(n - 1).skip(1) {
        *r = (slope(i) - slope(i - 1)) * 6.0;
    }
    match end {
        EndCondition::Natural => {}
        EndCondition::Clamped { start, end } => {
            m[0] = (slope(0) - start) * 6.0;
            m[n - 1] = (end - slope(n - 2)) * 6.0;
        }
        EndCondition::ClampedStart { start } => {
            m[0] = (slope(0) - start) * 6.0;
        }
        EndCondition::StartHeading { direction } => {
            let s0 = slope(0);
            let n0 = direction.norm();
            let start = if n0 > 0.0 {
                direction * (s0.norm() / n0)
            } else {
                s0
            };
            m[0] = (s0 - start) * 6.0;
        }
    }
    let row = |i: usize| system_row(&h, n, i, end);
    let mut diag = Vec::with_capacity(n);
    diag.push(row(0).1);
    for i in 1..n {
        let (sub, d, _) = row(i);
        let w = sub / diag[i - 1];
        diag.push(d - w * row(i - 1).2);
        let r = m[i - 1] * w;
        m[i] -= r;
    }
    m[n - 1] /= diag[n - 1];
    for i in (0..n - 1).rev() {
        m[i] = (m[i] - m[i + 1] * row(i).2) / diag[i];
    }
    m
}

/// Row `i` of the system for the second derivatives, `(sub, diag, sup)`:
/// `sub M[i-1] + diag M[i] + sup M[i+1]`, from the knot steps `h` and the kind of end
/// condition; `n` knots.
fn system_row(
    h: &dyn Fn(usize) -> Real,
    n: usize,
    i: usize,
    end: EndCondition,
) -> (Real, Real, Real) {
    if i > 0 && i < n - 1 {
        (h(i - 1), 2.0 * (h(i - 1) + h(i)), h(i))
    } else if i == 0 && !matches!(end, EndCondition::Natural) {
        (0.0, 2.0 * h(0), h(0))
    } else if i == n - 1 && matches!(end, EndCondition::Clamped { .. }) {
        (h(n - 2), 2.0 * h(n - 2), 0.0)
    } else {
        (0.0, 1.0, 0.0)
    }
}

/// The matrix of the system for the second derivatives, by rows:
/// `sub[i] M[i-1] + diag[i] M[i] + sup[i] M[i+1]`; it depends on the knot steps `h` and the
/// kind of end condition only.
fn system_matrix(h: &[Real], end: EndCondition) -> (Vec<Real>, Vec<Real>, Vec<Real>) {
    let n = h.len() + 1;
    let step = |i: usize| h[i];
    let rows: Vec<(Real, Real, Real)> = (0..n).map(|i| system_row(&step, n, i, end)).collect();
    (
        rows.iter().map(|r| r.0).collect(),
        rows.iter().map(|r| r.1).collect(),
        rows.iter().map(|r| r.2).collect(),
    )
}

/// Thomas' algorithm (no pivoting: the systems here are diagonally dominant).
fn solve_tridiagonal(
    sub: &[Real],
    mut diag: Vec<Real>,
    sup: &[Real],
    mut rhs: Vec<Vector>,
) -> Vec<Vector> {
    let n = diag.len();
    for i in 1..n {
        let w = sub[i] / diag[i - 1];
        diag[i] -= w * sup[i - 1];
        let r = rhs[i - 1] * w;
        rhs[i] -= r;
    }
    let mut m = vec![Vector::zeros(); n];
    m[n - 1] = rhs[n - 1] / diag[n - 1];
    for i in (0..n - 1).rev() {
        m[i] = (rhs[i] - m[i + 1] * sup[i]) / diag[i];
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_samples_are_the_positions_at_k_over_n() {
        let pts: Vec<Point> = (0..9)
            .map(|i| {
                Point::new(
                    i as Real * 1.7 + (i * i % 5) as Real,
                    (i as Real * 1.3).sin() * 4.0,
                )
            })
            .collect();
        for par in [Parametrization::Uniform, Parametrization::ChordLength] {
            let s = Spline::new(&pts, par, EndCondition::Natural).unwrap();
            for n in [1, 7, 8, 64, 101] {
                let walked = s.sample_uniform(n);
                for (k, p) in walked.iter().enumerate() {
                    assert_eq!(*p, s.position(k as Real / n as Real), "{par:?} n {n} k {k}");
                }
            }
        }
    }

    #[test]
    fn two_points_give_a_straight_line() {
        let s = Spline::natural(&[Point::new(0.0, 0.0), Point::new(3.0, 4.0)]).unwrap();
        assert!((s.length() - 5.0).abs() < 1e-12);
        assert!((s.position(0.5) - Point::new(1.5, 2.0)).norm() < 1e-12);
        assert!(s.acceleration(0.3).norm() < 1e-12);
    }

    #[test]
    fn natural_ends_have_zero_curvature_and_clamped_ends_their_slope() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 2.0),
            Point::new(3.0, -1.0),
            Point::new(4.0, 0.5),
        ];
        let s = Spline::natural(&pts).unwrap();
        assert!(s.acceleration(0.0).norm() < 1e-9 && s.acceleration(1.0).norm() < 1e-9);
        let (a, b) = (Vector::new(1.0, 0.0), Vector::new(0.0, -2.0));
        let c = Spline::new(
            &pts,
            Parametrization::ChordLength,
            EndCondition::Clamped { start: a, end: b },
        )
        .unwrap();
        assert!((c.velocity(0.0) - a).norm() < 1e-9 && (c.velocity(1.0) - b).norm() < 1e-9);
        for (k, p) in pts.iter().enumerate() {
            assert!((c.position(c.knots()[k]) - p).norm() < 1e-12);
        }
        let h = Spline::new(
            &pts,
            Parametrization::Uniform,
            EndCondition::StartHeading { direction: a },
        )
        .unwrap();
        let v0 = h.velocity(0.0);
        assert!(v0.y.abs() < 1e-9 && v0.x > 0.0 && h.acceleration(1.0).norm() < 1e-9);
        assert!((v0.norm() - (pts[1] - pts[0]).norm() * 3.0).abs() < 1e-9);
    }

    #[test]
    fn errors_are_typed() {
        assert_eq!(
            Spline::natural(&[Point::new(0.0, 0.0)]),
            Err(SplineError::TooFewPoints(1))
        );
        let p = [Point::new(0.0, 0.0), Point::new(Real::NAN, 0.0)];
        assert_eq!(Spline::natural(&p), Err(SplineError::NonFinite(1)));
        let p = [
            Point::new(0.0, 0.0),
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
        ];
        assert_eq!(
            Spline::new(&p, Parametrization::ChordLength, EndCondition::Natural),
            Err(SplineError::Coincident(0, 1))
        );
    }
}
