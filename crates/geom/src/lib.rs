//! Planar geometry for homospline: circles, compound obstacles, clearance queries and scenes.
//!
//! Everything here works in map units with one scalar, [`math::Real`] (`f64`). The crate
//! knows nothing about grids, graphs or splines; it does no file IO (callers hand it text).
//!
//! - [`math`]: `Real`, `Point`, `Vector`.
//! - [`shape`]: [`Circle`], [`Obstacle`], and the [`TopoObstacle`]s of a circle set
//!   (connected groups of touching circles).
//! - [`query`]: clearance, segment distance, intersection, line of sight and ray casts,
//!   with the [`CircleSet`] entry point that picks a plain loop or parry's BVH by size.
//! - [`polygon`]: a provable circle cover of simple polygons.
//! - [`scene`]: the scene file of `docs/formats.md`, validated.
//! - [`shortest`]: the exact shortest path that keeps a clearance from circles (the tangent
//!   graph), the optimum that checks a plan's length.
//! - [`yaml`]: YAML and JSON read with the project's limits, and the parser's errors in
//!   words, under the key at fault.
//!
//! ```
//! use homospline_geom::{Point, Scene};
//!
//! let text = std::fs::read_to_string("../../fixtures/scenes/convex.yaml").unwrap();
//! let scene = Scene::from_str(&text, "convex.yaml").unwrap();
//! let set = scene.circle_set(); // inflated by the robot radius
//! let c = set.clearance(&Point::new(30.0, 30.0)).unwrap();
//! assert!(c.distance > 0.0);
//! assert!(set.line_of_sight(&scene.start, &Point::new(5.0, 50.0)));
//! assert_eq!(scene.topological_obstacles().len(), 3);
//! ```

pub mod math;
pub mod polygon;
pub mod query;
pub mod scene;
pub mod shape;
pub mod shortest;
pub mod yaml;

pub use math::{Point, Real, Vector};
pub use polygon::{CoverError, Polygon, cover_polygon};
pub use query::{CircleSet, Clearance, QueryBackend, RayHit};
pub use scene::{CriticalPoint, DangerPoint, Scene, SceneError};
pub use shape::{
    Bounds, Circle, Obstacle, Placement, ROBOT_RADIUS_RULE, TopoObstacle, for_each_near_pair,
    is_robot_radius, topological_obstacles,
};
