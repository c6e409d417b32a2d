//! A map prepared once for many queries: its grid, brushfire, complete Voronoi graph and
//! clearance model, and the plans on it.

use homospline_geom::math::Num;
use homospline_geom::{Bounds, Point, Real};
use homospline_homotopy::Rays;
use homospline_optim::{Plan, PlanConfig, PlanError, PlanGraph, World, plan_world};
use homospline_voronoi::{BuildError, DistanceField, GraphError, Grid, MapGraph, VoronoiGraph};

use crate::config::*;
use crate::map::*;
use crate::{GridModel, footprint};

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
/// use homospline_maps::{OccupancyMap, PreparedMap};
/// use homospline_optim::PlanConfig;
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
/// let cfg = PlanConfig::maps();
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
            rays: std::borrow::Cow::Borrowed(&self.rays),
            grid_is_exact: true,
            circles: None,
        };
        let (cfg, dm_why) = resolve_map_dm(cfg, self.cell());
        plan_world(
            &world,
            || {
                self.graph
                    .query(&self.grid, &self.field, start, goal)
                    .map(PlanGraph::Query)
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
