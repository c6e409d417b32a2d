//! `homospline graph`: the Voronoi graph of a scene (start and goal attached) or the complete
//! graph of a map, saved for `plan --graph`, as JSON or as a picture; `--out-dir` for many.

use homospline_geom::math::Num;
use std::path::{Path, PathBuf};

use anyhow::Context;
use homospline_maps::input::Input;
use homospline_optim::default_resolution;
use homospline_spline::CostConfig;

use crate::args::GraphArgs;
use crate::bench_scen::shard_of;
use crate::input::{Reads, load_input};
use crate::out::{bad, check_outputs, write};
use crate::picture;

/// `graph`: one input and its outputs, or many into `--out-dir`.
pub fn run(a: GraphArgs) -> anyhow::Result<u8> {
    let grid = (a.resolution, a.robot_radius);
    match &a.out_dir {
        Some(dir) => graph_dir(
            &a.scene,
            grid,
            dir,
            a.shard.as_deref(),
            Outputs {
                out: a.out,
                json: a.json,
                svg: a.svg,
                png: a.png,
            },
        ),
        None if a.scene.len() == 1 && a.shard.is_none() => graph(
            &a.scene[0],
            grid,
            Outputs {
                out: a.out,
                json: a.json,
                svg: a.svg,
                png: a.png,
            },
        ),
        None => Err(bad(
            "several inputs (or --shard) need --out-dir: each graph is saved as DIR/STEM.msgpack",
        )),
    }
}

/// The input of `graph`, read and checked against its options (`--resolution` is a
/// scene's): what `graph --out-dir` checks of every input before it builds any graph.
fn graph_input(
    path: &Path,
    (resolution, robot_radius): (Option<f64>, Option<f64>),
    reads: &Reads,
) -> anyhow::Result<Input> {
    if let Some(r) = robot_radius
        && !homospline_geom::is_robot_radius(r)
    {
        return Err(bad(format!(
            "--robot-radius {}: {}",
            Num(r),
            homospline_geom::ROBOT_RADIUS_RULE
        )));
    }
    let input = load_input(path, reads)?;
    match input {
        Input::Map(_) if resolution.is_some() => Err(bad(format!(
            "{}: --resolution applies to scenes; a map's grid is its cells",
            path.display()
        ))),
        Input::Scene(mut scene) if robot_radius.is_some() => {
            scene.robot_radius = robot_radius.unwrap_or(0.0);
            scene
                .validate(&path.display().to_string())
                .map_err(|e| bad(format!("--robot-radius: {e}")))?;
            Ok(Input::Scene(scene))
        }
        input => Ok(input),
    }
}

/// The files `graph` writes for one input.
struct Outputs {
    out: Option<PathBuf>,
    json: Option<PathBuf>,
    svg: Option<PathBuf>,
    png: Option<PathBuf>,
}

fn graph(
    path: &Path,
    (resolution, robot_radius): (Option<f64>, Option<f64>),
    outputs: Outputs,
) -> anyhow::Result<u8> {
    let Outputs {
        out,
        json,
        svg,
        png,
    } = outputs;
    let reads = Reads::default();
    let input = graph_input(path, (resolution, robot_radius), &reads)?;
    // The input and the files it names (a ROS map's image): none of them is overwritten.
    let inputs = reads.paths();
    check_outputs(
        &inputs.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
        &[
            ("--out", "graph", out.as_deref()),
            ("--json", "graph JSON", json.as_deref()),
            ("--svg", "picture", svg.as_deref()),
            ("--png", "PNG picture", png.as_deref()),
        ],
    )?;
    let t = std::time::Instant::now();
    let (g, cells, res, name) = match &input {
        Input::Scene(scene) => {
            let res = resolution.unwrap_or_else(|| default_resolution(scene));
            homospline_front::memory::check(
                || format!("scene {} at --resolution {res}", scene.name),
                homospline_front::memory::scene_cells(scene, res),
            )?;
            let (grid, _, g) = homospline_voronoi::build(scene, res)
                .map_err(|e| bad(format!("{}: {e}", path.display())))?;
            (g, (grid.width(), grid.height()), res, scene.name.clone())
        }
        Input::Map(map) => {
            // The complete graph of the whole map, without start or goal: `plan MAP --graph`
            // attaches each query's start and goal to it.
            crate::plan::check_map_memory(map, robot_radius.unwrap_or(0.0))?;
            let prepared =
                homospline_maps::PreparedMap::for_robot(map, robot_radius.unwrap_or(0.0))
                    .map_err(|e| bad(format!("{}: {e}", path.display())))?;
            let res = prepared.grid.resolution();
            // Moved out, not cloned: a 4096 x 4096 map's graph is half a gigabyte.
            (
                prepared.graph.graph,
                (map.width, map.height),
                res,
                map.name.clone(),
            )
        }
    };
    say!(
        "graph of {}: {} x {} cells at {:.3} cells per unit, {} nodes, {} edges, {} cycles, {:.1} ms",
        name,
        cells.0,
        cells.1,
        res,
        g.nodes.len(),
        g.edges.len(),
        g.cycle_rank(),
        t.elapsed().as_secs_f64() * 1e3
    );
    if let Some(p) = out {
        write(&p, "graph", &g.to_msgpack())?;
    }
    if let Some(p) = json {
        write(&p, "graph JSON", g.to_json().as_bytes())?;
    }
    if svg.is_some() || png.is_some() {
        let bg = match &input {
            Input::Scene(scene) => picture::Background::Scene(scene, CostConfig::default().alpha),
            Input::Map(map) => picture::Background::Map(map),
        };
        let picture = picture::graph_svg(&bg, &g);
        if let Some(p) = svg {
            write(&p, "picture", picture.as_bytes())?;
        }
        if let Some(p) = png {
            crate::png::write_png(&p, "PNG picture", &picture)?;
        }
    }
    Ok(0)
}

/// `graph --out-dir`: every input's graph (or this shard's slice of them) saved as
/// `DIR/STEM.msgpack`.
fn graph_dir(
    inputs: &[PathBuf],
    grid: (Option<f64>, Option<f64>),
    dir: &Path,
    shard: Option<&str>,
    single: Outputs,
) -> anyhow::Result<u8> {
    if single.out.is_some() || single.json.is_some() || single.svg.is_some() || single.png.is_some()
    {
        return Err(bad(
            "--out-dir writes one file per input: drop --out, --json, --svg and --png",
        ));
    }
    let shard = shard_of(shard)?;
    let mut files = Vec::new();
    for p in inputs {
        if p.is_dir() {
            files.extend(homospline_front::bench::files_in(p, "map").map_err(bad)?);
        } else {
            files.push(p.clone());
        }
    }
    if files.is_empty() {
        return Err(bad(format!(
            "{}: no input to build a graph of (a directory gives its .map files)",
            inputs
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    // Every input is a regular file, in this shard or not: a mistyped path must not pass on
    // the shards that do not read it.
    for f in &files {
        match std::fs::metadata(f) {
            Ok(m) if m.is_file() => {}
            Ok(_) => {
                return Err(bad(format!(
                    "{}: cannot read: not a regular file (a directory, pipe or device)",
                    f.display()
                )));
            }
            Err(e) => return Err(bad(format!("{}: cannot read: {e}", f.display()))),
        }
    }
    // Every name is checked before anything is written: a clash found halfway left the
    // first inputs' graphs behind.
    let mut stems = std::collections::BTreeMap::new();
    for f in &files {
        let stem = f
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("graph")
            .to_owned();
        if let Some(first) = stems.insert(stem.clone(), f) {
            return Err(bad(format!(
                "{} and {} would both be saved as {stem}.msgpack",
                first.display(),
                f.display()
            )));
        }
    }
    // Every input of this shard is read, and dropped, before any graph is built: an
    // unreadable map found halfway left the first maps' graphs behind. Reading is a small
    // part of a graph's cost; a graph that cannot be built still stops the run where it is.
    let reads = Reads::default();
    for (i, f) in files.iter().enumerate() {
        if shard.takes(i) {
            graph_input(f, grid, &reads)?;
        }
    }
    let taken = (0..files.len()).filter(|&i| shard.takes(i)).count();
    if taken == 0 {
        say!(
            "graph: shard {}/{} gets none of the {} inputs (there are more shards than inputs): nothing to build",
            shard.k,
            shard.n,
            files.len()
        );
        return Ok(0);
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
    // No graph overwrites an input, this shard's or another's (a link in DIR to one of
    // them), or a file this shard's inputs read (a ROS map's image).
    let outputs: Vec<PathBuf> = files
        .iter()
        .enumerate()
        .filter(|&(i, _)| shard.takes(i))
        .map(|(_, f)| out_path(dir, f))
        .collect();
    let mut read = files.clone();
    read.extend(reads.paths());
    check_outputs(
        &read.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
        &outputs
            .iter()
            .map(|p| ("--out-dir", "graph", Some(p.as_path())))
            .collect::<Vec<_>>(),
    )?;
    for (i, f) in files.iter().enumerate() {
        if !shard.takes(i) {
            continue;
        }
        graph(
            f,
            grid,
            Outputs {
                out: Some(out_path(dir, f)),
                json: None,
                svg: None,
                png: None,
            },
        )?;
    }
    Ok(0)
}

/// Where `graph --out-dir DIR` saves the graph of `input`: `DIR/STEM.msgpack`.
fn out_path(dir: &Path, input: &Path) -> PathBuf {
    let stem = input
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("graph");
    dir.join(format!("{stem}.msgpack"))
}
