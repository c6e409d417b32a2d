//! The world file: a prior scene (the outdated map) and what it does not know (hidden and
//! cleared obstacles), with the team's robots.

use homospline_geom::{Circle, Obstacle, Point, Real, Scene, SceneError};
use serde::Deserialize;
use serde_saphyr::Spanned;

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
    /// when positive; on a map world both maps are inflated by it
    /// (`OccupancyMap::inflated`).
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
/// files) and joined with [`WorldFile::with_prior`].
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
    Map(crate::map::MapWorld),
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWorld {
    #[serde(default)]
    version: Option<Spanned<u32>>,
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    scene: Option<Spanned<String>>,
    #[serde(default)]
    map: Option<Spanned<String>>,
    #[serde(default)]
    truth_map: Option<Spanned<String>>,
    #[serde(default)]
    start: Option<Spanned<[Real; 2]>>,
    #[serde(default)]
    goal: Option<Spanned<[Real; 2]>>,
    #[serde(default)]
    hidden_obstacles: Vec<Spanned<RawObstacle>>,
    #[serde(default)]
    cleared_obstacles: Vec<Spanned<String>>,
    #[serde(default)]
    team: Option<Spanned<RawTeam>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObstacle {
    #[serde(default)]
    name: Option<String>,
    circles: Vec<Spanned<[Real; 3]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTeam {
    ugv: Spanned<RawUgv>,
    #[serde(default)]
    uavs: Vec<Spanned<RawUav>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawUgv {
    speed: Real,
    sensor_range: Real,
    #[serde(default)]
    radius: Real,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawUav {
    start: [Real; 2],
    speed: Real,
    sensor_range: Real,
}

fn error(source: &str, line: Option<u64>, field: Option<&str>, problem: String) -> SceneError {
    SceneError {
        source_name: source.to_owned(),
        line,
        column: None,
        field: field.map(str::to_owned),
        problem,
    }
}

fn line_of<T>(s: &Spanned<T>) -> u64 {
    s.referenced.line()
}

/// Largest coordinate or radius accepted, as for scenes.
const MAX_MAGNITUDE: Real = 1e9;

fn positive(v: Real) -> bool {
    v.is_finite() && v > 0.0 && v <= MAX_MAGNITUDE
}

impl WorldFile {
    /// Reads a world file (YAML or JSON); `source` names it in errors. Every error names the
    /// file, the line where it can and the field.
    pub fn from_str(text: &str, source: &str) -> Result<Self, SceneError> {
        if text.trim().is_empty() {
            return Err(error(
                source,
                None,
                None,
                "the file is empty (expected a world)".into(),
            ));
        }
        let raw: RawWorld = serde_saphyr::from_str(text).map_err(|e| {
            let loc = e.location().filter(|l| l.line() > 0);
            let msg = e.to_string();
            let first = msg.lines().next().unwrap_or("malformed world").trim();
            let first = first.strip_prefix("error:").unwrap_or(first).trim_start();
            let first = match first.strip_prefix("line ").and_then(|r| r.split_once(": ")) {
                Some((_, tail)) => tail,
                None => first,
            };
            SceneError {
                source_name: source.to_owned(),
                line: loc.map(|l| l.line()),
                column: loc.map(|l| l.column()).filter(|&c| c > 0),
                field: None,
                problem: first.to_owned(),
            }
        })?;
        if let Some(v) = &raw.version
            && v.value != WORLD_VERSION
        {
            return Err(error(
                source,
                Some(line_of(v)),
                Some("version"),
                format!(
                    "version {} is not supported (this build reads version {WORLD_VERSION})",
                    v.value
                ),
            ));
        }
        let mut lines = Vec::new();
        let map = match (&raw.scene, &raw.map) {
            (None, None) => {
                return Err(error(
                    source,
                    None,
                    Some("scene"),
                    "missing: a world needs `scene` (a scene file) or `map` (an occupancy map)"
                        .into(),
                ));
            }
            (Some(_), Some(m)) => {
                return Err(error(
                    source,
                    Some(line_of(m)),
                    Some("map"),
                    "a world has either `scene` or `map`, not both".into(),
                ));
            }
            (Some(sc), None) => {
                lines.push(("scene".to_owned(), line_of(sc)));
                if sc.value.trim().is_empty() {
                    return Err(error(
                        source,
                        Some(line_of(sc)),
                        Some("scene"),
                        "empty path (expected the prior scene's file)".into(),
                    ));
                }
                for (field, line) in [
                    ("truth_map", raw.truth_map.as_ref().map(line_of)),
                    ("start", raw.start.as_ref().map(line_of)),
                    ("goal", raw.goal.as_ref().map(line_of)),
                ] {
                    if let Some(l) = line {
                        return Err(error(
                            source,
                            Some(l),
                            Some(field),
                            "only for a map world (`map`); a scene has its own".into(),
                        ));
                    }
                }
                None
            }
            (None, Some(m)) => {
                lines.push(("map".to_owned(), line_of(m)));
                let map_line = line_of(m);
                let missing = |field: &str, what: &str| {
                    error(
                        source,
                        Some(map_line),
                        Some(field),
                        format!("missing: a map world needs {what}"),
                    )
                };
                if m.value.trim().is_empty() {
                    return Err(error(
                        source,
                        Some(map_line),
                        Some("map"),
                        "empty path (expected the prior map's file)".into(),
                    ));
                }
                let truth = raw
                    .truth_map
                    .as_ref()
                    .ok_or_else(|| missing("truth_map", "the truth map beside the prior"))?;
                lines.push(("truth_map".to_owned(), line_of(truth)));
                if truth.value.trim().is_empty() {
                    return Err(error(
                        source,
                        Some(line_of(truth)),
                        Some("truth_map"),
                        "empty path (expected the truth map's file)".into(),
                    ));
                }
                let mut ends = [Point::origin(); 2];
                for (k, (field, v)) in [("start", &raw.start), ("goal", &raw.goal)]
                    .into_iter()
                    .enumerate()
                {
                    let v = v
                        .as_ref()
                        .ok_or_else(|| missing(field, "the UGV's start and goal"))?;
                    lines.push((field.to_owned(), line_of(v)));
                    let [x, y] = v.value;
                    if !(x.is_finite() && y.is_finite()) {
                        return Err(error(
                            source,
                            Some(line_of(v)),
                            Some(field),
                            format!("({x}, {y}) must be finite"),
                        ));
                    }
                    ends[k] = Point::new(x, y);
                }
                for (field, v) in [
                    ("hidden_obstacles", raw.hidden_obstacles.first()),
                    ("cleared_obstacles", None),
                ] {
                    if let Some(v) = v {
                        return Err(error(
                            source,
                            Some(line_of(v)),
                            Some(field),
                            "not for a map world: the truth map holds what the map does not know"
                                .into(),
                        ));
                    }
                }
                if let Some(c) = raw.cleared_obstacles.first() {
                    return Err(error(
                        source,
                        Some(line_of(c)),
                        Some("cleared_obstacles"),
                        "not for a map world: the truth map holds what the map does not know"
                            .into(),
                    ));
                }
                Some(MapSpec {
                    map: m.value.clone(),
                    truth_map: truth.value.clone(),
                    start: ends[0],
                    goal: ends[1],
                })
            }
        };
        let mut hidden = Vec::with_capacity(raw.hidden_obstacles.len());
        for (i, o) in raw.hidden_obstacles.iter().enumerate() {
            let field = format!("hidden_obstacles[{i}]");
            lines.push((field.clone(), line_of(o)));
            if o.value.circles.is_empty() {
                return Err(error(
                    source,
                    Some(line_of(o)),
                    Some(&field),
                    "an obstacle needs at least one circle".into(),
                ));
            }
            let mut circles = Vec::new();
            for (j, c) in o.value.circles.iter().enumerate() {
                let f = format!("{field}.circles[{j}]");
                let [x, y, r] = c.value;
                if !(x.is_finite()
                    && y.is_finite()
                    && x.abs() <= MAX_MAGNITUDE
                    && y.abs() <= MAX_MAGNITUDE)
                {
                    return Err(error(
                        source,
                        Some(line_of(c)),
                        Some(&f),
                        format!("centre ({x}, {y}) must be finite numbers within 1e9"),
                    ));
                }
                if !positive(r) {
                    return Err(error(
                        source,
                        Some(line_of(c)),
                        Some(&f),
                        format!("radius {r} must be finite and > 0"),
                    ));
                }
                circles.push(Circle::new(x, y, r));
            }
            hidden.push(Obstacle {
                name: o
                    .value
                    .name
                    .clone()
                    .unwrap_or_else(|| format!("hidden-{i}")),
                circles,
            });
        }
        let cleared: Vec<String> = raw
            .cleared_obstacles
            .iter()
            .enumerate()
            .map(|(i, c)| {
                lines.push((format!("cleared_obstacles[{i}]"), line_of(c)));
                c.value.clone()
            })
            .collect();
        let team = match &raw.team {
            None => Team::default(),
            Some(t) => {
                lines.push(("team".into(), line_of(t)));
                let u = &t.value.ugv;
                for (what, v) in [
                    ("speed", u.value.speed),
                    ("sensor_range", u.value.sensor_range),
                ] {
                    if !positive(v) {
                        return Err(error(
                            source,
                            Some(line_of(u)),
                            Some(&format!("team.ugv.{what}")),
                            format!("{v} must be finite and > 0"),
                        ));
                    }
                }
                let r = u.value.radius;
                if !(r.is_finite() && (0.0..=MAX_MAGNITUDE).contains(&r)) {
                    return Err(error(
                        source,
                        Some(line_of(u)),
                        Some("team.ugv.radius"),
                        format!("{r} must be a finite number >= 0"),
                    ));
                }
                let mut uavs = Vec::new();
                for (i, a) in t.value.uavs.iter().enumerate() {
                    let field = format!("team.uavs[{i}]");
                    lines.push((field.clone(), line_of(a)));
                    for (what, v) in [
                        ("speed", a.value.speed),
                        ("sensor_range", a.value.sensor_range),
                    ] {
                        if !positive(v) {
                            return Err(error(
                                source,
                                Some(line_of(a)),
                                Some(&format!("{field}.{what}")),
                                format!("{v} must be finite and > 0"),
                            ));
                        }
                    }
                    let [x, y] = a.value.start;
                    if !(x.is_finite() && y.is_finite()) {
                        return Err(error(
                            source,
                            Some(line_of(a)),
                            Some(&format!("{field}.start")),
                            format!("({x}, {y}) must be finite"),
                        ));
                    }
                    uavs.push(Uav {
                        start: Point::new(x, y),
                        speed: a.value.speed,
                        sensor_range: a.value.sensor_range,
                    });
                }
                Team {
                    ugv: Ugv {
                        speed: u.value.speed,
                        sensor_range: u.value.sensor_range,
                        radius: u.value.radius,
                    },
                    uavs,
                }
            }
        };
        let name = raw.name.unwrap_or_else(|| {
            std::path::Path::new(source)
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("world")
                .to_owned()
        });
        Ok(Self {
            name,
            scene: raw.scene.map(|s| s.value).unwrap_or_default(),
            map,
            hidden_obstacles: hidden,
            cleared_obstacles: cleared,
            team,
            source: source.to_owned(),
            lines,
        })
    }

    /// Where a field is in the file.
    pub(crate) fn line(&self, field: &str) -> Option<u64> {
        self.lines.iter().find(|(f, _)| f == field).map(|(_, l)| *l)
    }

    /// Joins the file with its prior scene and checks them together: cleared obstacles exist
    /// on the map, hidden ones have names of their own, the start and the goal are free in
    /// the truth, the scouts start inside the bounds.
    pub fn with_prior(self, mut prior: Scene) -> Result<MissionWorld, SceneError> {
        let src = self.source.clone();
        let err =
            |field: &str, problem: String| error(&src, self.line(field), Some(field), problem);
        let r = self.team.ugv.radius;
        if r > 0.0 {
            prior.robot_radius = r;
            prior.validate(&src).map_err(|e| {
                err(
                    "team.ugv.radius",
                    format!("{r}: the scene at this robot radius: {}", e.problem),
                )
            })?;
        }
        for (i, name) in self.cleared_obstacles.iter().enumerate() {
            if self.cleared_obstacles[..i].contains(name) {
                return Err(err(
                    &format!("cleared_obstacles[{i}]"),
                    format!("'{name}' is listed twice"),
                ));
            }
            if !prior.obstacles.iter().any(|o| &o.name == name) {
                return Err(err(
                    &format!("cleared_obstacles[{i}]"),
                    format!("no obstacle named '{name}' in the scene"),
                ));
            }
        }
        for (i, h) in self.hidden_obstacles.iter().enumerate() {
            if prior.obstacles.iter().any(|o| o.name == h.name)
                || self.hidden_obstacles[..i].iter().any(|o| o.name == h.name)
            {
                return Err(err(
                    &format!("hidden_obstacles[{i}]"),
                    format!("the name '{}' is taken", h.name),
                ));
            }
            for (what, p) in [("start", prior.start), ("goal", prior.goal)] {
                if h.circles
                    .iter()
                    .any(|c| (p - c.center).norm() <= c.radius + prior.robot_radius)
                {
                    return Err(err(
                        &format!("hidden_obstacles[{i}]"),
                        format!(
                            "covers the {what} ({}, {}): the mission cannot be run",
                            p.x, p.y
                        ),
                    ));
                }
            }
        }
        for (i, u) in self.team.uavs.iter().enumerate() {
            if !prior.bounds.contains(&u.start) {
                return Err(err(
                    &format!("team.uavs[{i}]"),
                    format!("start ({}, {}) is outside the bounds", u.start.x, u.start.y),
                ));
            }
        }
        let mut truth = prior.clone();
        truth
            .obstacles
            .retain(|o| !self.cleared_obstacles.contains(&o.name));
        truth
            .obstacles
            .extend(self.hidden_obstacles.iter().cloned());
        truth.validate(&src)?;
        Ok(MissionWorld {
            name: self.name,
            hidden: self
                .hidden_obstacles
                .iter()
                .map(|o| o.name.clone())
                .collect(),
            cleared: self.cleared_obstacles,
            prior,
            truth,
            team: self.team,
        })
    }
}

impl MissionWorld {
    /// A world built in code (generators, tests): `hidden` added to and `cleared` removed
    /// from `prior`; checked like a file.
    pub fn new(
        name: &str,
        prior: Scene,
        hidden: Vec<Obstacle>,
        cleared: Vec<String>,
        team: Team,
    ) -> Result<Self, SceneError> {
        WorldFile {
            name: name.to_owned(),
            scene: prior.name.clone(),
            map: None,
            hidden_obstacles: hidden,
            cleared_obstacles: cleared,
            team,
            source: name.to_owned(),
            lines: Vec::new(),
        }
        .with_prior(prior)
    }
}

#[derive(serde::Serialize)]
struct OutWorld<'a> {
    version: u32,
    name: &'a str,
    scene: &'a str,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    hidden_obstacles: Vec<OutObstacle<'a>>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    cleared_obstacles: Vec<&'a str>,
    team: OutTeam,
}

#[derive(serde::Serialize)]
struct OutObstacle<'a> {
    name: &'a str,
    circles: Vec<[Real; 3]>,
}

#[derive(serde::Serialize)]
struct OutTeam {
    ugv: OutUgv,
    uavs: Vec<OutUav>,
}

#[derive(serde::Serialize)]
struct OutUgv {
    speed: Real,
    sensor_range: Real,
    #[serde(skip_serializing_if = "is_zero")]
    radius: Real,
}

fn is_zero(v: &Real) -> bool {
    *v == 0.0
}

#[derive(serde::Serialize)]
struct OutUav {
    start: [Real; 2],
    speed: Real,
    sensor_range: Real,
}

impl MissionWorld {
    /// The world as a world file (YAML) naming its prior scene by `scene_path`.
    pub fn to_yaml(&self, scene_path: &str) -> String {
        let out = OutWorld {
            version: WORLD_VERSION,
            name: &self.name,
            scene: scene_path,
            hidden_obstacles: self
                .truth
                .obstacles
                .iter()
                .filter(|o| self.hidden.contains(&o.name))
                .map(|o| OutObstacle {
                    name: &o.name,
                    circles: o
                        .circles
                        .iter()
                        .map(|c| [c.center.x, c.center.y, c.radius])
                        .collect(),
                })
                .collect(),
            cleared_obstacles: self.cleared.iter().map(String::as_str).collect(),
            team: OutTeam {
                ugv: OutUgv {
                    speed: self.team.ugv.speed,
                    sensor_range: self.team.ugv.sensor_range,
                    radius: self.team.ugv.radius,
                },
                uavs: self
                    .team
                    .uavs
                    .iter()
                    .map(|u| OutUav {
                        start: [u.start.x, u.start.y],
                        speed: u.speed,
                        sensor_range: u.sensor_range,
                    })
                    .collect(),
            },
        };
        serde_saphyr::to_string(&out).unwrap_or_default()
    }
}

/// Reads a world file and the scene it names (relative to the world file); the caller reads
/// the files (`read`). The error is the message a front end shows.
pub fn load(
    path: &std::path::Path,
    read: impl Fn(&std::path::Path) -> std::io::Result<Vec<u8>>,
) -> Result<MissionWorld, String> {
    let file = read_world_file(path, &read)?;
    if file.map.is_some() {
        return Err(format!(
            "{}: a map world (`map`): load it with `load_any`",
            path.display()
        ));
    }
    scene_world(path, file, &read)
}

/// The world file at `path`, read and checked.
fn read_world_file(
    path: &std::path::Path,
    read: &impl Fn(&std::path::Path) -> std::io::Result<Vec<u8>>,
) -> Result<WorldFile, String> {
    let name = path.display().to_string();
    let bytes = read(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        format!(
            "{name}: not a text file: invalid UTF-8 at byte {}",
            e.valid_up_to()
        )
    })?;
    WorldFile::from_str(text, &name).map_err(|e| e.to_string())
}

/// A scene world: `file` (read from `path`) joined with the scene it names.
fn scene_world(
    path: &std::path::Path,
    file: WorldFile,
    read: &impl Fn(&std::path::Path) -> std::io::Result<Vec<u8>>,
) -> Result<MissionWorld, String> {
    let name = path.display().to_string();
    let scene_path = path
        .parent()
        .unwrap_or(std::path::Path::new("."))
        .join(&file.scene);
    let scene_bytes = read(&scene_path)
        .map_err(|e| format!("{name}: scene: cannot read {}: {e}", scene_path.display()))?;
    let prior = Scene::from_bytes(&scene_bytes, &scene_path.display().to_string())
        .map_err(|e| e.to_string())?;
    file.with_prior(prior).map_err(|e| e.to_string())
}

/// Reads a world file of either form and the files it names (relative to the world file): a
/// scene, or a prior map and its truth map (MovingAI `.map` or ROS map YAML, as
/// `homospline plan MAP` reads them). The caller reads the files (`read`). The error is the
/// message a front end shows.
pub fn load_any(
    path: &std::path::Path,
    read: impl Fn(&std::path::Path) -> std::io::Result<Vec<u8>>,
) -> Result<AnyWorld, String> {
    let name = path.display().to_string();
    let file = read_world_file(path, &read)?;
    let Some(spec) = file.map.clone() else {
        return scene_world(path, file, &read).map(AnyWorld::Scene);
    };
    let dir = path.parent().unwrap_or(std::path::Path::new("."));
    let load_map = |field: &str, file_name: &str| {
        let p = dir.join(file_name);
        let at = file.line(field).map_or(String::new(), |l| format!(":{l}"));
        match homospline_maps::input::load(&p, &read)
            .map_err(|e| format!("{name}{at}: {field}: {e}"))?
        {
            homospline_maps::input::Input::Map(m) => Ok(m),
            homospline_maps::input::Input::Scene(_) => Err(format!(
                "{name}{at}: {field}: {} is a scene, not an occupancy map (.map or ROS map YAML)",
                p.display()
            )),
        }
    };
    let prior = load_map("map", &spec.map)?;
    let truth = load_map("truth_map", &spec.truth_map)?;
    file.with_maps(prior, truth, &spec)
        .map(AnyWorld::Map)
        .map_err(|e| e.to_string())
}
