//! Edge polylines: a chain of lattice points (corners, cell centres) simplified to within
//! [`POLYLINE_TOLERANCE`] cell by the workspace's one Douglas-Peucker
//! ([`homospline_geom::math::douglas_peucker`]), and an edge's length and clearances from
//! them. Shared by the crack graph, the complete graph and both ways of attaching start and
//! goal.

use homospline_geom::math::douglas_peucker;
use homospline_geom::{Point, Real};

use crate::graph::{Edge, POLYLINE_TOLERANCE};

/// `points` simplified to within [`POLYLINE_TOLERANCE`] cells (`cell` map units each), ends
/// kept.
pub(crate) fn simplify(points: &[Point], cell: Real) -> Vec<Point> {
    douglas_peucker(points, POLYLINE_TOLERANCE * cell, usize::MAX)
}

/// The edge from node `from` to node `to` along `polyline`: its length, and the smallest and
/// mean of `clearances` (the clearances along the chain it simplifies; 0 without any).
pub(crate) fn edge_along(from: usize, to: usize, polyline: &[Point], clearances: &[Real]) -> Edge {
    let (min_clearance, mean_clearance) = if clearances.is_empty() {
        (0.0, 0.0)
    } else {
        (
            clearances.iter().copied().fold(Real::INFINITY, Real::min),
            clearances.iter().sum::<Real>() / clearances.len() as Real,
        )
    };
    Edge {
        from,
        to,
        length: polyline.windows(2).map(|s| (s[1] - s[0]).norm()).sum(),
        min_clearance,
        mean_clearance,
        polyline: polyline.iter().map(|p| [p.x, p.y]).collect(),
    }
}
