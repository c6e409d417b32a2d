//! Loading a world from files: the world file, then the scene or the two maps it names
//! (relative to it). The caller reads the files; errors are the messages a front end shows.

use homospline_geom::Scene;

use super::types::{AnyWorld, MapWorld, MissionWorld, WorldFile};

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
    MissionWorld::from_file(file, prior).map_err(|e| e.to_string())
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
    MapWorld::from_file(file, prior, truth, &spec)
        .map(AnyWorld::Map)
        .map_err(|e| e.to_string())
}
