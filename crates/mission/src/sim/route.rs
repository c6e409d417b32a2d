//! The paths the UGV drives and the scouts fly: polylines with arc length, the class routes,
//! and the UGV's progress along its route.

use homospline_geom::{Point, Real, Vector};
use homospline_homotopy::Rays;

use super::record::{Adopted, Track};

/// A path being driven or flown, with cumulative arc length.
#[derive(Clone, Debug)]
pub struct Polyline {
    /// Its points.
    pub pts: Vec<Point>,
    /// Arc length at each point.
    pub cum: Vec<Real>,
}

impl Polyline {
    /// The polyline through `pts`.
    pub fn new(pts: Vec<Point>) -> Self {
        let mut cum = Vec::with_capacity(pts.len());
        let mut acc = 0.0;
        for (i, p) in pts.iter().enumerate() {
            if i > 0 {
                acc += (p - pts[i - 1]).norm();
            }
            cum.push(acc);
        }
        Self { pts, cum }
    }

    /// Its length.
    pub fn length(&self) -> Real {
        self.cum.last().copied().unwrap_or(0.0)
    }

    /// The point at arc length `s` and the index of the segment it is on.
    pub fn at(&self, s: Real) -> (Point, usize) {
        let n = self.pts.len();
        if n == 1 || s <= 0.0 {
            return (self.pts[0], 0);
        }
        if s >= self.length() {
            return (self.pts[n - 1], n - 2);
        }
        let i = self.cum.partition_point(|&c| c <= s).clamp(1, n - 1);
        let seg = self.cum[i] - self.cum[i - 1];
        let f = if seg > 0.0 {
            (s - self.cum[i - 1]) / seg
        } else {
            0.0
        };
        (self.pts[i - 1] + (self.pts[i] - self.pts[i - 1]) * f, i - 1)
    }

    /// The direction of travel at arc length `s`.
    pub fn heading(&self, s: Real) -> Vector {
        let (_, i) = self.at(s);
        let d = self.pts[(i + 1).min(self.pts.len() - 1)] - self.pts[i];
        if d.norm() > 0.0 {
            d / d.norm()
        } else {
            Vector::zeros()
        }
    }

    /// The part from arc length `a` to `b`.
    pub fn slice(&self, a: Real, b: Real) -> Vec<Point> {
        let (pa, ia) = self.at(a);
        let (pb, ib) = self.at(b);
        let mut out = vec![pa];
        out.extend(self.pts[ia + 1..=ib].iter().copied());
        out.push(pb);
        out.dedup();
        out
    }
}

/// A class path the UGV may drive.
#[derive(Clone, Debug)]
pub(super) struct Route {
    /// The signature, on the naming rays, of the UGV's track up to where the route was
    /// planned followed by the route: a class's name does not change as the UGV drives past
    /// a ray (a route's own word from the UGV's position would).
    pub(super) class: String,
    pub(super) line: Polyline,
    pub(super) via: Vec<Point>,
    pub(super) cost: Real,
    /// Samples of the UGV's track when the route was planned (for renaming).
    pub(super) track_len: usize,
}

impl Route {
    /// The UGV standing at `at`: a route of one point, in no class (before any plan).
    pub(super) fn standing(at: Point) -> Self {
        Self {
            class: String::new(),
            line: Polyline::new(vec![at]),
            via: vec![at],
            cost: 0.0,
            track_len: 1,
        }
    }

    /// The route's class name on `rays`, the UGV's track being `track` (see
    /// [`Route::class`]).
    pub(super) fn class_on(&self, rays: &Rays, track: &[(Real, Point)]) -> String {
        let mut pts: Vec<Point> = track[..self.track_len.min(track.len())]
            .iter()
            .map(|&(_, p)| p)
            .collect();
        pts.extend(self.line.pts.iter().copied());
        rays.signature(&pts).to_string()
    }
}

/// The UGV on its route: how far along it is, the other classes it may take, and how far it
/// has driven.
pub(super) struct Drive {
    /// The route being driven.
    pub(super) route: Route,
    /// The other collision-free classes, best first.
    pub(super) alternatives: Vec<Route>,
    /// Arc length along `route`.
    pub(super) s: Real,
    /// Distance driven since the start.
    pub(super) driven: Real,
    /// Distance driven when `route` was adopted.
    pub(super) adopted_at: Real,
    /// When the UGV last switched class.
    pub(super) last_switch: Real,
    /// Where along `route` the UGV re-plans, having driven on toward a blockage found
    /// ahead until it would see it itself (policies that weigh driving on).
    pub(super) replan_at: Option<Real>,
    /// Holding where it is while the scouts verify shorter classes (policies that
    /// [`verify`](super::policy::ScoutPolicy::verifies)).
    pub(super) hold: Option<Hold>,
    /// The version of the team's map on which a blockage the scouts found on this route was
    /// last weighed (a policy that verifies weighs it again only when the team's map has
    /// changed).
    pub(super) weighed: Option<u64>,
    /// The route is a verified detour: the robots saw it clear all along when the UGV took
    /// it, and the UGV keeps it unless it is found blocked.
    pub(super) verified: bool,
}

/// The UGV holding where it is, its route known blocked ahead by the scouts, while they
/// verify the classes that are shorter than driving on until it would see the blockage
/// itself.
#[derive(Clone, Debug)]
pub(super) struct Hold {
    /// Those classes from here, best first; a class the known world blocks is dropped.
    pub(super) candidates: Vec<Route>,
    /// The first point of the route the blockage blocks (`None`: holding at the start
    /// while the scouts sweep the offline plan's route).
    pub(super) blocked: Option<Point>,
    /// When it gives up holding and drives on.
    pub(super) until: Real,
}

impl Drive {
    /// At the start of `route`, nothing driven yet.
    pub(super) fn new(route: Route, alternatives: Vec<Route>) -> Self {
        Self {
            route,
            alternatives,
            s: 0.0,
            driven: 0.0,
            adopted_at: 0.0,
            last_switch: Real::NEG_INFINITY,
            replan_at: None,
            hold: None,
            weighed: None,
            verified: false,
        }
    }

    /// Where the UGV is.
    pub(super) fn position(&self) -> Point {
        self.route.line.at(self.s).0
    }

    /// Distance driven on the route since it was adopted.
    pub(super) fn on_route(&self) -> Real {
        self.driven - self.adopted_at
    }

    /// Drives `route` from here at time `t`, with `alternatives` beside it; `adopted`
    /// records it.
    pub(super) fn take(
        &mut self,
        route: Route,
        alternatives: Vec<Route>,
        t: Real,
        adopted: &mut Vec<Adopted>,
    ) {
        self.alternatives = alternatives;
        self.route = route;
        self.s = 0.0;
        self.replan_at = None;
        self.hold = None;
        self.weighed = None;
        self.verified = false;
        self.adopted_at = self.driven;
        adopted.push(Adopted {
            t,
            class: self.route.class.clone(),
            path: self.route.line.pts.clone(),
        });
    }

    /// Drives `step` along the route (less at its end) in the time step of `dt` that ends
    /// at `t`. The track follows the route's polyline, the certified path: every vertex
    /// passed in the step is a sample (at the time the UGV passes it), so that no segment of
    /// the track cuts a corner of the route; then the position at `t`. Whether the route's
    /// end was reached.
    pub(super) fn advance(&mut self, step: Real, dt: Real, t: Real, track: &mut Track) -> bool {
        let line = &self.route.line;
        let left = line.length() - self.s;
        let moved = step.min(left);
        let s = self.s;
        let t0 = t - dt;
        for (&c, &p) in line.cum.iter().zip(&line.pts) {
            if c > s && c < s + moved {
                track.samples.push((t0 + dt * (c - s) / moved, p));
            }
        }
        self.s += moved;
        self.driven += moved;
        track.samples.push((t, self.position()));
        left <= step
    }
}
