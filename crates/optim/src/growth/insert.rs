//! The growth after a round ([`Growth::grow_one`]): one more via-point where the curve is
//! most threatened or longest, kept if the grown curve is admissible and as clear as it
//! must be, else on probation.

use homospline_geom::{Point, Real};
use homospline_spline::{ClearanceModel, CostTerms, EndCondition, Spline, evaluate, min_clearance};

use super::config::GrowthConfig;
use super::guard::{Guard, admissible};
use super::state::{Growth, Probation, build, fixed_end};

impl Growth {
    /// One more via-point on the current curve, where it helps most: in the segment that
    /// holds the point of least clearance (the path is most threatened there), else the
    /// longest segment. The curve through one more point of itself is nearly the same curve,
    /// but not quite: the knots move, and a short curve can shift by a unit. It is kept if it
    /// is still admissible, no less clear than the floor's ratchet allows, and (if the curve
    /// keeps the dm rule's target) no less clear than the target. A curve held at the floor
    /// or the target often fails that by a hair, so the other segments are tried (longest
    /// first), then the curve resampled at the new knots. If none keeps it, the clearest
    /// admissible one seeds the next round on probation: that round must bring the curve
    /// back, or the loop ends on the curve before the growth. `false` when no grown curve is
    /// admissible.
    pub(super) fn grow_one(
        &mut self,
        model: &dyn ClearanceModel,
        cfg: &GrowthConfig,
        outer: &Guard<'_>,
        guard: &Guard<'_>,
    ) -> bool {
        let (s, t) = (self.s, self.t);
        let sp = &self.spline;
        let clear = min_clearance(sp, model, 1e-3);
        let mut order: Vec<usize> = (0..sp.segments()).collect();
        order.sort_by(|&a, &b| sp.segment_length(b).total_cmp(&sp.segment_length(a)));
        if clear.upper < cfg.cost.dm {
            let worst = sp.locate(clear.at).0;
            order.retain(|&i| i != worst);
            order.insert(0, worst);
        }
        let k = sp.knots();
        let n = self.points.len();
        let points = &self.points;
        let inserted = order.iter().map(|&seg| {
            let mut grown = points.clone();
            grown.insert(seg + 1, sp.position(0.5 * (k[seg] + k[seg + 1])));
            grown
        });
        let resampled = (0..=n)
            .map(|i| match i {
                0 => s,
                i if i == n => t,
                i => sp.position(i as Real / n as Real),
            })
            .collect::<Vec<_>>();
        // A grown curve must keep the ratchet's floor, and the target if the curve keeps it.
        let grown_guard = outer.ratchet(self.current);
        let floor = grown_guard.clearance_floor;
        let target = guard.clearance_target;
        let need = if self.current >= target {
            target
        } else {
            floor
        };
        let unfloored = Guard {
            clearance_floor: Real::NEG_INFINITY,
            ..guard.clone()
        };
        // Without a floor or a target (maps) only the first choice is tried, as the paper
        // does.
        let tries = if need.is_finite() { usize::MAX } else { 1 };
        let mut clearest: Option<(Vec<Point>, EndCondition, Spline, CostTerms)> = None;
        let mut kept = None;
        for grown in inserted.chain(std::iter::once(resampled)).take(tries) {
            let grown_end = fixed_end(&grown, cfg);
            let Some(sp2) = build(&grown, grown_end, cfg) else {
                continue;
            };
            if !(admissible(&sp2, &unfloored, cfg.guard_samples) && guard.certifies(&sp2, model)) {
                continue;
            }
            let terms = evaluate(&sp2, model, &cfg.cost);
            let m = terms.min_clearance;
            if grown_guard.rejects(m) {
                continue;
            }
            if m >= need {
                kept = Some((grown, grown_end, sp2, terms));
                break;
            }
            if clearest.as_ref().is_none_or(|c| m > c.3.min_clearance) {
                clearest = Some((grown, grown_end, sp2, terms));
            }
        }
        let Some((grown, grown_end, sp2, terms)) = kept.or_else(|| {
            self.probation = clearest.is_some().then(|| Probation {
                points: self.points.clone(),
                spline: self.spline.clone(),
                cost: self.best_cost,
                floor: need,
            });
            clearest
        }) else {
            return false;
        };
        self.best_cost = guard.value(&terms);
        self.current = terms.min_clearance;
        self.points = grown;
        self.spline = sp2;
        self.end = grown_end;
        true
    }
}
