//! `bench-scen` and `bench-merge` for every front end (the command line and the Python
//! package): `.scen` files and directories expanded, scenarios picked and sharded, every map
//! read and checked (only its size kept), those the shard plans on prepared once, rows
//! planned; CSV text to and from rows. This module reads files.

use homospline_geom::math::Num;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use homospline_maps::sweep::{self, CSV_HEADER, Row, Shard};
use homospline_maps::{OccupancyMap, PreparedMap, movingai};
use homospline_optim::PlanConfig;

use crate::options::{Opt, OptionError, PlanOptions};

/// A sweep, or one shard of it.
#[derive(Clone, Debug)]
pub struct BenchJob {
    /// `.scen` files, or directories of them.
    pub files: Vec<PathBuf>,
    /// Scenarios per file spread evenly over every bucket.
    pub sample: Option<usize>,
    /// The first scenarios of each file.
    pub limit: Option<usize>,
    /// This run's slice.
    pub shard: Shard,
    /// Classes per plan.
    pub classes: usize,
    /// Plans slower than this (ms) count as timeouts.
    pub time_limit: Option<f64>,
    /// Weights and parameters of the cost by name (`--weight NAME=VALUE`), over the map
    /// defaults.
    pub weights: Vec<(String, f64)>,
    /// The robot's radius, map units (0: a point).
    pub robot_radius: f64,
}

/// What a run did besides its rows.
#[derive(Clone, Debug, Default)]
pub struct BenchInfo {
    /// The `.scen` files, directories expanded.
    pub files: Vec<PathBuf>,
    /// How many scenarios the files hold, all together.
    pub total: usize,
    /// How many of them the sweep picked, before sharding: all (`total`) without options,
    /// `sample` of each file spread over every bucket, or the first `limit` of each file.
    /// The rows are this shard's slice of them: a run's message reads "ROWS of PICKED
    /// scenarios picked from TOTAL".
    pub picked: usize,
    /// Each map the files' scenarios name, with its size (`name (W x H)`): every one is read
    /// and checked against the sizes its scenarios declare; those this shard plans on are
    /// prepared.
    pub maps: Vec<String>,
    /// Time spent preparing maps, ms.
    pub prepare_ms: f64,
}

/// The files of directory `dir` whose extension is `ext`, sorted.
pub fn files_in(dir: &Path, ext: &str) -> Result<Vec<PathBuf>, String> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: cannot read the directory: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|f| f.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    Ok(v)
}

/// The `.scen` files named: files as given, directories expanded (sorted). A file named
/// twice (the same canonical path, given again, through another spelling or inside a
/// directory given) is refused: its scenarios would be planned twice, and `bench-merge`
/// refuses a CSV that holds a scenario twice.
pub fn scen_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out: Vec<PathBuf> = Vec::new();
    for p in paths {
        if p.is_dir() {
            let v = files_in(p, "scen")?;
            if v.is_empty() {
                return Err(format!("{}: no .scen file in the directory", p.display()));
            }
            out.extend(v);
        } else {
            out.push(p.clone());
        }
    }
    let mut seen: BTreeMap<PathBuf, &Path> = BTreeMap::new();
    for f in &out {
        let canonical = f
            .canonicalize()
            .map_err(|e| format!("{}: cannot read: {e}", f.display()))?;
        if let Some(first) = seen.insert(canonical, f) {
            let also = if first == f.as_path() {
                String::new()
            } else {
                format!(" (as {})", first.display())
            };
            return Err(format!(
                "{}: the same .scen file is given twice{also}: its scenarios would be planned twice",
                f.display()
            ));
        }
    }
    Ok(out)
}

/// The map file a scenario of `scen_file` names: beside the scenario file.
fn map_beside(scen_file: &Path, map: &str) -> PathBuf {
    let name = Path::new(map)
        .file_name()
        .map(PathBuf::from)
        .unwrap_or_default();
    scen_file.parent().unwrap_or(Path::new(".")).join(name)
}

/// Reads the map at `path`, which line `line` of `scen` names.
fn read_map_of(scen: &str, line: usize, path: &Path) -> Result<OccupancyMap, String> {
    let text = crate::read_regular_string(path).map_err(|e| {
        format!(
            "{scen}:{line}: its map {}: cannot read: {e}",
            path.display()
        )
    })?;
    movingai::read_map(&text, &path.display().to_string()).map_err(|e| e.to_string())
}

/// A map's name and size (width, height), all a run keeps of a map it does not plan on.
struct MapSize {
    name: String,
    size: (usize, usize),
}

/// Why a sweep stopped: an option it cannot take, or an input it cannot read.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// An option out of its range.
    #[error(transparent)]
    Option(#[from] OptionError),
    /// A file that cannot be read or does not hold what it should, with its name.
    #[error("{0}")]
    Input(String),
}

impl BenchJob {
    /// Checks the options and gives the plans' configuration (the map defaults).
    pub fn validate(&self) -> Result<PlanConfig, OptionError> {
        let cfg = PlanOptions {
            classes: Some(self.classes),
            weights: self.weights.clone(),
            ..Default::default()
        }
        .validate(None)?;
        if !homospline_geom::is_robot_radius(self.robot_radius) {
            return Err(OptionError::new(
                Opt::RobotRadius,
                Num(self.robot_radius),
                format!("{} (map units)", homospline_geom::ROBOT_RADIUS_RULE),
            ));
        }
        if self.limit.is_some() && self.sample.is_some() {
            return Err(
                OptionError::given(Opt::Limit, "and {} exclude each other").naming(Opt::Sample)
            );
        }
        for (o, n) in [(Opt::Sample, self.sample), (Opt::Limit, self.limit)] {
            if n == Some(0) {
                return Err(OptionError::new(o, 0, "must be at least 1"));
            }
        }
        if let Some(t) = self.time_limit
            && !(t.is_finite() && t > 0.0)
        {
            return Err(OptionError::new(
                Opt::TimeLimit,
                Num(t),
                "must be a positive number of ms",
            ));
        }
        Ok(cfg)
    }
}

/// The scenarios of a sweep's files and the ones this shard plans.
struct Picked {
    files: Vec<PathBuf>,
    scenarios: Vec<Vec<movingai::Scenario>>,
    /// This shard's scenarios, as (file, scenario) indices, in order.
    items: Vec<(usize, usize)>,
    total: usize,
    picked: usize,
}

/// Every file the job reads: its `.scen` files (directories expanded) and each map they
/// name, so that an output can be checked against them before any work. Reads only the
/// `.scen` files.
pub fn input_files(job: &BenchJob) -> Result<Vec<PathBuf>, String> {
    let p = pick(job)?;
    let maps: std::collections::BTreeSet<PathBuf> = p
        .files
        .iter()
        .zip(&p.scenarios)
        .flat_map(|(f, scen)| scen.iter().map(move |s| map_beside(f, &s.map)))
        .collect();
    let mut all = p.files;
    all.extend(maps);
    Ok(all)
}

/// Reads the job's `.scen` files and picks its scenarios: all, a sample spread over every
/// bucket of each file, or the first of each; then this shard's slice of them.
fn pick(job: &BenchJob) -> Result<Picked, String> {
    let files = scen_files(&job.files)?;
    let mut items: Vec<(usize, usize)> = Vec::new();
    let mut scenarios = Vec::new();
    let mut total = 0;
    for (f, path) in files.iter().enumerate() {
        let name = path.display().to_string();
        let text =
            crate::read_regular_string(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
        let scen = movingai::read_scen(&text, &name).map_err(|e| e.to_string())?;
        let chosen: Vec<usize> = match (job.limit, job.sample) {
            (Some(n), _) => (0..n.min(scen.len())).collect(),
            (_, Some(n)) => sweep::sample_indices(scen.len(), n),
            _ => (0..scen.len()).collect(),
        };
        total += scen.len();
        items.extend(chosen.into_iter().map(|k| (f, k)));
        scenarios.push(scen);
    }
    let picked = items.len();
    let items: Vec<(usize, usize)> = items
        .into_iter()
        .enumerate()
        .filter(|(i, _)| job.shard.takes(*i))
        .map(|(_, x)| x)
        .collect();
    Ok(Picked {
        files,
        scenarios,
        items,
        total,
        picked,
    })
}

/// Every map the files name is read, and every scenario checked against its size, whatever
/// this shard plans: each shard of a sweep refuses the same input. Only the size is kept.
fn map_sizes(p: &Picked) -> Result<BTreeMap<PathBuf, MapSize>, String> {
    let mut sizes: BTreeMap<PathBuf, MapSize> = BTreeMap::new();
    for (f, scen) in p.scenarios.iter().enumerate() {
        let name = p.files[f].display().to_string();
        for s in scen {
            let map_path = map_beside(&p.files[f], &s.map);
            if !sizes.contains_key(&map_path) {
                let map = read_map_of(&name, s.line, &map_path)?;
                let size = MapSize {
                    name: map.name,
                    size: (map.width, map.height),
                };
                sizes.insert(map_path.clone(), size);
            }
            s.check_map_size(
                &name,
                sizes[&map_path].size,
                &map_path.display().to_string(),
            )
            .map_err(|e| e.to_string())?;
        }
    }
    Ok(sizes)
}

/// A map prepared for the sweep, or why it has no room for the robot (no point keeps its
/// radius: every scenario on it is that error's row, and the sweep goes on).
type Prepared = Result<PreparedMap, String>;

/// The maps this shard plans on, each read again and prepared (a read map is dropped once
/// prepared: the prepared map holds its own copy), and the time that took, ms.
fn prepare(
    p: &Picked,
    sizes: &BTreeMap<PathBuf, MapSize>,
    robot_radius: f64,
) -> Result<(BTreeMap<PathBuf, Prepared>, f64), String> {
    let mut maps: BTreeMap<PathBuf, Prepared> = BTreeMap::new();
    let mut prepare_ms = 0.0;
    for &(f, k) in &p.items {
        let s = &p.scenarios[f][k];
        let map_path = map_beside(&p.files[f], &s.map);
        if maps.contains_key(&map_path) {
            continue;
        }
        let map = read_map_of(&p.files[f].display().to_string(), s.line, &map_path)?;
        let was = sizes[&map_path].size;
        if (map.width, map.height) != was {
            return Err(format!(
                "{}: changed during the run: {} x {} when read again to be prepared, {} x {} when its scenarios were checked",
                map_path.display(),
                map.width,
                map.height,
                was.0,
                was.1
            ));
        }
        crate::memory::check_map(&map_path.display().to_string(), &map, robot_radius)
            .map_err(|e| e.to_string())?;
        let t = std::time::Instant::now();
        let prepared = match PreparedMap::for_robot(&map, robot_radius) {
            Ok(m) => Ok(m),
            // An answer about this map at this radius, not bad input.
            Err(e) if e.is_no_route() => Err(format!("{}: {e}", map_path.display())),
            Err(e) => return Err(e.to_string()),
        };
        prepare_ms += t.elapsed().as_secs_f64() * 1e3;
        maps.insert(map_path, prepared);
    }
    Ok((maps, prepare_ms))
}

/// Checks the job and plans its shard: one row per scenario, in order.
pub fn run_files(
    job: &BenchJob,
    mut progress: impl FnMut(usize, usize),
) -> Result<(Vec<Row>, BenchInfo), BenchError> {
    let cfg = job.validate()?;
    let p = pick(job).map_err(BenchError::Input)?;
    let sizes = map_sizes(&p).map_err(BenchError::Input)?;
    let (maps, prepare_ms) = prepare(&p, &sizes, job.robot_radius).map_err(BenchError::Input)?;
    let mut rows = Vec::with_capacity(p.items.len());
    for (done, &(f, k)) in p.items.iter().enumerate() {
        let s = &p.scenarios[f][k];
        let file = p.files[f].display().to_string();
        rows.push(match &maps[&map_beside(&p.files[f], &s.map)] {
            Ok(prepared) => sweep::run(prepared, &file, k, s, &cfg, job.time_limit),
            Err(why) => sweep::unplanned(&file, k, s, why),
        });
        progress(done + 1, p.items.len());
    }
    let info = BenchInfo {
        maps: sizes
            .values()
            .map(|m| format!("{} ({} x {})", m.name, m.size.0, m.size.1))
            .collect(),
        files: p.files,
        total: p.total,
        picked: p.picked,
        prepare_ms,
    };
    Ok((rows, info))
}

/// Rows as CSV text: the header, then one line per row.
pub fn csv_text(rows: &[Row]) -> String {
    let mut text = String::from(CSV_HEADER);
    text.push('\n');
    for r in rows {
        text.push_str(&r.to_csv());
        text.push('\n');
    }
    text
}

/// The rows of several CSV texts (shards of one sweep), sorted by file and scenario; a
/// scenario in two of them, or twice in one, is refused. `names` name the texts in errors.
pub fn rows_of_named(texts: &[(String, String)]) -> Result<Vec<Row>, String> {
    // Each row with the text and line it came from.
    let mut rows: Vec<(Row, usize, usize)> = Vec::new();
    for (t, (name, text)) in texts.iter().enumerate() {
        let mut lines = text.lines();
        match lines.next() {
            Some(h) if h.trim() == CSV_HEADER => {}
            _ => {
                return Err(format!(
                    "{name}:1: not a bench-scen CSV (expected the header {CSV_HEADER})"
                ));
            }
        }
        for (i, l) in lines.enumerate() {
            if l.trim().is_empty() {
                continue;
            }
            let row = Row::from_csv(l, name, i + 2).map_err(|e| e.to_string())?;
            rows.push((row, t, i + 2));
        }
    }
    rows.sort_by(|(a, ..), (b, ..)| a.file.cmp(&b.file).then(a.index.cmp(&b.index)));
    if let Some(w) = rows
        .windows(2)
        .find(|w| w[0].0.file == w[1].0.file && w[0].0.index == w[1].0.index)
    {
        let ((row, t0, l0), (_, t1, l1)) = (&w[0], &w[1]);
        // Sorting is stable: the first of the two comes first.
        let (first, again) = (&texts[*t0].0, &texts[*t1].0);
        return Err(if t0 == t1 {
            format!(
                "{again}:{l1}: scenario {} of {} is also at line {l0} of the same CSV",
                row.index, row.file
            )
        } else {
            let twice = if first == again {
                "; the same CSV given twice?"
            } else {
                ""
            };
            format!(
                "{again}:{l1}: scenario {} of {} is in more than one CSV (also {first}:{l0}{twice}): overlapping shards?",
                row.index, row.file
            )
        });
    }
    Ok(rows.into_iter().map(|(r, ..)| r).collect())
}

/// [`rows_of_named`] for unnamed texts (`csv 1`, `csv 2`, ...).
pub fn rows_of(texts: &[String]) -> Result<Vec<Row>, String> {
    let named: Vec<(String, String)> = texts
        .iter()
        .enumerate()
        .map(|(i, t)| (format!("csv {}", i + 1), t.clone()))
        .collect();
    rows_of_named(&named)
}
