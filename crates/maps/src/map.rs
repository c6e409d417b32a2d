//! The occupancy map: cells in map coordinates, its checks and errors, and what it answers
//! (free space, a robot's free space, the grid the Voronoi graph is built on).

use homospline_geom::math::Num;
use homospline_geom::{Bounds, Point, ROBOT_RADIUS_RULE, Real, is_robot_radius};
use homospline_optim::PlanError;
use homospline_voronoi::{BuildError, DistanceField, Grid, GridError};
use thiserror::Error;

use crate::{GridModel, footprint, ros};

/// An occupancy map in map coordinates: `width x height` square cells of side `cell` from
/// `origin`, row-major (`occupied[j * width + i]` is cell `(i, j)`, whose square is
/// `origin + [i, i + 1] x [j, j + 1]` cells); occupied cells are closed squares and the
/// map's edge is a wall. Read from MovingAI `.map` files ([`crate::movingai::read_map`]) and ROS
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
/// See also [`crate::PreparedMap`] (plan on it), [`OccupancyMap::robot_space`].
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
pub(crate) fn check_radius(radius: Real) -> Result<(), MapError> {
    if is_robot_radius(radius) {
        Ok(())
    } else {
        Err(MapError::Radius(radius))
    }
}

pub(crate) fn no_route_message(radius: Real, widest: &footprint::Widest) -> String {
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

pub(crate) fn round4(x: Real) -> Real {
    (x * 1e4).round() / 1e4
}

/// Most cells a map may have: 4096 x 4096. Preparing a map (grid, brushfire, complete
/// Voronoi graph and its index, clearance model) takes a roughly fixed number of bytes per
/// cell on the hardest maps (`cargo xtask map-memory`), and at this size that fits in
/// [`MAP_MEMORY`] (measured: docs/performance.md, "Measurements behind the defaults").
/// Larger maps are refused before anything of their size is allocated, with
/// [`MapError::TooLarge`].
pub const MAX_MAP_CELLS: usize = 4096 * 4096;

/// The memory a map's preparation may take, as the refusal of a larger map says.
pub const MAP_MEMORY: &str = "1.5 GB";

/// Checks a map's cell size and origin, as every front end gives them (a ROS YAML, a NumPy
/// array's `resolution` and `origin`): the cell at least [`ros::MIN_RESOLUTION`], the origin
/// finite, and the map within [`homospline_geom::scene::MAX_MAGNITUDE`] of the frame's origin,
/// as a scene's coordinates are (huge resolutions hung the planner or asked for more path
/// samples than any memory holds; measured: docs/performance.md, "Measurements behind the
/// defaults"). `Err((field, problem))`, the field being
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
    /// itself. (Missions plan on maps inflated so; [`crate::PreparedMap::for_robot`] frees the cells
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
    pub(crate) fn check_endpoint_for(
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

    pub(crate) fn check_endpoint(&self, what: &'static str, p: &Point) -> Result<(), MapError> {
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

/// A file stem for names.
pub(crate) fn stem(source: &str) -> String {
    std::path::Path::new(source)
        .file_name()
        .and_then(|s| s.to_str())
        .map(|s| s.split('.').next().unwrap_or(s).to_owned())
        .unwrap_or_else(|| "map".to_owned())
}
