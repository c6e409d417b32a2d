//! What the team knows of the world while a mission runs: the interface the simulation
//! drives ([`Known`]), for a scene of circles ([`scene`]) and an occupancy map ([`map`])
//! alike.

pub(crate) mod map;
pub(crate) mod scene;

use homospline_geom::{Point, Real};
use homospline_homotopy::Rays;
use homospline_optim::{Plan, PlanConfig};
use homospline_spline::ClearanceModel;

/// What the team knows of the world while the mission runs, and the truth its sensors read:
/// a scene of circles or an occupancy map. The simulation loop is the same for both.
pub(crate) trait Known {
    /// The UGV's start.
    fn start(&self) -> Point;
    /// The goal.
    fn goal(&self) -> Point;
    /// A plan from `from` to the goal on the known world (`None`: no plan); `online`: a
    /// re-plan during the mission (not the offline plan).
    fn plan_from(&self, from: Point, cfg: &PlanConfig, online: bool) -> Option<Plan>;
    /// The clearance model of the known world.
    fn model(&self) -> &dyn ClearanceModel;
    /// What a robot at `p` seeing `range` discovers now: `(name, hidden)` for each
    /// difference between the known world and the truth that comes within range (`hidden`:
    /// something is there that the known world lacks). Marked known; the known world itself
    /// changes at [`Known::update`].
    fn sense(&mut self, p: &Point, range: Real) -> Vec<(String, bool)>;
    /// Applies what was sensed since the last update to the known world; its wall time, ms.
    fn update(&mut self) -> Real;
    /// The rays that name classes, when mapped obstacles found gone renamed them.
    fn renamed(&self) -> Option<Rays>;
}
