//! [`CostConfig`], the weights and parameters of the cost, with the paper's presets, and
//! [`ClearanceSearch`], where `m(C)` is looked for between the quadrature nodes.

use homospline_geom::{Point, Real, Scene};

use crate::roughness::RoughnessForm;

/// Weights and parameters of the cost: the paper's criteria (potential, roughness, length,
/// safety) and the optional ones, each with its weight, and `dm`, the clearance the safety
/// term asks for.
///
/// # Examples
///
/// ```
/// use homospline_spline::CostConfig;
///
/// // Ask for 2 units of clearance and weigh length more.
/// let cfg = CostConfig { dm: 2.0, w_length: 1.0, ..CostConfig::default() };
/// assert_eq!(cfg.dm, 2.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct CostConfig {
    /// `g1`: topology (collision) term.
    pub w_topology: Real,
    /// `g2`: roughness.
    pub w_roughness: Real,
    /// `g3`: length.
    pub w_length: Real,
    /// `g4`: safety.
    pub w_safety: Real,
    /// Maximal-clearance term.
    pub w_max_clearance: Real,
    /// Start visibility.
    pub w_start_visibility: Real,
    /// Goal visibility.
    pub w_goal_visibility: Real,
    /// Danger points.
    pub w_danger: Real,
    /// Critical points.
    pub w_critical: Real,
    /// Sheltered share.
    pub w_sheltered: Real,
    /// Passing time.
    pub w_passing_time: Real,
    /// The form of roughness (4).
    pub roughness: RoughnessForm,
    /// `alpha` of the potential (1).
    pub alpha: Real,
    /// Required clearance `dm` of the safety term.
    pub dm: Real,
    /// Base `omega` of the safety term.
    pub omega: Real,
    /// `d_max` of the maximal-clearance term.
    pub d_max: Real,
    /// Speed limit on straight parts (passing time).
    pub v_max: Real,
    /// Lateral acceleration limit (passing time): `v <= sqrt(a_lat / kappa)`.
    pub lateral_accel: Real,
    /// Gauss-Legendre nodes per piece (2 to 64).
    pub nodes: usize,
    /// Pieces per spline segment.
    pub pieces: usize,
    /// Relative truncation allowed in the topology term: the potential of far circles may be
    /// left out as long as what is left out is at most `tolerance * (g2 R + g3 L + g4 D_knots)`
    /// (`D_knots`: `D` at the least knot clearance, at most `D`), a lower
    /// bound of the total times `tolerance`. 0 keeps every circle whose potential exceeds
    /// `2 exp(-30)` per unit length; reports use 0.
    pub tolerance: Real,
    /// Danger points `(at, min_distance)`.
    pub danger_points: Vec<(Point, Real)>,
    /// Critical points `(at, max_distance)`.
    pub critical_points: Vec<(Point, Real)>,
    /// Hazard sources.
    pub hazards: Vec<Point>,
    /// Where `m(C)` is searched between the quadrature nodes.
    pub clearance_search: ClearanceSearch,
    /// The safety term integrated along the curve, `D = (1 / |S T|) integral omega^(dm - d(q))
    /// dl`, instead of (7)'s `omega^(dm - m(C))` at the least clearance only (maps). On a
    /// straight path of constant clearance it is (7); it sees every stretch that comes near
    /// an obstacle (each pulls with its own share), and a start or goal next to a wall
    /// weighs only over the stretch near it: with (7) the least clearance of a map path is
    /// usually its start's or a one-cell door's, `D` is then the same for every curve, and
    /// the rest of the path grazed corners. The scale is the fixed `|S T|` (1 when `S = T`),
    /// not the curve's length: divided by its own length, `D` paid a detour through open
    /// space (it lowered the mean), and paths on small cluttered maps came out twice as long.
    pub safety_along: bool,
}

/// Where the cost looks for `m(C)` between its quadrature nodes, which can be several units
/// apart on a long segment: a curve passing a small circle between two nodes dips below
/// both (by up to `a^2 / 8 rho` for nodes `a` apart passing a centre at `rho`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ClearanceSearch {
    /// Brent's method between the worst node's two neighbours: the optimiser's default. It
    /// misses a dip between two other nodes (a fair share of the classes whose `m(C)` kept
    /// `dm` were certified below it; measured: docs/performance.md, "Measurements behind the
    /// defaults"). The planner gives a class whose final
    /// curve has such a dip, and that could rank first, one more round with `EveryStretch`
    /// (`homospline_optim::Growth::repair`).
    #[default]
    WorstNode,
    /// As `WorstNode`, then every stretch between two consecutive nodes (and from each end
    /// to its nearest node) whose bound lets the clearance dip below the least value found
    /// is halved, the lowest bound first, until no bound is more than `1e-5` below it. The
    /// bound is the larger of the Lipschitz one and one from how sharply the clearance can
    /// bend ([`ClearanceModel::bend_radius`](crate::clearance_model::ClearanceModel::bend_radius));
    /// the worst node's two stretches are searched too (Brent's method follows one valley,
    /// and a second dip beside it escapes it). An evaluation costs 1.6 times as much on the
    /// cost bench: a curve held near `dm` has many stretches close to it. A model without the bend bound gets `WorstNode` (a map's
    /// grid has it: the distance to a square bends as a disc of radius 0's).
    EveryStretch,
}

impl ClearanceSearch {
    /// Both, in order.
    pub const ALL: [Self; 2] = [Self::WorstNode, Self::EveryStretch];

    /// `worst-node` or `every-stretch`, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Self::WorstNode => "worst-node",
            Self::EveryStretch => "every-stretch",
        }
    }

    /// The search called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

impl Default for CostConfig {
    fn default() -> Self {
        Self::paper_voronoi()
    }
}

impl CostConfig {
    /// The paper's original cost (9): `F = T + R + 0.5 L`, `alpha = 0.5`.
    pub fn paper_original() -> Self {
        Self {
            w_topology: 1.0,
            w_roughness: 1.0,
            w_length: 0.5,
            w_safety: 0.0,
            w_max_clearance: 0.0,
            w_start_visibility: 0.0,
            w_goal_visibility: 0.0,
            w_danger: 0.0,
            w_critical: 0.0,
            w_sheltered: 0.0,
            w_passing_time: 0.0,
            roughness: RoughnessForm::Paper,
            alpha: 0.5,
            dm: 3.0,
            omega: 20.0,
            d_max: 10.0,
            v_max: 1.0,
            lateral_accel: 0.5,
            nodes: 5,
            pieces: 2,
            tolerance: 1e-6,
            danger_points: Vec::new(),
            critical_points: Vec::new(),
            hazards: Vec::new(),
            clearance_search: ClearanceSearch::WorstNode,
            safety_along: false,
        }
    }

    /// The cost used with the Voronoi seeds (10): `F = T + R + 0.5 L + D`, `dm = 3`,
    /// `omega = 20`.
    pub fn paper_voronoi() -> Self {
        Self {
            w_safety: 1.0,
            ..Self::paper_original()
        }
    }

    /// A named preset: `paper-original` (9) or `paper-voronoi` (10).
    pub fn preset(name: &str) -> Option<Self> {
        match name {
            "paper-original" | "original" => Some(Self::paper_original()),
            "paper-voronoi" | "voronoi" | "paper" => Some(Self::paper_voronoi()),
            _ => None,
        }
    }

    /// Takes the scene's danger points, critical points and hazards.
    pub fn with_scene_points(mut self, scene: &Scene) -> Self {
        self.danger_points = scene
            .danger_points
            .iter()
            .map(|d| (d.at, d.min_distance))
            .collect();
        self.critical_points = scene
            .critical_points
            .iter()
            .map(|d| (d.at, d.max_distance))
            .collect();
        self.hazards = scene.hazards.clone();
        self
    }
}
