//! What the team has seen: square cells, each marked once a robot's sensor disc held all of
//! it, and the stretches of a route no robot has seen yet.

use homospline_geom::{Point, Real};
use rustc_hash::FxHashSet;

use super::route::Polyline;

/// The cells of the plane some robot has seen whole (the world is static: seen stays seen).
///
/// # Examples
///
/// ```
/// use homospline_geom::Point;
/// use homospline_mission::sim::policy::{Coverage, Polyline};
///
/// let mut seen = Coverage::new(1.0);
/// seen.look(&Point::new(0.5, 0.5), 3.0);
/// let route = Polyline::new(vec![Point::new(0.5, 0.5), Point::new(10.5, 0.5)]);
/// // Seen up to about 2.5 along the route; the rest is to look at.
/// let unseen = seen.unseen(&route, 0.0);
/// assert_eq!(unseen.len(), 1);
/// assert!(unseen[0].0 > 2.0 && unseen[0].1 == 10.0);
/// ```
#[derive(Clone, Debug)]
pub struct Coverage {
    /// Side of a cell.
    cell: Real,
    seen: FxHashSet<(i64, i64)>,
}

impl Coverage {
    /// Nothing seen yet, on cells of side `cell` (`> 0`).
    pub fn new(cell: Real) -> Self {
        Self {
            cell,
            seen: FxHashSet::default(),
        }
    }

    /// The side of a cell.
    pub fn cell(&self) -> Real {
        self.cell
    }

    fn key(&self, p: &Point) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    /// Marks the cells a sensor at `p` seeing `range` holds whole.
    pub fn look(&mut self, p: &Point, range: Real) {
        let (ci, cj) = self.key(p);
        let n = (range / self.cell).ceil() as i64 + 1;
        let r2 = range * range;
        for j in cj - n..=cj + n {
            for i in ci - n..=ci + n {
                // The cell's farthest corner from `p`.
                let x0 = i as Real * self.cell;
                let y0 = j as Real * self.cell;
                let dx = (p.x - x0).abs().max((p.x - x0 - self.cell).abs());
                let dy = (p.y - y0).abs().max((p.y - y0 - self.cell).abs());
                if dx * dx + dy * dy <= r2 {
                    self.seen.insert((i, j));
                }
            }
        }
    }

    /// Whether the cell holding `p` has been seen.
    pub fn seen(&self, p: &Point) -> bool {
        self.seen.contains(&self.key(p))
    }

    /// The stretches `(from, to)` (arc lengths) of `line` beyond arc length `from` whose
    /// points lie in cells not seen yet, sampled every half cell (at most 4,000 samples);
    /// stretches closer than a cell apart are joined.
    pub fn unseen(&self, line: &Polyline, from: Real) -> Vec<(Real, Real)> {
        let len = line.length();
        let step = (0.5 * self.cell).max(len / 4000.0);
        let mut out: Vec<(Real, Real)> = Vec::new();
        let mut s = from.max(0.0);
        while s <= len {
            let (p, _) = line.at(s);
            if !self.seen(&p) {
                match out.last_mut() {
                    Some(last) if s - last.1 <= self.cell => last.1 = s,
                    _ => out.push((s, s)),
                }
            }
            if s == len {
                break;
            }
            s = (s + step).min(len);
        }
        out
    }

    /// Length of `line` beyond arc length `from` not seen yet.
    pub fn unseen_length(&self, line: &Polyline, from: Real) -> Real {
        self.unseen(line, from)
            .iter()
            .map(|(a, b)| (b - a).max(0.5 * self.cell))
            .sum()
    }
}
