//! Joining a map world file with its prior and truth maps: the checks of the two maps
//! together, the robot's radius, and the changes between them.

use homospline_geom::math::Num;
use homospline_geom::{Point, SceneError};
use homospline_maps::OccupancyMap;

use super::changes::changes;
use crate::world::types::{MapSpec, MapWorld, Team, WorldFile};

impl MapWorld {
    /// Joins the file with its prior and truth maps and checks them together.
    pub fn from_file(
        file: WorldFile,
        prior: OccupancyMap,
        truth: OccupancyMap,
        spec: &MapSpec,
    ) -> Result<Self, SceneError> {
        check_same_grid(&file, &prior, &truth, spec)?;
        check_ends_free(&file, &prior, &truth, spec)?;
        let (prior, truth) = keep_radius(&file, prior, truth, spec)?;
        check_scouts_on(&file, &prior)?;
        let changes = changes(&prior, &truth);
        Ok(MapWorld {
            name: file.name,
            prior,
            truth,
            start: spec.start,
            goal: spec.goal,
            team: file.team,
            changes,
        })
    }

    /// A world built in code or from a file: checks that the maps have the same size, cell
    /// and origin, that start and goal are free on both, and that the scouts start on the
    /// map. `name` names the world in errors.
    pub fn new(
        name: &str,
        prior: OccupancyMap,
        truth: OccupancyMap,
        start: Point,
        goal: Point,
        team: Team,
    ) -> Result<Self, SceneError> {
        Self::from_file(
            WorldFile::unread(name, String::new(), team),
            prior,
            truth,
            &MapSpec {
                map: String::new(),
                truth_map: String::new(),
                start,
                goal,
            },
        )
    }
}

/// ` (FILE)`, or nothing for a map built in code.
fn named(f: &str) -> String {
    if f.is_empty() {
        String::new()
    } else {
        format!(" ({f})")
    }
}

/// The truth map has the prior's size, cell size, origin and axis.
fn check_same_grid(
    file: &WorldFile,
    prior: &OccupancyMap,
    truth: &OccupancyMap,
    spec: &MapSpec,
) -> Result<(), SceneError> {
    if (truth.width, truth.height) != (prior.width, prior.height) {
        return Err(file.field_error(
            "truth_map",
            format!(
                "the truth map{} is {} x {} cells; the prior map{} is {} x {}: they must be the same size",
                named(&spec.truth_map),
                truth.width,
                truth.height,
                named(&spec.map),
                prior.width,
                prior.height
            ),
        ));
    }
    if (truth.cell - prior.cell).abs() > 1e-9 * prior.cell
        || (truth.origin - prior.origin).norm() > 1e-9 * prior.cell
        || truth.y_down != prior.y_down
    {
        return Err(file.field_error(
            "truth_map",
            format!(
                "the truth map{} has another cell size, origin or axis than the prior map{}",
                named(&spec.truth_map),
                named(&spec.map)
            ),
        ));
    }
    Ok(())
}

/// The first problem `problem` finds with the start or the goal on the prior or the truth
/// map (named "prior map" or "truth map"), as an error of the end's field.
fn check_ends(
    file: &WorldFile,
    (prior, truth): (&OccupancyMap, &OccupancyMap),
    spec: &MapSpec,
    problem: impl Fn(Point, &str, &OccupancyMap) -> Option<String>,
) -> Result<(), SceneError> {
    for (field, p) in [("start", spec.start), ("goal", spec.goal)] {
        for (which, m) in [("prior map", prior), ("truth map", truth)] {
            if let Some(why) = problem(p, which, m) {
                return Err(file.field_error(field, why));
            }
        }
    }
    Ok(())
}

/// The start and the goal are on both maps, in free cells that touch no obstacle.
fn check_ends_free(
    file: &WorldFile,
    prior: &OccupancyMap,
    truth: &OccupancyMap,
    spec: &MapSpec,
) -> Result<(), SceneError> {
    check_ends(file, (prior, truth), spec, |p, which, m| {
        match m.free_at(&p) {
            None => Some(format!(
                "({}, {}) is outside the map {}",
                Num(p.x),
                Num(p.y),
                m.bounds()
            )),
            Some(false) => Some(format!(
                "({}, {}) is in an occupied cell of the {which}",
                Num(p.x),
                Num(p.y)
            )),
            Some(true) => m
                .touches_obstacle(&p)
                .map(|why| format!("({}, {}) {why} of the {which}", p.x, p.y)),
        }
    })
}

/// With a positive `team.ugv.radius`, the start and the goal must keep the radius on both
/// maps, and stand in cells of the robot's lattice (`OccupancyMap::robot_space`, the free
/// space the mission plans in); the maps are kept as given.
fn keep_radius(
    file: &WorldFile,
    prior: OccupancyMap,
    truth: OccupancyMap,
    spec: &MapSpec,
) -> Result<(OccupancyMap, OccupancyMap), SceneError> {
    let r = file.team.ugv.radius;
    if !homospline_geom::is_robot_radius(r) {
        return Err(file.field_error(
            "team.ugv.radius",
            format!("{r} {}", homospline_geom::ROBOT_RADIUS_RULE),
        ));
    }
    if r > 0.0 {
        // More clearance than the radius on both maps...
        check_ends(file, (&prior, &truth), spec, |p, which, m| {
            let c = m.clearance_within(&p, r + 2.0 * m.cell);
            (c <= r).then(|| {
                format!(
                    "({}, {}) has clearance {c:.4} on the {which}, not more than team.ugv.radius {r}",
                    p.x, p.y
                )
            })
        })?;
        // ...and free cells touching no blocked cell on the robot's lattices of both.
        let lattice = |m: &OccupancyMap| {
            m.robot_space(r)
                .map(|(free, _)| free)
                .map_err(|e| file.field_error("team.ugv.radius", format!("{r}: {e}")))
        };
        check_ends(
            file,
            (&lattice(&prior)?, &lattice(&truth)?),
            spec,
            |p, which, m| {
                (m.free_at(&p) != Some(true) || m.touches_obstacle(&p).is_some()).then(|| {
                format!(
                    "({}, {}) keeps team.ugv.radius {r} on the {which}, but the nearest point of the robot's lattice does not (free space is sampled every half cell): move it up to half a cell away from the wall",
                    p.x, p.y
                )
            })
            },
        )?;
    }
    Ok((prior, truth))
}

/// Every scout starts on the map.
fn check_scouts_on(file: &WorldFile, prior: &OccupancyMap) -> Result<(), SceneError> {
    for (i, u) in file.team.uavs.iter().enumerate() {
        if !prior.bounds().contains(&u.start) {
            return Err(file.field_error(
                &format!("team.uavs[{i}]"),
                format!(
                    "start ({}, {}) is outside the map",
                    Num(u.start.x),
                    Num(u.start.y)
                ),
            ));
        }
    }
    Ok(())
}
