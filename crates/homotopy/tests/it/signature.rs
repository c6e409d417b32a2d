//! Property tests of the homotopy signature.

use homospline_geom::{Point, Vector};
use homospline_homotopy::{Rays, Signature, h_distance, h_signature};
use proptest::prelude::*;

fn pts(v: &[(f64, f64)]) -> Vec<Point> {
    v.iter().map(|&(x, y)| Point::new(x, y)).collect()
}

/// Whether `p` lies in the closed triangle `abc`.
fn in_triangle(p: &Point, a: &Point, b: &Point, c: &Point) -> bool {
    let s = |u: &Point, v: &Point| (v - u).perp(&(p - u));
    let (d1, d2, d3) = (s(a, b), s(b, c), s(c, a));
    let neg = d1 < 0.0 || d2 < 0.0 || d3 < 0.0;
    let pos = d1 > 0.0 || d2 > 0.0 || d3 > 0.0;
    !(neg && pos)
}

fn path() -> impl Strategy<Value = Vec<Point>> {
    prop::collection::vec((-50.0..50.0, -50.0..50.0), 1..8).prop_map(|mid| {
        let mut v = vec![Point::new(-60.0, 0.0)];
        v.extend(mid.into_iter().map(|(x, y)| Point::new(x, y)));
        v.push(Point::new(60.0, 0.0));
        v
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Moving one vertex so that the swept triangles hold no obstacle keeps the class.
    #[test]
    fn signature_is_invariant_under_deformations_that_cross_no_obstacle(
        reps in prop::collection::vec((-50.0..50.0, -50.0..50.0), 1..30),
        p in path(),
        k in any::<prop::sample::Index>(),
        d in (-15.0..15.0, -15.0..15.0),
    ) {
        let rays = Rays::new(pts(&reps));
        let i = 1 + k.index(p.len() - 2);
        let mut q = p.clone();
        q[i] += Vector::new(d.0, d.1);
        let swept = rays.origins().iter().any(|o| in_triangle(o, &p[i - 1], &p[i], &q[i]) || in_triangle(o, &p[i], &q[i], &p[i + 1]));
        if !swept {
            prop_assert_eq!(rays.signature(&p), rays.signature(&q));
            // The H-signatures agree too.
            prop_assert!(h_distance(&h_signature(&p, rays.origins()), &h_signature(&q, rays.origins())) < 1e-9);
        }
        // Subdividing a segment never changes the class.
        let mut r = p.clone();
        r.insert(i, p[i - 1] + (p[i] - p[i - 1]) * 0.37);
        prop_assert_eq!(rays.signature(&p), rays.signature(&r));
    }

    /// A path followed by its own reverse is null-homotopic.
    #[test]
    fn a_path_and_its_reverse_give_the_identity(reps in prop::collection::vec((-50.0..50.0, -50.0..50.0), 1..30), p in path()) {
        let rays = Rays::new(pts(&reps));
        let mut there_and_back = p.clone();
        there_and_back.extend(p.iter().rev().skip(1));
        prop_assert!(rays.signature(&there_and_back).is_identity());
        let s = rays.signature(&p);
        prop_assert!(s.concat(&s.inverse()).is_identity());
    }

    /// Going round any one obstacle on its two sides gives two classes, among 200.
    #[test]
    fn the_two_sides_of_an_obstacle_are_different_classes(
        reps in prop::collection::vec((-50.0..50.0, -50.0..50.0), 200),
        which in any::<prop::sample::Index>(),
    ) {
        let origins = pts(&reps);
        let rays = Rays::new(origins.clone());
        let o = origins[which.index(200)];
        let (s, t) = (Point::new(-60.0, -60.0), Point::new(60.0, 60.0));
        // Two paths that differ only by a small loop around `o`: above and below it.
        let eps = 1e-3;
        let above = vec![s, o + Vector::new(-eps, 0.0), o + Vector::new(0.0, eps), o + Vector::new(eps, 0.0), t];
        let below = vec![s, o + Vector::new(-eps, 0.0), o + Vector::new(0.0, -eps), o + Vector::new(eps, 0.0), t];
        let near = origins.iter().filter(|q| (*q - o).norm() < 2.0 * eps).count();
        if near == 1 {
            prop_assert_ne!(rays.signature(&above), rays.signature(&below));
            // The loop above-then-back-below winds once around `o`: its word is a conjugate
            // of `o`'s letter (other rays may pass through the small loop), so cyclic
            // reduction leaves that one letter.
            let mut lp = above.clone();
            lp.extend(below.iter().rev().skip(1));
            let mut w = rays.signature(&lp).0;
            while w.len() > 1 && w[0] == -w[w.len() - 1] {
                w.remove(0);
                w.pop();
            }
            prop_assert_eq!(w.len(), 1);
            prop_assert_eq!(w[0].unsigned_abs() as usize, origins.iter().position(|q| *q == o).unwrap() + 1);
        }
    }
}

#[test]
fn text_form_is_stable() {
    assert_eq!(Signature::identity().to_string(), "e");
    assert_eq!(Signature(vec![3, -1, 12]).to_string(), "+3-1+12");
}

#[test]
fn winding_twice_is_not_winding_once() {
    // Homotopy, not homology: a commutator loop around two obstacles is not null-homotopic,
    // though its H-signature (homology) is zero.
    let rays = Rays::new(vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0)]);
    // Loops based at B = (5, -5), each going once round one obstacle from below.
    let base = Point::new(5.0, -5.0);
    let around = |c: Point, r: f64| -> Vec<Point> {
        let mut v = vec![base];
        v.extend((0..=16).map(|k| {
            let a = -std::f64::consts::FRAC_PI_2 + k as f64 / 16.0 * std::f64::consts::TAU;
            c + Vector::new(a.cos(), a.sin()) * r
        }));
        v.push(base);
        v
    };
    let (a, b) = (
        around(Point::new(0.0, 0.0), 2.0),
        around(Point::new(10.0, 0.0), 2.0),
    );
    let a_inv: Vec<Point> = a.iter().rev().copied().collect();
    let b_inv: Vec<Point> = b.iter().rev().copied().collect();
    let mut lp = Vec::new();
    for part in [&a, &b, &a_inv, &b_inv] {
        lp.extend(part.iter().copied());
    }
    let w = rays.signature(&lp);
    assert_eq!(w.0.len(), 4, "{w}");
    let h = h_signature(&lp, rays.origins());
    assert!(h.iter().all(|(_, im)| im.abs() < 1e-9), "{h:?}");
}

/// The direction by testing every pair of origins: the definition `Rays::new` must keep
/// while testing only neighbours in order along the ray's normal.
fn direction_by_all_pairs(origins: &[Point]) -> Vector {
    let mut angle: f64 = 1.4137;
    loop {
        let dir = Vector::new(angle.cos(), angle.sin());
        let collinear = origins.iter().enumerate().any(|(i, a)| {
            origins[i + 1..].iter().any(|b| {
                let v = b - a;
                (dir.x * v.y - dir.y * v.x).abs() <= 1e-9 * (1.0 + v.norm())
            })
        });
        if !collinear || angle > 1.7 {
            return dir;
        }
        angle += 0.0123;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Origins on a few lines along the first candidate directions (cell centres of a grid
    /// line up along many of them) pick the same ray direction as the all-pairs test.
    #[test]
    fn the_ray_direction_is_the_all_pairs_one(
        free in prop::collection::vec((-60.0..60.0, -60.0..60.0), 0..40),
        lined in prop::collection::vec((-60.0..60.0, -60.0..60.0, 0..4usize, -30.0..30.0), 0..20),
        grid in prop::collection::vec((-40i32..40, -40i32..40), 0..40),
    ) {
        let mut origins: Vec<Point> = free.into_iter().map(|(x, y)| Point::new(x, y)).collect();
        for (x, y, k, t) in lined {
            // A point and its copy moved along candidate direction k.
            let a = 1.4137 + 0.0123 * k as f64;
            origins.push(Point::new(x, y));
            origins.push(Point::new(x + t * a.cos(), y + t * a.sin()));
        }
        origins.extend(grid.into_iter().map(|(i, j)| Point::new(i as f64 + 0.5, j as f64 + 0.5)));
        let rays = Rays::new(origins.clone());
        prop_assert_eq!(rays.direction(), direction_by_all_pairs(&origins));
    }
}

/// The path from (-35, 0) through `inner` to (35, 0).
fn path_through(inner: &[(f64, f64)]) -> Vec<Point> {
    let mut path = vec![Point::new(-35.0, 0.0)];
    path.extend(inner.iter().map(|&(x, y)| Point::new(x, y)));
    path.push(Point::new(35.0, 0.0));
    path
}

/// `path` with its inner point `k` moved by `moves[k]` times `scale`, its ends kept.
fn moved_inner(path: &[Point], moves: &[(f64, f64)], scale: f64) -> Vec<Point> {
    let n = path.len();
    path.iter()
        .enumerate()
        .map(|(k, p)| {
            if k == 0 || k == n - 1 {
                *p
            } else {
                p + Vector::new(moves[k].0, moves[k].1) * scale
            }
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A sweep proven clear means equal signatures; and a small move far from every origin
    /// is proven clear (the proof is not vacuous).
    #[test]
    fn a_clear_sweep_keeps_the_signature(
        reps in prop::collection::vec((-30.0..30.0, -30.0..30.0), 0..60),
        inner in prop::collection::vec((-30.0..30.0, -30.0..30.0), 1..12),
        moves in prop::collection::vec((-8.0..8.0, -8.0..8.0), 12),
        tiny in 1e-6..1e-3,
    ) {
        let rays = Rays::new(reps.iter().map(|&(x, y)| Point::new(x, y)).collect());
        let from = path_through(&inner);
        let moved = |scale: f64| moved_inner(&from, &moves, scale);
        for to in [moved(1.0), moved(0.1), moved(tiny)] {
            if rays.sweep_is_clear(&from, &to) {
                prop_assert_eq!(rays.signature(&from), rays.signature(&to));
            }
        }
        // Far from every origin (no origin within 1 of the path), a tiny move is proven clear.
        let far = reps.iter().all(|&(x, y)| {
            from.windows(2).all(|w| {
                homospline_geom::math::distance_point_segment(&Point::new(x, y), &w[0], &w[1]) > 1.0
            })
        });
        if far {
            prop_assert!(rays.sweep_is_clear(&from, &moved(tiny)));
        }
    }

    /// A polyline whose every point moves by less than `word_margin` (ends kept) has the
    /// same signature, for moves up to the margin itself; and the margin is the least
    /// distance from an origin to the polyline, less rounding.
    #[test]
    fn a_move_within_the_word_margin_keeps_the_signature(
        reps in prop::collection::vec((-30.0..30.0, -30.0..30.0), 0..60),
        inner in prop::collection::vec((-30.0..30.0, -30.0..30.0), 1..12),
        moves in prop::collection::vec((-1.0..1.0, -1.0..1.0), 12),
        share in 0.0..1.0f64,
    ) {
        let origins: Vec<Point> = reps.iter().map(|&(x, y)| Point::new(x, y)).collect();
        let rays = Rays::new(origins.clone());
        let from = path_through(&inner);
        let margin = rays.word_margin(&from);
        let least = origins
            .iter()
            .map(|o| {
                from.windows(2)
                    .map(|w| homospline_geom::math::distance_point_segment(o, &w[0], &w[1]))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(f64::INFINITY, f64::min);
        if origins.is_empty() {
            prop_assert_eq!(margin, f64::INFINITY);
            return Ok(());
        }
        prop_assert!(margin <= least && margin >= (least - 1e-6).max(0.0), "{} {}", margin, least);
        // Each inner point moved by at most `share` of the margin (each move's length is at
        // most sqrt(2) before scaling).
        let to = moved_inner(&from, &moves, share * margin / 2f64.sqrt());
        prop_assert!(from.iter().zip(&to).all(|(a, b)| (a - b).norm() < margin || margin == 0.0));
        if margin > 0.0 {
            prop_assert_eq!(rays.signature(&from), rays.signature(&to));
        }
    }

    /// Whenever the local proof decides, it says what the signatures say: for moves of every
    /// size, for polylines of other point counts (the same path with points added, and
    /// another path altogether), among few and many origins.
    #[test]
    fn same_class_agrees_with_the_signatures(
        reps in prop::collection::vec((-30.0..30.0, -30.0..30.0), 0..200),
        inner in prop::collection::vec((-30.0..30.0, -30.0..30.0), 1..12),
        moves in prop::collection::vec((-8.0..8.0, -8.0..8.0), 12),
        other in prop::collection::vec((-30.0..30.0, -30.0..30.0), 0..20),
        split in 1usize..5,
    ) {
        let rays = Rays::new(reps.iter().map(|&(x, y)| Point::new(x, y)).collect());
        let from = path_through(&inner);
        let (s, t) = (from[0], from[from.len() - 1]);
        let moved = |scale: f64| moved_inner(&from, &moves, scale);
        // The same path with each segment cut in `split` pieces.
        let mut finer = vec![s];
        for w in from.windows(2) {
            for j in 1..=split {
                finer.push(w[0] + (w[1] - w[0]) * (j as f64 / split as f64));
            }
        }
        let mut another = vec![s];
        another.extend(other.iter().map(|&(x, y)| Point::new(x, y)));
        another.push(t);
        let sig = rays.signature(&from);
        for to in [moved(1.0), moved(0.1), moved(0.01), finer, another] {
            if let Some(same) = rays.same_class(&from, &to) {
                prop_assert_eq!(same, sig == rays.signature(&to));
            }
            if let Some(same) = rays.same_class(&to, &from) {
                prop_assert_eq!(same, sig == rays.signature(&to));
            }
        }
    }
}

/// The local proof decides where it should: a path and the same path cut finer (the same
/// class, with no sweep at all), and a move across one origin among many (another class),
/// each without reading more than the origins near the move.
#[test]
fn same_class_decides_a_finer_cut_and_a_move_across_one_origin() {
    // A 40 x 40 lattice of origins, one per unit square's centre.
    let reps: Vec<Point> = (0..40)
        .flat_map(|i| (0..40).map(move |j| Point::new(i as f64 + 0.5, j as f64 + 0.5)))
        .collect();
    let rays = Rays::new(reps);
    let (s, t) = (Point::new(0.0, 20.0), Point::new(40.0, 20.0));
    let path: Vec<Point> = (0..=40).map(|i| Point::new(i as f64, 20.0)).collect();
    let finer: Vec<Point> = (0..=80).map(|i| Point::new(i as f64 * 0.5, 20.0)).collect();
    assert_eq!((path[0], path[40]), (s, t));
    assert_eq!(rays.same_class(&path, &finer), Some(true));
    assert_eq!(rays.same_class(&finer, &path), Some(true));
    // Point 10 moved up by one unit: the path now passes above the origin at (9.5, 20.5)
    // and (10.5, 20.5), which it passed below.
    let mut up = path.clone();
    up[10] = Point::new(10.0, 21.2);
    assert_eq!(rays.same_class(&path, &up), Some(false));
    assert_ne!(rays.signature(&path), rays.signature(&up));
    // Moved by a hundredth, inside its unit square: the same class.
    let mut nudged = path.clone();
    nudged[10] = Point::new(10.0, 20.01);
    assert_eq!(rays.same_class(&path, &nudged), Some(true));
}
