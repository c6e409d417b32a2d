//! The planner on the known world as the mission uses it: the classes from the UGV's
//! position as routes named on the class-naming rays, the cost of the rest of a route, and
//! the check that a path is clear.

use std::time::Instant;

use homospline_geom::{Point, Real, Vector};
use homospline_homotopy::Rays;
use homospline_optim::Plan;
use homospline_spline::{EndCondition, Spline, evaluate};

use super::config::MissionConfig;
use super::coverage::Coverage;
use super::record::Record;
use super::route::{Polyline, Route};
use crate::known::Known;

/// The known world with the planner's settings and the rays that name classes.
pub(super) struct Planner<'a, K: Known> {
    pub(super) cfg: &'a MissionConfig,
    pub(super) known: K,
    /// The rays that name classes.
    pub(super) rays: Rays,
    /// Wall time of map updates not yet counted in a re-plan.
    pub(super) pending_ms: Real,
    /// What the robots have seen so far.
    pub(super) seen: Coverage,
    /// How many times the known world has changed.
    pub(super) version: u64,
}

impl<K: Known> Planner<'_, K> {
    /// The collision-free classes of a plan from `from` on the known map, best first:
    /// leaving along `heading` when given (a UGV on the move), `online`: a re-plan during the
    /// mission, not the offline plan. The plan's wall time (with the map updates' not yet
    /// counted) goes to `record`, whose UGV track names the classes.
    pub(super) fn routes_from(
        &mut self,
        from: Point,
        heading: Option<Vector>,
        online: bool,
        record: &mut Record,
    ) -> Vec<Route> {
        let cfg = match heading {
            Some(h) => self.cfg.replan_config(h),
            None => self.cfg.plan.clone(),
        };
        let t0 = Instant::now();
        let p: Option<Plan> = self.known.plan_from(from, &cfg, online);
        let ms = t0.elapsed().as_secs_f64() * 1e3 + std::mem::take(&mut self.pending_ms);
        record.replan_ms.push(ms);
        let track = &record.ugv.samples;
        let driven: Vec<Point> = track.iter().map(|&(_, p)| p).collect();
        let prefix = self.rays.signature(&driven);
        p.map(|p| {
            p.classes
                .into_iter()
                .filter(|c| c.collision_free)
                .map(|c| Route {
                    class: prefix.concat(&self.rays.signature(&c.path)).to_string(),
                    line: Polyline::new(c.path),
                    via: c.via_points,
                    cost: c.cost.total,
                    track_len: track.len(),
                })
                .collect()
        })
        .unwrap_or_default()
    }

    /// The cost of driving the rest of `route` from arc length `s` on the known map: the
    /// spline through the UGV's position and the via-points still ahead.
    pub(super) fn remaining_cost(&self, route: &Route, s: Real, heading: Vector) -> Real {
        let (pos, _) = route.line.at(s);
        let goal = *route.via.last().unwrap_or(&pos);
        let ahead_of = |p: &Point| {
            // A via-point is ahead if the path reaches its nearest sample after `s`.
            let k = (0..route.line.pts.len())
                .min_by(|&a, &b| {
                    (route.line.pts[a] - p)
                        .norm_squared()
                        .total_cmp(&(route.line.pts[b] - p).norm_squared())
                })
                .unwrap_or(0);
            route.line.cum[k] > s
        };
        let mut pts = vec![pos];
        let inner = route
            .via
            .get(1..route.via.len().saturating_sub(1))
            .unwrap_or(&[]);
        pts.extend(inner.iter().filter(|p| ahead_of(p)));
        pts.push(goal);
        pts.dedup();
        let end = EndCondition::StartHeading { direction: heading };
        match Spline::new(&pts, self.cfg.plan.growth.parametrization, end) {
            Ok(sp) => evaluate(&sp, self.known.model(), &self.cfg.plan.growth.cost).total,
            Err(_) => Real::INFINITY,
        }
    }

    /// What a route costs more for what no robot has seen of it from arc length `from`:
    /// `1 + P u`, `u` the unseen share of that stretch, `P` the blockage prior
    /// ([`MissionConfig::blockage_prior`]; 1 when it is 0).
    pub(super) fn unseen_factor(&self, line: &Polyline, from: Real) -> Real {
        let prior = self.cfg.blockage_prior;
        let len = line.length() - from;
        if prior <= 0.0 || len <= 0.0 {
            return 1.0;
        }
        1.0 + prior * (self.seen.unseen_length(line, from) / len).min(1.0)
    }

    /// Whether the path `pts` keeps clear of the known world's obstacles (a single point
    /// does).
    pub(super) fn clear(&self, pts: &[Point]) -> bool {
        pts.len() < 2 || self.known.model().polyline_clearance(pts) > 0.0
    }
}
