//! The world's data: the team, the world file as read, and the worlds ready to simulate (a
//! prior scene, or a prior occupancy map with its truth map).

use homospline_geom::{Obstacle, Point, Real, Scene};
use homospline_maps::OccupancyMap;

/// The world file format version this build reads.
pub const WORLD_VERSION: u32 = 1;

/// The ground robot.
#[derive(Clone, Debug, PartialEq)]
pub struct Ugv {
    /// Map units per second.
    pub speed: Real,
    /// Obstacles (and their absence) within this distance are discovered, map units.
    pub sensor_range: Real,
    /// The robot's radius, map units (`team.ugv.radius`, default 0): its plans and its track
    /// keep it from every obstacle. On a scene world it replaces the scene's `robot_radius`
    /// when positive; on a map world the missions plan in the robot's exact free space
    /// (`OccupancyMap::robot_space`: the half-cell lattice of points that keep the radius,
    /// and the maps' exact clearance less it), as `plan --robot-radius` does.
    pub radius: Real,
}

/// One aerial scout. It flies over obstacles; it sees what is within its sensor range.
#[derive(Clone, Debug, PartialEq)]
pub struct Uav {
    /// Where it takes off.
    pub start: Point,
    /// Map units per second.
    pub speed: Real,
    /// Sensor range, map units.
    pub sensor_range: Real,
}

/// The team.
#[derive(Clone, Debug, PartialEq)]
pub struct Team {
    /// The ground robot that must reach the goal.
    pub ugv: Ugv,
    /// The scouts.
    pub uavs: Vec<Uav>,
}

impl Default for Team {
    fn default() -> Self {
        Self {
            ugv: Ugv {
                speed: 1.0,
                sensor_range: 6.0,
                radius: 0.0,
            },
            uavs: Vec::new(),
        }
    }
}

/// A world file as read: the scene it names is loaded by the caller (only front ends read
/// files) and joined with [`MissionWorld::from_file`] or [`MapWorld::from_file`].
#[derive(Clone, Debug, PartialEq)]
pub struct WorldFile {
    /// Name (the file stem when the file gives none).
    pub name: String,
    /// The prior scene's path as written (relative to the world file); empty for a map world.
    pub scene: String,
    /// For a map world: the prior and truth maps and the UGV's start and goal.
    pub map: Option<MapSpec>,
    /// Obstacles in the world but not on the map.
    pub hidden_obstacles: Vec<Obstacle>,
    /// Names of obstacles on the map that are gone from the world.
    pub cleared_obstacles: Vec<String>,
    /// The robots.
    pub team: Team,
    pub(crate) source: String,
    pub(crate) lines: Vec<(String, u64)>,
}

/// The map form of a world file: an occupancy map as the prior, the truth map beside it, and
/// the UGV's start and goal in map coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct MapSpec {
    /// The prior map's path as written (relative to the world file).
    pub map: String,
    /// The truth map's path as written.
    pub truth_map: String,
    /// The UGV's start.
    pub start: Point,
    /// The goal.
    pub goal: Point,
}

/// A world of either form, as a front end loads it.
#[derive(Clone, Debug)]
pub enum AnyWorld {
    /// A prior scene of circles.
    Scene(MissionWorld),
    /// A prior occupancy map and its truth map.
    Map(MapWorld),
}

/// A world ready to simulate: the prior map, the truth, the team.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionWorld {
    /// Name.
    pub name: String,
    /// What the robots know at the start.
    pub prior: Scene,
    /// What is there: the prior without the cleared obstacles, with the hidden ones.
    pub truth: Scene,
    /// Names of the obstacles of `truth` that the prior does not have.
    pub hidden: Vec<String>,
    /// Names of the prior's obstacles that `truth` does not have.
    pub cleared: Vec<String>,
    /// The robots.
    pub team: Team,
}

/// Cells that differ between the prior map and the truth, discovered together.
#[derive(Clone, Debug, PartialEq)]
pub struct Change {
    /// `blocked-N` (cells occupied in the truth, free on the map) or `freed-N`.
    pub name: String,
    /// Whether the cells are occupied in the truth (a blockage) rather than free.
    pub blocked: bool,
    /// The cells `(i, j)` of the map (column, row), in raster order.
    pub cells: Vec<(usize, usize)>,
}

/// A map world ready to simulate.
#[derive(Clone, Debug, PartialEq)]
pub struct MapWorld {
    /// Name.
    pub name: String,
    /// What the robots know at the start.
    pub prior: OccupancyMap,
    /// What is there (same size, cell and origin).
    pub truth: OccupancyMap,
    /// The UGV's start, map coordinates.
    pub start: Point,
    /// The goal.
    pub goal: Point,
    /// The robots.
    pub team: Team,
    /// Where the maps differ, in raster order of their first cells.
    pub changes: Vec<Change>,
}
