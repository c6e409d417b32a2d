//! What the planner plans in ([`World`]: a scene of circles or an occupancy map), and the
//! exact geometry the dm rule asks of a scene's circles ([`ExactCircles`], [`keeps_dm`]).

use std::sync::OnceLock;

use homospline_geom::shortest::TangentGraph;
use homospline_geom::{Bounds, Circle, Point, Real};
use homospline_homotopy::{Rays, Signature, shortest_in_class_within};
use homospline_spline::ClearanceModel;

/// What the planner plans in: bounds, start, goal, the obstacles as the cost sees them, and
/// the rays that name homotopy classes. A scene of circles and an occupancy map are both one.
pub struct World<'a> {
    /// Name for the plan.
    pub name: String,
    /// The robot stays inside.
    pub bounds: Bounds,
    /// Start.
    pub start: Point,
    /// Goal.
    pub goal: Point,
    /// Obstacles for the cost and the collision checks.
    pub model: &'a dyn ClearanceModel,
    /// One ray per obstacle representative: a scene's own, or borrowed from a prepared map
    /// (hundreds of thousands of rays on a large map, which a copy per query would double).
    pub rays: std::borrow::Cow<'a, Rays>,
    /// Whether the Voronoi grid is the world itself (an occupancy map) rather than a
    /// rasterisation of it (circles). Passages narrower than one cell are offered only then.
    pub grid_is_exact: bool,
    /// The obstacles as circles, when they are circles (a scene): the dm rule then asks the
    /// exact geometry whether a class whose graph path is less clear than `dm` can keep it
    /// ([`keeps_dm`]). `None` on a map.
    pub circles: Option<&'a ExactCircles>,
}

/// A scene's circles for the dm rule's exact check ([`keeps_dm`]), with the tangent graph at
/// the rule's clearance built once, by the first class that asks, for all of them.
pub struct ExactCircles {
    circles: Vec<Circle>,
    /// The graph, and the start, goal and clearance it was built for.
    graph: OnceLock<(Point, Point, Real, Option<TangentGraph>)>,
}

impl ExactCircles {
    /// The scene's circles.
    pub fn new(circles: Vec<Circle>) -> Self {
        Self {
            circles,
            graph: OnceLock::new(),
        }
    }

    /// The tangent graph from the world's start to its goal at `clearance`, built anew (not
    /// kept); `None` as for [`ExactCircles::graph`].
    fn graph_at(&self, world: &World<'_>, clearance: Real) -> Option<TangentGraph> {
        if self.circles.len() > KEEPS_DM_CIRCLES {
            return None;
        }
        TangentGraph::build(&world.start, &world.goal, &self.circles, clearance)
            .ok()
            .flatten()
    }

    /// The tangent graph from the world's start to its goal at `clearance` (`None` when an
    /// end is less clear, the input is not valid, or there are more than
    /// [`KEEPS_DM_CIRCLES`] circles).
    fn graph(&self, world: &World<'_>, clearance: Real) -> Option<&TangentGraph> {
        if self.circles.len() > KEEPS_DM_CIRCLES {
            return None;
        }
        let build = || {
            TangentGraph::build(&world.start, &world.goal, &self.circles, clearance)
                .ok()
                .flatten()
        };
        let (start, goal, at, graph) = self
            .graph
            .get_or_init(|| (world.start, world.goal, clearance, build()));
        // Every class of a plan asks for the same; a world that shares these circles with
        // another start, goal or clearance gets no answer rather than a wrong one.
        (*start == world.start && *goal == world.goal && *at == clearance)
            .then_some(graph.as_ref())
            .flatten()
    }
}

/// How much longer than its graph path a class's shortest path that keeps `dm` may be for
/// [`keeps_dm`] to look for it. With this bound and [`KEEPS_DM_STATES`] the chosen plans are
/// those of looser bounds and of an unlimited search, and a search that finds nothing ends
/// sooner: re-plans during a mission take it too; fewer states lost classes (measured:
/// docs/performance.md, "Measurements behind the defaults").
pub const KEEPS_DM_LENGTH: Real = 1.25;

/// The most (node, word) states [`keeps_dm`]'s search may hold.
pub const KEEPS_DM_STATES: usize = 1024;

/// Scenes of more circles than this keep the rule's graph-path target: the tangent graph's
/// build is cubic in the circles, and on large scenes costs more than the plan gains
/// (measured: docs/performance.md, "Measurements behind the defaults").
pub const KEEPS_DM_CIRCLES: usize = 128;

/// Whether a path of the class `signature` keeps `clearance` from every circle and stays in
/// the world's bounds, within [`KEEPS_DM_LENGTH`] times the length of `poly` (its graph
/// path): the class's exact shortest path at that clearance ([`taut_in_class`]). The graph
/// path's clearance (at its vertices, from the grid) does not say what the class can keep:
/// about half of the classes whose graph path is less clear than `dm / 0.9` can keep `dm`.
/// The rule aimed those at 0.9 of it, and a class could end a hair below `dm` while a much
/// longer safe class was chosen (measured: docs/performance.md, "Measurements behind the
/// defaults"). `false` when the search gives up.
pub fn keeps_dm(
    world: &World<'_>,
    circles: &ExactCircles,
    poly: &[Point],
    signature: &Signature,
    clearance: Real,
) -> bool {
    let length = super::polyline_length(poly);
    taut_in_class(
        world,
        circles,
        signature,
        clearance,
        KEEPS_DM_LENGTH * length,
    )
    .is_some()
}

/// The class `signature`'s exact shortest path, as [`taut_in_class`] gives it: at
/// `clearance` if it stays inside the bounds there; else at half the greatest clearance
/// below `clearance` at which it does (found to 1/256 of `clearance` by bisection; at that
/// clearance itself if the path at half of it is not found), so that a route between a
/// circle and a side of the bounds keeps as far from both as that lets it. For a class whose every
/// smooth curve came out in collision or out of bounds (a gap of 0.1 between a circle and
/// the bounds, narrower than the Voronoi grid's cells). `None` when the class has no path
/// inside the bounds at any clearance tried, or the world has no circles.
pub fn taut_within_bounds(
    world: &World<'_>,
    signature: &Signature,
    clearance: Real,
    bound: Real,
) -> Option<Vec<Point>> {
    let circles = world.circles?;
    if let Some(p) = taut_in_class(world, circles, signature, clearance, bound) {
        return Some(p);
    }
    let at = |c: Real| taut_at(world, signature, c, bound);
    let (mut lo, mut hi) = (0.0, clearance);
    let mut found = None;
    for _ in 0..8 {
        let mid = 0.5 * (lo + hi);
        if at(mid).is_some() {
            (lo, found) = (mid, Some(mid));
        } else {
            hi = mid;
        }
    }
    found.and_then(|c| at(0.5 * c).or_else(|| at(c)))
}

/// [`taut_in_class`] on a tangent graph built for `clearance` alone (not kept), for a
/// clearance other than the dm rule's.
pub fn taut_at(
    world: &World<'_>,
    signature: &Signature,
    clearance: Real,
    bound: Real,
) -> Option<Vec<Point>> {
    let graph = world.circles?.graph_at(world, clearance)?;
    taut_on(world, &graph, signature, bound)
}

/// The class `signature`'s exact shortest path from the world's start to its goal that keeps
/// `clearance` from every circle ([`homospline_homotopy::shortest_in_class_within`], at most
/// [`KEEPS_DM_STATES`] states), if it is no longer than `bound` and stays in the world's
/// bounds: as a polyline, its arcs with points a degree apart. `None` when there is none,
/// when an end is less clear than `clearance`, or when the search gives up.
pub fn taut_in_class(
    world: &World<'_>,
    circles: &ExactCircles,
    signature: &Signature,
    clearance: Real,
    bound: Real,
) -> Option<Vec<Point>> {
    taut_on(world, circles.graph(world, clearance)?, signature, bound)
}

/// [`taut_in_class`] on a tangent graph already built.
fn taut_on(
    world: &World<'_>,
    graph: &TangentGraph,
    signature: &Signature,
    bound: Real,
) -> Option<Vec<Point>> {
    let path = shortest_in_class_within(
        graph,
        &world.rays,
        |w| w == signature,
        bound,
        KEEPS_DM_STATES,
    )
    .ok()??;
    let mut out: Vec<Point> = Vec::new();
    for piece in &path.pieces {
        for p in piece.points(ARC_STEP) {
            if out.last() != Some(&p) {
                out.push(p);
            }
        }
    }
    // The ends are the start and the goal to the bit (a piece's end is computed, and can be
    // an ulp off).
    if let (Some(first), Some(last)) = (out.first().copied(), out.last().copied()) {
        let n = out.len();
        if n >= 2 && (first - world.start).norm() < 1e-9 * (1.0 + world.start.coords.norm()) {
            out[0] = world.start;
        }
        if n >= 2 && (last - world.goal).norm() < 1e-9 * (1.0 + world.goal.coords.norm()) {
            out[n - 1] = world.goal;
        }
    }
    // In bounds: every piece's ends and, on an arc, points a degree apart.
    out.iter().all(|p| world.bounds.contains(p)).then_some(out)
}

/// The angle between consecutive points of [`taut_in_class`]'s arcs: a degree, in radians.
const ARC_STEP: Real = 0.0175;
