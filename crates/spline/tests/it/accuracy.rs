//! Accuracy of the spline and its integrals against analytic values and dense references,
//! and the certified clearance against brute force.

use homospline_geom::{Circle, Point, Real, Vector};
use homospline_spline::{
    CertifiedClearance, CircleModel, ClearanceModel, ClearanceSearch, CostConfig, EndCondition,
    Parametrization, RoughnessForm, Spline, evaluate, is_clear_by, is_collision_free,
    min_clearance,
};
use proptest::prelude::*;

fn no_obstacles() -> CircleModel {
    CircleModel::new(vec![Circle::new(1e4, 1e4, 1.0)])
}

fn only(cfg: CostConfig) -> CostConfig {
    CostConfig {
        nodes: 8,
        pieces: 2,
        tolerance: 0.0,
        ..cfg
    }
}

/// Simpson's rule with `n` (even) intervals.
fn simpson(f: impl Fn(Real) -> Real, n: usize) -> Real {
    let h = 1.0 / n as Real;
    (0..=n)
        .map(|i| {
            f(i as Real * h)
                * if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                }
        })
        .sum::<Real>()
        * h
        / 3.0
}

#[test]
fn straight_line_has_zero_roughness_and_its_length() {
    let pts = [
        Point::new(1.0, 2.0),
        Point::new(4.0, 6.0),
        Point::new(7.0, 10.0),
    ];
    let s = Spline::natural(&pts).unwrap();
    let t = evaluate(&s, &no_obstacles(), &only(CostConfig::paper_original()));
    assert!(t.roughness.abs() < 1e-12, "R = {}", t.roughness);
    assert!((t.length - 10.0).abs() < 1e-12, "L = {}", t.length);
    assert!(t.topology < 1e-12, "T far from obstacles = {}", t.topology);
}

#[test]
fn a_clamped_spline_reproduces_a_cubic_and_its_integrals() {
    // q(t) = (t, t^3): a clamped spline with the true end slopes is exactly q.
    let pts: Vec<Point> = (0..=5)
        .map(|i| i as Real / 5.0)
        .map(|t| Point::new(t, t * t * t))
        .collect();
    let end = EndCondition::Clamped {
        start: Vector::new(1.0, 0.0),
        end: Vector::new(1.0, 3.0),
    };
    let s = Spline::new(&pts, Parametrization::Uniform, end).unwrap();
    for k in 0..=100 {
        let t = k as Real / 100.0;
        assert!((s.position(t) - Point::new(t, t * t * t)).norm() < 1e-13);
    }
    // q'' = (0, 6t): integral |q''| = 3 (paper), integral |q''|^2 = 12 (energy), and the
    // authors' sqrt(12).
    for (form, expect) in [
        (RoughnessForm::Paper, 3.0),
        (RoughnessForm::Energy, 12.0),
        (RoughnessForm::Authors, Real::sqrt(12.0)),
    ] {
        let cfg = CostConfig {
            roughness: form,
            ..only(CostConfig::paper_original())
        };
        let r = evaluate(&s, &no_obstacles(), &cfg).roughness;
        assert!(
            (r - expect).abs() < 1e-12,
            "{form}: R = {r}, expected {expect}"
        );
    }
    let terms = evaluate(&s, &no_obstacles(), &only(CostConfig::paper_original()));
    let exact_len = simpson(|t| (1.0 + 9.0 * t.powi(4)).sqrt(), 200_000);
    assert!(
        (terms.length - exact_len).abs() < 1e-12,
        "L = {} vs {}",
        terms.length,
        exact_len
    );
}

#[test]
fn an_arc_has_the_length_of_the_arc() {
    // 41 points on a half circle of radius 10: the spline is within interpolation error.
    let pts: Vec<Point> = (0..=40)
        .map(|i| std::f64::consts::PI * i as Real / 40.0)
        .map(|a| Point::new(10.0 * a.cos(), 10.0 * a.sin()))
        .collect();
    let s = Spline::new(&pts, Parametrization::ChordLength, EndCondition::Natural).unwrap();
    let energy = CostConfig {
        roughness: RoughnessForm::Energy,
        ..only(CostConfig::paper_original())
    };
    let t = evaluate(&s, &no_obstacles(), &energy);
    // Natural ends put the interpolation error at the ends (measured 1.7e-4 of 31.4).
    assert!(
        (t.length - 10.0 * std::f64::consts::PI).abs() < 1e-3,
        "L = {}",
        t.length
    );
    // Roughness in arc-length-like parameters: |q''| ~ kappa * (dl/dt)^2 = L^2 / 10.
    let expect = (10.0 * std::f64::consts::PI).powi(4) / 100.0;
    assert!(
        (t.roughness / expect - 1.0).abs() < 0.02,
        "R = {} vs {}",
        t.roughness,
        expect
    );
    // The paper's form: integral |q''| ~ L^2 / 10.
    let paper = evaluate(&s, &no_obstacles(), &only(CostConfig::paper_original())).roughness;
    let expect = (10.0 * std::f64::consts::PI).powi(2) / 10.0;
    assert!(
        (paper / expect - 1.0).abs() < 0.02,
        "R = {paper} vs {expect}"
    );
}

/// Each roughness form against Simpson's rule on 200,000 intervals of its own integrand, on
/// a curve whose q'' changes direction (so |q''| is not a polynomial in t).
#[test]
fn every_roughness_form_matches_a_dense_reference() {
    let pts = [
        Point::new(0.0, 0.0),
        Point::new(10.0, 8.0),
        Point::new(20.0, -3.0),
        Point::new(24.0, 12.0),
        Point::new(40.0, 5.0),
    ];
    let s = Spline::natural(&pts).unwrap();
    let acc = |t: Real| {
        let (seg, u) = s.locate(t);
        s.eval_segment(seg, u).2
    };
    // The integrand has kinks at the knots: integrate segment by segment.
    let per_segment = |f: &dyn Fn(Real) -> Real| -> Real {
        let k = s.knots();
        (0..s.segments())
            .map(|i| {
                let (a, b) = (k[i], k[i + 1]);
                simpson(|x| f(a + (b - a) * x.min(1.0 - 1e-15)), 200_000) * (b - a)
            })
            .sum()
    };
    let bending = per_segment(&|t| acc(t).norm());
    let energy = per_segment(&|t| acc(t).norm_squared());
    for (form, expect) in [
        (RoughnessForm::Paper, bending),
        (RoughnessForm::Energy, energy),
        (RoughnessForm::Authors, energy.sqrt()),
    ] {
        let cfg = CostConfig {
            roughness: form,
            ..CostConfig::paper_original()
        };
        let r = evaluate(&s, &no_obstacles(), &cfg).roughness;
        assert!(
            (r / expect - 1.0).abs() < 1e-6,
            "{form}: R = {r}, reference {expect}"
        );
    }
}

#[test]
fn topology_far_from_every_obstacle_tends_to_zero() {
    let pts = [
        Point::new(0.0, 0.0),
        Point::new(5.0, 1.0),
        Point::new(10.0, 0.0),
    ];
    let s = Spline::natural(&pts).unwrap();
    let mut last = Real::INFINITY;
    for dist in [5.0, 10.0, 20.0, 40.0] {
        let model = CircleModel::new(vec![Circle::new(5.0, 1.0 + dist + 2.0, 2.0)]);
        let t = evaluate(&s, &model, &only(CostConfig::paper_original()));
        assert!(t.topology < last);
        last = t.topology;
    }
    assert!(last < 1e-12, "{last}");
}

/// A wiggly 12-via-point path through a 60-circle field.
fn field() -> (Spline, CircleModel) {
    let mut circles = Vec::new();
    for i in 0..60 {
        let (x, y) = ((i % 10) as Real * 9.0 + 5.0, (i / 10) as Real * 11.0 + 3.0);
        circles.push(Circle::new(
            x + (i as Real * 0.7).sin() * 2.0,
            y,
            1.5 + (i % 3) as Real * 0.5,
        ));
    }
    let pts: Vec<Point> = (0..14)
        .map(|i| {
            let t = i as Real / 13.0;
            Point::new(2.0 + 86.0 * t, 35.0 + 9.0 * (t * 11.0).sin())
        })
        .collect();
    (Spline::natural(&pts).unwrap(), CircleModel::new(circles))
}

fn full_cfg() -> CostConfig {
    let mut cfg = CostConfig::paper_voronoi();
    cfg.w_max_clearance = 0.1;
    cfg.w_danger = 0.5;
    cfg.w_critical = 0.5;
    cfg.w_passing_time = 0.2;
    cfg.danger_points = vec![(Point::new(40.0, 40.0), 8.0)];
    cfg.critical_points = vec![(Point::new(45.0, 35.0), 30.0)];
    cfg
}

#[test]
fn default_quadrature_is_within_1e_6_of_a_dense_reference() {
    let (s, model) = field();
    let cfg = full_cfg();
    let dense_cfg = CostConfig {
        nodes: 32,
        pieces: 16,
        tolerance: 0.0,
        ..cfg.clone()
    };
    let dense = evaluate(&s, &model, &dense_cfg);
    let exact = evaluate(
        &s,
        &model,
        &CostConfig {
            tolerance: 0.0,
            ..cfg.clone()
        },
    );
    let fast = evaluate(&s, &model, &cfg);
    for (name, a, b) in [
        ("total", fast.total, dense.total),
        ("topology (no truncation)", exact.topology, dense.topology),
        ("roughness", fast.roughness, dense.roughness),
        ("length", fast.length, dense.length),
        ("safety", fast.safety, dense.safety),
        ("passing_time", fast.passing_time, dense.passing_time),
    ] {
        assert!(
            (a - b).abs() <= 1e-6 * b.abs().max(1e-3),
            "{name}: {a} vs dense {b}"
        );
    }
    // The far circles' potential left out is bounded by tolerance * (g2 R + g3 L + g4 D_knots),
    // D_knots = omega^(dm - least knot clearance) <= D: at most tolerance * total.
    let least_knot = s
        .points()
        .iter()
        .map(|p| model.clearance(p).0)
        .fold(Real::INFINITY, Real::min);
    assert!(fast.min_clearance <= least_knot, "m(C) takes in the knots");
    let d_knots = cfg.omega.powf(cfg.dm - least_knot);
    let budget = cfg.tolerance
        * (cfg.w_roughness * fast.roughness + cfg.w_length * fast.length + cfg.w_safety * d_knots);
    let left_out = exact.topology - fast.topology;
    assert!(
        (0.0..=budget).contains(&left_out),
        "left out {left_out}, budget {budget}"
    );
    assert!(left_out <= cfg.tolerance * fast.total);
    assert!(
        left_out > 0.0,
        "the bench scene should exercise the truncation"
    );
}

#[test]
fn doubling_the_samples_changes_the_cost_by_less_than_1e_6() {
    let (s, model) = field();
    let cfg = full_cfg();
    let a = evaluate(&s, &model, &cfg).total;
    let b = evaluate(
        &s,
        &model,
        &CostConfig {
            pieces: cfg.pieces * 2,
            ..cfg.clone()
        },
    )
    .total;
    assert!((a - b).abs() <= 1e-6 * b.abs(), "{a} vs {b}");
}

#[test]
fn arc_length_samples_are_spaced_as_asked() {
    let (s, _) = field();
    let spacing = (s.length() / 1000.0).min(0.5);
    let samples = s.sample_by_arc_length(spacing);
    assert_eq!(samples[0].1, s.points()[0]);
    assert_eq!(samples.last().unwrap().1, *s.points().last().unwrap());
    for w in samples.windows(2) {
        assert!(w[1].0 > w[0].0);
        assert!((w[1].1 - w[0].1).norm() <= spacing * (1.0 + 1e-9));
    }
    let chord: Real = samples.windows(2).map(|w| (w[1].1 - w[0].1).norm()).sum();
    assert!((chord - s.length()).abs() < 1e-3 * s.length());
}

/// A circle model of `(x, y, r)` triples, as the strategies give them.
fn model_of(circles: Vec<(Real, Real, Real)>) -> CircleModel {
    CircleModel::new(
        circles
            .into_iter()
            .map(|(x, y, r)| Circle::new(x, y, r))
            .collect(),
    )
}

fn random_spline() -> impl Strategy<Value = Spline> {
    prop::collection::vec((0.0..60.0, 0.0..60.0), 2..10).prop_filter_map("distinct points", |v| {
        let pts: Vec<Point> = v.into_iter().map(|(x, y)| Point::new(x, y)).collect();
        Spline::natural(&pts).ok()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn spline_interpolates_and_is_c2(
        pts in prop::collection::vec((0.0..60.0, 0.0..60.0), 2..12),
        chord in any::<bool>(),
    ) {
        let pts: Vec<Point> = pts.into_iter().map(|(x, y)| Point::new(x, y)).collect();
        let param = if chord { Parametrization::ChordLength } else { Parametrization::Uniform };
        let Ok(s) = Spline::new(&pts, param, EndCondition::Natural) else { return Ok(()) };
        for (i, p) in pts.iter().enumerate() {
            prop_assert!((s.position(s.knots()[i]) - p).norm() < 1e-9);
        }
        let knots = s.knots();
        for i in 1..s.segments() {
            let h = knots[i] - knots[i - 1];
            let (p0, v0, a0) = s.eval_segment(i - 1, h);
            let (p1, v1, a1) = s.eval_segment(i, 0.0);
            let scale = 1.0 + v0.norm() + a0.norm();
            prop_assert!((p0 - p1).norm() < 1e-9 * scale);
            prop_assert!((v0 - v1).norm() < 1e-7 * scale);
            prop_assert!((a0 - a1).norm() < 1e-7 * scale);
        }
    }

    /// The deviation bound of two curves of the same knots is never below their gap at any
    /// parameter (dense samples), and is the via-points' largest move or more; curves of
    /// other knots have none. Uniform samples begin at the start exactly and end at
    /// `position(1)`.
    #[test]
    fn the_deviation_bound_bounds_the_gap(
        pts in prop::collection::vec((0.0..60.0, 0.0..60.0), 3..10),
        moves in prop::collection::vec((-3.0..3.0, -3.0..3.0), 10),
        clamped in any::<bool>(),
    ) {
        let pts: Vec<Point> = pts.into_iter().map(|(x, y)| Point::new(x, y)).collect();
        let n = pts.len();
        let moved: Vec<Point> = pts
            .iter()
            .enumerate()
            .map(|(k, p)| if k == 0 || k == n - 1 { *p } else { p + Vector::new(moves[k].0, moves[k].1) })
            .collect();
        let end = if clamped {
            EndCondition::Clamped { start: Vector::new(1.0, 2.0), end: Vector::new(-3.0, 0.5) }
        } else {
            EndCondition::Natural
        };
        let (Ok(a), Ok(b)) = (
            Spline::new(&pts, Parametrization::Uniform, end),
            Spline::new(&moved, Parametrization::Uniform, end),
        ) else { return Ok(()) };
        let bound = a.deviation_bound(&b).unwrap();
        prop_assert_eq!(b.deviation_bound(&a).unwrap(), bound);
        let largest_move = pts.iter().zip(&moved).map(|(p, q)| (p - q).norm()).fold(0.0, f64::max);
        prop_assert!(bound >= largest_move * (1.0 - 1e-12), "{} {}", bound, largest_move);
        for k in 0..=2000 {
            let t = k as f64 / 2000.0;
            let gap = (a.position(t) - b.position(t)).norm();
            prop_assert!(gap <= bound * (1.0 + 1e-12) + 1e-12, "t {} gap {} bound {}", t, gap, bound);
        }
        prop_assert_eq!(a.deviation_bound(&a).unwrap(), 0.0);
        // The guard's tube reads a curve's last sample as `position(1)`: the same bits.
        for per in [2, 8] {
            let s = a.sample_uniform(a.segments() * per);
            prop_assert_eq!(s[s.len() - 1], a.position(1.0));
            prop_assert_eq!(s[0], pts[0]);
        }
        let fewer = Spline::new(&[pts[0], pts[n - 1]], Parametrization::Uniform, end).unwrap();
        prop_assert!(a.deviation_bound(&fewer).is_none());
    }

    #[test]
    fn an_evaluation_stopped_early_bounds_the_full_one_and_one_not_stopped_is_it(
        s in random_spline(),
        circles in prop::collection::vec((0.0..60.0, 0.0..60.0, 0.5..6.0), 1..20),
        share in 0.5..1.5f64,
    ) {
        let model = model_of(circles);
        let cfg = CostConfig::paper_voronoi();
        let exact = homospline_spline::evaluate_weighted(&s, &model, &cfg);
        let bound = exact.total * share;
        let enough = |low: &homospline_spline::CostTerms| low.total >= bound;
        match homospline_spline::evaluate_weighted_unless(&s, &model, &cfg, &enough) {
            // Not stopped early: the same terms, to the bit.
            Ok(t) => prop_assert_eq!(t, exact),
            // Stopped: terms bounding the exact ones, their total at or above the bound.
            Err(low) => {
                prop_assert!(low.total >= bound && low.total <= exact.total, "{} {} {}", bound, low.total, exact.total);
                prop_assert!(low.min_clearance >= exact.min_clearance);
                prop_assert!(low.roughness <= exact.roughness && low.length <= exact.length);
                prop_assert!(low.topology <= exact.topology && low.safety <= exact.safety);
            }
        }
        // Never enough: never stopped.
        let never = homospline_spline::evaluate_weighted_unless(&s, &model, &cfg, &|_| false);
        prop_assert_eq!(never, Ok(exact));
        // A clearance target, as the dm rule's guard asks: stopped (within the field pass,
        // once a node shows it) only when the bound on m(C) is below the target.
        let target = exact.min_clearance + share - 0.5;
        let short = |low: &homospline_spline::CostTerms| low.min_clearance < target;
        match homospline_spline::evaluate_weighted_unless(&s, &model, &cfg, &short) {
            Ok(t) => prop_assert_eq!(t, exact),
            Err(low) => {
                prop_assert!(low.min_clearance < target);
                prop_assert!(low.min_clearance >= exact.min_clearance);
                prop_assert!(low.topology <= exact.topology && low.total <= exact.total);
            }
        }
    }

    #[test]
    fn box_clearance_bounds_every_segment_in_the_box(
        circles in prop::collection::vec((0.0..60.0, 0.0..60.0, 0.5..6.0), 1..40),
        corner in (0.0..60.0, 0.0..60.0),
        size in (0.0..20.0f64, 0.0..20.0f64),
        ends in prop::collection::vec((0.0..1.0, 0.0..1.0), 2),
    ) {
        let model = model_of(circles);
        let lo = Point::new(corner.0, corner.1);
        let hi = Point::new(corner.0 + size.0, corner.1 + size.1);
        let at = |(u, v): (f64, f64)| Point::new(lo.x + u * size.0, lo.y + v * size.1);
        let (a, b) = (at(ends[0]), at(ends[1]));
        let bound = model.box_clearance(&lo, &hi);
        let exact = model.segment_clearance(&a, &b);
        prop_assert!(bound <= exact + 1e-9, "{} > {}", bound, exact);
        // Not vacuous: the box's own corner is no nearer than the bound either, and the
        // bound is attained or undercut within the box's size.
        let corner_clear = model.clearance(&lo).0;
        prop_assert!(bound <= corner_clear + 1e-9);
        prop_assert!(bound >= corner_clear - size.0.hypot(size.1) - 1e-9);
    }

    #[test]
    fn certified_clearance_brackets_dense_brute_force(
        s in random_spline(),
        circles in prop::collection::vec((0.0..60.0, 0.0..60.0, 0.5..6.0), 1..20),
    ) {
        let model = model_of(circles);
        let tol = 1e-4;
        let c = min_clearance(&s, &model, tol);
        let n = 20_000;
        let brute = (0..=n).map(|k| model.clearance(&s.position(k as Real / n as Real)).0).fold(Real::INFINITY, Real::min);
        prop_assert!(c.lower <= brute + 1e-9, "lower {} > brute {}", c.lower, brute);
        prop_assert!(c.upper - c.lower <= tol + 1e-12);
        // The attained value is a real clearance of the curve.
        prop_assert!((model.clearance(&s.position(c.at)).0 - c.upper).abs() < 1e-9);
        // lower <= true minimum <= brute, and upper - lower <= tol.
        prop_assert!(c.upper - brute <= tol + 1e-9, "upper {} brute {}", c.upper, brute);
        // The yes/no certificate: never free when a sample collides; free whenever the
        // bracket proves it; and it agrees with the bracket away from a tol-wide band at 0.
        let free = is_collision_free(&s, &model);
        if brute <= 0.0 {
            prop_assert!(!free, "certified free, yet a sample has clearance {}", brute);
        }
        if c.collision_free() {
            prop_assert!(free, "the bracket proves it free (lower {})", c.lower);
        }
        if c.lower > tol || c.upper <= 0.0 {
            prop_assert_eq!(free, c.collision_free());
        }
    }
}

proptest! {
    /// `m(C)` refined by Brent's method (tolerance 1e-10 in `t`) is the curve's least
    /// clearance where it has one basin: a circle beside a gentle arc through three points,
    /// against a dense search (20,000 samples, then golden sections in the best sample's
    /// bracket down to 1e-15). Brent's answer is an attained clearance, so it is never below
    /// the least, and it is above it by rounding only.
    #[test]
    fn refined_least_clearance_matches_a_dense_search(
        cx in 3.0..7.0f64,
        cy in 1.5..4.0f64,
        r in 0.3..1.2f64,
        y in -0.3..0.3f64,
        x in 3.0..7.0f64,
    ) {
        let pts = [Point::new(0.0, 0.0), Point::new(x, y), Point::new(10.0, 0.0)];
        let s = Spline::natural(&pts).unwrap();
        let model = CircleModel::new(vec![Circle::new(cx, cy, r)]);
        let f = |t: Real| model.clearance(&s.position(t)).0;
        let dense = 20_000;
        let best = (0..=dense).min_by(|&a, &b| {
            f(a as Real / dense as Real).total_cmp(&f(b as Real / dense as Real))
        }).unwrap();
        let (mut a, mut b) = (
            (best.max(1) - 1) as Real / dense as Real,
            ((best + 1).min(dense)) as Real / dense as Real,
        );
        while b - a > 1e-15 {
            let (m1, m2) = (a + (b - a) * 0.382, b - (b - a) * 0.382);
            if f(m1) < f(m2) { b = m2 } else { a = m1 }
        }
        let least = f(0.5 * (a + b)).min(f(best as Real / dense as Real));
        let m = evaluate(&s, &model, &CostConfig::paper_voronoi()).min_clearance;
        prop_assert!(m >= least - 1e-12, "m(C) {m} below the least clearance {least}");
        prop_assert!(m - least < 1e-12, "m(C) {m} vs the least clearance {least}");
    }
}

/// The paper's cost with `m(C)` searched between every two quadrature nodes.
fn every_stretch() -> CostConfig {
    CostConfig {
        clearance_search: ClearanceSearch::EveryStretch,
        ..CostConfig::paper_voronoi()
    }
}

/// `m(C)` with [`ClearanceSearch::EveryStretch`] lies in the certified bracket `c` of the
/// least clearance: at most `below` under its lower end (an attained clearance, up to
/// rounding) and at most the search's tolerance (1e-5) over its upper end.
fn every_stretch_within(
    s: &Spline,
    model: &CircleModel,
    c: &CertifiedClearance,
    below: Real,
) -> Result<(), TestCaseError> {
    let m = evaluate(s, model, &every_stretch()).min_clearance;
    prop_assert!(
        m >= c.lower - below,
        "m(C) {} below the least clearance {}",
        m,
        c.lower
    );
    prop_assert!(
        m <= c.upper + 1e-5 + 1e-9,
        "m(C) {} above the least clearance {}",
        m,
        c.upper
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// With [`ClearanceSearch::EveryStretch`], `m(C)` of a collision-free curve is its least
    /// clearance to within the search's tolerance (1e-5), against the certified bracket
    /// (1e-7): long curves among circles of all sizes, whose quadrature nodes can be units
    /// apart. It is an attained clearance, so never below the least.
    #[test]
    fn every_stretch_finds_the_least_clearance(
        s in random_spline(),
        circles in prop::collection::vec((0.0..60.0, 0.0..60.0, 0.2..6.0), 1..20),
    ) {
        let model = model_of(circles);
        let c = min_clearance(&s, &model, 1e-7);
        prop_assume!(c.lower > 0.0);
        every_stretch_within(&s, &model, &c, 1e-12)?;
    }

    /// The same for curves through obstacles, discs of radius 0 among them: the bound
    /// holds inside a disc (it is the distance to the disc's centre that cannot fall below
    /// zero), and where it says nothing (a stretch that may reach a centre) the halving
    /// goes on, up to its cap, and still finds the least clearance. Never below it.
    #[test]
    fn every_stretch_finds_the_least_clearance_in_collision_too(
        s in random_spline(),
        circles in prop::collection::vec((0.0..60.0, 0.0..60.0, 0.0..8.0), 1..20),
        points in prop::collection::vec((0.0..60.0, 0.0..60.0), 0..3),
    ) {
        let mut circles = circles;
        circles.extend(points.into_iter().map(|(x, y)| (x, y, 0.0)));
        let model = model_of(circles);
        let c = min_clearance(&s, &model, 1e-7);
        every_stretch_within(&s, &model, &c, 1e-9)?;
    }

    /// `is_clear_by(margin)` proves what the certified bracket says: a curve whose bracket
    /// lies above the margin is proven clear by it, and one that comes within it anywhere
    /// (its attained least clearance) is not.
    #[test]
    fn clear_by_agrees_with_the_certified_bracket(
        s in random_spline(),
        circles in prop::collection::vec((0.0..60.0, 0.0..60.0, 0.5..6.0), 1..20),
    ) {
        let model = model_of(circles);
        let c = min_clearance(&s, &model, 1e-6);
        prop_assert!(is_clear_by(&s, &model, c.lower - 1e-3));
        prop_assert!(!is_clear_by(&s, &model, c.upper));
        prop_assert_eq!(is_clear_by(&s, &model, 0.0), is_collision_free(&s, &model));
    }
}

/// A small circle beside a long, nearly straight curve, slid along it: between two
/// quadrature nodes the curve passes nearer to it than either node is. The default search
/// (around the worst node) misses such a dip for some positions; `EveryStretch` finds it
/// at every position, to within its tolerance.
#[test]
fn every_stretch_finds_a_dip_between_nodes_that_the_worst_node_misses() {
    let pts = [
        Point::new(0.0, 0.0),
        Point::new(40.0, 1.0),
        Point::new(80.0, 0.0),
    ];
    let s = Spline::natural(&pts).unwrap();
    let mut missed: Real = 0.0;
    for k in 0..200 {
        let x = 2.0 + 0.38 * k as Real;
        // The small circle sits about 2.5 units off the curve; the big one 2.9 off it near
        // the goal, where the nodes' least clearance then is, unless the nodes beside the
        // small circle come nearer.
        let y = |x: Real| s.position((x / 80.0).clamp(0.0, 1.0)).y;
        let model = CircleModel::new(vec![
            Circle::new(x, y(x) + 3.0, 0.5),
            Circle::new(70.0, y(70.0) - 4.9, 2.0),
        ]);
        let c = min_clearance(&s, &model, 1e-7);
        assert!(c.lower > 0.0);
        let worst = evaluate(&s, &model, &CostConfig::paper_voronoi()).min_clearance;
        let every = evaluate(&s, &model, &every_stretch()).min_clearance;
        assert!(
            every >= c.lower - 1e-12 && every <= c.upper + 1e-5,
            "at x = {x}: m(C) {every} against [{}, {}]",
            c.lower,
            c.upper
        );
        missed = missed.max(worst - c.upper);
    }
    assert!(
        missed > 0.1,
        "the default search missed by at most {missed}"
    );
}

#[test]
fn minimal_clearance_at_the_goal_is_found_exactly() {
    // The path runs straight into a circle's reach and ends there: the clearance decreases
    // all the way, so its minimum is the goal's.
    let model = CircleModel::new(vec![Circle::new(10.5, 0.3, 1.0)]);
    let pts = [
        Point::new(0.0, 0.0),
        Point::new(5.0, 0.0),
        Point::new(10.0, 0.0),
    ];
    let s = Spline::natural(&pts).unwrap();
    let t = evaluate(&s, &model, &CostConfig::paper_voronoi());
    let at_goal = model.clearance(&pts[2]).0;
    assert_eq!(t.min_clearance, at_goal);
}

/// The optimiser's evaluation skips the unweighted terms and changes nothing else: the same
/// total and `m(C)` as the full report, to the bit, with and without the optional terms.
#[test]
fn the_weighted_evaluation_has_the_full_total_and_least_clearance() {
    let (s, model) = field();
    for cfg in [
        CostConfig::paper_voronoi(),
        CostConfig::paper_original(),
        full_cfg(),
    ] {
        let (all, weighted) = (
            evaluate(&s, &model, &cfg),
            homospline_spline::evaluate_weighted(&s, &model, &cfg),
        );
        assert_eq!(all.total, weighted.total);
        assert_eq!(all.min_clearance, weighted.min_clearance);
    }
    let cfg = CostConfig::paper_voronoi();
    let weighted = homospline_spline::evaluate_weighted(&s, &model, &cfg);
    assert_eq!(weighted.passing_time, 0.0, "an unweighted term is skipped");
    assert!(evaluate(&s, &model, &cfg).passing_time > 0.0);
}
