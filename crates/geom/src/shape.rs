//! Circles, named obstacles, bounds, and the topological obstacles of a circle set.

use serde::{Deserialize, Serialize};

use crate::math::{Num, Point, Real, Vector};

/// Whether `r` is a robot radius: a finite number `>= 0` (0: a point robot). Every front
/// end and crate checks a radius with this, and words a refusal with
/// [`ROBOT_RADIUS_RULE`].
///
/// # Examples
///
/// ```
/// use homospline_geom::{ROBOT_RADIUS_RULE, is_robot_radius};
///
/// assert!(is_robot_radius(0.0) && is_robot_radius(0.3));
/// assert!(!is_robot_radius(-0.1) && !is_robot_radius(f64::NAN) && !is_robot_radius(f64::INFINITY));
/// assert_eq!(ROBOT_RADIUS_RULE, "must be a finite number >= 0");
/// ```
pub fn is_robot_radius(r: Real) -> bool {
    r.is_finite() && r >= 0.0
}

/// What [`is_robot_radius`] asks, as a refusal says it after the value.
pub const ROBOT_RADIUS_RULE: &str = "must be a finite number >= 0";

/// A closed disc: every obstacle is a union of these.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Circle {
    /// Centre.
    pub center: Point,
    /// Radius, strictly positive in a valid scene.
    pub radius: Real,
}

impl Circle {
    /// A circle from its centre coordinates and radius.
    pub fn new(x: Real, y: Real, radius: Real) -> Self {
        Self {
            center: Point::new(x, y),
            radius,
        }
    }

    /// Signed distance from `p` to the circle's boundary: negative inside.
    #[inline]
    pub fn signed_distance(&self, p: &Point) -> Real {
        let v = p - self.center;
        let n2 = v.x * v.x + v.y * v.y;
        // The squares underflow (or overflow) on scenes scaled to 1e-160 (or 1e160): a start
        // 35 units clear at scale 1e-170 measured 0 from the centre, inside the circle.
        let norm = if n2.is_normal() {
            n2.sqrt()
        } else {
            v.x.hypot(v.y)
        };
        norm - self.radius
    }

    /// Whether the two closed discs share at least one point.
    #[inline]
    pub fn touches(&self, other: &Circle) -> bool {
        let r = self.radius + other.radius;
        (self.center - other.center).norm_squared() <= r * r
    }

    /// The same circle grown by `by` (the robot radius).
    #[inline]
    pub fn inflated(&self, by: Real) -> Self {
        Self {
            center: self.center,
            radius: self.radius + by,
        }
    }
}

/// A named obstacle of a scene: a set of circles that may intersect (a compound, possibly
/// concave shape).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Obstacle {
    /// Name from the scene file (`obstacle-N` when the file gives none).
    pub name: String,
    /// The circles, as listed.
    pub circles: Vec<Circle>,
}

/// An axis-aligned rectangle: the region the robot must stay in.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    /// Lower-left corner.
    pub min: Point,
    /// Upper-right corner.
    pub max: Point,
}

/// `[x0, x1] x [y0, y1]`, as messages name a rectangle.
impl std::fmt::Display for Bounds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "[{}, {}] x [{}, {}]",
            Num(self.min.x),
            Num(self.max.x),
            Num(self.min.y),
            Num(self.max.y)
        )
    }
}

impl Bounds {
    /// Whether `p` lies inside or on the rectangle.
    pub fn contains(&self, p: &Point) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// Distance from an inside point to the nearest wall (negative outside).
    pub fn wall_clearance(&self, p: &Point) -> Real {
        (p.x - self.min.x)
            .min(self.max.x - p.x)
            .min(p.y - self.min.y)
            .min(self.max.y - p.y)
    }

    /// Width and height.
    pub fn extent(&self) -> Vector {
        self.max - self.min
    }

    /// Where the closed disc `c` lies against the rectangle: strictly inside it, meeting a
    /// wall, or apart from it (not even touching). A disc with a NaN coordinate or radius is
    /// placed on the wall: never a hole, never dismissed.
    pub fn place_disc(&self, c: &Circle) -> Placement {
        let p = c.center;
        let r = c.radius;
        if p.x - r > self.min.x
            && p.x + r < self.max.x
            && p.y - r > self.min.y
            && p.y + r < self.max.y
        {
            return Placement::Inside;
        }
        // max-then-min, not clamp: no panic on bounds whose min exceeds their max.
        let nearest = Point::new(
            p.x.max(self.min.x).min(self.max.x),
            p.y.max(self.min.y).min(self.max.y),
        );
        if (p - nearest).norm_squared() > r * r {
            Placement::Outside
        } else {
            Placement::OnWall
        }
    }

    /// Where a group of discs lies (see [`Bounds::place_disc`]): inside if every disc is,
    /// outside if every disc is, on the wall otherwise. A connected group that is neither
    /// inside nor outside meets a wall, so it is no hole in the free space within the
    /// rectangle: it belongs to the outer boundary. An empty group is inside.
    pub fn place_discs<'a>(&self, discs: impl IntoIterator<Item = &'a Circle>) -> Placement {
        let mut seen: Option<Placement> = None;
        for c in discs {
            let here = self.place_disc(c);
            seen = match seen {
                None => Some(here),
                Some(before) if before == here => Some(here),
                Some(_) => return Placement::OnWall,
            };
        }
        seen.unwrap_or(Placement::Inside)
    }
}

/// Where a disc, or a group of discs, lies against a [`Bounds`] rectangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// Strictly inside the rectangle: a group inside is a hole in free space.
    Inside,
    /// Meeting a wall (crossing or touching it): part of the outer boundary, not a hole.
    OnWall,
    /// Apart from the rectangle: not part of the free space's shape at all.
    Outside,
}

/// A topological obstacle: a maximal connected group of touching circles, possibly drawn
/// from several listed obstacles; a hole in free space when it lies strictly within the
/// bounds ([`Bounds::place_discs`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TopoObstacle {
    /// Indices into the circle slice the group was computed from, ascending.
    pub circles: Vec<usize>,
    /// A point strictly inside the group: the centre of its largest circle (lowest index on
    /// ties). Homotopy signatures cast their rays from here.
    pub representative: Point,
}

/// Calls `f(i, j)` for every pair of `circles` whose extents along x, the first's grown by
/// `reach` on its right, overlap: every pair whose gap is at most `reach`, and others. A
/// sweep over the circles sorted by their left edge (ties by index), so `O(n log n +
/// pairs)`; `i` is the pair's circle with the lower left edge, and the pairs come in a
/// fixed order.
pub fn for_each_near_pair(circles: &[Circle], reach: Real, mut f: impl FnMut(usize, usize)) {
    let mut order: Vec<usize> = (0..circles.len()).collect();
    order.sort_by(|&a, &b| {
        let ka = circles[a].center.x - circles[a].radius;
        let kb = circles[b].center.x - circles[b].radius;
        ka.total_cmp(&kb).then(a.cmp(&b))
    });
    for (k, &i) in order.iter().enumerate() {
        let right = circles[i].center.x + circles[i].radius + reach;
        for &j in &order[k + 1..] {
            if circles[j].center.x - circles[j].radius > right {
                break;
            }
            f(i, j);
        }
    }
}

/// Groups `circles` into connected components of the "discs touch" relation.
///
/// Deterministic: groups are ordered by their lowest circle index. Runs a sweep over the
/// circles sorted by their left edge, so it is `O(n log n + pairs)`.
pub fn topological_obstacles(circles: &[Circle]) -> Vec<TopoObstacle> {
    let n = circles.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for_each_near_pair(circles, 0.0, |i, j| {
        if circles[i].touches(&circles[j]) {
            let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
            if ri != rj {
                let (lo, hi) = if ri < rj { (ri, rj) } else { (rj, ri) };
                parent[hi] = lo;
            }
        }
    });
    let mut group_of_root: Vec<Option<usize>> = vec![None; n];
    let mut members: Vec<Vec<usize>> = Vec::new();
    for i in 0..n {
        let root = find(&mut parent, i);
        let g = *group_of_root[root].get_or_insert_with(|| {
            members.push(Vec::new());
            members.len() - 1
        });
        members[g].push(i);
    }
    members
        .into_iter()
        .map(|circles_in| {
            // Largest radius wins; on a tie the lowest index (members are ascending).
            let mut best = circles_in[0];
            for &i in &circles_in[1..] {
                if circles[i].radius > circles[best].radius {
                    best = i;
                }
            }
            TopoObstacle {
                representative: circles[best].center,
                circles: circles_in,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_distance_holds_at_any_scale() {
        // The squares of 1e-170 underflow to 0 and those of 1e170 overflow: the point, 15
        // radii from the centre, was measured inside at the first scale.
        for k in [1e-170, 1e-160, 1.0, 1e150, 1e170] {
            let c = Circle::new(20.0 * k, 28.0 * k, 5.0 * k);
            let d = c.signed_distance(&Point::new(5.0 * k, 30.0 * k));
            let expect = (15.0f64.hypot(2.0) - 5.0) * k;
            assert!((d - expect).abs() <= 1e-12 * expect, "{k}: {d} vs {expect}");
        }
    }

    #[test]
    fn discs_are_placed_at_the_edges_of_the_bounds() {
        let b = Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(10.0, 10.0),
        };
        let place = |x, y, r| b.place_disc(&Circle::new(x, y, r));
        // Exact in binary: tangent from inside or outside meets the wall (touching counts,
        // as in `Circle::touches`).
        assert_eq!(place(5.0, 5.0, 4.5), Placement::Inside);
        assert_eq!(place(5.0, 5.0, 5.0), Placement::OnWall);
        assert_eq!(place(5.0, 12.0, 2.0), Placement::OnWall);
        assert_eq!(place(5.0, 12.0, 1.75), Placement::Outside);
        // Near a corner the box around the disc overlaps the rectangle, but the disc does
        // not reach the corner: (13, 14) is 5 from (10, 10).
        assert_eq!(place(13.0, 14.0, 4.5), Placement::Outside);
        assert_eq!(place(13.0, 14.0, 5.0), Placement::OnWall);
        assert_eq!(place(-3.0, -4.0, 4.75), Placement::Outside);
        // A disc holding the whole rectangle meets its walls.
        assert_eq!(place(5.0, 5.0, 100.0), Placement::OnWall);
        // Bounds whose min exceeds their max give an answer, not a panic.
        let flipped = Bounds {
            min: b.max,
            max: b.min,
        };
        assert_ne!(
            flipped.place_disc(&Circle::new(5.0, 5.0, 1.0)),
            Placement::Inside
        );
        // Groups: all inside, all outside, or (mixed) on the wall; a group of none is
        // vacuously inside.
        let inside = Circle::new(5.0, 5.0, 1.0);
        let outside = Circle::new(20.0, 20.0, 1.0);
        assert_eq!(b.place_discs([&inside, &inside]), Placement::Inside);
        assert_eq!(b.place_discs([&outside, &outside]), Placement::Outside);
        assert_eq!(b.place_discs([&inside, &outside]), Placement::OnWall);
        assert_eq!(b.place_discs([]), Placement::Inside);
    }

    #[test]
    fn chains_of_touching_circles_form_one_group() {
        let circles = [
            Circle::new(0.0, 0.0, 1.0),
            Circle::new(10.0, 0.0, 1.0),
            Circle::new(2.0, 0.0, 1.0), // touches circle 0 exactly
            Circle::new(3.5, 0.0, 1.0), // overlaps circle 2
        ];
        let groups = topological_obstacles(&circles);
        assert_eq!(groups.len(), 2);
        assert_eq!(groups[0].circles, vec![0, 2, 3]);
        assert_eq!(groups[1].circles, vec![1]);
    }

    #[test]
    fn representative_is_the_largest_circle_centre() {
        let circles = [Circle::new(0.0, 0.0, 1.0), Circle::new(1.5, 0.0, 2.0)];
        let groups = topological_obstacles(&circles);
        assert_eq!(groups.len(), 1);
        assert_eq!(groups[0].representative, Point::new(1.5, 0.0));
    }
}
