//! Where a map's cells size the planner's settings: the certificate's tolerance and the
//! `dm` in cells of the map profile ([`PlanConfig::maps`]).

use homospline_geom::Real;
use homospline_geom::math::Num;
use homospline_optim::PlanConfig;

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
