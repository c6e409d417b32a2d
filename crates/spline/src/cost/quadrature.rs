//! Step 1 of an evaluation: the curve at its Gauss-Legendre quadrature nodes
//! ([`CostConfig::nodes`] per piece, [`CostConfig::pieces`] pieces per spline segment), with
//! its length.

use homospline_geom::{Point, Real, Vector};

use super::config::CostConfig;
use crate::curve::Spline;
use crate::quad::gauss_legendre_cached;

/// One quadrature node of the curve.
#[derive(Clone, Copy)]
pub(super) struct Node {
    /// Spline segment.
    pub(super) seg: usize,
    /// Parameter within the segment.
    pub(super) s: Real,
    /// Quadrature weight times the piece's parameter length (`dt`).
    pub(super) dt: Real,
    /// `q'`.
    pub(super) v: Vector,
    /// `q''`.
    pub(super) a: Vector,
    /// `|q'|`.
    pub(super) speed: Real,
}

/// The curve at its quadrature nodes, with its length.
#[derive(Default)]
pub(super) struct Samples {
    pub(super) points: Vec<Point>,
    pub(super) nodes: Vec<Node>,
    pub(super) length: Real,
}

/// Step 1: every quadrature node of the curve, and its length, into `out`.
pub(super) fn sample(spline: &Spline, cfg: &CostConfig, out: &mut Samples) {
    let (gx, gw) = gauss_legendre_cached(cfg.nodes.clamp(2, 64));
    let pieces = cfg.pieces.max(1);
    let knots = spline.knots();
    out.points.clear();
    out.nodes.clear();
    // Summed in a local, in the same order (the same bits), then stored.
    let mut length = 0.0;
    for seg in 0..spline.segments() {
        let h = (knots[seg + 1] - knots[seg]) / pieces as Real;
        for piece in 0..pieces {
            let base = h * piece as Real;
            for (&x, &w) in gx.iter().zip(gw.iter()) {
                let s = base + h * x;
                let (p, v, a) = spline.eval_segment(seg, s);
                let speed = v.norm();
                let dt = w * h;
                length += dt * speed;
                out.points.push(p);
                out.nodes.push(Node {
                    seg,
                    s,
                    dt,
                    v,
                    a,
                    speed,
                });
            }
        }
    }
    out.length = length;
}
