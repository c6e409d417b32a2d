//! The known map of a map mission: grid, brushfire, complete graph and clearance model, kept
//! up to date as changes are discovered, and the planner on it.

use std::time::Instant;

use homospline_geom::{Point, Real};
use homospline_homotopy::Rays;
use homospline_maps::{GridModel, MapError, rays_of};
use homospline_optim::{Plan, PlanConfig, World, plan_world};
use homospline_spline::ClearanceModel;
use homospline_voronoi::{BuildError, DistanceField, Grid, MapGraph};

use crate::known::Known;
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
    /// Wall time of the clearance model's rebuild, ms.
    pub model_ms: Real,
}

/// The known map of a map mission: grid, brushfire, complete graph and clearance model, kept
/// up to date as changes are discovered.
pub(crate) struct MapKnown<'w> {
    world: &'w MapWorld,
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
        let grid = world.prior.to_grid()?;
        let field = DistanceField::build(&grid);
        let graph = MapGraph::build(&grid, &field);
        let model = GridModel::new(&grid, &field);
        let rays = rays_of(&graph);
        Ok(Self {
            world,
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

    /// Applies the `pending` changes to the grid and the brushfire. The cells changed, and
    /// whether the brushfire was updated locally throughout.
    fn update_field(&mut self, pending: &[usize]) -> (usize, bool) {
        let world = self.world;
        let mut cells = 0;
        let mut local = true;
        for &c in pending {
            let change = &world.changes[c];
            // Map cell (i, j) is grid cell (i + 1, j + 1): the grid has a wall ring.
            let on_grid: Vec<(usize, usize)> =
                change.cells.iter().map(|&(i, j)| (i + 1, j + 1)).collect();
            cells += on_grid.len();
            if change.blocked {
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

    /// The complete graph after the `pending` changes: kept with the blocked cells closed,
    /// or rebuilt from the field. Whether it was rebuilt.
    ///
    /// The complete graph cannot be updated locally: the homotopic thinning removes cells in
    /// the order of their distance over the whole free space, and its chains are traced
    /// map-wide into nodes and edges whose numbering the class search relies on. After
    /// blockages only, it is kept and the edges entering a blocked cell (a disc round the
    /// cell's square) are closed; freed cells open ways it lacks, so it is rebuilt.
    fn update_graph(&mut self, pending: &[usize]) -> bool {
        let world = self.world;
        let rebuild = pending.iter().any(|&c| !world.changes[c].blocked);
        if rebuild {
            self.graph = MapGraph::build(&self.grid, &self.field);
            self.rays = rays_of(&self.graph);
            self.closed.clear();
        } else {
            let map = &world.prior;
            let radius = map.cell * std::f64::consts::FRAC_1_SQRT_2 * (1.0 + 1e-9);
            for &c in pending {
                self.closed
                    .extend(world.changes[c].cells.iter().map(|&(i, j)| {
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

impl Known for MapKnown<'_> {
    fn start(&self) -> Point {
        self.world.start
    }

    fn goal(&self) -> Point {
        self.world.goal
    }

    fn plan_from(&self, from: Point, cfg: &PlanConfig, _online: bool) -> Option<Plan> {
        let plan_on = |graph: &MapGraph, rays: &Rays, cfg: &PlanConfig| {
            let world = World {
                name: self.world.name.clone(),
                bounds: self.world.prior.bounds(),
                start: from,
                goal: self.world.goal,
                model: &self.model,
                rays: rays.clone(),
                grid_is_exact: true,
                circles: None,
            };
            plan_world(
                &world,
                || {
                    graph
                        .with_endpoints(&self.grid, &self.field, from, self.world.goal)
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
        let t0 = Instant::now();
        let pending = std::mem::take(&mut self.pending);
        if pending.is_empty() {
            return 0.0;
        }
        let (cells, local) = self.update_field(&pending);
        let field_ms = t0.elapsed().as_secs_f64() * 1e3;
        let t1 = Instant::now();
        let rebuild = self.update_graph(&pending);
        let graph_ms = t1.elapsed().as_secs_f64() * 1e3;
        let t2 = Instant::now();
        self.model = GridModel::new(&self.grid, &self.field);
        let model_ms = t2.elapsed().as_secs_f64() * 1e3;
        self.updates.push(MapUpdate {
            cells,
            local,
            field_ms,
            graph_ms,
            graph_rebuilt: rebuild,
            model_ms,
        });
        t0.elapsed().as_secs_f64() * 1e3
    }

    fn renamed(&self) -> Option<Rays> {
        // Map classes keep the prior map's names throughout.
        None
    }
}
