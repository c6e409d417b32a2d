//! Sensing: every robot looks around, and what it finds updates the known world.

use homospline_geom::{Point, Real};

use super::planner::Planner;
use super::record::{EventKind, Record, Robot};
use super::route::{Drive, Polyline};
use super::scouts::Scout;
use crate::known::Known;

/// What one look found.
pub(super) struct Found {
    /// Something the known world lacks.
    hidden: bool,
    /// A mapped obstacle gone.
    cleared: bool,
}

impl Found {
    /// Nothing found.
    pub(super) fn nothing() -> Self {
        Self {
            hidden: false,
            cleared: false,
        }
    }

    /// What either found.
    pub(super) fn or(self, other: Found) -> Found {
        Found {
            hidden: self.hidden || other.hidden,
            cleared: self.cleared || other.cleared,
        }
    }

    /// Whether a mapped obstacle was found gone.
    pub(super) fn cleared(&self) -> bool {
        self.cleared
    }

    /// Whether anything was found.
    pub(super) fn any(&self) -> bool {
        self.hidden || self.cleared
    }
}

/// The robots look around at time `t`: the UGV at `at` seeing `range` (when given), then
/// each of `scouts` where it is. Each difference between the known world and the truth that
/// comes within range is an event `Discovered` at the UGV's position.
pub(super) fn look<K: Known>(
    known: &mut K,
    (at, range): (Point, Option<Real>),
    scouts: &[Scout],
    record: &mut Record,
    t: Real,
) -> Found {
    let mut found = Found::nothing();
    let observers: Vec<(Robot, Point, Real)> = range
        .map(|r| (Robot::Ugv, at, r))
        .into_iter()
        .chain(
            scouts
                .iter()
                .enumerate()
                .map(|(i, sc)| (Robot::Uav(i), sc.pos, sc.uav.sensor_range)),
        )
        .collect();
    for (by, p, range) in observers {
        for (obstacle, hidden) in known.sense(&p, range) {
            record.event(
                t,
                at,
                EventKind::Discovered {
                    obstacle,
                    hidden,
                    by,
                },
            );
            if hidden {
                found.hidden = true;
            } else {
                found.cleared = true;
            }
        }
    }
    found
}

/// Applies what was `found` to the known world (the update's wall time waits for the next
/// re-plan): mapped obstacles found gone may rename the classes of the route and its
/// alternatives; alternatives now blocked are closed (events at `t`, the UGV at `at`).
pub(super) fn discover<K: Known>(
    planner: &mut Planner<'_, K>,
    drive: &mut Drive,
    record: &mut Record,
    found: &Found,
    (t, at): (Real, Point),
) {
    planner.pending_ms += planner.known.update();
    if found.cleared
        && let Some(rays) = planner.known.renamed()
    {
        planner.rays = rays;
        let track = &record.ugv.samples;
        drive.route.class = drive.route.class_on(&planner.rays, track);
        for a in &mut drive.alternatives {
            a.class = a.class_on(&planner.rays, track);
        }
    }
    drive.alternatives.retain(|a| {
        let ok = planner.clear(&a.line.pts);
        if !ok {
            record.event(
                t,
                at,
                EventKind::ClassClosed {
                    class: a.class.clone(),
                },
            );
        }
        ok
    });
}

/// Takes onto the UGV's map what covers the point `b` of the team's map (a blockage the
/// scouts found on the UGV's route, when the UGV leaves its route for it): the least range
/// about `b` that finds something (the clearance is the robot body's, so the obstacle may be
/// up to its radius away, and a map's cells are whole). Its events were recorded when the
/// scouts found it.
pub(super) fn admit<K: Known>(own: &mut Planner<'_, K>, b: &Point) {
    for range in [1e-6, 0.25, 0.5, 1.0, 2.0, 4.0] {
        if !own.known.sense(b, range).is_empty() {
            own.pending_ms += own.known.update();
            return;
        }
    }
}

/// Takes onto the UGV's map (`own`) what the UGV, seeing `range`, would see itself driving
/// `line` from arc length `from` on, where the robots have seen it already (`own.seen`):
/// every find within `range` of the line's points a quarter of `range` apart (at most 4,000
/// of them) in those stretches. Events are not recorded again: the scouts' were. What was
/// found; the caller applies it ([`discover`]).
pub(super) fn take_in_along<K: Known>(
    own: &mut Planner<'_, K>,
    line: &Polyline,
    from: Real,
    range: Real,
) -> Found {
    let unseen = own.seen.unseen(line, from);
    let end = line.length();
    let step = (0.25 * range).max(end / 4000.0).max(1e-9);
    let mut found = Found::nothing();
    let mut s = from;
    while s <= end {
        if !unseen.iter().any(|&(a, b)| a <= s && s <= b) {
            for (_, hidden) in own.known.sense(&line.at(s).0, range) {
                if hidden {
                    found.hidden = true;
                } else {
                    found.cleared = true;
                }
            }
        }
        s += step;
    }
    found
}
