//! What keeps a growth loop's candidates in place ([`Guard`]): the class, the bounds, the
//! collision check, the clearance floor and the dm rule's target, and the checks behind it.

use std::cell::RefCell;

use homospline_geom::{Bounds, Point, Real, Vector};
use homospline_homotopy::{Rays, Signature};
use homospline_spline::{
    ClearanceModel, CostTerms, Spline, evaluate_weighted_unless, is_clear_by, is_collision_free,
};

use super::config::GrowthConfig;

/// What keeps candidates in place: the class to stay in and the bounds.
#[derive(Clone, Debug)]
pub struct Guard<'a> {
    /// Ray system and the class's signature; `None` lets the curve change class.
    pub class: Option<(&'a Rays, &'a Signature)>,
    /// The robot stays inside.
    pub bounds: Bounds,
    /// Reject candidates whose clearance (at the quadrature nodes, refined near the minimum)
    /// is not positive: a seed that is collision-free stays so. Off for the straight seed,
    /// which starts in collision.
    pub collision_free: bool,
    /// Reject candidates whose clearance is below this (`-inf`: no floor). [`grow`](super::grow) applies
    /// it as a ratchet: while the current curve is below the floor, a candidate may not fall
    /// below the current curve's clearance, so a seed below the floor can still climb to it.
    pub clearance_floor: Real,
    /// A clearance to reach and keep (the dm rule; `-inf`: none). A candidate below it is
    /// not rejected: it ranks after every candidate that keeps it, by how far it falls short
    /// (then by its cost). From a seed below it the optimiser first climbs to it, then keeps
    /// it while it lowers the cost: the cost is minimised under the constraint
    /// `m(C) >= target` (an extreme barrier once it holds). Nelder-Mead compares values
    /// only, so the ranking is all it needs; L-BFGS takes it as a ratchet like the floor.
    pub clearance_target: Real,
    /// The guard's own memory: the samples of the last candidate found in the class (start
    /// with `Default::default()`). A candidate is compared with it from the obstacles near
    /// where they differ, without its signature being computed ([`Rays::same_class`]): on a
    /// map with thousands of obstacles the signature of every candidate was most of the
    /// optimisation's time.
    pub proven: RefCell<Option<Vec<Point>>>,
    /// The last candidate whose class was proven by its signature among few obstacles, and
    /// how far its samples may move and keep it ([`Rays::word_margin`]); start with
    /// `Default::default()`. A candidate of the same knots whose curve stays that close to
    /// it ([`Spline::deviation_bound`]) is in the class without its samples' signature. The
    /// answer is the signature's: only the work differs.
    pub tube: RefCell<Option<Tube>>,
}

/// A curve known to be in its class, with how far its guard samples may move and keep it
/// ([`Guard::tube`]).
#[derive(Clone, Debug)]
pub struct Tube {
    spline: Spline,
    /// [`Rays::word_margin`] of its samples.
    margin: Real,
    /// How many samples it was proven on.
    samples: usize,
    /// Its last sample (`q(1)` as computed, which may differ from the goal by rounding).
    last: Point,
    /// How far that last sample may move crossing no ray's line ([`Rays::line_gap`]).
    end_gap: Real,
}

impl Guard<'_> {
    /// The cost of a candidate, or `+inf` when the guard rejects it.
    pub fn cost(&self, spline: &Spline, model: &dyn ClearanceModel, cfg: &GrowthConfig) -> Real {
        self.cost_below(spline, model, cfg, Real::INFINITY)
    }

    /// [`Guard::cost`] for an optimiser that needs the value only below `bound`
    /// ([`crate::nelder_mead::BoundedObjective`]): the exact value below it, else a value at
    /// or above it. The cost comes first, and stops early once terms bounding it reach the
    /// bound ([`homospline_spline::cost::evaluate_weighted_unless`]: [`Guard::value`] falls
    /// as the clearance rises and rises with the total); the class and bounds checks
    /// run only for a candidate whose value is below the bound, since a rejected candidate's
    /// `+inf` is at or above it too. Whether a candidate is in its class does not depend on
    /// which candidates were checked before it (the guard's memory only speeds the check).
    pub fn cost_below(
        &self,
        spline: &Spline,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        bound: Real,
    ) -> Real {
        let enough = |low: &CostTerms| self.value(low) >= bound;
        let value = match evaluate_weighted_unless(spline, model, &cfg.cost, &enough) {
            Ok(terms) => self.value(&terms),
            Err(low) => return self.value(&low),
        };
        if value >= bound {
            return value;
        }
        if admissible(spline, self, cfg.guard_samples) {
            value
        } else {
            Real::INFINITY
        }
    }

    /// The value of a candidate of cost terms `terms`: `+inf` when rejected, above
    /// [`SHORT_OF_TARGET`] when below the clearance target, else its cost.
    pub fn value(&self, terms: &CostTerms) -> Real {
        let m = terms.min_clearance;
        if self.rejects(m) {
            Real::INFINITY
        } else if m < self.clearance_target {
            SHORT_OF_TARGET * (1.0 + (self.clearance_target - m)) + terms.total
        } else {
            terms.total
        }
    }

    /// Whether the curve is certified collision-free where the guard asks for it (samples
    /// can miss a thin overlap) and stays inside the bounds between the guard's samples:
    /// what a round's result, a grown curve and a finish's stage must pass.
    pub fn certifies(&self, spline: &Spline, model: &dyn ClearanceModel) -> bool {
        (!self.collision_free || is_collision_free(spline, model))
            && stays_in_bounds(spline, &self.bounds)
    }

    /// Whether a candidate of minimum clearance `m` is rejected.
    pub fn rejects(&self, m: Real) -> bool {
        (self.collision_free && m <= 0.0) || m < self.clearance_floor
    }

    /// This guard with its floor lowered to `current` when the current curve is below it.
    pub(super) fn ratchet(&self, current: Real) -> Self {
        let mut g = self.clone();
        if g.clearance_floor.is_finite() {
            g.clearance_floor = g.clearance_floor.min(current);
        }
        g
    }
}

/// How far below its clearance target a growth loop's final curve may be proven clear
/// before the loop takes its `m(C)` to have missed a dip ([`Growth::needs_repair`](super::Growth::needs_repair)): a
/// curve held at the target by the default search, whose least clearance Brent's method
/// finds to `1e-10` in `t`, passes.
pub const STRICT_SLACK: Real = 1e-9;

/// Whether `spline` is proven at least `clearance` clear ([`is_clear_by`], less
/// [`STRICT_SLACK`]); any curve is, against a clearance of `-inf`.
pub(super) fn proven_at(spline: &Spline, model: &dyn ClearanceModel, clearance: Real) -> bool {
    !clearance.is_finite() || is_clear_by(spline, model, clearance - STRICT_SLACK)
}

/// The value of a candidate below the clearance target is more than this; every cost is
/// far less (the largest seen, on maps, are in the tens of thousands).
pub const SHORT_OF_TARGET: Real = 1e9;

/// Up to this many obstacles (rays), the class check computes the samples' signature
/// directly; beyond, it first compares them with a polyline known to be in the class
/// ([`in_class_beside`]). The answer is the same either way. On the paper scenes (3 to 6 obstacles) the direct signature is
/// cheaper; on a map's thousands of wall pieces the sweep is (measured: docs/performance.md,
/// "Measurements behind the defaults").
pub const DIRECT_SIGNATURE_RAYS: usize = 64;

/// Up to this many obstacles (and more than [`DIRECT_SIGNATURE_RAYS`]), a candidate whose
/// sweep from the guard's last in-class samples is not clear gets its signature; beyond, the
/// loops where the sweep is not clear are read first ([`Rays::same_class`]). The answer is
/// the same either way. Among the 73 to 607 obstacles of the city and room maps the
/// signature is the cheaper (the MovingAI plans about 2 % faster); among the 18,615 of
/// random512-20-0 and the hundreds of thousands of a random 4096^2 map the loops are
/// (measured: docs/performance.md, "Class checks from the obstacles nearby").
pub const LOCAL_PROOF_RAYS: usize = 1024;

/// Whether the spline stays in bounds and (when asked) in its class, on dense samples. The
/// class holds when the samples' signature is the class's: with more than
/// [`DIRECT_SIGNATURE_RAYS`] obstacles, first by the sweep from the guard's last in-class
/// samples ([`Rays::sweep_is_clear`]) and, beyond [`LOCAL_PROOF_RAYS`], by the words of the
/// loops where it is not clear ([`Rays::same_class`]), the signature computed only when
/// those do not decide; the samples in the class become
/// the guard's new reference. Up to [`DIRECT_SIGNATURE_RAYS`] obstacles, a candidate whose
/// curve stays within the guard's [`Tube`] (the last curve whose samples' signature was
/// computed, and how far they may move keeping it) is in the class without a signature;
/// and a curve whose Bezier control boxes are inside the bounds needs no samples for them
/// (an optimiser's steps are small; the answers are the same). The collision test of a guarded candidate
/// is the cost's own `m(C)` (every quadrature node, refined near the worst one), checked
/// after the evaluation; a round's result is certified.
pub fn admissible(spline: &Spline, guard: &Guard<'_>, samples_per_segment: usize) -> bool {
    let n = spline.segments() * samples_per_segment.max(2);
    // The curve's Bezier boxes inside the bounds, by more than the samples' rounding, put
    // every sample inside.
    let boxed = boxes_inside(spline, &guard.bounds, true);
    if boxed {
        match guard.class {
            None => return true,
            Some(_) if in_tube(spline, guard, n) => return true,
            Some(_) => {}
        }
    }
    let pts = spline.sample_uniform(n);
    if !boxed && !pts.iter().all(|p| guard.bounds.contains(p)) {
        return false;
    }
    match guard.class {
        Some((rays, sig)) => {
            let mut proven = guard.proven.borrow_mut();
            let same = in_class_beside(rays, sig, proven.as_deref(), &pts);
            if same {
                if rays.len() <= DIRECT_SIGNATURE_RAYS {
                    *guard.tube.borrow_mut() = Some(Tube {
                        spline: spline.clone(),
                        margin: rays.word_margin(&pts),
                        samples: n,
                        last: pts[pts.len() - 1],
                        end_gap: rays.line_gap(&pts[pts.len() - 1]),
                    });
                }
                *proven = Some(pts);
            }
            same
        }
        None => true,
    }
}

/// Whether every segment's Bezier control box lies inside `bounds` (then so does the
/// curve); with `rounding`, inside by more than a bound on the rounding of the curve's
/// points as computed from the segment's coefficients (`1e-12` of their sizes, thousands of
/// times the rounding), so that every computed sample is inside too.
fn boxes_inside(spline: &Spline, bounds: &Bounds, rounding: bool) -> bool {
    (0..spline.segments()).all(|i| {
        let (mut lo, mut hi) = spline.segment_box(i);
        if rounding {
            let e = 1e-12 * spline.segment_size(i);
            lo -= Vector::new(e, e);
            hi += Vector::new(e, e);
        }
        bounds.contains(&lo) && bounds.contains(&hi)
    })
}

/// Whether `spline` is proven in the guard's class by its tube (for `samples` samples): it
/// has the tube curve's knots and first point, comes nowhere as far from it as the tube's
/// margin (so each of its samples lies closer than that to the tube curve's sample at the
/// same parameter), and its last sample, which rounding may move off the goal, lies within
/// both the margin and the tube's end gap of the tube's (so that the end's own move crosses
/// no ray).
fn in_tube(spline: &Spline, guard: &Guard<'_>, samples: usize) -> bool {
    let tube = guard.tube.borrow();
    let Some(tube) = tube.as_ref() else {
        return false;
    };
    let end_move = (spline.position(1.0) - tube.last).norm();
    tube.samples == samples
        && spline.points().first() == tube.spline.points().first()
        && end_move < tube.end_gap.min(tube.margin)
        && spline
            .deviation_bound(&tube.spline)
            .is_some_and(|gap| gap < tube.margin)
}

/// Whether the polyline `pts` is in the class `sig`, given `known`, a polyline known to be
/// in it (the guard's last in-class samples): up to [`DIRECT_SIGNATURE_RAYS`] obstacles by
/// its signature (cheaper than any proof there); up to [`LOCAL_PROOF_RAYS`] by the sweep
/// from `known` ([`Rays::sweep_is_clear`]), else its signature; beyond, by the words of the
/// loops where the two differ ([`Rays::same_class`]), else its signature. The answer is
/// the signature's in every case.
pub fn in_class_beside(
    rays: &Rays,
    sig: &Signature,
    known: Option<&[Point]>,
    pts: &[Point],
) -> bool {
    if rays.len() <= DIRECT_SIGNATURE_RAYS {
        &rays.signature(pts) == sig
    } else if rays.len() <= LOCAL_PROOF_RAYS {
        known.is_some_and(|k| rays.sweep_is_clear(k, pts)) || &rays.signature(pts) == sig
    } else {
        known
            .and_then(|k| rays.same_class(k, pts))
            .unwrap_or_else(|| &rays.signature(pts) == sig)
    }
}

/// Samples along a reported path, at most, before each segment's rounding up and the
/// refinement around its least clearance ([`report_spacing`]; together below twice this).
pub const MAX_REPORT_SAMPLES: Real = 100_000.0;

/// Spacing of the reported path's samples along a curve of length `length`: a thousandth of
/// it, at most half a unit (two samples per cell of a map), but no finer than
/// [`MAX_REPORT_SAMPLES`] along the curve: a scene of kilometres in metres has paths
/// of millions of half units, and an enormous scene would otherwise need billions of
/// samples (measured: docs/performance.md, "Measurements behind the defaults").
pub fn report_spacing(length: Real) -> Real {
    (length / 1000.0).min(0.5).max(length / MAX_REPORT_SAMPLES)
}

/// Whether the curve stays inside `bounds`: certified per segment by its Bezier control box,
/// else checked at the samples of the reported path (`report_spacing`).
pub fn stays_in_bounds(spline: &Spline, bounds: &Bounds) -> bool {
    boxes_inside(spline, bounds, false)
        || spline
            .sample_by_arc_length(report_spacing(spline.length()))
            .iter()
            .all(|(_, p)| bounds.contains(p))
}

/// [`in_tube`], for the unit tests.
#[cfg(test)]
pub(super) fn in_tube_for_test(spline: &Spline, guard: &Guard<'_>, samples: usize) -> bool {
    in_tube(spline, guard, samples)
}
