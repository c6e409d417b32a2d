//! Joining a world file with its prior scene: the checks of the two together, and the truth
//! (the prior without the cleared obstacles, with the hidden ones).

use homospline_geom::{Obstacle, Scene, SceneError};

use super::types::{MissionWorld, Team, WorldFile};

impl MissionWorld {
    /// Joins the file with its prior scene and checks them together: cleared obstacles exist
    /// on the map, hidden ones have names of their own, the start and the goal are free in
    /// the truth, the scouts start inside the bounds.
    pub fn from_file(file: WorldFile, mut prior: Scene) -> Result<Self, SceneError> {
        apply_radius(&file, &mut prior)?;
        check_cleared(&file, &prior)?;
        check_hidden(&file, &prior)?;
        check_scouts_in(&file, &prior)?;
        let mut truth = prior.clone();
        truth
            .obstacles
            .retain(|o| !file.cleared_obstacles.contains(&o.name));
        truth
            .obstacles
            .extend(file.hidden_obstacles.iter().cloned());
        truth.validate(&file.source)?;
        Ok(MissionWorld {
            name: file.name,
            hidden: file
                .hidden_obstacles
                .iter()
                .map(|o| o.name.clone())
                .collect(),
            cleared: file.cleared_obstacles,
            prior,
            truth,
            team: file.team,
        })
    }

    /// A world built in code (generators, tests): `hidden` added to and `cleared` removed
    /// from `prior`; checked like a file.
    pub fn new(
        name: &str,
        prior: Scene,
        hidden: Vec<Obstacle>,
        cleared: Vec<String>,
        team: Team,
    ) -> Result<Self, SceneError> {
        let file = WorldFile {
            hidden_obstacles: hidden,
            cleared_obstacles: cleared,
            ..WorldFile::unread(name, prior.name.clone(), team)
        };
        Self::from_file(file, prior)
    }
}

/// A positive `team.ugv.radius` becomes the scene's robot radius; the scene must keep
/// it.
fn apply_radius(file: &WorldFile, prior: &mut Scene) -> Result<(), SceneError> {
    let r = file.team.ugv.radius;
    if r > 0.0 {
        prior.robot_radius = r;
        prior.validate(&file.source).map_err(|e| {
            file.field_error(
                "team.ugv.radius",
                format!("{r}: the scene at this robot radius: {}", e.problem),
            )
        })?;
    }
    Ok(())
}

/// Every cleared obstacle is listed once and is on the map.
fn check_cleared(file: &WorldFile, prior: &Scene) -> Result<(), SceneError> {
    for (i, name) in file.cleared_obstacles.iter().enumerate() {
        let field = format!("cleared_obstacles[{i}]");
        if file.cleared_obstacles[..i].contains(name) {
            return Err(file.field_error(&field, format!("'{name}' is listed twice")));
        }
        if !prior.obstacles.iter().any(|o| &o.name == name) {
            return Err(
                file.field_error(&field, format!("no obstacle named '{name}' in the scene"))
            );
        }
    }
    Ok(())
}

/// Every hidden obstacle has a name of its own and leaves the start and the goal free.
fn check_hidden(file: &WorldFile, prior: &Scene) -> Result<(), SceneError> {
    for (i, h) in file.hidden_obstacles.iter().enumerate() {
        let field = format!("hidden_obstacles[{i}]");
        if prior.obstacles.iter().any(|o| o.name == h.name)
            || file.hidden_obstacles[..i].iter().any(|o| o.name == h.name)
        {
            return Err(file.field_error(&field, format!("the name '{}' is taken", h.name)));
        }
        for (what, p) in [("start", prior.start), ("goal", prior.goal)] {
            if h.circles
                .iter()
                .any(|c| (p - c.center).norm() <= c.radius + prior.robot_radius)
            {
                return Err(file.field_error(
                    &field,
                    format!(
                        "covers the {what} ({}, {}): the mission cannot be run",
                        p.x, p.y
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Every scout starts inside the scene's bounds.
fn check_scouts_in(file: &WorldFile, prior: &Scene) -> Result<(), SceneError> {
    for (i, u) in file.team.uavs.iter().enumerate() {
        if !prior.bounds.contains(&u.start) {
            return Err(file.field_error(
                &format!("team.uavs[{i}]"),
                format!("start ({}, {}) is outside the bounds", u.start.x, u.start.y),
            ));
        }
    }
    Ok(())
}
