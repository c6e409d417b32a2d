//! Writing a scene world as a world file (YAML).

use homospline_geom::Real;
use homospline_geom::scene::WrittenObstacle;

use super::types::{MissionWorld, WORLD_VERSION};

#[derive(serde::Serialize)]
struct OutWorld<'a> {
    version: u32,
    name: &'a str,
    scene: &'a str,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    hidden_obstacles: Vec<WrittenObstacle<'a>>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    cleared_obstacles: Vec<&'a str>,
    team: OutTeam,
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
                .map(WrittenObstacle::from)
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
