//! One loader for every front end: a planning input (a scene file, a MovingAI map or a ROS
//! map YAML with its image) recognised by its name and content. The caller reads the files
//! (this crate does no IO): `read` gets each path the input needs.

use std::path::Path;

use homospline_geom::Scene;

use crate::{OccupancyMap, movingai, ros};

/// What a file holds.
#[derive(Clone, Debug)]
pub enum Input {
    /// A scene of circles (YAML or JSON).
    Scene(Scene),
    /// An occupancy map.
    Map(OccupancyMap),
}

/// The top-level keys of a ROS map YAML, none of which a scene file has.
const ROS_KEYS: [&str; 6] = [
    "image",
    "resolution",
    "origin",
    "negate",
    "occupied_thresh",
    "free_thresh",
];

/// Reads the input at `path`: `.map` is a MovingAI map, a `.yaml`/`.yml` with a top-level
/// key of a ROS map (`image:`, `resolution:`, ... ; `ROS_KEYS`) a ROS map (its image read
/// beside it), anything else a scene. (With `image:` alone, a ROS map YAML that lacked it was
/// read as a scene: "unknown field `resolution`".) The error is the message a
/// front end shows: file, line and field where known.
pub fn load(
    path: &Path,
    read: impl Fn(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<Input, String> {
    let name = path.display().to_string();
    let bytes = read(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    let is_map = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("map"));
    let text = std::str::from_utf8(&bytes).ok();
    let is_ros = !is_map
        && path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"))
        && text.is_some_and(|t| {
            t.lines().any(|l| {
                ROS_KEYS.iter().any(|k| {
                    l.strip_prefix(k)
                        .is_some_and(|r| r.trim_start().starts_with(':'))
                })
            })
        });
    if is_map {
        let text = text.ok_or_else(|| format!("{name}: not a text file"))?;
        return movingai::read_map(text, &name)
            .map(Input::Map)
            .map_err(|e| e.to_string());
    }
    if is_ros {
        let yaml = ros::read_yaml(text.unwrap_or_default(), &name).map_err(|e| e.to_string())?;
        let image = path.parent().unwrap_or(Path::new(".")).join(&yaml.image);
        let img = read(&image)
            .map_err(|e| format!("{name}: image {}: cannot read: {e}", image.display()))?;
        return ros::read_map(&yaml, &name, &img, &image.display().to_string())
            .map(Input::Map)
            .map_err(|e| e.to_string());
    }
    Scene::from_bytes(&bytes, &name)
        .map(Input::Scene)
        .map_err(|e| e.to_string())
}
