//! Scenes: the scene file of `docs/formats.md` (version 1), read from YAML or JSON,
//! validated with errors that name the file, the line and the field, and written back.
//!
//! JSON is read with the YAML parser too (JSON is YAML 1.2's flow style), so both formats
//! report lines. Unknown fields are errors: a typo must not pass silently.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};
use serde_saphyr::Spanned;
use thiserror::Error;

use crate::math::{Num, Point, Real, Short, Vector};
use crate::query::CircleSet;
use crate::shape::{Bounds, Circle, Obstacle, TopoObstacle, topological_obstacles};
pub use crate::yaml::{MAX_YAML_NODES, from_yaml, from_yaml_within, yaml_problem};
use crate::yaml::{Number, Whole};

/// Largest coordinate or length magnitude a scene may hold. Far beyond any map, and small
/// enough that squared distances stay finite.
pub const MAX_MAGNITUDE: Real = 1e9;

/// Smallest side the bounds may have: the scale's other end. The planner's geometric
/// tolerances are absolute near `1e-12`, and squared distances underflow on scenes scaled
/// to `1e-160`: a scene scaled by `1e-170` had its start "inside" an obstacle it was 35
/// units clear of.
pub const MIN_EXTENT: Real = 1e-9;

/// The scene file version this crate reads and writes.
pub const SCENE_VERSION: u32 = 1;

/// A point the path must keep at least `min_distance` away from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DangerPoint {
    /// Where it is.
    pub at: Point,
    /// Minimal permitted distance.
    pub min_distance: Real,
}

/// A point the path must stay within `max_distance` of (a radio router, say).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CriticalPoint {
    /// Where it is.
    pub at: Point,
    /// Maximal permitted distance.
    pub max_distance: Real,
}

/// A validated planning problem: bounds, start, goal, obstacles as unions of circles, and
/// optionally danger points, critical points and a robot radius (`docs/formats.md`,
/// section 1). [`Scene::from_str`] reads YAML or JSON and names the file, line and field of
/// any problem.
///
/// # Examples
///
/// ```
/// use homospline_geom::Scene;
///
/// let scene = Scene::from_str(
///     r#"
/// name: two-discs
/// bounds: {min: [0, 0], max: [40, 20]}
/// start: [2, 10]
/// goal: [38, 10]
/// obstacles:
///   - name: a
///     circles: [[14, 10, 3]]
///   - name: b
///     circles: [[26, 10, 3]]
/// "#,
///     "two-discs.yaml",
/// )?;
/// assert_eq!(scene.circles().len(), 2);
/// // A start inside an obstacle is refused with the field that is wrong.
/// let bad = Scene::from_str(
///     "name: x\nbounds: {min: [0, 0], max: [10, 10]}\nstart: [5, 5]\ngoal: [9, 9]\n\
///      obstacles:\n  - name: a\n    circles: [[5, 5, 1]]\n",
///     "x.yaml",
/// );
/// assert!(bad.unwrap_err().to_string().contains("start"));
/// # Ok::<(), homospline_geom::SceneError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Name (the file stem when the file gives none).
    pub name: String,
    /// The robot stays inside; the bounds are walls for the Voronoi graph.
    pub bounds: Bounds,
    /// Start `S`.
    pub start: Point,
    /// Target `T`.
    pub goal: Point,
    /// Robot radius: every circle is inflated by it for planning.
    pub robot_radius: Real,
    /// The obstacles as listed (not inflated).
    pub obstacles: Vec<Obstacle>,
    /// Points to keep away from.
    pub danger_points: Vec<DangerPoint>,
    /// Points to stay near.
    pub critical_points: Vec<CriticalPoint>,
    /// Hazard sources the path should hide from.
    pub hazards: Vec<Point>,
}

/// A scene that cannot be used, with where and why.
#[derive(Clone, Debug, PartialEq, Error)]
#[error("{}", self.render())]
pub struct SceneError {
    /// The file (or other source) the scene came from.
    pub source_name: String,
    /// 1-based line, when known.
    pub line: Option<u64>,
    /// 1-based column, when known (syntax and type errors).
    pub column: Option<u64>,
    /// The field, as a path such as `obstacles[1].circles[3]`, when one is to blame.
    pub field: Option<String>,
    /// What is wrong.
    pub problem: String,
}

impl SceneError {
    fn render(&self) -> String {
        let mut s = self.source_name.clone();
        if let Some(l) = self.line {
            s.push_str(&format!(":{l}"));
            if let Some(c) = self.column {
                s.push_str(&format!(":{c}"));
            }
        }
        s.push_str(": ");
        if let Some(f) = &self.field {
            s.push_str(f);
            s.push_str(": ");
        }
        s.push_str(&self.problem);
        s
    }
}

// ---------------------------------------------------------------------------------------
// The file as written: spans on every value a check may blame.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    #[serde(default)]
    version: Option<Spanned<Whole>>,
    #[serde(default)]
    name: Option<String>,
    bounds: Spanned<RawBounds>,
    start: Spanned<[Number; 2]>,
    goal: Spanned<[Number; 2]>,
    #[serde(default)]
    robot_radius: Option<Spanned<Number>>,
    #[serde(default)]
    obstacles: Vec<Spanned<ObstacleEntry>>,
    #[serde(default)]
    danger_points: Vec<Spanned<RawDanger>>,
    #[serde(default)]
    critical_points: Vec<Spanned<RawCritical>>,
    #[serde(default)]
    hazards: Vec<Spanned<[Number; 2]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBounds {
    min: Spanned<[Number; 2]>,
    max: Spanned<[Number; 2]>,
}

/// An obstacle as a scene file or a world file writes it (`name:` and `circles:`), each
/// circle with its place in the file: the one reader of obstacles ([`ObstacleEntry::obstacle`],
/// then [`check_obstacle`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleEntry {
    /// Its name, when the file gives one.
    #[serde(default)]
    pub name: Option<String>,
    /// Its circles `[x, y, r]`.
    pub circles: Vec<Spanned<[Number; 3]>>,
}

impl ObstacleEntry {
    /// The obstacle, called `unnamed()` when the file gives no name; not checked yet
    /// ([`check_obstacle`]).
    pub fn obstacle(&self, unnamed: impl FnOnce() -> String) -> Obstacle {
        Obstacle {
            name: self.name.clone().unwrap_or_else(unnamed),
            circles: self
                .circles
                .iter()
                .map(|c| Circle::new(c.value[0].0, c.value[1].0, c.value[2].0))
                .collect(),
        }
    }
}

/// An obstacle as scene and world files write it: the one writer of obstacles.
#[derive(Debug, Serialize)]
pub struct WrittenObstacle<'a> {
    name: &'a str,
    circles: Vec<[Real; 3]>,
}

impl<'a> From<&'a Obstacle> for WrittenObstacle<'a> {
    fn from(o: &'a Obstacle) -> Self {
        Self {
            name: &o.name,
            circles: o
                .circles
                .iter()
                .map(|c| [c.center.x, c.center.y, c.radius])
                .collect(),
        }
    }
}

/// The checks of one obstacle, `field` its place (`obstacles[3]`): a name without control
/// characters, at least one circle, each circle's centre and radius finite and at most
/// [`MAX_MAGNITUDE`] in magnitude, its radius `> 0`. The error is the field to blame
/// (`obstacles[3].circles[1]`) and the problem. Scenes and world files' hidden obstacles
/// both use it.
///
/// # Examples
///
/// ```
/// use homospline_geom::{Circle, Obstacle, scene::check_obstacle};
///
/// let rock = Obstacle { name: "rock".into(), circles: vec![Circle::new(1.0, 2.0, 0.5)] };
/// assert!(check_obstacle("obstacles[0]", &rock).is_ok());
/// let flat = Obstacle { name: "flat".into(), circles: vec![Circle::new(1.0, 2.0, 0.0)] };
/// let (field, problem) = check_obstacle("obstacles[1]", &flat).unwrap_err();
/// assert_eq!(field, "obstacles[1].circles[0]");
/// assert_eq!(problem, "radius must be > 0, got 0 (obstacle 'flat')");
/// ```
pub fn check_obstacle(field: &str, o: &Obstacle) -> Result<(), (String, String)> {
    check_name(&format!("{field}.name"), &o.name)?;
    if o.circles.is_empty() {
        return Err((
            format!("{field}.circles"),
            format!("obstacle '{}' has no circles", o.name),
        ));
    }
    for (j, c) in o.circles.iter().enumerate() {
        let f = format!("{field}.circles[{j}]");
        check_point(&f, &c.center)?;
        check_number(&f, "radius", c.radius)?;
        if c.radius <= 0.0 {
            return Err((
                f,
                format!(
                    "radius must be > 0, got {} (obstacle '{}')",
                    c.radius, o.name
                ),
            ));
        }
    }
    Ok(())
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDanger {
    at: [Number; 2],
    min_distance: Number,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCritical {
    at: [Number; 2],
    max_distance: Number,
}

/// Where each checked field sits in the file.
#[derive(Default)]
struct Lines(HashMap<String, u64>);

impl Lines {
    /// The line of `field`, or of its nearest enclosing field that has one
    /// (`obstacles[1].name` falls back to `obstacles[1]`).
    fn get(&self, field: &str) -> Option<u64> {
        let mut f = field;
        loop {
            if let Some(&l) = self.0.get(f) {
                return Some(l);
            }
            f = &f[..f.rfind(['.', '['])?];
        }
    }
    fn put<T>(&mut self, field: String, s: &Spanned<T>) {
        let line = s.referenced.line();
        if line > 0 {
            self.0.insert(field, line);
        }
    }
}

// ---------------------------------------------------------------------------------------
// The file as written back.

#[derive(Serialize)]
struct OutScene<'a> {
    version: u32,
    name: &'a str,
    bounds: OutBounds,
    start: [Real; 2],
    goal: [Real; 2],
    robot_radius: Real,
    obstacles: Vec<WrittenObstacle<'a>>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    danger_points: Vec<OutDanger>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    critical_points: Vec<OutCritical>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    hazards: Vec<[Real; 2]>,
}

#[derive(Serialize)]
struct OutBounds {
    min: [Real; 2],
    max: [Real; 2],
}

#[derive(Serialize)]
struct OutDanger {
    at: [Real; 2],
    min_distance: Real,
}

#[derive(Serialize)]
struct OutCritical {
    at: [Real; 2],
    max_distance: Real,
}

fn xy(p: &Point) -> [Real; 2] {
    [p.x, p.y]
}

fn pt(a: [Number; 2]) -> Point {
    Point::new(a[0].0, a[1].0)
}

fn stem(source: &str) -> String {
    std::path::Path::new(source)
        .file_stem()
        .and_then(|s| s.to_str())
        .map(|s| s.strip_suffix(".scene").unwrap_or(s).to_owned())
        .unwrap_or_else(|| "scene".to_owned())
}

impl Scene {
    /// Reads a scene from the bytes of a YAML or JSON file; `source` names the file in errors
    /// and gives the default name. Rejects empty, binary and non-UTF-8 input clearly.
    pub fn from_bytes(bytes: &[u8], source: &str) -> Result<Self, SceneError> {
        let err = |problem: String| SceneError {
            source_name: source.to_owned(),
            line: None,
            column: None,
            field: None,
            problem,
        };
        let text = std::str::from_utf8(bytes).map_err(|e| {
            err(format!(
                "not a text file: invalid UTF-8 at byte {} (a scene is YAML or JSON text)",
                e.valid_up_to()
            ))
        })?;
        if let Some(pos) = text.find('\0') {
            return Err(err(format!(
                "not a text file: NUL byte at byte {pos} (a scene is YAML or JSON text)"
            )));
        }
        Self::from_str(text, source)
    }

    /// Reads a scene from YAML or JSON text; `source` names the file in errors.
    pub fn from_str(text: &str, source: &str) -> Result<Self, SceneError> {
        let err = |line: Option<u64>, field: Option<String>, problem: String| SceneError {
            source_name: source.to_owned(),
            line,
            column: None,
            field,
            problem,
        };
        if text.trim().is_empty() {
            return Err(err(
                None,
                None,
                "the file is empty (expected a scene)".to_owned(),
            ));
        }
        let raw: RawScene =
            from_yaml(text).map_err(|e| yaml_error(text, &e, source, "malformed scene"))?;
        let (scene, lines) = Self::from_raw(raw, source);
        if let Some(v) = lines.version
            && v.0 != SCENE_VERSION
        {
            return Err(err(
                Some(v.1),
                Some("version".to_owned()),
                format!(
                    "version {} is not supported (this build reads version {SCENE_VERSION})",
                    v.0
                ),
            ));
        }
        scene.check().map_err(|(field, problem)| {
            let line = lines.lines.get(&field);
            err(line, Some(field), problem)
        })?;
        Ok(scene)
    }

    fn from_raw(raw: RawScene, source: &str) -> (Self, RawLines) {
        let mut lines = Lines::default();
        let version = raw
            .version
            .as_ref()
            .map(|v| (v.value.0, v.referenced.line()));
        lines.put("bounds".into(), &raw.bounds);
        lines.put("bounds.min".into(), &raw.bounds.value.min);
        lines.put("bounds.max".into(), &raw.bounds.value.max);
        lines.put("start".into(), &raw.start);
        lines.put("goal".into(), &raw.goal);
        if let Some(r) = &raw.robot_radius {
            lines.put("robot_radius".into(), r);
        }
        let obstacles = raw
            .obstacles
            .iter()
            .enumerate()
            .map(|(i, o)| {
                lines.put(format!("obstacles[{i}]"), o);
                for (j, c) in o.value.circles.iter().enumerate() {
                    lines.put(format!("obstacles[{i}].circles[{j}]"), c);
                }
                o.value.obstacle(|| format!("obstacle-{i}"))
            })
            .collect();
        let danger_points = raw
            .danger_points
            .iter()
            .enumerate()
            .map(|(i, d)| {
                lines.put(format!("danger_points[{i}]"), d);
                DangerPoint {
                    at: pt(d.value.at),
                    min_distance: d.value.min_distance.0,
                }
            })
            .collect();
        let critical_points = raw
            .critical_points
            .iter()
            .enumerate()
            .map(|(i, d)| {
                lines.put(format!("critical_points[{i}]"), d);
                CriticalPoint {
                    at: pt(d.value.at),
                    max_distance: d.value.max_distance.0,
                }
            })
            .collect();
        let hazards = raw
            .hazards
            .iter()
            .enumerate()
            .map(|(i, h)| {
                lines.put(format!("hazards[{i}]"), h);
                pt(h.value)
            })
            .collect();
        let scene = Scene {
            name: raw.name.unwrap_or_else(|| stem(source)),
            bounds: Bounds {
                min: pt(raw.bounds.value.min.value),
                max: pt(raw.bounds.value.max.value),
            },
            start: pt(raw.start.value),
            goal: pt(raw.goal.value),
            robot_radius: raw.robot_radius.map_or(0.0, |r| r.value.0),
            obstacles,
            danger_points,
            critical_points,
            hazards,
        };
        (scene, RawLines { version, lines })
    }

    /// Checks a scene built in code; the error names the field but no line.
    pub fn validate(&self, source: &str) -> Result<(), SceneError> {
        self.check().map_err(|(field, problem)| SceneError {
            source_name: source.to_owned(),
            line: None,
            column: None,
            field: Some(field),
            problem,
        })
    }

    /// Every rule of formats.md; returns the blamed field and the problem.
    fn check(&self) -> Result<(), (String, String)> {
        check_name("name", &self.name)?;
        self.check_frame()?;
        self.check_obstacles()?;
        self.check_points()?;
        self.check_ends()
    }

    /// The bounds (finite, not empty), start and goal (finite) and the robot radius
    /// (finite, `>= 0`).
    fn check_frame(&self) -> Result<(), (String, String)> {
        let b = &self.bounds;
        check_point("bounds.min", &b.min)?;
        check_point("bounds.max", &b.max)?;
        if !(b.min.x < b.max.x && b.min.y < b.max.y) {
            return Err((
                "bounds".to_owned(),
                format!(
                    "bounds are empty: min [{}, {}] must be below max [{}, {}] in both x and y",
                    b.min.x, b.min.y, b.max.x, b.max.y
                ),
            ));
        }
        let ext = b.extent();
        if ext.x.min(ext.y) < MIN_EXTENT {
            return Err((
                "bounds".to_owned(),
                format!(
                    "{} x {} across: each side must be at least {MIN_EXTENT:e}; scale the scene's units up",
                    Num(ext.x),
                    Num(ext.y)
                ),
            ));
        }
        check_point("start", &self.start)?;
        check_point("goal", &self.goal)?;
        check_number("robot_radius", "robot_radius", self.robot_radius)?;
        if !crate::shape::is_robot_radius(self.robot_radius) {
            return Err((
                "robot_radius".to_owned(),
                format!(
                    "robot_radius {}: {}",
                    Num(self.robot_radius),
                    crate::shape::ROBOT_RADIUS_RULE
                ),
            ));
        }
        Ok(())
    }

    /// The obstacles: unique names, at least one circle each, finite centres and positive
    /// radii.
    fn check_obstacles(&self) -> Result<(), (String, String)> {
        let mut names: HashMap<&str, usize> = HashMap::new();
        for (i, o) in self.obstacles.iter().enumerate() {
            check_obstacle(&format!("obstacles[{i}]"), o)?;
            if let Some(first) = names.insert(&o.name, i) {
                // An obstacle without a name is called after its index: say so, or the
                // message blames a name the file does not hold.
                let unnamed = if o.name == format!("obstacle-{i}") {
                    format!("; obstacles[{i}] has no name and is called after its index")
                } else {
                    String::new()
                };
                return Err((
                    format!("obstacles[{i}].name"),
                    format!(
                        "duplicate obstacle name '{}' (also obstacles[{first}]){unnamed}",
                        o.name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The danger and critical points (finite, positive distances) and the hazards
    /// (finite).
    fn check_points(&self) -> Result<(), (String, String)> {
        for (i, d) in self.danger_points.iter().enumerate() {
            let f = format!("danger_points[{i}]");
            check_point(&f, &d.at)?;
            check_positive(&f, "min_distance", d.min_distance)?;
        }
        for (i, d) in self.critical_points.iter().enumerate() {
            let f = format!("critical_points[{i}]");
            check_point(&f, &d.at)?;
            check_positive(&f, "max_distance", d.max_distance)?;
        }
        for (i, h) in self.hazards.iter().enumerate() {
            check_point(&format!("hazards[{i}]"), h)?;
        }
        Ok(())
    }

    /// Start and goal inside the bounds and outside every inflated circle.
    fn check_ends(&self) -> Result<(), (String, String)> {
        let b = &self.bounds;
        for (field, p) in [("start", &self.start), ("goal", &self.goal)] {
            if !b.contains(p) {
                return Err((
                    field.to_owned(),
                    format!(
                        "[{}, {}] is outside the bounds [{}, {}] .. [{}, {}]",
                        Num(p.x),
                        Num(p.y),
                        Num(b.min.x),
                        Num(b.min.y),
                        Num(b.max.x),
                        Num(b.max.y)
                    ),
                ));
            }
            if let Some((o, j, d)) = self.deepest_circle_at(p) {
                let inflated = if self.robot_radius > 0.0 {
                    format!(
                        " after inflating by robot_radius {}",
                        Num(self.robot_radius)
                    )
                } else {
                    String::new()
                };
                return Err((
                    field.to_owned(),
                    format!(
                        "[{}, {}] is inside obstacle '{}' (circle {j}, clearance {}{inflated})",
                        Num(p.x),
                        Num(p.y),
                        self.obstacles[o].name,
                        Short(d)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The (obstacle, circle, clearance) of the inflated circle that `p` is on or inside.
    fn deepest_circle_at(&self, p: &Point) -> Option<(usize, usize, Real)> {
        let mut hit = None;
        for (i, o) in self.obstacles.iter().enumerate() {
            for (j, c) in o.circles.iter().enumerate() {
                let d = c.inflated(self.robot_radius).signed_distance(p);
                if d <= 0.0 && hit.is_none_or(|(_, _, best)| d < best) {
                    hit = Some((i, j, d));
                }
            }
        }
        hit
    }

    /// All circles of all obstacles, in listed order, inflated by the robot radius.
    pub fn circles(&self) -> Vec<Circle> {
        self.obstacles
            .iter()
            .flat_map(|o| o.circles.iter().map(|c| c.inflated(self.robot_radius)))
            .collect()
    }

    /// The part of the bounds where a route has anything to go round: the box of the
    /// (inflated) circles, the start and the goal, grown on every side by its longer side,
    /// within the bounds. Outside it there is no obstacle, so every homotopy class has a path
    /// inside it (push a path's points that leave it back onto its sides: the straight
    /// homotopy between the two meets no obstacle). A scene's Voronoi grid covers this area:
    /// bounds of a billion units round a rock of radius 1 put the rock inside one cell of a
    /// grid over the bounds, and its two classes became one. For scenes whose bounds are
    /// within three times their contents, it is the bounds.
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_geom::Scene;
    ///
    /// let huge = Scene::from_str(
    ///     "bounds: {min: [-1e9, -1e9], max: [1e9, 1e9]}\nstart: [-10, 0]\ngoal: [10, 0]\n\
    ///      obstacles:\n  - name: rock\n    circles: [[0, 0, 1]]\n",
    ///     "huge.yaml",
    /// )?;
    /// let a = huge.working_area();
    /// assert_eq!((a.min.x, a.min.y, a.max.x, a.max.y), (-30.0, -21.0, 30.0, 21.0));
    /// # Ok::<(), homospline_geom::SceneError>(())
    /// ```
    pub fn working_area(&self) -> Bounds {
        let (mut lo, mut hi) = (self.start.inf(&self.goal), self.start.sup(&self.goal));
        for c in self.circles() {
            let r = Vector::new(c.radius, c.radius);
            lo = lo.inf(&(c.center - r));
            hi = hi.sup(&(c.center + r));
        }
        let grow = (hi - lo).max();
        if !(grow.is_finite() && grow > 0.0) {
            return self.bounds;
        }
        let g = Vector::new(grow, grow);
        Bounds {
            min: (lo - g).sup(&self.bounds.min),
            max: (hi + g).inf(&self.bounds.max),
        }
    }

    /// The inflated circles ready for queries.
    pub fn circle_set(&self) -> CircleSet {
        CircleSet::new(self.circles())
    }

    /// For each index of [`Scene::circles`], the obstacle it comes from.
    pub fn circle_owners(&self) -> Vec<usize> {
        self.obstacles
            .iter()
            .enumerate()
            .flat_map(|(i, o)| std::iter::repeat_n(i, o.circles.len()))
            .collect()
    }

    /// The topological obstacles: connected groups of touching (inflated) circles, across
    /// listed obstacles (holes in free space where they lie strictly within the bounds:
    /// [`Bounds::place_discs`]). Circle indices refer to [`Scene::circles`].
    pub fn topological_obstacles(&self) -> Vec<TopoObstacle> {
        topological_obstacles(&self.circles())
    }

    fn out(&self) -> OutScene<'_> {
        OutScene {
            version: SCENE_VERSION,
            name: &self.name,
            bounds: OutBounds {
                min: xy(&self.bounds.min),
                max: xy(&self.bounds.max),
            },
            start: xy(&self.start),
            goal: xy(&self.goal),
            robot_radius: self.robot_radius,
            obstacles: self.obstacles.iter().map(WrittenObstacle::from).collect(),
            danger_points: self
                .danger_points
                .iter()
                .map(|d| OutDanger {
                    at: xy(&d.at),
                    min_distance: d.min_distance,
                })
                .collect(),
            critical_points: self
                .critical_points
                .iter()
                .map(|d| OutCritical {
                    at: xy(&d.at),
                    max_distance: d.max_distance,
                })
                .collect(),
            hazards: self.hazards.iter().map(xy).collect(),
        }
    }

    /// The scene as YAML (version 1); reads back to an equal scene.
    pub fn to_yaml(&self) -> String {
        // Serialising plain structs of strings and numbers cannot fail.
        serde_saphyr::to_string(&self.out()).unwrap_or_default()
    }

    /// The scene as pretty JSON (version 1); reads back to an equal scene.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(&self.out()).unwrap_or_default()
    }
}

/// A YAML parser's error on `text` (the file `source`) as a [`SceneError`]: see
/// [`crate::yaml::locate`].
pub fn yaml_error(text: &str, e: &serde_saphyr::Error, source: &str, fallback: &str) -> SceneError {
    let f = crate::yaml::locate(text, e, fallback);
    SceneError {
        source_name: source.to_owned(),
        line: f.line,
        column: f.column,
        field: f.field,
        problem: f.problem,
    }
}

struct RawLines {
    version: Option<(u32, u64)>,
    lines: Lines,
}

/// A name holds no control character: names are printed in tables, messages and
/// pictures, where an escape sequence would reach the terminal.
fn check_name(field: &str, name: &str) -> Result<(), (String, String)> {
    match name.chars().find(|c| c.is_control()) {
        Some(c) => Err((
            field.to_owned(),
            format!(
                "'{}' holds the control character {:?}: names are printed",
                name.escape_debug(),
                c
            ),
        )),
        None => Ok(()),
    }
}

/// `v`, the `what` of `field`, is finite and at most [`MAX_MAGNITUDE`] in magnitude.
fn check_number(field: &str, what: &str, v: Real) -> Result<(), (String, String)> {
    if v.is_nan() {
        Err((field.to_owned(), format!("{what} is NaN")))
    } else if v.is_infinite() {
        Err((field.to_owned(), format!("{what} is infinite")))
    } else if v.abs() > MAX_MAGNITUDE {
        Err((
            field.to_owned(),
            format!("{what} = {v:e} is too large (|value| must be at most {MAX_MAGNITUDE:e})"),
        ))
    } else {
        Ok(())
    }
}

/// Both coordinates of `p`, the point of `field`, pass [`check_number`].
fn check_point(field: &str, p: &Point) -> Result<(), (String, String)> {
    check_number(field, "x", p.x)?;
    check_number(field, "y", p.y)
}

/// `v` passes [`check_number`] and is `> 0`.
fn check_positive(field: &str, what: &str, v: Real) -> Result<(), (String, String)> {
    check_number(field, what, v)?;
    if v > 0.0 {
        Ok(())
    } else {
        Err((field.to_owned(), format!("{what} must be > 0, got {v}")))
    }
}
