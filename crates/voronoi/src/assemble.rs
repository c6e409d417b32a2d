//! [`VoronoiGraph::build`]: the crack graph of a rasterised scene (the paper's GVG) with start
//! and goal attached, on top of the steps that make it: the cracks between the
//! nearest-obstacle regions (`crack`), traced into nodes and chains (`trace`), the chains'
//! polylines (`simplify`), then start and goal joined to it ([`crate::attach`]).

use homospline_geom::Point;

use crate::attach::{attach_to_cracks, join_directly};
use crate::crack::CrackGraph;
use crate::field::DistanceField;
use crate::graph::{GraphError, GridObstacle, NodeKind, VoronoiGraph};
use crate::grid::Grid;

impl VoronoiGraph {
    /// The graph of `field` over `grid`; start and goal attached when given.
    pub fn build(
        grid: &Grid,
        field: &DistanceField,
        start: Option<Point>,
        goal: Option<Point>,
    ) -> Result<Self, GraphError> {
        let mut cg = CrackGraph::build(grid, field);
        let mut g = VoronoiGraph {
            resolution: grid.resolution(),
            nodes: cg.nodes(),
            edges: Vec::new(),
            start: None,
            goal: None,
            obstacles: GridObstacle::of_field(grid, field),
            built_for: None,
        };
        if let (Some(s), Some(t)) = (start, goal)
            && let Some(connector) = join_directly(&cg, &mut g, s, t)?
        {
            g.edges = cg.edges();
            g.edges.push(connector);
            return Ok(g);
        }
        if let Some(s) = start {
            g.start = Some(attach_to_cracks(
                &mut cg,
                &mut g,
                s,
                "start",
                NodeKind::Start,
            )?);
        }
        if let Some(t) = goal {
            g.goal = Some(attach_to_cracks(
                &mut cg,
                &mut g,
                t,
                "goal",
                NodeKind::Goal,
            )?);
        }
        // The chains' edges first, then the connectors.
        let connectors = std::mem::take(&mut g.edges);
        g.edges = cg.edges();
        g.edges.extend(connectors);
        if let (Some(s), Some(t)) = (g.start, g.goal)
            && !g.connected(s, t)
        {
            return Err(GraphError::DifferentRegions);
        }
        Ok(g)
    }
}
