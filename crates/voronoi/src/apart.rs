//! When a scene's grid finds start and goal apart: the narrowest gap the grid may have
//! closed and the finer grid that opens it, or the obstacles that truly wall them apart.
//!
//! A grid cell is occupied when its centre is in a circle, so a gap narrower than a few
//! cells can be closed on the grid while the circles leave it open. Whether it matters is
//! decided from the circles themselves. Let `h` be the cell size. If every positive gap
//! (between two inflated circles, or between one and a side of the bounds) is at least
//! [`GAP_CELLS`] cells and start and goal keep [`END_CELLS`] cells from every circle,
//! then growing every circle by `2h` and pulling the bounds in by as much makes no
//! new contact: the obstacles meet each other and the sides as they did, so any route
//! between start and goal can be pushed to a clearance of `2h`, and such a route runs
//! through free, 4-connected cells. The grid's verdict is then the circles' own: start and
//! goal are walled apart. Otherwise the grid is made fine enough for the narrowest gap, when
//! that fits in [`MAX_CELLS`](crate::grid::MAX_CELLS), and built again.

use homospline_geom::{
    Circle, Placement, Point, Real, Scene, for_each_near_pair, topological_obstacles,
};

use crate::attach::{free_bfs, free_cell};
use crate::grid::Grid;

/// A gap counts as open on a grid when it is at least this many cells wide.
pub const GAP_CELLS: Real = 6.0;

/// Most cells of the finer grid [`build`](crate::build) makes by itself for a narrow gap:
/// half the grid's limit (a plan on 13 million cells peaked at 261 MB and took 0.24 s);
/// past it the error says which `--resolution` would resolve the gap.
pub const REFINE_MAX_CELLS: usize = 1 << 24;

/// Start and goal count as clear on a grid when they keep this many cells from every
/// circle.
pub const END_CELLS: Real = 3.0;

/// The narrowest place the grid may have closed: a gap between two things, or an end's
/// clearance.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Narrowest {
    /// The cell size the place needs, `width / GAP_CELLS` (a gap) or `clearance /
    /// END_CELLS` (an end).
    pub need: Real,
    /// Its width.
    pub width: Real,
    /// What it lies between, in words.
    pub between: String,
}

/// What the grid's "apart" means for the scene.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Apart {
    /// Every gap is open on the grid: start and goal are walled apart by these obstacles
    /// (their names, in words), or by several together when `None`.
    Walled(Option<String>),
    /// The narrowest place needs a finer grid.
    Narrow(Narrowest),
}

/// What the grid of cell size `h` finding start and goal apart means for `scene`.
pub(crate) fn judge(scene: &Scene, grid: &Grid) -> Apart {
    let h = grid.cell();
    let circles = scene.circles();
    match narrowest(scene, &circles, h) {
        Some(n) if n.need < h => Apart::Narrow(n),
        _ => Apart::Walled(walling(scene, &circles, grid)),
    }
}

/// The narrowest gap or end clearance that needs cells smaller than `h` (`None` when none
/// does): gaps under [`GAP_CELLS`] cells between two circles (a sweep over the circles by
/// their left edge) or a circle and a side, ends within [`END_CELLS`] cells of a circle.
fn narrowest(scene: &Scene, circles: &[Circle], h: Real) -> Option<Narrowest> {
    let owners = scene.circle_owners();
    let name = |i: usize| format!("'{}'", scene.obstacles[owners[i]].name);
    let b = &scene.bounds;
    let sides = [
        (
            "the bounds' left side",
            Point::new(b.min.x, b.min.y),
            Point::new(b.min.x, b.max.y),
        ),
        (
            "the bounds' right side",
            Point::new(b.max.x, b.min.y),
            Point::new(b.max.x, b.max.y),
        ),
        (
            "the bounds' lower side",
            Point::new(b.min.x, b.min.y),
            Point::new(b.max.x, b.min.y),
        ),
        (
            "the bounds' upper side",
            Point::new(b.min.x, b.max.y),
            Point::new(b.max.x, b.max.y),
        ),
    ];
    let reach = GAP_CELLS * h;
    let mut best: Option<Narrowest> = None;
    let mut offer = |need: Real, width: Real, between: &dyn Fn() -> String| {
        if need < h && best.as_ref().is_none_or(|b| need < b.need) {
            best = Some(Narrowest {
                need,
                width,
                between: between(),
            });
        }
    };
    for_each_near_pair(circles, reach, |i, j| {
        let (ci, cj) = (&circles[i], &circles[j]);
        let gap = (ci.center - cj.center).norm() - ci.radius - cj.radius;
        if gap > 0.0 {
            offer(gap / GAP_CELLS, gap, &|| {
                format!("{} and {}", name(i.min(j)), name(i.max(j)))
            });
        }
    });
    for (i, c) in circles.iter().enumerate() {
        for (side, a, z) in &sides {
            let gap = homospline_geom::math::distance_point_segment(&c.center, a, z) - c.radius;
            if gap > 0.0 {
                offer(gap / GAP_CELLS, gap, &|| format!("{} and {side}", name(i)));
            }
        }
    }
    // The ends' clearance from the circles only: a start on a side of the bounds (which a
    // scene allows) still lies in a free cell, the wall ring being outside the bounds.
    for (end, p) in [("start", scene.start), ("goal", scene.goal)] {
        let (clearance, nearest) = circles
            .iter()
            .enumerate()
            .map(|(i, c)| ((p - c.center).norm() - c.radius, i))
            .fold((Real::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
        offer(clearance / END_CELLS, clearance, &|| {
            format!("the {end} and {}", name(nearest))
        });
    }
    best
}

/// The topological obstacle (touching circles) that alone walls start and goal apart on
/// `grid`'s cells, named by its listed obstacles; `None` when none of those tried does
/// alone. Only groups that can wall anything off are tried: those of three or more circles
/// (a ring) or that reach a side of the bounds, the [`WALL_TRIES`] nearest the segment from
/// start to goal.
fn walling(scene: &Scene, circles: &[Circle], grid: &Grid) -> Option<String> {
    let owners = scene.circle_owners();
    // Nearest the segment from start to goal first (a wall across it, a ring round an
    // end), at most `WALL_TRIES` of them: each try fills the whole grid.
    let gap_to_segment = |c: &Circle| {
        homospline_geom::math::distance_point_segment(&c.center, &scene.start, &scene.goal)
            - c.radius
    };
    let mut groups: Vec<(Real, Vec<usize>)> = topological_obstacles(circles)
        .into_iter()
        .filter(|g| {
            g.circles.len() >= 3
                || scene
                    .bounds
                    .place_discs(g.circles.iter().map(|&i| &circles[i]))
                    != Placement::Inside
        })
        .map(|g| {
            let near = g
                .circles
                .iter()
                .map(|&i| gap_to_segment(&circles[i]))
                .fold(Real::INFINITY, Real::min);
            (near, g.circles)
        })
        .collect();
    groups.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (_, members) in groups.into_iter().take(WALL_TRIES) {
        let Ok(mut alone) = Grid::new(grid.width(), grid.height(), grid.origin(), grid.cell())
        else {
            return None;
        };
        for &i in &members {
            alone.fill_disc(&circles[i].center, circles[i].radius);
        }
        if !joined(&alone, &scene.start, &scene.goal) {
            let mut names: Vec<usize> = members.iter().map(|&i| owners[i]).collect();
            names.sort_unstable();
            names.dedup();
            let listed: Vec<String> = names
                .iter()
                .take(6)
                .map(|&o| format!("'{}'", scene.obstacles[o].name))
                .collect();
            let more = names.len().saturating_sub(listed.len());
            return Some(if more > 0 {
                format!("{} and {more} more", listed.join(", "))
            } else {
                listed.join(", ")
            });
        }
    }
    None
}

/// Most groups [`walling`] tries alone on the grid before it names none.
const WALL_TRIES: usize = 32;

/// Whether the free cells of `grid` join those of `a` and `b` (4-connected), each found
/// as the graph's own start and goal are ([`free_cell`]: a point on a cell's side takes a
/// free cell beside it).
fn joined(grid: &Grid, a: &Point, b: &Point) -> bool {
    let (Ok(from), Ok(to)) = (free_cell(grid, *a, "start"), free_cell(grid, *b, "goal")) else {
        return false;
    };
    free_bfs(grid, from, |i, j| ((i, j) == to).then_some(())).is_some()
}
