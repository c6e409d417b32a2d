//! The clearance model: how every obstacle term of the cost sees the obstacles.
//!
//! [`ClearanceModel`] answers "how far is this point from obstacles, and towards where" and
//! the repulsive potential of equation (1). [`CircleModel`] is exact for circle sets; a grid
//! distance field (occupancy maps) implements the same trait in a later crate.

use homospline_geom::query::{distance_segment_circle, intersects_segment_circle};
use homospline_geom::{Circle, CircleSet, Point, Real, Vector};
use multiversion::multiversion;

/// Potential tails below `2 exp(-POTENTIAL_CUTOFF)` per unit length and circle are always
/// dropped: `U_c = 1 + tanh(alpha (r - d)) = 2 / (1 + exp(2 alpha (d - r)))`, so a circle whose
/// `2 alpha (d - r)` exceeds the cutoff adds less than `1.9e-13` per unit length. A cost
/// evaluation may allow more (see [`ClearanceModel::field_batch`]).
pub const POTENTIAL_CUTOFF: Real = 30.0;

/// Points per block of [`CircleModel::field_batch`]: circles are culled against the bounding
/// box of each block of consecutive points, and the kernel runs over a block's lanes.
pub const FIELD_BLOCK: usize = 8;

/// `exp(x)` without branches or library calls, so that loops over it vectorise: range
/// reduction `x = k ln 2 + r`, `|r| <= ln 2 / 2`, a degree-11 Taylor polynomial for `e^r`
/// (truncation below 6e-15 relative, evaluated by Estrin's scheme) and `2^k` assembled in
/// the exponent bits. `x` is clamped to `[-700, 700]` (the potential needs no more: `e^700`
/// already makes `U` zero).
#[inline(always)]
pub fn exp_fast(x: Real) -> Real {
    const LOG2E: Real = std::f64::consts::LOG2_E;
    const LN2_HI: Real = Real::from_bits(0x3fe6_2e42_fee0_0000); // ln 2, upper bits
    const LN2_LO: Real = Real::from_bits(0x3dea_39ef_3579_3c76); // ln 2 - LN2_HI
    const SHIFTER: Real = 6_755_399_441_055_744.0; // 1.5 * 2^52: rounds to an integer
    let x = x.clamp(-700.0, 700.0);
    let shifted = x * LOG2E + SHIFTER;
    let kf = shifted - SHIFTER;
    let r = (x - kf * LN2_HI) - kf * LN2_LO;
    // Estrin's scheme: the same polynomial in a few independent steps instead of eleven
    // dependent ones, so that consecutive calls overlap in the pipeline.
    const C: [Real; 12] = [
        1.0,
        1.0,
        0.5,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5_040.0,
        1.0 / 40_320.0,
        1.0 / 362_880.0,
        1.0 / 3_628_800.0,
        1.0 / 39_916_800.0,
    ];
    let r2 = r * r;
    let r4 = r2 * r2;
    let a0 = C[0] + C[1] * r;
    let a1 = C[2] + C[3] * r;
    let a2 = C[4] + C[5] * r;
    let a3 = C[6] + C[7] * r;
    let a4 = C[8] + C[9] * r;
    let a5 = C[10] + C[11] * r;
    let (b0, b1, b2) = (a0 + a1 * r2, a2 + a3 * r2, a4 + a5 * r2);
    let p = b0 + r4 * (b1 + r4 * b2);
    // k sits in the low mantissa bits of `shifted`: integer arithmetic only, so it vectorises.
    let k = shifted.to_bits().wrapping_sub(SHIFTER.to_bits());
    p * Real::from_bits(k.wrapping_add(1023) << 52)
}

/// What [`ClearanceModel::field_batch`] returns for one point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FieldSample {
    /// Repulsive potential.
    pub potential: Real,
    /// Its gradient.
    pub potential_grad: Vector,
    /// Clearance `d(q)`.
    pub clearance: Real,
    /// Its gradient.
    pub clearance_grad: Vector,
}

/// Obstacles as the cost sees them.
pub trait ClearanceModel: Send + Sync {
    /// Clearance `d(q)` (equation 6; negative inside) and its gradient.
    fn clearance(&self, p: &Point) -> (Real, Vector);

    /// The repulsive potential, the clearance and their gradients at each point of `pts`,
    /// written to `out`. For circles the potential is `sum_c U_c(q)` (equations 1-2); a
    /// distance field gives `1 + tanh(-alpha d(q))`.
    ///
    /// `allowance` bounds what the model may leave out: at every point, the potential of the
    /// obstacles it skips sums to at most `allowance` (and always below `2 exp(-`
    /// [`POTENTIAL_CUTOFF`]`)` per obstacle when `allowance` is 0). The clearance and its
    /// gradient stay exact.
    ///
    /// A model may treat the points in blocks of [`FIELD_BLOCK`] consecutive points (the
    /// circle model culls circles per block): a caller that splits a batch at multiples of
    /// [`FIELD_BLOCK`] gets the same values, to the bit.
    fn field_batch(&self, pts: &[Point], alpha: Real, allowance: Real, out: &mut [FieldSample]);

    /// [`ClearanceModel::field_batch`] for a caller that needs no gradient: the same
    /// potential and clearance, to the bit; the gradients are left unspecified (zero for
    /// circles). By default the full batch.
    fn field_values(&self, pts: &[Point], alpha: Real, allowance: Real, out: &mut [FieldSample]) {
        self.field_batch(pts, alpha, allowance, out);
    }

    /// The clearance at each point of `pts`, written to `out`: the same values as
    /// [`ClearanceModel::clearance`], without the gradients (a model may batch them).
    fn clearances(&self, pts: &[Point], out: &mut [Real]) {
        for (p, o) in pts.iter().zip(out.iter_mut()) {
            *o = self.clearance(p).0;
        }
    }

    /// The clearance at `p` without its gradient: [`ClearanceModel::clearances`] of the one
    /// point (the same value as [`ClearanceModel::clearance`]'s, maybe computed more cheaply).
    fn clearance_value(&self, p: &Point) -> Real {
        let mut d = [0.0];
        self.clearances(std::slice::from_ref(p), &mut d);
        d[0]
    }

    /// Whether the segment `[a, b]` is free of obstacles.
    fn line_of_sight(&self, a: &Point, b: &Point) -> bool;

    /// A lower bound of the clearance over the segment `[a, b]` (exact for circles).
    fn segment_clearance(&self, a: &Point, b: &Point) -> Real;

    /// The smallest [`ClearanceModel::segment_clearance`] over the segments of `pts` (+inf for
    /// fewer than two points).
    fn polyline_clearance(&self, pts: &[Point]) -> Real {
        pts.windows(2)
            .map(|w| self.segment_clearance(&w[0], &w[1]))
            .fold(Real::INFINITY, Real::min)
    }

    /// A lower bound of [`ClearanceModel::segment_clearance`] over every segment inside the
    /// box `[lo, hi]`; by default `-inf` (no bound). A long path checked segment by segment
    /// skips the runs of segments whose box is clearer than its least segment.
    fn box_clearance(&self, lo: &Point, hi: &Point) -> Real {
        let _ = (lo, hi);
        Real::NEG_INFINITY
    }

    /// [`ClearanceModel::segment_clearance`] when the caller already knows the
    /// [`ClearanceModel::exact_clearance`] of both ends, `da` and `db`: a model whose bound is
    /// built from them skips recomputing them. By default they are not used.
    fn segment_clearance_between(&self, a: &Point, b: &Point, da: Real, db: Real) -> Real {
        let _ = (da, db);
        self.segment_clearance(a, b)
    }

    /// A cheaper stand-in for this model inside the box `[lo, hi]`: its clearance equals this
    /// model's at every point of the box where that is at most `reach`, and is never smaller.
    /// The cost's refinement of `m(C)` asks for one around the worst node. `None` (the
    /// default) when the model has no cheaper local form.
    fn restricted(
        &self,
        _lo: &Point,
        _hi: &Point,
        _reach: Real,
    ) -> Option<Box<dyn ClearanceModel + '_>> {
        None
    }

    /// A radius `r >= 0` that bounds how sharply the clearance can bend along a curve: where
    /// the clearance `d` of a curve `q(t)` is positive, `d'' <= |q'|^2 / (d + r) + |q''|`
    /// (true of the distance to any union of discs of radius at least `r`, and of any union
    /// of convex sets with `r = 0`). The cost's `m(C)` then looks between every two
    /// quadrature nodes where this bound lets the clearance dip below its least value so
    /// far. `None` (the default): only the worst node's neighbourhood is searched.
    fn bend_radius(&self) -> Option<Real> {
        None
    }

    /// Whether [`ClearanceModel::field_batch`] leaves out potential within its `allowance`:
    /// the cost then spends a clearance query per knot to raise the allowance by the safety
    /// term's lower bound. By default not.
    fn truncates(&self) -> bool {
        false
    }

    /// The clearance that collision checks trust, at one point: the same function that
    /// `segment_clearance` bounds from below. By default the cost's clearance.
    fn exact_clearance(&self, p: &Point) -> Real {
        self.clearance(p).0
    }
}

/// Exact model of a circle set (circles already inflated by the robot radius).
#[derive(Clone, Debug)]
pub struct CircleModel {
    set: CircleSet,
    /// Centres and radii sorted by `x`, so that a block's candidates are one index range.
    xs: Vec<Real>,
    ys: Vec<Real>,
    rs: Vec<Real>,
    r_max: Real,
    /// The least radius (`inf` without circles).
    r_min: Real,
}

impl CircleModel {
    /// A model over `circles`.
    pub fn new(circles: Vec<Circle>) -> Self {
        let mut sorted = circles.clone();
        sorted.sort_by(|a, b| a.center.x.total_cmp(&b.center.x));
        Self {
            set: CircleSet::new(circles),
            xs: sorted.iter().map(|c| c.center.x).collect(),
            ys: sorted.iter().map(|c| c.center.y).collect(),
            rs: sorted.iter().map(|c| c.radius).collect(),
            r_max: sorted.iter().map(|c| c.radius).fold(0.0, Real::max),
            r_min: sorted
                .iter()
                .map(|c| c.radius)
                .fold(Real::INFINITY, Real::min),
        }
    }

    /// The underlying query set.
    pub fn set(&self) -> &CircleSet {
        &self.set
    }

    /// The exact clearance at every lane of `lanes` ([`nearest_of_all`]: every circle
    /// scanned).
    fn nearest_in_block(&self, lanes: &Lanes) -> [Real; FIELD_BLOCK] {
        let mut exact = Lanes {
            x: lanes.x,
            y: lanes.y,
            ..Lanes::default()
        };
        nearest_of_all(&mut exact, &self.xs, &self.ys, &self.rs);
        exact.best
    }

    /// [`ClearanceModel::field_batch`], with the gradients when `GRAD` (else zero).
    fn field<const GRAD: bool>(
        &self,
        pts: &[Point],
        alpha: Real,
        allowance: Real,
        out: &mut [FieldSample],
    ) {
        // A skipped circle adds at most 2 exp(-cutoff) at every point of a block; with at most
        // n circles skipped, 2 n exp(-cutoff) <= allowance bounds their sum.
        let n_circles = self.xs.len().max(1) as Real;
        let cutoff = if allowance > 0.0 {
            (2.0 * n_circles / allowance).ln().min(POTENTIAL_CUTOFF)
        } else {
            POTENTIAL_CUTOFF
        };
        let two_alpha = 2.0 * alpha;
        let cutoff_distance = cutoff / two_alpha;
        // The kept circles' indices: on the stack for the usual few dozen circles (this runs
        // once per stretch of an optimiser's evaluation: the array is zeroed each time, so
        // it is no larger than the scene needs), on the heap beyond.
        let (mut small, mut large, mut on_heap);
        let kept: &mut [usize] = if self.xs.len() <= 32 {
            small = [0usize; 32];
            &mut small[..self.xs.len()]
        } else if self.xs.len() <= 128 {
            large = [0usize; 128];
            &mut large[..self.xs.len()]
        } else {
            on_heap = vec![0usize; self.xs.len()];
            &mut on_heap
        };
        let n = pts.len().min(out.len());
        for (block_pts, block_out) in pts[..n]
            .chunks(FIELD_BLOCK)
            .zip(out[..n].chunks_mut(FIELD_BLOCK))
        {
            let mut lanes = Lanes::default();
            lanes.load(block_pts);
            let last = block_pts[block_pts.len() - 1];
            let (mut lo, mut hi) = (last, last);
            for p in block_pts {
                lo = lo.inf(p);
                hi = hi.sup(p);
            }
            // Kept when the box is within `cutoff_distance + r` of the centre; compacted
            // without branches.
            let mut n_kept = 0;
            let margin = cutoff_distance + self.r_max;
            let first = self.xs.partition_point(|&x| x < lo.x - margin);
            let end = self.xs.partition_point(|&x| x <= hi.x + margin);
            for k in first..end.max(first) {
                let gap2 = box_gap2(&lo, &hi, self.xs[k], self.ys[k]);
                let reach = cutoff_distance + self.rs[k];
                kept[n_kept] = k;
                n_kept += usize::from(reach >= 0.0 && gap2 <= reach * reach);
            }
            let kept = &kept[..n_kept];
            if GRAD {
                potential_block(&mut lanes, kept, &self.xs, &self.ys, &self.rs, alpha);
            } else {
                potential_values(&mut lanes, kept, &self.xs, &self.ys, &self.rs, alpha);
            }
            // Skipped circles are farther than the cutoff distance from every point; where no
            // kept circle is nearer than that, ask the exact query (for the whole block at
            // once when every circle is scanned).
            let far = |l: usize| lanes.best[l] > cutoff_distance;
            let all = (!GRAD && self.xs.len() <= SCAN_ALL && (0..block_pts.len()).any(far))
                .then(|| self.nearest_in_block(&lanes));
            for (l, (p, o)) in block_pts.iter().zip(block_out.iter_mut()).enumerate() {
                let (clearance, clearance_grad) = if !GRAD {
                    // The exact query's distance: both scans give the same bits.
                    let d = if !far(l) {
                        lanes.best[l]
                    } else if let Some(all) = &all {
                        all[l]
                    } else {
                        least_distance(&self.xs, &self.ys, &self.rs, self.r_max, p, p)
                    };
                    (d, Vector::zeros())
                } else if lanes.best[l] <= cutoff_distance {
                    let k = lanes.best_k[l];
                    let v = Vector::new(p.x - self.xs[k], p.y - self.ys[k]);
                    let d = v.norm();
                    (lanes.best[l], if d > 0.0 { v / d } else { Vector::zeros() })
                } else {
                    self.clearance(p)
                };
                *o = FieldSample {
                    potential: lanes.u[l],
                    potential_grad: Vector::new(lanes.gx[l], lanes.gy[l]),
                    clearance,
                    clearance_grad,
                };
            }
        }
    }
}

impl ClearanceModel for CircleModel {
    fn truncates(&self) -> bool {
        true
    }

    fn bend_radius(&self) -> Option<Real> {
        // The distance to a disc of radius `r` is `|q - c| - r`, whose second derivative
        // along `q` is at most `|q'|^2 / |q - c| + |q''|`, and `|q - c| = d + r`; the least
        // clearance of several discs lies above each disc's interpolation between two points.
        Some(self.r_min.max(0.0))
    }

    fn clearance(&self, p: &Point) -> (Real, Vector) {
        match self.set.clearance(p) {
            Some(c) => (c.distance, c.gradient),
            None => (Real::INFINITY, Vector::zeros()),
        }
    }

    fn exact_clearance(&self, p: &Point) -> Real {
        // The distance of `clearance`, to the bit, without the nearest circle's direction.
        least_distance(&self.xs, &self.ys, &self.rs, self.r_max, p, p)
    }

    fn clearances(&self, pts: &[Point], out: &mut [Real]) {
        let n = pts.len().min(out.len());
        if self.xs.len() > SCAN_ALL {
            for (p, o) in pts[..n].iter().zip(out[..n].iter_mut()) {
                *o = least_distance(&self.xs, &self.ys, &self.rs, self.r_max, p, p);
            }
            return;
        }
        for (block_pts, block_out) in pts[..n]
            .chunks(FIELD_BLOCK)
            .zip(out[..n].chunks_mut(FIELD_BLOCK))
        {
            let mut lanes = Lanes::default();
            lanes.load(block_pts);
            let exact = self.nearest_in_block(&lanes);
            block_out.copy_from_slice(&exact[..block_out.len()]);
        }
    }

    fn field_batch(&self, pts: &[Point], alpha: Real, allowance: Real, out: &mut [FieldSample]) {
        self.field::<true>(pts, alpha, allowance, out);
    }

    fn field_values(&self, pts: &[Point], alpha: Real, allowance: Real, out: &mut [FieldSample]) {
        self.field::<false>(pts, alpha, allowance, out);
    }

    fn restricted(
        &self,
        lo: &Point,
        hi: &Point,
        reach: Real,
    ) -> Option<Box<dyn ClearanceModel + '_>> {
        // A circle farther than `reach` from the whole box is never the nearest where the
        // clearance is at most `reach`. Counted first: where every circle is near (the
        // usual case among a few circles) nothing is allocated.
        let is_near = |k: usize| {
            let r = reach + self.rs[k];
            r >= 0.0 && box_gap2(lo, hi, self.xs[k], self.ys[k]) <= r * r * (1.0 + 1e-12)
        };
        let count = (0..self.xs.len()).filter(|&k| is_near(k)).count();
        if count == 0 || count == self.xs.len() {
            return None;
        }
        let near: Vec<Circle> = (0..self.xs.len())
            .filter(|&k| is_near(k))
            .map(|k| Circle::new(self.xs[k], self.ys[k], self.rs[k]))
            .collect();
        Some(Box::new(NearCircles(near)))
    }

    fn line_of_sight(&self, a: &Point, b: &Point) -> bool {
        self.set.line_of_sight(a, b)
    }

    fn segment_clearance(&self, a: &Point, b: &Point) -> Real {
        self.set
            .distance_to_segment(a, b)
            .map_or(Real::INFINITY, |d| d.0)
    }

    fn box_clearance(&self, lo: &Point, hi: &Point) -> Real {
        least_distance(&self.xs, &self.ys, &self.rs, self.r_max, lo, hi)
    }
}

/// The few circles of a [`CircleModel::restricted`] stand-in: plain loops, one allocation.
struct NearCircles(Vec<Circle>);

impl ClearanceModel for NearCircles {
    fn clearance(&self, p: &Point) -> (Real, Vector) {
        // The linear query of `CircleSet`: first circle among ties.
        let mut best: Option<(&Circle, Real)> = None;
        for c in &self.0 {
            let d = c.signed_distance(p);
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((c, d));
            }
        }
        match best {
            Some((c, d)) => {
                let v = p - c.center;
                let n = v.norm();
                (d, if n > 0.0 { v / n } else { Vector::zeros() })
            }
            None => (Real::INFINITY, Vector::zeros()),
        }
    }

    fn clearances(&self, pts: &[Point], out: &mut [Real]) {
        // The distance of `clearance` (the least signed distance; ties give the same value)
        // without its gradient: Brent's refinement of `m(C)` asks for a dozen points.
        for (p, o) in pts.iter().zip(out.iter_mut()) {
            *o = self
                .0
                .iter()
                .map(|c| c.signed_distance(p))
                .fold(Real::INFINITY, |best, d| if d < best { d } else { best });
        }
    }

    fn field_batch(&self, pts: &[Point], alpha: Real, _allowance: Real, out: &mut [FieldSample]) {
        for (p, o) in pts.iter().zip(out.iter_mut()) {
            let (clearance, clearance_grad) = self.clearance(p);
            let (mut u, mut g) = (0.0, Vector::zeros());
            for c in &self.0 {
                let v = p - c.center;
                let d = v.norm();
                let uc = 2.0 / (1.0 + (2.0 * alpha * (d - c.radius)).exp());
                u += uc;
                if d > 0.0 {
                    g += v * (-alpha * uc * (2.0 - uc) / d);
                }
            }
            *o = FieldSample {
                potential: u,
                potential_grad: g,
                clearance,
                clearance_grad,
            };
        }
    }

    fn line_of_sight(&self, a: &Point, b: &Point) -> bool {
        !self.0.iter().any(|c| intersects_segment_circle(a, b, c))
    }

    fn segment_clearance(&self, a: &Point, b: &Point) -> Real {
        self.0
            .iter()
            .map(|c| distance_segment_circle(a, b, c))
            .fold(Real::INFINITY, Real::min)
    }
}

/// One block of points and the sums [`potential_block`] accumulates for them.
struct Lanes {
    x: [Real; FIELD_BLOCK],
    y: [Real; FIELD_BLOCK],
    u: [Real; FIELD_BLOCK],
    gx: [Real; FIELD_BLOCK],
    gy: [Real; FIELD_BLOCK],
    best: [Real; FIELD_BLOCK],
    best_k: [usize; FIELD_BLOCK],
}

impl Lanes {
    /// The block's points; lanes past the end repeat the last point (their results are not
    /// read).
    fn load(&mut self, pts: &[Point]) {
        let last = pts[pts.len() - 1];
        for l in 0..FIELD_BLOCK {
            let p = pts.get(l).unwrap_or(&last);
            self.x[l] = p.x;
            self.y[l] = p.y;
        }
    }
}

impl Default for Lanes {
    fn default() -> Self {
        Self {
            x: [0.0; FIELD_BLOCK],
            y: [0.0; FIELD_BLOCK],
            u: [0.0; FIELD_BLOCK],
            gx: [0.0; FIELD_BLOCK],
            gy: [0.0; FIELD_BLOCK],
            best: [Real::INFINITY; FIELD_BLOCK],
            best_k: [usize::MAX; FIELD_BLOCK],
        }
    }
}

/// The squared distance from the box `[lo, hi]` to the point `(cx, cy)` (0 inside). For a
/// point (`lo = hi`) it is `dx^2 + dy^2` of `p - c` exactly: `max(x - cx, cx - x, 0)` is
/// `|x - cx|`.
#[inline]
fn box_gap2(lo: &Point, hi: &Point, cx: Real, cy: Real) -> Real {
    let dx = (lo.x - cx).max(cx - hi.x).max(0.0);
    let dy = (lo.y - cy).max(cy - hi.y).max(0.0);
    dx * dx + dy * dy
}

/// `min_k dist(box, (xs_k, ys_k)) - rs_k` over circles sorted by `xs` (+inf for none), for
/// the box `[lo, hi]`: no point of the box (and so of a segment in it) is nearer to a circle.
/// For a point (`lo = hi`) the distance is `|p - c|` computed as
/// [`homospline_geom::Circle::signed_distance`] does ([`box_gap2`]), so equal to
/// `CircleSet::clearance`'s. The scan starts at the box's `x` and walks
/// out both ways until the gap in `x` less `r_max` cannot beat the best: a few circles
/// instead of all.
fn least_distance(
    xs: &[Real],
    ys: &[Real],
    rs: &[Real],
    r_max: Real,
    lo: &Point,
    hi: &Point,
) -> Real {
    let at = |k: usize| box_gap2(lo, hi, xs[k], ys[k]).sqrt() - rs[k];
    let mut best = Real::INFINITY;
    let first = xs.partition_point(|&x| x < lo.x);
    for (k, &cx) in xs.iter().enumerate().skip(first) {
        if cx - hi.x - r_max > best {
            break;
        }
        best = best.min(at(k));
    }
    for (k, &cx) in xs[..first].iter().enumerate().rev() {
        if lo.x - cx - r_max > best {
            break;
        }
        best = best.min(at(k));
    }
    best
}

/// Up to this many circles, a batch of exact clearances scans every circle for
/// [`FIELD_BLOCK`] points at a time ([`nearest_of_all`], vectorised); beyond, each point's
/// x-sorted scan ([`least_distance`]) visits fewer. Both give the same bits.
const SCAN_ALL: usize = 24;

/// The least `|p - c| - r` over every circle at every lane, into `lanes.best` (which must
/// start at `+inf`): the distance computed as [`least_distance`] computes it (`|p.x - c.x|`
/// squares to the bits of `(p.x - c.x)^2`), and the least of the same values.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2", "x86_64+avx2"))]
fn nearest_of_all(lanes: &mut Lanes, xs: &[Real], ys: &[Real], rs: &[Real]) {
    for ((&cx, &cy), &r) in xs.iter().zip(ys).zip(rs) {
        for l in 0..FIELD_BLOCK {
            let (vx, vy) = (lanes.x[l] - cx, lanes.y[l] - cy);
            let c = (vx * vx + vy * vy).sqrt() - r;
            lanes.best[l] = if c < lanes.best[l] { c } else { lanes.best[l] };
        }
    }
}

/// Adds the potential of the circles `kept` at every lane, with its gradient, and tracks the
/// nearest circle.
///
/// Branch-free over the lanes so that it vectorises; compiled for AVX2 too and chosen at run
/// time. No fused multiply-add is enabled, and every operation is an IEEE one, so the AVX2
/// and the baseline versions give bit-identical results.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2", "x86_64+avx2"))]
fn potential_block(
    lanes: &mut Lanes,
    kept: &[usize],
    xs: &[Real],
    ys: &[Real],
    rs: &[Real],
    alpha: Real,
) {
    potential_kernel::<true>(lanes, kept, xs, ys, rs, alpha);
}

/// [`potential_block`] without the gradient: the same potential and nearest circle, to the
/// bit, for an optimiser that compares values only.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2", "x86_64+avx2"))]
fn potential_values(
    lanes: &mut Lanes,
    kept: &[usize],
    xs: &[Real],
    ys: &[Real],
    rs: &[Real],
    alpha: Real,
) {
    potential_kernel::<false>(lanes, kept, xs, ys, rs, alpha);
}

/// The body of both kernels, inlined into each (and so compiled for its targets).
#[inline(always)]
fn potential_kernel<const GRAD: bool>(
    lanes: &mut Lanes,
    kept: &[usize],
    xs: &[Real],
    ys: &[Real],
    rs: &[Real],
    alpha: Real,
) {
    let two_alpha = 2.0 * alpha;
    for &k in kept {
        let (cx, cy, r) = (xs[k], ys[k], rs[k]);
        for l in 0..FIELD_BLOCK {
            let (vx, vy) = (lanes.x[l] - cx, lanes.y[l] - cy);
            let d = (vx * vx + vy * vy).sqrt();
            // U = 2 / (1 + e), e = exp(2 alpha (d - r)); dU/dd = -alpha U (2 - U), and the
            // gradient is that times v / d. One division serves both: q = 1 / ((1 + e) d).
            // At the centre v = 0 and the gradient term vanishes (d is floored at 1e-150).
            // Without the gradient U is computed the same way, so its bits are the same.
            let c = d - r;
            let den = 1.0 + exp_fast(two_alpha * c);
            let ds = d.max(1e-150);
            let q = 1.0 / (den * ds);
            let u = 2.0 * ds * q;
            lanes.u[l] += u;
            if GRAD {
                let g = -alpha * u * (2.0 - u) * (den * q);
                lanes.gx[l] += g * vx;
                lanes.gy[l] += g * vy;
            }
            let better = c < lanes.best[l];
            lanes.best[l] = if better { c } else { lanes.best[l] };
            if GRAD {
                lanes.best_k[l] = if better { k } else { lanes.best_k[l] };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_fast_matches_the_library_exp() {
        let mut worst: Real = 0.0;
        let mut x = -700.0;
        while x <= 700.0 {
            let rel = (exp_fast(x) - x.exp()).abs() / x.exp();
            worst = worst.max(rel);
            x += 0.0137;
        }
        assert!(worst < 1e-14, "worst relative error {worst}");
    }

    /// `n` circles spread over `[0, w) x [0, h)` by fixed strides, radii 0.5 to 1.7.
    fn scattered(n: usize, w: Real, h: Real) -> Vec<Circle> {
        (0..n)
            .map(|i| {
                let t = i as Real;
                Circle::new((t * 7.3) % w, (t * 3.1) % h, 0.5 + (i % 4) as Real * 0.4)
            })
            .collect()
    }

    /// `n` points by fixed strides over `[-margin, span_x - margin) x [-margin, span_y -
    /// margin)`.
    fn strided_points(n: usize, span_x: Real, span_y: Real, margin: Real) -> Vec<Point> {
        (0..n)
            .map(|i| {
                let t = i as Real;
                Point::new((t * 1.37) % span_x - margin, (t * 0.73) % span_y - margin)
            })
            .collect()
    }

    #[test]
    fn batched_clearances_equal_the_single_queries_exactly() {
        // Both sides of `SCAN_ALL` (every circle scanned, or the x-sorted scan), and batches
        // that end inside a block.
        for n in [0, 1, 7, 60, SCAN_ALL, SCAN_ALL + 1, 300] {
            let model = CircleModel::new(scattered(n, 90.0, 66.0));
            for len in [500, 13, 1] {
                let pts = strided_points(len, 110.0, 86.0, 10.0);
                let mut got = vec![0.0; pts.len()];
                model.clearances(&pts, &mut got);
                for (p, g) in pts.iter().zip(&got) {
                    let want = model.clearance(p).0;
                    assert_eq!(g.to_bits(), want.to_bits(), "{n} circles at {p}");
                    let exact = model.exact_clearance(p);
                    assert_eq!(exact.to_bits(), want.to_bits(), "{n} circles at {p}");
                }
            }
        }
    }

    #[test]
    fn field_batch_keeps_clearance_exact_and_potential_within_the_allowance() {
        let circles = scattered(40, 50.0, 40.0);
        let model = CircleModel::new(circles.clone());
        let pts: Vec<Point> = (0..37)
            .map(|i| {
                Point::new(
                    i as Real * 1.37 - 3.0,
                    20.0 + (i as Real * 0.9).sin() * 15.0,
                )
            })
            .collect();
        for allowance in [0.0, 1e-9, 1e-4, 0.5] {
            let mut out = vec![FieldSample::default(); pts.len()];
            model.field_batch(&pts, 0.5, allowance, &mut out);
            for (p, o) in pts.iter().zip(&out) {
                let exact: Real = circles
                    .iter()
                    .map(|c| 1.0 + (0.5 * (c.radius - (p - c.center).norm())).tanh())
                    .sum();
                let bound = allowance.max(2.0 * 40.0 * (-POTENTIAL_CUTOFF).exp()) + 1e-12;
                assert!(
                    o.potential <= exact + 1e-12 && exact - o.potential <= bound,
                    "allowance {allowance}: {} vs {exact}",
                    o.potential
                );
                assert_eq!(o.clearance, model.clearance(p).0, "at {p}");
            }
        }
    }

    #[test]
    fn values_alone_and_split_batches_give_the_full_batch_bits() {
        for n in [0, 1, 7, 60, 300] {
            let model = CircleModel::new(scattered(n, 90.0, 66.0));
            // Points far outside the circles too, where the exact query answers.
            let pts = strided_points(203, 150.0, 120.0, 30.0);
            for allowance in [0.0, 1e-6, 0.5] {
                let mut full = vec![FieldSample::default(); pts.len()];
                model.field_batch(&pts, 0.5, allowance, &mut full);
                let mut values = vec![FieldSample::default(); pts.len()];
                model.field_values(&pts, 0.5, allowance, &mut values);
                let mut split = vec![FieldSample::default(); pts.len()];
                for (p, o) in pts
                    .chunks(3 * FIELD_BLOCK)
                    .zip(split.chunks_mut(3 * FIELD_BLOCK))
                {
                    model.field_values(p, 0.5, allowance, o);
                }
                for (i, ((f, v), s)) in full.iter().zip(&values).zip(&split).enumerate() {
                    let at = format!("{n} circles, allowance {allowance}, point {i}");
                    assert_eq!(f.potential.to_bits(), v.potential.to_bits(), "{at}");
                    assert_eq!(f.clearance.to_bits(), v.clearance.to_bits(), "{at}");
                    assert_eq!(f.potential.to_bits(), s.potential.to_bits(), "{at}");
                    assert_eq!(f.clearance.to_bits(), s.clearance.to_bits(), "{at}");
                }
            }
        }
    }

    #[test]
    fn restricted_model_agrees_where_the_clearance_is_within_reach() {
        let model = CircleModel::new(scattered(30, 40.0, 30.0));
        let (lo, hi) = (Point::new(10.0, 8.0), Point::new(16.0, 12.0));
        for reach in [-0.5, 0.3, 2.0] {
            let near = model.restricted(&lo, &hi, reach).expect("a strict subset");
            for k in 0..400 {
                let p = Point::new(lo.x + (k % 20) as Real * 0.3, lo.y + (k / 20) as Real * 0.2);
                let (full, g) = model.clearance(&p);
                let (local, gl) = near.clearance(&p);
                if full <= reach {
                    assert_eq!((local, gl), (full, g), "at {p}, reach {reach}");
                } else {
                    assert!(local >= full, "at {p}: {local} < {full}");
                }
            }
        }
    }
}
