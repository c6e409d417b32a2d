//! Reading the command line's inputs: scenes, maps and saved graphs from files that must be
//! regular files, and the values of options that are points or weights.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use homospline_geom::Point;
use homospline_maps::input::Input;
use homospline_voronoi::VoronoiGraph;

use crate::out::bad;

/// `--weight NAME=VALUE` options as names and numbers (the names are checked later, by
/// the cost).
pub fn parse_weights(weights: &[String]) -> anyhow::Result<Vec<(String, f64)>> {
    weights
        .iter()
        .map(|w| {
            let (name, value) = w
                .split_once('=')
                .ok_or_else(|| bad(format!("--weight {w}: expected NAME=VALUE")))?;
            let v: f64 = value
                .trim()
                .parse()
                .map_err(|_| bad(format!("--weight {w}: '{value}' is not a number")))?;
            Ok((name.trim().to_owned(), v))
        })
        .collect()
}

/// `--start` or `--goal` (`opt`) `X,Y` as a point.
pub fn parse_point(opt: &str, text: &str) -> anyhow::Result<Point> {
    let (x, y) = text
        .split_once(',')
        .ok_or_else(|| bad(format!("{opt} {text}: expected X,Y")))?;
    let p = |v: &str| v.trim().parse::<f64>().ok().filter(|f| f.is_finite());
    match (p(x), p(y)) {
        (Some(x), Some(y)) => Ok(Point::new(x, y)),
        _ => Err(bad(format!(
            "{opt} {text}: expected two finite numbers X,Y"
        ))),
    }
}

/// Reads a scene, a MovingAI map or a ROS map YAML (with its image), by content and name.
pub fn load_input(path: &Path, reads: &Reads) -> anyhow::Result<Input> {
    homospline_maps::input::load(path, |p| reads.read(p)).map_err(|e| refused_input(path, e, false))
}

/// The error of an input that its command's reader refused with `e`: for a file of another
/// command (a world or scenario file given to `plan`, a scene or map given to `simulate`
/// when `simulate`), what it is and the command that takes it; else `e`.
pub fn refused_input(path: &Path, e: impl Into<String>, simulate: bool) -> anyhow::Error {
    let text = homospline_front::read_regular(path).ok();
    let text = text.as_deref().and_then(|b| std::str::from_utf8(b).ok());
    match homospline_front::check::other_command(path, text, simulate) {
        Some(hint) => bad(format!("{}: {hint}", path.display())),
        None => bad(e),
    }
}

/// Reads input files (regular files only) and keeps every path read, so that the outputs
/// can be checked against each file an input names (a ROS map's image, a world's maps) as
/// well as the input itself.
#[derive(Default)]
pub struct Reads(RefCell<Vec<PathBuf>>);

impl Reads {
    /// Reads `p` whole, and keeps its path.
    pub fn read(&self, p: &Path) -> std::io::Result<Vec<u8>> {
        self.0.borrow_mut().push(p.to_path_buf());
        homospline_front::read_regular(p)
    }

    /// Every path read, in order.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.0.borrow().clone()
    }
}

/// Reads a graph saved by `graph --out`, checked for its own consistency.
pub fn read_graph(p: &Path) -> anyhow::Result<VoronoiGraph> {
    let bytes = homospline_front::read_regular(p)
        .map_err(|e| bad(format!("{}: cannot read: {e}", p.display())))?;
    VoronoiGraph::from_msgpack(&bytes).map_err(|e| bad(format!("{}: {e}", p.display())))
}
