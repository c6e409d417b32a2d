//! Real maps: MovingAI benchmark grids and ROS map_server occupancy maps, the grid clearance
//! model, and planning on them (the Voronoi graph straight from the grid).
//!
//! - [`movingai`]: `.map` and `.scen` from text, with errors that name the line.
//! - [`ros`]: the map YAML and its PGM or PNG image (nav2's conversion rules).
//! - [`model`]: [`GridModel`], the [`homospline_spline::ClearanceModel`] of a grid.
//! - [`plan_map`]: a plan on an [`OccupancyMap`], with the same result as on a scene.
//!
//! Topological obstacles of a map are the 8-connected components of occupied cells not
//! touching the map's border (those merge with the wall); each is represented by the centre
//! of its first cell in raster order, which is inside it.

pub mod bench;
pub mod footprint;
pub mod input;
pub mod model;
pub mod movingai;
pub mod ros;

pub use model::GridModel;

/// Via-points a map plan allows by default: one-cell doors and corridors need the curve held
/// close, more than the scenes' default of 10.
pub const MAX_VIA_POINTS: usize = 32;

/// Evaluation budget of one optimisation round on a map, whatever the path's length (each
/// L-BFGS evaluation, a cost and its gradient, counts as four budget units): the work per
/// plan grows linearly with the path.
pub const MAX_EVALUATIONS_PER_ROUND: usize = 800;

/// Curves of more segments than this get a smaller budget per round, in proportion, down to
/// [`MIN_EVALUATIONS_PER_ROUND`] (40 evaluations) from 100 segments on. The seeds are pulled
/// taut in their class before they are optimised, so a long curve starts close to where its
/// cost flattens out. Measured with `plan --json` on 6 scenarios spread over each of the ten
/// full-scale MovingAI maps, this budget (20 segments, 40 evaluations) against the previous
/// one (40 segments, 80 evaluations): the summed cost of the chosen classes moved by at most
/// 0.6 % on every map (ost003d +0.6 %, 16room_000 +0.3 %, den520d -0.1 %, the others under
/// 0.05 %). Short curves (the small maps' goldens) keep the whole budget: their rounds do
/// improve with it.
pub const BUDGET_SEGMENTS: usize = 20;

/// The floor of the shrinking budget on long curves.
pub const MIN_EVALUATIONS_PER_ROUND: usize = 160;

/// Budget of the class search on a map: the graph of a whole map has thousands of cycles, and
/// past the classes near the shortest path each further one costs a wide sweep; when the
/// budget runs out the classes found so far are optimised (the result says so).
pub const MAX_EXPANSIONS: usize = 20_000;

/// `dm` of the safety term on maps, map units: kept along the path where the corridor allows.
pub const MAP_DM: Real = 1.5;

/// `omega` of the safety term on maps.
pub const MAP_OMEGA: Real = 1000.0;

/// The planner's default configuration for maps: [`PlanConfig::default`] with
/// [`MAX_VIA_POINTS`] and L-BFGS. A map path needs up to 64 dimensions, where Nelder-Mead
/// (the paper's optimiser, the default on scenes) spends twice the time for the same success
/// on the fixture maps (README, performance).
pub fn map_config() -> PlanConfig {
    let mut cfg = PlanConfig::default();
    cfg.growth.max_via_points = MAX_VIA_POINTS;
    cfg.growth.optimizer = homospline_optim::Optimizer::Lbfgs;
    cfg.search.one_path_per_state = true;
    cfg.search.max_expansions = MAX_EXPANSIONS;
    cfg.growth.max_evaluations_per_round = MAX_EVALUATIONS_PER_ROUND;
    cfg.growth.budget_segments = BUDGET_SEGMENTS;
    cfg.growth.min_evaluations_per_round = MIN_EVALUATIONS_PER_ROUND;
    // A map's doors and corners are a cell or two wide: `dm` stays a penalty there, and a
    // hard margin is the user's `--clearance-floor`.
    cfg.dm_rule = false;
    map_safety(&mut cfg.growth.cost);
    // Like `--polish`, the chosen class's finish is for scenes: a map's classes are
    // optimised while the search goes on.
    cfg.finish_within = None;
    // No detour for nothing: the safety term along the path weighs every stretch, and a
    // loop three times as long kept 0.002 cells more than the straight way (decision 0022).
    cfg.detour = Some(homospline_optim::Detour::default());
    cfg.map_dm = Some(MAP_DM_CELLS);
    cfg.growth.lbfgs_value_tolerance = LBFGS_VALUE_TOLERANCE;
    cfg
}

/// The safety term of maps, set on `cost` (whatever preset it came from): it sees every
/// stretch of the path, not only its least clear point (a start next to a wall or a one-cell
/// door), so the whole path keeps away from walls where the corridor allows (docs/method.md,
/// 5.5); `dm` is [`MAP_DM`], what a stretch should keep where the corridor allows, and a
/// steep `omega` ([`MAP_OMEGA`]) tells a grazing stretch from one in the middle of a
/// one-cell gap (decision 0021). The one owner of these three values: [`map_config`], the
/// front ends' options and the missions' map profile all set them with it.
pub fn map_safety(cost: &mut homospline_spline::CostConfig) {
    cost.safety_along = true;
    cost.dm = MAP_DM;
    cost.omega = MAP_OMEGA;
}

/// L-BFGS on maps stops at a step that lowers the cost by less than this share of it: the
/// last steps of a round bought less and ran its budget out (docs/method.md, 5.5).
pub const LBFGS_VALUE_TOLERANCE: Real = 1e-3;

/// The default `dm` on maps, in cells ([`PlanConfig::map_dm`]): a path that keeps a quarter
/// of a cell (beyond the robot's radius) from every occupied cell is `safe`. A map places a
/// wall only to within its cell; half a cell is what a point robot keeps through a one-cell
/// door at best, so a quarter cell can be kept through every passage the robot fits, and
/// a path that comes closer to a wall than that cuts a corner.
pub const MAP_DM_CELLS: Real = 0.25;

/// The most the certified clearance's tolerance may be on a map, in cells
/// ([`resolve_map_dm`]): the planner's default (1e-3 map units) is 0.02 of a ROS map's 5 cm
/// cell and 0.001 of a MovingAI cell, but a thousand cells of a map at 1 micrometre a cell,
/// where no path could be certified `safe`.
pub const CERTIFY_TOLERANCE_CELLS: Real = 0.02;

/// The configuration `cfg` on a map of cells of `cell` map units: the certificate's
/// tolerance at most [`CERTIFY_TOLERANCE_CELLS`] of a cell; with [`PlanConfig::map_dm`]
/// set, the cost's `dm` becomes that many cells and the safety weight keeps the push of the
/// `dm` it replaces; the reason, for the plan's report.
pub fn resolve_map_dm(cfg: &PlanConfig, cell: Real) -> (PlanConfig, Option<String>) {
    let mut cfg = cfg.clone();
    cfg.certify_tolerance = cfg.certify_tolerance.min(CERTIFY_TOLERANCE_CELLS * cell);
    let Some(cells) = cfg.map_dm else {
        return (cfg, None);
    };
    let cost = &mut cfg.growth.cost;
    let dm = cells * cell;
    cost.w_safety *= cost.omega.powf(cost.dm - dm);
    cost.dm = dm;
    cfg.map_dm = None;
    let why = format!(
        "map default: {} of a cell of {} beyond the robot's radius",
        Num(cells),
        Num(cell)
    );
    (cfg, Some(why))
}

use homospline_geom::math::Num;
use homospline_geom::{Bounds, Point, ROBOT_RADIUS_RULE, Real, is_robot_radius};
use homospline_homotopy::Rays;
use homospline_optim::{Plan, PlanConfig, PlanError, World, plan_world};
use homospline_voronoi::{
    BuildError, DistanceField, GraphError, Grid, GridError, MapGraph, VoronoiGraph,
};
use thiserror::Error;

/// An occupancy map in map coordinates: `width x height` square cells of side `cell` from
/// `origin`, row-major (`occupied[j * width + i]` is cell `(i, j)`, whose square is
/// `origin + [i, i + 1] x [j, j + 1]` cells); occupied cells are closed squares and the
/// map's edge is a wall. Read from MovingAI `.map` files ([`movingai::read_map`]) and ROS
/// map YAML with its image ([`ros`]).
///
/// # Examples
///
/// ```
/// use homospline_geom::Point;
/// use homospline_maps::OccupancyMap;
///
/// let (w, h) = (16, 10);
/// // A wall across the map with a diagonal door between the corners (8, 4) and (9, 5).
/// let map = OccupancyMap {
///     name: "door".into(),
///     width: w,
///     height: h,
///     cell: 1.0,
///     origin: Point::origin(),
///     occupied: (0..w * h)
///         .map(|k| (k % w == 7 && k / w <= 3) || (k % w == 9 && k / w >= 5))
///         .collect(),
///     y_down: true,
/// };
/// assert_eq!(map.free_at(&Point::new(3.5, 4.5)), Some(true));
/// assert_eq!(map.free_at(&Point::new(7.5, 1.5)), Some(false));
/// // The door is sqrt 2 wide: a disc of radius 0.7 still stands in its middle.
/// let (free, _model) = map.robot_space(0.7)?;
/// assert_eq!(free.free_at(&Point::new(8.5, 4.5)), Some(true));
/// # Ok::<(), homospline_maps::MapError>(())
/// ```
///
/// See also [`PreparedMap`] (plan on it), [`OccupancyMap::robot_space`].
#[derive(Clone, Debug, PartialEq)]
pub struct OccupancyMap {
    /// Name (the file stem).
    pub name: String,
    /// Cells across.
    pub width: usize,
    /// Cells up (or down, see `y_down`).
    pub height: usize,
    /// Cell size, map units.
    pub cell: Real,
    /// Map coordinates of the corner of cell `(0, 0)` with the smallest x and y.
    pub origin: Point,
    /// Row-major, row `j` holding the cells whose y index is `j`; `true` is occupied.
    pub occupied: Vec<bool>,
    /// Whether y grows downwards on screen (MovingAI) rather than upwards (ROS).
    pub y_down: bool,
}

/// Why a map cannot be read or planned on.
#[derive(Debug, Error)]
pub enum MapError {
    /// The file is malformed.
    #[error("{source_name}{}: {problem}", line.map_or(String::new(), |l| format!(":{l}")))]
    Format {
        /// The file.
        source_name: String,
        /// 1-based line, when known.
        line: Option<usize>,
        /// What is wrong.
        problem: String,
    },
    /// Start or goal unusable.
    #[error("{what} [{}, {}] {problem}", Num(*x), Num(*y))]
    Endpoint {
        /// `start` or `goal`.
        what: &'static str,
        /// x.
        x: Real,
        /// y.
        y: Real,
        /// What is wrong.
        problem: String,
    },
    /// Grid.
    #[error(transparent)]
    Grid(#[from] GridError),
    /// Graph.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// Planner.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// A saved graph that does not fit the map.
    #[error("{0}")]
    Graph(String),
    /// A robot radius that is not a finite number `>= 0` ([`is_robot_radius`]).
    #[error(
        "robot radius {}: {ROBOT_RADIUS_RULE} (map units; metres on a ROS map)",
        Num(*.0)
    )]
    Radius(Real),
    /// No point of the map keeps the robot radius: no route for the robot anywhere (not
    /// bad input: exit 1 on the command line).
    #[error("no route: no point of the map keeps the robot radius {}", Num(*.0))]
    NoRoom(Real),
    /// No route joins start and goal for the robot: not bad input, an answer (exit 1 on the
    /// command line). `widest` is the widest route and its narrowest point
    /// ([`footprint::widest_route`]).
    #[error("{}", no_route_message(*radius, widest))]
    NoRoute {
        /// The robot radius, map units (0 for a point).
        radius: Real,
        /// The widest route between start and goal.
        widest: footprint::Widest,
    },
    /// More cells than a map may have ([`MAX_MAP_CELLS`]).
    #[error(
        "map {name} is {width} x {height} cells ({} cells); at most {MAX_MAP_CELLS} cells (4096 x 4096) fit in the {MAP_MEMORY} a map may take: crop or downsample the map",
        *width as u128 * *height as u128
    )]
    TooLarge {
        /// The map.
        name: String,
        /// Cells across.
        width: usize,
        /// Cells up.
        height: usize,
    },
}

impl MapError {
    /// Whether this is no route for the robot ([`MapError::NoRoute`], [`MapError::NoRoom`]):
    /// an answer about the map, not bad input (exit 1 on the command line).
    pub fn is_no_route(&self) -> bool {
        matches!(self, MapError::NoRoute { .. } | MapError::NoRoom(_))
    }
}

/// [`MapError::Radius`] unless `radius` [`is_robot_radius`].
fn check_radius(radius: Real) -> Result<(), MapError> {
    if is_robot_radius(radius) {
        Ok(())
    } else {
        Err(MapError::Radius(radius))
    }
}

fn no_route_message(radius: Real, widest: &footprint::Widest) -> String {
    let w = widest.clearance;
    if w <= 0.0 {
        return "no route: start and goal are in different free regions of the map (no gap \
                joins them)"
            .to_owned();
    }
    format!(
        "no route for a robot of radius {}: the widest route between start and goal keeps \
         {} at ({}, {}); the robot needs more than {}",
        Num(radius),
        Num(round4(w)),
        Num(round4(widest.at.x)),
        Num(round4(widest.at.y)),
        Num(radius)
    )
}

fn round4(x: Real) -> Real {
    (x * 1e4).round() / 1e4
}

/// Most cells a map may have: 4096 x 4096. Preparing a map (grid, brushfire, complete
/// Voronoi graph and its index, clearance model) peaks at about 80 bytes per cell on the
/// hardest maps (20 % random one-cell obstacles, a cycle every 14 cells; `cargo xtask
/// map-memory`), so the largest map fits in [`MAP_MEMORY`]. Larger maps are refused before
/// anything of their size is allocated, with [`MapError::TooLarge`].
pub const MAX_MAP_CELLS: usize = 4096 * 4096;

/// The memory a map's preparation may take, as the refusal of a larger map says.
pub const MAP_MEMORY: &str = "1.5 GB";

/// Checks a map's cell size and origin, as every front end gives them (a ROS YAML, a NumPy
/// array's `resolution` and `origin`): the cell at least [`ros::MIN_RESOLUTION`], the origin
/// finite, and the map within [`homospline_geom::scene::MAX_MAGNITUDE`] of the frame's origin,
/// as a scene's coordinates are (a resolution of 1e300 hung the planner, 1e9 asked for
/// 104 GB of path samples, 1e13 took 78 s). `Err((field, problem))`, the field being
/// `resolution` or `origin`.
pub fn check_geometry(
    resolution: Real,
    origin: [Real; 2],
    width: usize,
    height: usize,
) -> Result<(), (&'static str, String)> {
    use homospline_geom::scene::MAX_MAGNITUDE;
    if !(resolution.is_finite() && resolution >= ros::MIN_RESOLUTION) {
        return Err((
            "resolution",
            format!(
                "must be a cell size of at least {:e} map units, got {}",
                ros::MIN_RESOLUTION,
                Num(resolution)
            ),
        ));
    }
    if !(origin[0].is_finite() && origin[1].is_finite()) {
        return Err((
            "origin",
            format!(
                "must be finite, got [{}, {}]",
                Num(origin[0]),
                Num(origin[1])
            ),
        ));
    }
    let extent = resolution * width.max(height) as Real;
    let far = origin[0].abs().max(origin[1].abs()) + extent;
    if far.is_nan() || far > MAX_MAGNITUDE {
        // The field at fault: the origin when it alone is too far, else the resolution.
        let field = if far - extent > MAX_MAGNITUDE {
            "origin"
        } else {
            "resolution"
        };
        return Err((
            field,
            format!(
                "{} per cell over {width} x {height} cells from origin [{}, {}] reaches {far:e}; coordinates must stay within {MAX_MAGNITUDE:e}",
                Num(resolution),
                Num(origin[0]),
                Num(origin[1])
            ),
        ));
    }
    Ok(())
}

/// Refuses a map of `width x height` cells beyond [`MAX_MAP_CELLS`] (from its header,
/// before its cells are read).
pub fn check_map_size(name: &str, width: usize, height: usize) -> Result<(), MapError> {
    if width.saturating_mul(height) > MAX_MAP_CELLS {
        return Err(MapError::TooLarge {
            name: name.to_owned(),
            width,
            height,
        });
    }
    Ok(())
}

impl OccupancyMap {
    /// The bounds in map coordinates.
    pub fn bounds(&self) -> Bounds {
        Bounds {
            min: self.origin,
            max: Point::new(
                self.origin.x + self.width as Real * self.cell,
                self.origin.y + self.height as Real * self.cell,
            ),
        }
    }

    /// Whether the cell holding `p` is free; `None` outside the map.
    pub fn free_at(&self, p: &Point) -> Option<bool> {
        let fx = (p.x - self.origin.x) / self.cell;
        let fy = (p.y - self.origin.y) / self.cell;
        if !(fx >= 0.0 && fy >= 0.0) {
            return None;
        }
        let (i, j) = (fx as usize, fy as usize);
        (i < self.width && j < self.height).then(|| !self.occupied[j * self.width + i])
    }

    /// Why `p` cannot be a robot's position though its cell is free ([`OccupancyMap::free_at`]):
    /// cells are closed squares and the map's edge is a wall, so a point on the side or
    /// corner of an occupied cell, or on the edge, touches an obstacle (clearance 0).
    /// `None` when `p` is clear of both.
    pub fn touches_obstacle(&self, p: &Point) -> Option<&'static str> {
        // Within a billionth of a cell counts as on it (`cells_holding`).
        use homospline_voronoi::grid::{ON_SIDE, cells_holding};
        let fx = (p.x - self.origin.x) / self.cell;
        let fy = (p.y - self.origin.y) / self.cell;
        let (w, h) = (self.width as Real, self.height as Real);
        if fx <= ON_SIDE || fy <= ON_SIDE || fx >= w - ON_SIDE || fy >= h - ON_SIDE {
            return Some("lies on the map's edge");
        }
        // The cells whose closed square holds `p`.
        let (is, js) = (
            cells_holding(fx, self.width),
            cells_holding(fy, self.height),
        );
        let touches = js.iter().flatten().any(|&j| {
            is.iter()
                .flatten()
                .any(|&i| self.occupied[j * self.width + i])
        });
        touches.then_some("lies on the side or corner of an occupied cell")
    }

    /// Distance from `p` to the closed square of cell `(i, j)` (0 inside it).
    pub fn distance_to_cell(&self, p: &Point, cell: (usize, usize)) -> Real {
        self.squared_distance_to_cell(p, cell).sqrt()
    }

    fn squared_distance_to_cell(&self, p: &Point, (i, j): (usize, usize)) -> Real {
        let lo = Point::new(
            self.origin.x + i as Real * self.cell,
            self.origin.y + j as Real * self.cell,
        );
        let dx = (lo.x - p.x).max(0.0).max(p.x - (lo.x + self.cell));
        let dy = (lo.y - p.y).max(0.0).max(p.y - (lo.y + self.cell));
        dx * dx + dy * dy
    }

    /// Marks as occupied every cell that the closed disc overlaps (a blockage reported on
    /// the way); returns how many cells were free before.
    pub fn block_disc(&mut self, centre: &Point, radius: Real) -> usize {
        let mut count = 0;
        for j in 0..self.height {
            for i in 0..self.width {
                let k = j * self.width + i;
                if self.squared_distance_to_cell(centre, (i, j)) <= radius * radius
                    && !self.occupied[k]
                {
                    self.occupied[k] = true;
                    count += 1;
                }
            }
        }
        count
    }

    /// The map as a disc robot of radius `radius` (map units) sees it, conservatively: a cell
    /// stays free when every point of its closed square keeps at least `radius` from every
    /// occupied cell and from the map's edge (square to square), so a point of a free cell
    /// of the result is at least `radius` from the obstacles and a clearance `c` on the
    /// result is a clearance of at least `radius + c` on `self`. `radius` 0 gives the map
    /// itself. (Missions plan on maps inflated so; [`PreparedMap::for_robot`] frees the cells
    /// whose centre keeps the radius and measures clearances exactly.)
    ///
    /// The squared distance in cells between the squares of cells `a` and `b` is
    /// `sum over axes of max(0, |a - b| - 1)^2`: the squared distance between `a`'s centre
    /// and the nearest centre of `b`'s 3 x 3 block. So it is the exact brushfire of the
    /// occupied cells dilated by their 8 neighbours (the wall ring included).
    pub fn inflated(&self, radius: Real) -> Result<OccupancyMap, MapError> {
        check_radius(radius)?;
        if radius == 0.0 {
            return Ok(self.clone());
        }
        let d2 = self.square_distances()?;
        let reach = radius / self.cell;
        let mut out = self.clone();
        for (o, &q) in out.occupied.iter_mut().zip(&d2) {
            *o |= (q as Real).sqrt() < reach;
        }
        Ok(out)
    }

    /// Per cell (row-major, as `occupied`), the squared distance in cells from its closed
    /// square to the nearest occupied cell's or to the map's edge (see
    /// [`OccupancyMap::inflated`]).
    fn square_distances(&self) -> Result<Vec<i64>, MapError> {
        let grid = self.to_grid()?;
        let (w, h) = (grid.width(), grid.height());
        let occ = grid.occupancy();
        // Dilation by the 3 x 3 block: along rows, then along columns.
        let mut rows = vec![false; w * h];
        for j in 0..h {
            for i in 0..w {
                let k = j * w + i;
                rows[k] = occ[k] || (i > 0 && occ[k - 1]) || (i + 1 < w && occ[k + 1]);
            }
        }
        let mut block = vec![false; w * h];
        for j in 0..h {
            for i in 0..w {
                let k = j * w + i;
                block[k] = rows[k] || (j > 0 && rows[k - w]) || (j + 1 < h && rows[k + w]);
            }
        }
        drop(rows);
        let dilated = Grid::from_occupancy(w, h, grid.origin(), grid.cell(), block)?;
        drop(grid);
        let field = DistanceField::build(&dilated);
        drop(dilated);
        let mut out = vec![0i64; self.width * self.height];
        let mut row = vec![0i64; w];
        for j in 0..self.height {
            field.d2_row(j + 1, &mut row);
            out[j * self.width..(j + 1) * self.width].copy_from_slice(&row[1..=self.width]);
        }
        Ok(out)
    }

    /// A disc robot's space on this map: where a robot of `radius` (map units, `> 0`) can
    /// stand, as an occupancy map of the half-cell lattice ([`footprint`]: a lattice cell is
    /// free where its centre keeps more than `radius` from every occupied cell and the edge),
    /// and the exact clearance model of this map less `radius`
    /// ([`GridModel::for_radius`]), whose clearances are the robot body's. The lattice gives
    /// the topology a plan searches; the model its costs and certificates. This is the free
    /// space of `plan --robot-radius` and of map missions.
    ///
    /// Errors when the radius blocks every lattice point ([`MapError::NoRoom`]), or as
    /// [`OccupancyMap::to_grid`].
    pub fn robot_space(&self, radius: Real) -> Result<(OccupancyMap, GridModel), MapError> {
        // A point robot's space is the map itself (`to_grid`): this is for a disc.
        check_radius(radius)?;
        if radius == 0.0 {
            return Err(MapError::Radius(radius));
        }
        let grid = self.to_grid()?;
        let model = GridModel::new(&grid, &DistanceField::build(&grid));
        drop(grid);
        let free = self.free_for_robot(radius, &model)?;
        if free.occupied.iter().all(|&o| o) {
            return Err(MapError::NoRoom(radius));
        }
        Ok((free, model.for_radius(radius)))
    }

    /// Where a disc robot of radius `radius` can stand, as an occupancy map of the
    /// half-cell lattice ([`footprint`]): exact, by `truth`, the model of this map.
    fn free_for_robot(&self, radius: Real, truth: &GridModel) -> Result<OccupancyMap, MapError> {
        let square = self.square_distances()?;
        Ok(footprint::free_space(self, &square, radius, truth))
    }

    /// The exact clearance of `p`: its distance to the nearest occupied cell (a closed
    /// square) or to the map's edge, searched up to `reach` map units (a farther clearance
    /// reads as `reach`). 0 outside the map or in an occupied cell.
    pub fn clearance_within(&self, p: &Point, reach: Real) -> Real {
        let b = self.bounds();
        let edge = (p.x - b.min.x)
            .min(b.max.x - p.x)
            .min(p.y - b.min.y)
            .min(b.max.y - p.y);
        if self.free_at(p) != Some(true) {
            return 0.0;
        }
        let mut best = edge.min(reach);
        let fx = (p.x - self.origin.x) / self.cell;
        let fy = (p.y - self.origin.y) / self.cell;
        let span = (best / self.cell).ceil() + 1.0;
        let (i0, i1) = (
            (fx - span).max(0.0) as usize,
            ((fx + span) as usize).min(self.width - 1),
        );
        let (j0, j1) = (
            (fy - span).max(0.0) as usize,
            ((fy + span) as usize).min(self.height - 1),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                if self.occupied[j * self.width + i] {
                    best = best.min(self.distance_to_cell(p, (i, j)));
                }
            }
        }
        best
    }

    /// The grid: the map plus a one-cell wall ring around it. A map of more than
    /// [`MAX_MAP_CELLS`] cells is refused before the grid is allocated.
    pub fn to_grid(&self) -> Result<Grid, MapError> {
        check_map_size(&self.name, self.width, self.height)?;
        let (w, h) = (self.width + 2, self.height + 2);
        let mut occ = vec![true; w * h];
        for j in 0..self.height {
            for i in 0..self.width {
                occ[(j + 1) * w + i + 1] = self.occupied[j * self.width + i];
            }
        }
        Grid::from_occupancy(
            w,
            h,
            Point::new(self.origin.x - self.cell, self.origin.y - self.cell),
            self.cell,
            occ,
        )
        .map_err(MapError::from)
    }

    /// [`OccupancyMap::check_endpoint`], and that `p` keeps `radius` from every obstacle;
    /// returns its clearance (searched up to `radius` plus two cells).
    fn check_endpoint_for(
        &self,
        what: &'static str,
        p: &Point,
        radius: Real,
    ) -> Result<Real, MapError> {
        self.check_endpoint(what, p)?;
        let c = self.clearance_within(p, radius + 2.0 * self.cell);
        if c < radius || (radius > 0.0 && c == radius) {
            let than = if c < radius {
                "less than"
            } else {
                "no more than"
            };
            return Err(MapError::Endpoint {
                what,
                x: p.x,
                y: p.y,
                problem: format!(
                    "has clearance {c:.4}, {than} the robot radius {}",
                    Num(radius)
                ),
            });
        }
        Ok(c)
    }

    /// Refuses a start or goal outside the map, in or on an occupied cell, or closer than
    /// `radius` to an obstacle (naming its clearance): bad input, before any preparation.
    pub fn check_endpoints_for(
        &self,
        start: &Point,
        goal: &Point,
        radius: Real,
    ) -> Result<(), MapError> {
        check_radius(radius)?;
        self.check_endpoint_for("start", start, radius)?;
        self.check_endpoint_for("goal", goal, radius)?;
        Ok(())
    }

    fn check_endpoint(&self, what: &'static str, p: &Point) -> Result<(), MapError> {
        let err = |problem: &str| MapError::Endpoint {
            what,
            x: p.x,
            y: p.y,
            problem: problem.to_owned(),
        };
        match self.free_at(p) {
            None => Err(err(&format!("is outside the map {}", self.bounds()))),
            Some(false) => Err(err("is in an occupied cell")),
            Some(true) => match self.touches_obstacle(p) {
                Some(why) => Err(err(why)),
                None => Ok(()),
            },
        }
    }
}

/// Everything planning on a map needs, built once and shared by every query on the map: the
/// grid, the brushfire, the complete Voronoi graph with its index, the clearance model and the
/// rays that name homotopy classes.
///
/// # Examples
///
/// Prepare once, plan many; a disc robot plans in its exact free space
/// ([`PreparedMap::for_robot`]):
///
/// ```
/// use homospline_geom::Point;
/// use homospline_maps::{OccupancyMap, PreparedMap, map_config};
///
/// let (w, h) = (16, 10);
/// // A wall across the map with a diagonal door between the corners (8, 4) and (9, 5).
/// let map = OccupancyMap {
///     name: "door".into(),
///     width: w,
///     height: h,
///     cell: 1.0,
///     origin: Point::origin(),
///     occupied: (0..w * h)
///         .map(|k| (k % w == 7 && k / w <= 3) || (k % w == 9 && k / w >= 5))
///         .collect(),
///     y_down: true,
/// };
/// let prepared = PreparedMap::for_robot(&map, 0.6)?;
/// let cfg = map_config();
/// for goal in [Point::new(13.5, 3.5), Point::new(12.5, 1.5)] {
///     let plan = prepared.plan(Point::new(3.5, 4.5), goal, &cfg)?;
///     let chosen = plan.chosen().expect("through the door");
///     assert!(chosen.collision_free && chosen.min_clearance >= 0.0);
/// }
/// # Ok::<(), homospline_maps::MapError>(())
/// ```
pub struct PreparedMap {
    /// Name (the map's).
    pub name: String,
    /// Bounds in map coordinates.
    pub bounds: Bounds,
    /// The grid (map plus wall ring).
    pub grid: Grid,
    /// The brushfire.
    pub field: DistanceField,
    /// The complete Voronoi graph of the whole map (no start or goal), indexed.
    pub graph: MapGraph,
    /// The clearance model.
    pub model: GridModel,
    /// One ray per obstacle inside the wall.
    pub rays: Rays,
    /// The robot's radius: the grid and graph are those of the cells where the robot can
    /// stand, and the model's clearances are the robot body's ([`PreparedMap::for_robot`]).
    pub robot_radius: Real,
    /// The map as given, when the radius is positive (its endpoints' clearances).
    truth: Option<OccupancyMap>,
    map: OccupancyMap,
}

impl PreparedMap {
    /// Builds the grid, brushfire, complete graph and clearance model of `map`, for a point
    /// robot.
    pub fn new(map: &OccupancyMap) -> Result<Self, MapError> {
        Self::for_robot(map, 0.0)
    }

    /// The same for a disc robot of radius `radius` (map units). The free space is the cells
    /// whose centre keeps `radius` from every occupied cell and the map's edge: the grid, the
    /// brushfire and the graph are those of that map; the clearance model is the exact one
    /// of `map`, less `radius` ([`GridModel::for_radius`]), so costs, certificates and
    /// reported clearances are the robot body's, and a plan certified collision-free keeps
    /// `radius` from every occupied cell. A start or goal closer than `radius` to an obstacle
    /// is refused with the clearance it has.
    pub fn for_robot(map: &OccupancyMap, radius: Real) -> Result<Self, MapError> {
        let (free, model, truth) = Self::footprint(map, radius)?;
        let grid = free.to_grid()?;
        let field = DistanceField::build(&grid);
        let graph = MapGraph::build(&grid, &field);
        Ok(Self::assemble(
            &free, grid, field, graph, model, radius, truth,
        ))
    }

    /// The map of the cells a robot of `radius` can stand in, the model (of `map` itself,
    /// for the radius), and the map as given when `radius` is positive.
    #[allow(clippy::type_complexity)]
    fn footprint(
        map: &OccupancyMap,
        radius: Real,
    ) -> Result<(OccupancyMap, Option<GridModel>, Option<OccupancyMap>), MapError> {
        check_radius(radius)?;
        if radius == 0.0 {
            return Ok((map.clone(), None, None));
        }
        let (free, model) = map.robot_space(radius)?;
        Ok((free, Some(model), Some(map.clone())))
    }

    /// The same with a complete graph built before (`homospline graph MAP --out`, with the
    /// same robot radius); refused when it is not a graph of this map at this radius
    /// (resolution, obstacles or start/goal attached).
    pub fn with_graph(
        map: &OccupancyMap,
        graph: VoronoiGraph,
        radius: Real,
    ) -> Result<Self, MapError> {
        let (free, model, truth) = Self::footprint(map, radius)?;
        let map = &free;
        let grid = map.to_grid()?;
        let field = DistanceField::build(&grid);
        let fresh_obstacles: Vec<u32> = field
            .obstacles()
            .filter(|&k| k != field.wall_key())
            .collect();
        let saved: Vec<u32> = graph.obstacles.iter().map(|o| o.key).collect();
        if graph.start.is_some() || graph.goal.is_some() {
            return Err(MapError::Graph(
                "the graph has a start or goal attached: save it with `homospline graph MAP`"
                    .into(),
            ));
        }
        if (graph.resolution - grid.resolution()).abs() > 1e-9 * grid.resolution()
            || fresh_obstacles != saved
        {
            return Err(MapError::Graph(format!(
                "the graph was not built for map {} at robot radius {} (resolution, \
                 obstacles or robot radius differ)",
                map.name,
                Num(radius)
            )));
        }
        // Every node and polyline point in a free cell of this map at this radius: a graph of
        // another radius whose obstacles happen to match (all merged with the wall) runs
        // through cells now blocked, and points far off the map made the index's sampling
        // loop for ever.
        let off = graph
            .nodes
            .iter()
            .map(|n| n.at)
            .chain(graph.edges.iter().flat_map(|e| e.polyline.iter().copied()))
            .find(|p| map.free_at(&Point::new(p[0], p[1])) != Some(true));
        if let Some(p) = off {
            return Err(MapError::Graph(format!(
                "the graph was not built for map {} at robot radius {}: its point [{}, {}] \
                 is not in a free cell",
                map.name,
                Num(radius),
                Num(p[0]),
                Num(p[1])
            )));
        }
        let graph = MapGraph::from_graph(&grid, graph);
        Ok(Self::assemble(
            map, grid, field, graph, model, radius, truth,
        ))
    }

    #[allow(clippy::too_many_arguments)]
    fn assemble(
        map: &OccupancyMap,
        grid: Grid,
        field: DistanceField,
        graph: MapGraph,
        model: Option<GridModel>,
        robot_radius: Real,
        truth: Option<OccupancyMap>,
    ) -> Self {
        let model = model.unwrap_or_else(|| GridModel::new(&grid, &field));
        let rays = rays_of(&graph);
        Self {
            name: map.name.clone(),
            // The map's own bounds: the robot's lattice reaches half a lattice step past them.
            bounds: truth.as_ref().unwrap_or(map).bounds(),
            grid,
            field,
            graph,
            model,
            rays,
            robot_radius,
            truth,
            map: map.clone(),
        }
    }

    /// The cell size of the map as given, map units.
    pub fn cell(&self) -> Real {
        self.truth.as_ref().unwrap_or(&self.map).cell
    }

    /// The map it was built from; with a positive robot radius, the cells where the robot
    /// can stand (its centre keeps the radius).
    pub fn map(&self) -> &OccupancyMap {
        &self.map
    }

    /// Refuses an endpoint outside the map, in or on an occupied cell, closer than the robot
    /// radius to an obstacle (naming the clearance it has), or in a cell that the radius
    /// blocks.
    fn check_endpoint(&self, what: &'static str, p: &Point) -> Result<(), MapError> {
        let Some(truth) = &self.truth else {
            return self.map.check_endpoint(what, p);
        };
        let r = self.robot_radius;
        let c = truth.check_endpoint_for(what, p, r)?;
        self.map
            .check_endpoint(what, p)
            .map_err(|_| MapError::Endpoint {
                what,
                x: p.x,
                y: p.y,
                problem: format!(
                    "has clearance {c:.4} > the robot radius {r}, but the nearest point of the \
                 robot's lattice does not keep it (free space is sampled every half cell): \
                 move it up to half a cell away from the wall"
                ),
            })
    }

    /// The graph of one query: start and goal joined to the complete graph along
    /// maximum-clearance routes, dead ends to neither pruned.
    pub fn query_graph(&self, start: Point, goal: Point) -> Result<VoronoiGraph, MapError> {
        self.check_endpoint("start", &start)?;
        self.check_endpoint("goal", &goal)?;
        Ok(self
            .graph
            .with_endpoints(&self.grid, &self.field, start, goal)
            .map_err(BuildError::from)?)
    }

    /// Plans from `start` to `goal` (map coordinates) with the same result as on a scene.
    pub fn plan(&self, start: Point, goal: Point, cfg: &PlanConfig) -> Result<Plan, MapError> {
        self.check_endpoint("start", &start)?;
        self.check_endpoint("goal", &goal)?;
        let world = World {
            name: self.name.clone(),
            bounds: self.bounds,
            start,
            goal,
            model: &self.model,
            rays: self.rays.clone(),
            grid_is_exact: true,
            circles: None,
        };
        let (cfg, dm_why) = resolve_map_dm(cfg, self.cell());
        plan_world(
            &world,
            || {
                self.graph
                    .with_endpoints(&self.grid, &self.field, start, goal)
                    .map_err(BuildError::from)
            },
            &cfg,
        )
        .map(|mut plan| {
            plan.dm_why = dm_why;
            plan
        })
        .map_err(|e| match e {
            PlanError::Build(BuildError::Graph(GraphError::DifferentRegions)) => {
                self.no_route(start, goal)
            }
            e => MapError::Plan(e),
        })
    }

    /// The answer when no route of the robot's free space joins `start` and `goal`: the
    /// widest route on the map as given and its narrowest point.
    pub fn no_route(&self, start: Point, goal: Point) -> MapError {
        let map = self.truth.as_ref().unwrap_or(&self.map);
        MapError::NoRoute {
            radius: self.robot_radius,
            widest: footprint::widest_route(map, &self.model, start, goal),
        }
    }
}

/// The rays that name homotopy classes on a map's complete graph: one per obstacle inside
/// the wall, from its representative point.
pub fn rays_of(graph: &MapGraph) -> Rays {
    Rays::new(
        graph
            .graph
            .obstacles
            .iter()
            .map(|o| Point::new(o.representative[0], o.representative[1]))
            .collect(),
    )
}

/// Plans on `map` from `start` to `goal` (map coordinates), with the same result as on a
/// scene; the complete Voronoi graph comes from the grid directly. Builds the map's
/// preparation and returns it; to plan many queries on one map, build a [`PreparedMap`]
/// once and call [`PreparedMap::plan`].
pub fn plan_map(
    map: &OccupancyMap,
    start: Point,
    goal: Point,
    cfg: &PlanConfig,
) -> Result<(Plan, PreparedMap), MapError> {
    plan_map_for_robot(map, 0.0, start, goal, cfg)
}

/// [`plan_map`] for a disc robot of radius `radius` (map units; [`PreparedMap::for_robot`]).
pub fn plan_map_for_robot(
    map: &OccupancyMap,
    radius: Real,
    start: Point,
    goal: Point,
    cfg: &PlanConfig,
) -> Result<(Plan, PreparedMap), MapError> {
    map.check_endpoints_for(&start, &goal, radius)?;
    let prepared = PreparedMap::for_robot(map, radius)?;
    let plan = prepared.plan(start, goal, cfg)?;
    Ok((plan, prepared))
}

/// A file stem for names.
pub(crate) fn stem(source: &str) -> String {
    std::path::Path::new(source)
        .file_name()
        .and_then(|s| s.to_str())
        .map(|s| s.split('.').next().unwrap_or(s).to_owned())
        .unwrap_or_else(|| "map".to_owned())
}
