//! Reading a world file (YAML or JSON), section by section: the version, the prior (a scene,
//! or a prior map with its truth map and the UGV's ends), the hidden and cleared obstacles,
//! and the team. Every error names the file, the line where it can and the field.

use homospline_geom::math::Num;
use homospline_geom::scene::{MAX_MAGNITUDE, ObstacleEntry, check_obstacle};
use homospline_geom::yaml::{Number, Whole};
use homospline_geom::{Obstacle, Point, ROBOT_RADIUS_RULE, Real, SceneError, is_robot_radius};
use serde::Deserialize;
use serde_saphyr::Spanned;

use super::types::{MapSpec, Team, Uav, Ugv, WORLD_VERSION, WorldFile};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWorld {
    #[serde(default)]
    version: Option<Spanned<Whole>>,
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    scene: Option<Spanned<String>>,
    #[serde(default)]
    map: Option<Spanned<String>>,
    #[serde(default)]
    truth_map: Option<Spanned<String>>,
    #[serde(default)]
    start: Option<Spanned<[Number; 2]>>,
    #[serde(default)]
    goal: Option<Spanned<[Number; 2]>>,
    #[serde(default)]
    hidden_obstacles: Vec<Spanned<ObstacleEntry>>,
    #[serde(default)]
    cleared_obstacles: Vec<Spanned<String>>,
    #[serde(default)]
    team: Option<Spanned<RawTeam>>,
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
    speed: Number,
    sensor_range: Number,
    #[serde(default)]
    radius: Number,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawUav {
    start: [Number; 2],
    speed: Number,
    sensor_range: Number,
}

fn line_of<T>(s: &Spanned<T>) -> u64 {
    s.referenced.line()
}

fn positive(v: Real) -> bool {
    v.is_finite() && v > 0.0 && v <= MAX_MAGNITUDE
}

/// A file being read: its name for errors, and the line of each field read so far.
struct Reader<'a> {
    source: &'a str,
    lines: Vec<(String, u64)>,
}

impl Reader<'_> {
    /// The error `problem` at `line` with `field`.
    fn error(&self, line: Option<u64>, field: Option<&str>, problem: String) -> SceneError {
        SceneError {
            source_name: self.source.to_owned(),
            line,
            column: None,
            field: field.map(str::to_owned),
            problem,
        }
    }

    /// The error `problem` with `field` at the line of `at`.
    fn at<T>(&self, at: &Spanned<T>, field: &str, problem: String) -> SceneError {
        self.error(Some(line_of(at)), Some(field), problem)
    }

    /// Notes where `field` is in the file.
    fn note<T>(&mut self, field: impl Into<String>, at: &Spanned<T>) {
        self.lines.push((field.into(), line_of(at)));
    }

    /// The line of a field noted so far.
    fn line_of_field(&self, field: &str) -> Option<u64> {
        self.lines.iter().find(|(f, _)| f == field).map(|(_, l)| *l)
    }
}

impl WorldFile {
    /// Reads a world file (YAML or JSON); `source` names it in errors. Every error names the
    /// file, the line where it can and the field.
    pub fn from_str(text: &str, source: &str) -> Result<Self, SceneError> {
        let mut reader = Reader {
            source,
            lines: Vec::new(),
        };
        let raw = deserialize(text, &reader)?;
        check_version(&raw, &reader)?;
        let map = prior_section(&raw, &mut reader)?;
        let hidden = hidden_obstacles(&raw.hidden_obstacles, &mut reader)?;
        let cleared = cleared_obstacles(&raw.cleared_obstacles, &mut reader);
        let team = match &raw.team {
            None => Team::default(),
            Some(t) => team(t, &mut reader)?,
        };
        Ok(Self {
            name: world_name(raw.name, source),
            scene: raw.scene.map(|s| s.value).unwrap_or_default(),
            map,
            hidden_obstacles: hidden,
            cleared_obstacles: cleared,
            team,
            source: source.to_owned(),
            lines: reader.lines,
        })
    }

    /// A file built in code (no lines to point at): `name` names it in errors.
    pub(crate) fn unread(name: &str, scene: String, team: Team) -> Self {
        Self {
            name: name.to_owned(),
            scene,
            map: None,
            hidden_obstacles: Vec::new(),
            cleared_obstacles: Vec::new(),
            team,
            source: name.to_owned(),
            lines: Vec::new(),
        }
    }

    /// Where a field is in the file.
    pub(crate) fn line(&self, field: &str) -> Option<u64> {
        self.lines.iter().find(|(f, _)| f == field).map(|(_, l)| *l)
    }

    /// The error `problem` with `field`, at the field's line in the file.
    pub(crate) fn field_error(&self, field: &str, problem: String) -> SceneError {
        SceneError {
            source_name: self.source.clone(),
            line: self.line(field),
            column: None,
            field: Some(field.to_owned()),
            problem,
        }
    }
}

/// The file's fields as written, or the parser's error (its first line, at its place).
fn deserialize(text: &str, reader: &Reader) -> Result<RawWorld, SceneError> {
    if text.trim().is_empty() {
        return Err(reader.error(None, None, "the file is empty (expected a world)".into()));
    }
    homospline_geom::scene::from_yaml(text)
        .map_err(|e| homospline_geom::scene::yaml_error(text, &e, reader.source, "malformed world"))
}

/// `version`, when given, is the one this build reads.
fn check_version(raw: &RawWorld, reader: &Reader) -> Result<(), SceneError> {
    match &raw.version {
        Some(v) if v.value.0 != WORLD_VERSION => Err(reader.at(
            v,
            "version",
            format!(
                "version {} is not supported (this build reads version {WORLD_VERSION})",
                v.value.0
            ),
        )),
        _ => Ok(()),
    }
}

/// The prior: `scene` (no map fields then), or `map` with the map world's fields (`None`:
/// a scene world).
fn prior_section(raw: &RawWorld, reader: &mut Reader) -> Result<Option<MapSpec>, SceneError> {
    match (&raw.scene, &raw.map) {
        (None, None) => Err(reader.error(
            None,
            Some("scene"),
            "missing: a world needs `scene` (a scene file) or `map` (an occupancy map)".into(),
        )),
        (Some(_), Some(m)) => Err(reader.at(
            m,
            "map",
            "a world has either `scene` or `map`, not both".into(),
        )),
        (Some(sc), None) => scene_form(raw, sc, reader).map(|()| None),
        (None, Some(m)) => map_form(raw, m, reader).map(Some),
    }
}

/// A scene world: a path to the scene, and none of the map world's fields.
fn scene_form(raw: &RawWorld, sc: &Spanned<String>, reader: &mut Reader) -> Result<(), SceneError> {
    reader.note("scene", sc);
    if sc.value.trim().is_empty() {
        return Err(reader.at(
            sc,
            "scene",
            "empty path (expected the prior scene's file)".into(),
        ));
    }
    for (field, line) in [
        ("truth_map", raw.truth_map.as_ref().map(line_of)),
        ("start", raw.start.as_ref().map(line_of)),
        ("goal", raw.goal.as_ref().map(line_of)),
    ] {
        if let Some(l) = line {
            return Err(reader.error(
                Some(l),
                Some(field),
                "only for a map world (`map`); a scene has its own".into(),
            ));
        }
    }
    Ok(())
}

/// A map world: the prior map, the truth map, the UGV's start and goal, and no obstacle
/// lists (the truth map holds what the map does not know).
fn map_form(
    raw: &RawWorld,
    m: &Spanned<String>,
    reader: &mut Reader,
) -> Result<MapSpec, SceneError> {
    reader.note("map", m);
    let map_line = line_of(m);
    let missing = |reader: &Reader, field: &str, what: &str| {
        reader.error(
            Some(map_line),
            Some(field),
            format!("missing: a map world needs {what}"),
        )
    };
    if m.value.trim().is_empty() {
        return Err(reader.at(
            m,
            "map",
            "empty path (expected the prior map's file)".into(),
        ));
    }
    let Some(truth) = raw.truth_map.as_ref() else {
        return Err(missing(
            reader,
            "truth_map",
            "the truth map beside the prior",
        ));
    };
    reader.note("truth_map", truth);
    if truth.value.trim().is_empty() {
        return Err(reader.at(
            truth,
            "truth_map",
            "empty path (expected the truth map's file)".into(),
        ));
    }
    let mut ends = [Point::origin(); 2];
    for (k, (field, v)) in [("start", &raw.start), ("goal", &raw.goal)]
        .into_iter()
        .enumerate()
    {
        let Some(v) = v.as_ref() else {
            return Err(missing(reader, field, "the UGV's start and goal"));
        };
        reader.note(field, v);
        ends[k] = finite_point(v.value, reader, v, field)?;
    }
    let not_for_maps = "not for a map world: the truth map holds what the map does not know";
    if let Some(h) = raw.hidden_obstacles.first() {
        return Err(reader.at(h, "hidden_obstacles", not_for_maps.into()));
    }
    if let Some(c) = raw.cleared_obstacles.first() {
        return Err(reader.at(c, "cleared_obstacles", not_for_maps.into()));
    }
    Ok(MapSpec {
        map: m.value.clone(),
        truth_map: truth.value.clone(),
        start: ends[0],
        goal: ends[1],
    })
}

/// `[x, y]` as a point, if both are finite; else the error with `field` at `at`.
fn finite_point<T>(
    [Number(x), Number(y)]: [Number; 2],
    reader: &Reader,
    at: &Spanned<T>,
    field: &str,
) -> Result<Point, SceneError> {
    if !(x.is_finite() && y.is_finite()) {
        return Err(reader.at(
            at,
            field,
            format!("({}, {}) must be finite", Num(x), Num(y)),
        ));
    }
    Ok(Point::new(x, y))
}

/// The obstacles not on the map, named `hidden-I` when they have no name, checked as a
/// scene's obstacles are ([`check_obstacle`]).
fn hidden_obstacles(
    raw: &[Spanned<ObstacleEntry>],
    reader: &mut Reader,
) -> Result<Vec<Obstacle>, SceneError> {
    let mut hidden = Vec::with_capacity(raw.len());
    for (i, o) in raw.iter().enumerate() {
        let field = format!("hidden_obstacles[{i}]");
        reader.note(field.clone(), o);
        for (j, c) in o.value.circles.iter().enumerate() {
            reader.note(format!("{field}.circles[{j}]"), c);
        }
        let obstacle = o.value.obstacle(|| format!("hidden-{i}"));
        if let Err((at, problem)) = check_obstacle(&field, &obstacle) {
            let line = reader.line_of_field(&at).unwrap_or(line_of(o));
            return Err(reader.error(Some(line), Some(&at), problem));
        }
        hidden.push(obstacle);
    }
    Ok(hidden)
}

/// The names of the mapped obstacles that are gone (checked against the scene later).
fn cleared_obstacles(raw: &[Spanned<String>], reader: &mut Reader) -> Vec<String> {
    raw.iter()
        .enumerate()
        .map(|(i, c)| {
            reader.note(format!("cleared_obstacles[{i}]"), c);
            c.value.clone()
        })
        .collect()
}

/// The team: the UGV and the scouts, every speed and sensor range positive.
fn team(t: &Spanned<RawTeam>, reader: &mut Reader) -> Result<Team, SceneError> {
    reader.note("team", t);
    let ugv = ugv(&t.value.ugv, reader)?;
    let mut uavs = Vec::new();
    for (i, a) in t.value.uavs.iter().enumerate() {
        uavs.push(uav(i, a, reader)?);
    }
    Ok(Team { ugv, uavs })
}

/// `team.ugv`: a positive speed and sensor range, a radius of at least 0.
fn ugv(u: &Spanned<RawUgv>, reader: &Reader) -> Result<Ugv, SceneError> {
    for (what, v) in [
        ("speed", u.value.speed.0),
        ("sensor_range", u.value.sensor_range.0),
    ] {
        if !positive(v) {
            return Err(reader.at(
                u,
                &format!("team.ugv.{what}"),
                format!("{} must be finite, > 0 and at most 1e9", Num(v)),
            ));
        }
    }
    let r = u.value.radius.0;
    if !(is_robot_radius(r) && r <= MAX_MAGNITUDE) {
        return Err(reader.at(
            u,
            "team.ugv.radius",
            format!("{r} {ROBOT_RADIUS_RULE} and at most {MAX_MAGNITUDE:e}"),
        ));
    }
    Ok(Ugv {
        speed: u.value.speed.0,
        sensor_range: u.value.sensor_range.0,
        radius: u.value.radius.0,
    })
}

/// `team.uavs[i]`: a positive speed and sensor range, a finite start.
fn uav(i: usize, a: &Spanned<RawUav>, reader: &mut Reader) -> Result<Uav, SceneError> {
    let field = format!("team.uavs[{i}]");
    reader.note(field.clone(), a);
    for (what, v) in [
        ("speed", a.value.speed.0),
        ("sensor_range", a.value.sensor_range.0),
    ] {
        if !positive(v) {
            return Err(reader.at(
                a,
                &format!("{field}.{what}"),
                format!("{} must be finite, > 0 and at most 1e9", Num(v)),
            ));
        }
    }
    Ok(Uav {
        start: finite_point(a.value.start, reader, a, &format!("{field}.start"))?,
        speed: a.value.speed.0,
        sensor_range: a.value.sensor_range.0,
    })
}

/// The world's name: as given, else the file's stem.
fn world_name(name: Option<String>, source: &str) -> String {
    name.unwrap_or_else(|| {
        std::path::Path::new(source)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("world")
            .to_owned()
    })
}
