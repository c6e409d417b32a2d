//! Joining a world file with its prior scene: the checks of the two together, and the truth
//! (the prior without the cleared obstacles, with the hidden ones).

use homospline_geom::{Obstacle, Scene, SceneError};

use super::types::{MissionWorld, Team, WorldFile};

impl WorldFile {
    /// Joins the file with its prior scene and checks them together: cleared obstacles exist
    /// on the map, hidden ones have names of their own, the start and the goal are free in
    /// the truth, the scouts start inside the bounds.
    pub fn with_prior(self, mut prior: Scene) -> Result<MissionWorld, SceneError> {
        self.apply_radius(&mut prior)?;
        self.check_cleared(&prior)?;
        self.check_hidden(&prior)?;
        self.check_scouts_in(&prior)?;
        let mut truth = prior.clone();
        truth
            .obstacles
            .retain(|o| !self.cleared_obstacles.contains(&o.name));
        truth
            .obstacles
            .extend(self.hidden_obstacles.iter().cloned());
        truth.validate(&self.source)?;
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

    /// A positive `team.ugv.radius` becomes the scene's robot radius; the scene must keep
    /// it.
    fn apply_radius(&self, prior: &mut Scene) -> Result<(), SceneError> {
        let r = self.team.ugv.radius;
        if r > 0.0 {
            prior.robot_radius = r;
            prior.validate(&self.source).map_err(|e| {
                self.field_error(
                    "team.ugv.radius",
                    format!("{r}: the scene at this robot radius: {}", e.problem),
                )
            })?;
        }
        Ok(())
    }

    /// Every cleared obstacle is listed once and is on the map.
    fn check_cleared(&self, prior: &Scene) -> Result<(), SceneError> {
        for (i, name) in self.cleared_obstacles.iter().enumerate() {
            let field = format!("cleared_obstacles[{i}]");
            if self.cleared_obstacles[..i].contains(name) {
                return Err(self.field_error(&field, format!("'{name}' is listed twice")));
            }
            if !prior.obstacles.iter().any(|o| &o.name == name) {
                return Err(
                    self.field_error(&field, format!("no obstacle named '{name}' in the scene"))
                );
            }
        }
        Ok(())
    }

    /// Every hidden obstacle has a name of its own and leaves the start and the goal free.
    fn check_hidden(&self, prior: &Scene) -> Result<(), SceneError> {
        for (i, h) in self.hidden_obstacles.iter().enumerate() {
            let field = format!("hidden_obstacles[{i}]");
            if prior.obstacles.iter().any(|o| o.name == h.name)
                || self.hidden_obstacles[..i].iter().any(|o| o.name == h.name)
            {
                return Err(self.field_error(&field, format!("the name '{}' is taken", h.name)));
            }
            for (what, p) in [("start", prior.start), ("goal", prior.goal)] {
                if h.circles
                    .iter()
                    .any(|c| (p - c.center).norm() <= c.radius + prior.robot_radius)
                {
                    return Err(self.field_error(
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
    fn check_scouts_in(&self, prior: &Scene) -> Result<(), SceneError> {
        for (i, u) in self.team.uavs.iter().enumerate() {
            if !prior.bounds.contains(&u.start) {
                return Err(self.field_error(
                    &format!("team.uavs[{i}]"),
                    format!("start ({}, {}) is outside the bounds", u.start.x, u.start.y),
                ));
            }
        }
        Ok(())
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
            hidden_obstacles: hidden,
            cleared_obstacles: cleared,
            ..WorldFile::unread(name, prior.name.clone(), team)
        }
        .with_prior(prior)
    }
}
