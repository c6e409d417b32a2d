//! The known map of a map mission: grid, brushfire, complete graph and clearance model, kept
//! up to date as changes are discovered, and the planner on it.

use std::time::Instant;

use homospline_geom::{Point, Real};
use homospline_homotopy::Rays;
use homospline_maps::{GridModel, MapError, OccupancyMap, rays_of};
use homospline_optim::{Plan, PlanConfig, PlanGraph, World, plan_world};
use homospline_spline::ClearanceModel;
use homospline_voronoi::{BuildError, DistanceField, Grid, MapGraph};

use super::Known;
use crate::world::types::MapWorld;

/// One update of the known map at a discovery.
#[derive(Clone, Debug, PartialEq)]
pub struct MapUpdate {
    /// Cells changed.
    pub cells: usize,
    /// The brushfire was updated locally (`false`: rebuilt, obstacles would be renamed).
    pub local: bool,
    /// Wall time of the brushfire's update, ms.
    pub field_ms: Real,
    /// Wall time of the graph's rebuild from the field, ms (0 when it was kept).
    pub graph_ms: Real,
    /// Whether the graph was rebuilt (`false`: kept, with its edges through the blocked
    /// cells closed).
    pub graph_rebuilt: bool,
    /// Wall time of the clearance model's rebuild (with a robot radius, the robot's lattice
    /// judged again with it), ms.
    pub model_ms: Real,
}

/// With a positive robot radius, the two maps behind the planner: the known map as given
/// (its exact clearance, less the radius, is the model: costs and certificates) and where
/// the robot can stand on it, the half-cell lattice (the grid, brushfire and graph: the
/// topology), as `PreparedMap::for_robot` plans on.
struct Footprint {
    radius: Real,
    known: OccupancyMap,
    free: OccupancyMap,
}

/// Cells of the planner's map that changed, all blocked or all freed.
struct Edit {
    cells: Vec<(usize, usize)>,
    blocked: bool,
}

/// The known map of a map mission: grid, brushfire, complete graph and clearance model, kept
/// up to date as changes are discovered.
pub(crate) struct MapKnown<'w> {
    world: &'w MapWorld,
    /// With a positive robot radius, the known map and the robot's lattice on it (the grid
    /// below is the lattice's).
    footprint: Option<Footprint>,
    grid: Grid,
    field: DistanceField,
    graph: MapGraph,
    model: GridModel,
    /// The rays of the known map's obstacles (the planner's).
    rays: Rays,
    /// The rays of the prior map's obstacles (class names).
    naming: Rays,
    known: Vec<bool>,
    pending: Vec<usize>,
    /// Discs around the cells blocked since the graph was last built: the class search
    /// leaves out the edges that enter them.
    closed: Vec<(Point, Real)>,
    /// Every update so far.
    pub(crate) updates: Vec<MapUpdate>,
}

impl<'w> MapKnown<'w> {
    /// The prior map's preparation.
    pub(crate) fn new(world: &'w MapWorld) -> Result<Self, MapError> {
        let radius = world.team.ugv.radius;
        let (footprint, model_of) = if radius > 0.0 {
            let (free, model) = world.prior.robot_space(radius)?;
            let fp = Footprint {
                radius,
                known: world.prior.clone(),
                free,
            };
            (Some(fp), Some(model))
        } else {
            (None, None)
        };
        let grid = footprint
            .as_ref()
            .map_or(&world.prior, |fp| &fp.free)
            .to_grid()?;
        let field = DistanceField::build(&grid);
        let graph = MapGraph::build(&grid, &field);
        let model = model_of.unwrap_or_else(|| GridModel::new(&grid, &field));
        let rays = rays_of(&graph);
        Ok(Self {
            world,
            footprint,
            naming: rays.clone(),
            grid,
            field,
            graph,
            model,
            rays,
            known: vec![false; world.changes.len()],
            pending: Vec::new(),
            closed: Vec::new(),
            updates: Vec::new(),
        })
    }

    /// The rays that name classes: the prior map's obstacles.
    pub(crate) fn naming_rays(&self) -> Rays {
        self.naming.clone()
    }

    /// Frees the cells of a change on the grid and updates the brushfire: locally when they
    /// are a whole obstacle, else by a rebuild (freeing part of an obstacle may split it or
    /// free its smallest cell, which renames obstacles anywhere on the map). Whether it was
    /// local.
    fn free(&mut self, cells: &[(usize, usize)]) -> bool {
        let (i, j) = cells[0];
        let key = self.field.nearest(i, j);
        let whole = key != self.field.wall_key()
            && cells
                .iter()
                .all(|&(a, b)| self.field.d2(a, b) == 0 && self.field.nearest(a, b) == key)
            && component_size(&self.grid, (i, j), cells.len() + 1) == cells.len();
        if whole && self.field.remove_obstacle(&mut self.grid, key).is_ok() {
            return true;
        }
        for &(a, b) in cells {
            self.grid.set(a, b, false);
        }
        self.field = DistanceField::build(&self.grid);
        false
    }

    /// The edits of the planner's map for the `pending` changes: their cells, or with a
    /// robot radius the lattice cells that changed once they are applied to the known map
    /// (the model is renewed with it).
    fn edits(&mut self, pending: &[usize]) -> Vec<Edit> {
        let world = self.world;
        let Some(fp) = &mut self.footprint else {
            return pending
                .iter()
                .map(|&c| Edit {
                    cells: world.changes[c].cells.clone(),
                    blocked: world.changes[c].blocked,
                })
                .collect();
        };
        for &c in pending {
            let change = &world.changes[c];
            for &(i, j) in &change.cells {
                fp.known.occupied[j * fp.known.width + i] = change.blocked;
            }
        }
        // The lattice is judged again map-wide (a radius's reach of every changed cell would
        // do; the brushfire and graph below are updated locally).
        let fresh = match fp.known.robot_space(fp.radius) {
            Ok((free, model)) => {
                self.model = model;
                free
            }
            // No lattice point keeps the radius any more: every cell blocked.
            Err(_) => OccupancyMap {
                occupied: vec![true; fp.free.occupied.len()],
                ..fp.free.clone()
            },
        };
        let w = fp.free.width;
        let changed = |blocked: bool| Edit {
            cells: (0..fp.free.occupied.len())
                .filter(|&k| {
                    fp.free.occupied[k] != fresh.occupied[k] && fresh.occupied[k] == blocked
                })
                .map(|k| (k % w, k / w))
                .collect(),
            blocked,
        };
        let edits: Vec<Edit> = [changed(true), changed(false)]
            .into_iter()
            .filter(|e| !e.cells.is_empty())
            .collect();
        fp.free = fresh;
        edits
    }

    /// Applies `edits` to the grid and the brushfire. The cells changed, and whether the
    /// brushfire was updated locally throughout.
    fn update_field(&mut self, edits: &[Edit]) -> (usize, bool) {
        let mut cells = 0;
        let mut local = true;
        for edit in edits {
            // Map cell (i, j) is grid cell (i + 1, j + 1): the grid has a wall ring.
            let on_grid: Vec<(usize, usize)> =
                edit.cells.iter().map(|&(i, j)| (i + 1, j + 1)).collect();
            cells += on_grid.len();
            if edit.blocked {
                if self.field.add_cells(&mut self.grid, &on_grid).is_err() {
                    // The blockage joins two obstacles (or becomes an obstacle's smallest
                    // cell): obstacles are renamed, possibly far away: rebuild.
                    for &(i, j) in &on_grid {
                        self.grid.set(i, j, true);
                    }
                    self.field = DistanceField::build(&self.grid);
                    local = false;
                }
            } else {
                local &= self.free(&on_grid);
            }
        }
        (cells, local)
    }

    /// The complete graph after the `edits`: kept with the blocked cells closed, or rebuilt
    /// from the field. Whether it was rebuilt.
    ///
    /// The complete graph cannot be updated locally: the homotopic thinning removes cells in
    /// the order of their distance over the whole free space, and its chains are traced
    /// map-wide into nodes and edges whose numbering the class search relies on. After
    /// blockages only, it is kept and the edges entering a blocked cell (a disc round the
    /// cell's square) are closed; freed cells open ways it lacks, so it is rebuilt.
    fn update_graph(&mut self, edits: &[Edit]) -> bool {
        let rebuild = edits.iter().any(|e| !e.blocked);
        if rebuild {
            self.graph = MapGraph::build(&self.grid, &self.field);
            self.rays = rays_of(&self.graph);
            self.closed.clear();
        } else {
            let map = self
                .footprint
                .as_ref()
                .map_or(&self.world.prior, |fp| &fp.free);
            let radius = map.cell * std::f64::consts::FRAC_1_SQRT_2 * (1.0 + 1e-9);
            for edit in edits {
                self.closed.extend(edit.cells.iter().map(|&(i, j)| {
                    let centre = Point::new(
                        map.origin.x + (i as Real + 0.5) * map.cell,
                        map.origin.y + (j as Real + 0.5) * map.cell,
                    );
                    (centre, radius)
                }));
            }
        }
        rebuild
    }
}

/// Cells of the 8-connected occupied component holding `from`, counted up to `limit`.
fn component_size(grid: &Grid, from: (usize, usize), limit: usize) -> usize {
    let mut seen = std::collections::HashSet::from([from]);
    let mut stack = vec![from];
    while let Some((i, j)) = stack.pop() {
        if seen.len() >= limit {
            break;
        }
        for dj in -1i64..=1 {
            for di in -1i64..=1 {
                let (x, y) = (i as i64 + di, j as i64 + dj);
                if x < 0 || y < 0 || x >= grid.width() as i64 || y >= grid.height() as i64 {
                    continue;
                }
                let n = (x as usize, y as usize);
                if grid.occupied(n.0, n.1) && seen.insert(n) {
                    stack.push(n);
                }
            }
        }
    }
    seen.len().min(limit)
}

impl MapKnown<'_> {
    /// A plan from `from` (in a free cell of the planner's grid) to the goal.
    fn plan_on_grid(&self, from: Point, cfg: &PlanConfig) -> Option<Plan> {
        let plan_on = |graph: &MapGraph, rays: &Rays, cfg: &PlanConfig| {
            let world = World {
                name: self.world.name.clone(),
                bounds: self.world.prior.bounds(),
                start: from,
                goal: self.world.goal,
                model: &self.model,
                rays: std::borrow::Cow::Borrowed(rays),
                grid_is_exact: true,
                circles: None,
            };
            plan_world(
                &world,
                || {
                    graph
                        .query(&self.grid, &self.field, from, self.world.goal)
                        .map(PlanGraph::Query)
                        .map_err(BuildError::from)
                },
                cfg,
            )
            .ok()
        };
        if self.closed.is_empty() {
            return plan_on(&self.graph, &self.rays, cfg);
        }
        let mut closed_cfg = cfg.clone();
        closed_cfg
            .search
            .blocked_regions
            .extend(self.closed.iter().copied());
        let kept = plan_on(&self.graph, &self.rays, &closed_cfg);
        // `best` is a collision-free class (meeting the clearance floor) when there is one.
        if kept.as_ref().is_some_and(|p| p.best.is_some()) {
            return kept;
        }
        // Closing whole edges is conservative: a blockage in a wide corridor closes it on
        // the kept graph although the robot could pass beside it. The graph of the updated
        // field has every way that is left.
        let graph = MapGraph::build(&self.grid, &self.field);
        plan_on(&graph, &rays_of(&graph), cfg)
    }

    /// The centre of the lattice cell nearest `from` (within two lattice steps) where the
    /// robot stands, joined to `from` by a segment that keeps the radius.
    fn snap(&self, free: &OccupancyMap, from: Point) -> Option<Point> {
        let (fx, fy) = (
            (from.x - free.origin.x) / free.cell,
            (from.y - free.origin.y) / free.cell,
        );
        let (ci, cj) = (fx.floor() as i64, fy.floor() as i64);
        let mut best: Option<(Real, Point)> = None;
        for j in cj - 2..=cj + 2 {
            for i in ci - 2..=ci + 2 {
                let q = Point::new(
                    free.origin.x + (i as Real + 0.5) * free.cell,
                    free.origin.y + (j as Real + 0.5) * free.cell,
                );
                let d = (q - from).norm();
                if best.is_some_and(|(b, _)| b <= d)
                    || !stands(free, &q)
                    || self.model.polyline_clearance(&[from, q]) <= 0.0
                {
                    continue;
                }
                best = Some((d, q));
            }
        }
        best.map(|(_, q)| q)
    }
}

/// Whether the robot's centre may start at `p` on the planner's map: a free cell, not on
/// the side or corner of an occupied one.
fn stands(map: &OccupancyMap, p: &Point) -> bool {
    map.free_at(p) == Some(true) && map.touches_obstacle(p).is_none()
}

impl Known for MapKnown<'_> {
    fn start(&self) -> Point {
        self.world.start
    }

    fn goal(&self) -> Point {
        self.world.goal
    }

    fn plan_from(&self, from: Point, cfg: &PlanConfig, _online: bool) -> Option<Plan> {
        let Some(fp) = &self.footprint else {
            return self.plan_on_grid(from, cfg);
        };
        if stands(&fp.free, &from) {
            return self.plan_on_grid(from, cfg);
        }
        // A point the robot keeps its radius at can lie in a lattice cell whose centre does
        // not (up to a quarter cell away): the plan starts at the nearest lattice point
        // joined to it by a clear segment, and the segment is put in front of every class.
        let q = self.snap(&fp.free, from)?;
        let mut plan = self.plan_on_grid(q, cfg)?;
        for c in &mut plan.classes {
            c.path.insert(0, from);
            c.via_points.insert(0, from);
            c.seed_path.insert(0, from);
        }
        Some(plan)
    }

    fn model(&self) -> &dyn ClearanceModel {
        &self.model
    }

    fn sense(&mut self, p: &Point, range: Real) -> Vec<(String, bool)> {
        let mut found = Vec::new();
        for (c, change) in self.world.changes.iter().enumerate() {
            if !self.known[c]
                && change
                    .cells
                    .iter()
                    .any(|&cell| self.world.prior.distance_to_cell(p, cell) <= range)
            {
                self.known[c] = true;
                self.pending.push(c);
                // A blockage is something the map lacks (`hidden`); freed cells are a mapped
                // obstacle found gone.
                found.push((change.name.clone(), change.blocked));
            }
        }
        found
    }

    fn update(&mut self) -> Real {
        let start = Instant::now();
        let pending = std::mem::take(&mut self.pending);
        if pending.is_empty() {
            return 0.0;
        }
        let edits = self.edits(&pending);
        // With a robot radius `edits` judged the lattice again and renewed the model: that
        // time is the model's.
        let lattice_ms = if self.footprint.is_some() {
            start.elapsed().as_secs_f64() * 1e3
        } else {
            0.0
        };
        let t0 = Instant::now();
        let (cells, local) = self.update_field(&edits);
        let field_ms = t0.elapsed().as_secs_f64() * 1e3;
        let t1 = Instant::now();
        let rebuild = self.update_graph(&edits);
        let graph_ms = t1.elapsed().as_secs_f64() * 1e3;
        let t2 = Instant::now();
        if self.footprint.is_none() {
            self.model = GridModel::new(&self.grid, &self.field);
        }
        let model_ms = t2.elapsed().as_secs_f64() * 1e3 + lattice_ms;
        self.updates.push(MapUpdate {
            cells,
            local,
            field_ms,
            graph_ms,
            graph_rebuilt: rebuild,
            model_ms,
        });
        start.elapsed().as_secs_f64() * 1e3
    }

    fn renamed(&self) -> Option<Rays> {
        // Map classes keep the prior map's names throughout.
        None
    }
}
