//! The Python package `homospline` (PyO3): scenes, plans, occupancy maps as NumPy arrays,
//! Voronoi graphs and missions. Errors are Python exceptions carrying the command line's
//! messages (file, line, field); planning releases the GIL.

use std::path::PathBuf;

use homospline_front::{Opt, OptionError, OrOff, PlanOptions, Spelling};
use homospline_front::{mission, report};
use homospline_geom::math::Num;
use homospline_geom::{Point, Scene};
use homospline_maps::OccupancyMap;
use homospline_mission::{AnyWorld, MissionConfig, Policy};
use homospline_optim::{ClassPlan, Plan, PlanConfig};
use homospline_voronoi::VoronoiGraph;
use numpy::{PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

fn bad(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}

/// Runs `work` (a plan holding `interrupt`) on its own thread with the GIL released, and
/// looks for Python signals every [`SIGNAL_POLL`]: on Ctrl-C (or any handler that raises)
/// the plan is interrupted, the thread joined (it ends after its running growth rounds) and
/// the handler's exception, `KeyboardInterrupt`, raised. Else `work`'s result.
fn interruptible<T: Send>(
    py: Python<'_>,
    interrupt: &homospline_optim::Interrupt,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    std::thread::scope(|scope| {
        let (tx, mut rx) = std::sync::mpsc::channel();
        let worker = scope.spawn(move || {
            let _ = tx.send(work());
        });
        loop {
            // The receiver goes into the GIL-free closure and back (it is not `Sync`).
            let (got, back) = py.detach(move || (rx.recv_timeout(SIGNAL_POLL), rx));
            rx = back;
            match got {
                Ok(result) => {
                    let _ = worker.join();
                    return Ok(result);
                }
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                    if let Err(e) = py.check_signals() {
                        interrupt.raise();
                        let _ = py.detach(|| worker.join());
                        return Err(e);
                    }
                }
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                    // The worker ended without a result: it panicked; pass the panic on.
                    return match worker.join() {
                        Err(panic) => std::panic::resume_unwind(panic),
                        Ok(()) => Err(PyValueError::new_err("the plan ended without a result")),
                    };
                }
            }
        }
    })
}

/// `time_limit=` (milliseconds) as a duration for [`Interrupt::raise_after`]; `None` when
/// left out or too large for one. A `ValueError` unless a positive number.
///
/// [`Interrupt::raise_after`]: homospline_optim::Interrupt::raise_after
fn deadline_of(ms: Option<f64>) -> PyResult<Option<std::time::Duration>> {
    match ms {
        None => Ok(None),
        Some(ms) if ms.is_finite() && ms > 0.0 => {
            Ok(std::time::Duration::try_from_secs_f64(ms / 1e3).ok())
        }
        Some(ms) => Err(bad(format!(
            "time_limit={}: must be a positive number of ms",
            Num(ms)
        ))),
    }
}

/// The `TimeoutError` of a plan on `name` stopped by `time_limit=` (as `plan --time-limit`
/// exits 4).
fn timed_out(name: &str, ms: Option<f64>) -> PyErr {
    pyo3::exceptions::PyTimeoutError::new_err(format!(
        "{name}: no plan within time_limit={} ms (the plan stopped there; a larger limit, \
         fewer classes or fewer rounds let it finish)",
        Num(ms.unwrap_or(f64::NAN))
    ))
}

/// How often [`interruptible`] looks for Python signals.
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// A count given by keyword: `None` (or Python's `None`) when left out, else an int from 0
/// up. Another int is a `ValueError` naming the keyword (it was an `OverflowError` that
/// named nothing), anything else a `TypeError`.
fn count(keyword: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if v.is_instance_of::<pyo3::types::PyBool>() || !v.is_instance_of::<pyo3::types::PyInt>() {
        return Err(PyTypeError::new_err(format!(
            "{keyword}: expected an int, got {}",
            v.get_type().name()?
        )));
    }
    v.extract::<usize>().map(Some).map_err(|_| {
        bad(format!(
            "{keyword}={}: must be a whole number >= 0",
            v.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))
    })
}

/// `MemoryError` when a grid of `cells` cells may need more memory than the process may use.
fn check_memory(what: impl FnOnce() -> String, cells: u64) -> PyResult<()> {
    homospline_front::memory::check(what, cells).map_err(|e| PyMemoryError::new_err(e.to_string()))
}

fn read(path: &std::path::Path) -> PyResult<Vec<u8>> {
    std::fs::read(path)
        .map_err(|e| PyOSError::new_err(format!("{}: cannot read: {e}", path.display())))
}

fn json_loads<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

fn points<'py>(py: Python<'py>, pts: &[Point]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows: Vec<Vec<f64>> = pts.iter().map(|p| vec![p.x, p.y]).collect();
    if rows.is_empty() {
        return Ok(PyArray2::zeros(py, [0, 2], false));
    }
    PyArray2::from_vec2(py, &rows).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// A scene: bounds, start, goal and obstacles made of circles (`docs/formats.md`).
#[pyclass(name = "Scene", module = "homospline", frozen)]
struct PyScene {
    inner: Scene,
}

#[pymethods]
impl PyScene {
    /// Reads a scene file (YAML or JSON).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let bytes = read(&path)?;
        Scene::from_bytes(&bytes, &path.display().to_string())
            .map(|inner| Self { inner })
            .map_err(|e| bad(e.to_string()))
    }

    /// A scene from a dict with the fields of a scene file.
    #[staticmethod]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyAny>) -> PyResult<Self> {
        if !d.is_instance_of::<PyDict>() {
            return Err(PyTypeError::new_err(format!(
                "<dict>: expected a dict with the fields of a scene file, got {}",
                d.get_type().name()?
            )));
        }
        let text: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
        Scene::from_str(&text, "<dict>")
            .map(|inner| Self { inner })
            .map_err(|e| bad(e.to_string()))
    }

    /// The built-in example (the paper's Fig. 5: two cups with a narrow pass).
    #[staticmethod]
    fn example() -> PyResult<Self> {
        Scene::from_str(
            homospline_front::EXAMPLE_SCENE,
            "narrow-pass.yaml (built-in example)",
        )
        .map(|inner| Self { inner })
        .map_err(|e| bad(e.to_string()))
    }

    /// Name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// Start `(x, y)`.
    #[getter]
    fn start(&self) -> (f64, f64) {
        (self.inner.start.x, self.inner.start.y)
    }

    /// Goal `(x, y)`.
    #[getter]
    fn goal(&self) -> (f64, f64) {
        (self.inner.goal.x, self.inner.goal.y)
    }

    /// The scene as a dict (the scene file's fields).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_loads(py, &self.inner.to_json())
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, {} obstacles, start ({}, {}), goal ({}, {}))",
            self.inner.name,
            self.inner.obstacles.len(),
            self.inner.start.x,
            self.inner.start.y,
            self.inner.goal.x,
            self.inner.goal.y
        )
    }
}

/// A Voronoi graph, built once (offline) and reused by `plan(scene, graph=...)`.
#[pyclass(name = "Graph", module = "homospline", frozen)]
struct PyGraph {
    inner: VoronoiGraph,
}

#[pymethods]
impl PyGraph {
    /// Reads a graph saved by `save` or `homospline graph --out`.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        let bytes = read(&path)?;
        VoronoiGraph::from_msgpack(&bytes)
            .map(|inner| Self { inner })
            .map_err(|e| bad(format!("{}: {e}", path.display())))
    }

    /// Saves the graph (MessagePack, versioned).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        std::fs::write(&path, self.inner.to_msgpack()).map_err(|e| {
            PyOSError::new_err(format!("{}: cannot write the graph: {e}", path.display()))
        })
    }

    /// Nodes.
    #[getter]
    fn nodes(&self) -> usize {
        self.inner.nodes.len()
    }

    /// Edges.
    #[getter]
    fn edges(&self) -> usize {
        self.inner.edges.len()
    }

    /// The graph as the JSON of `docs/formats.md`, as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_loads(py, &self.inner.to_json())
    }
}

/// The Voronoi graph of a scene, start and goal attached.
#[pyfunction]
#[pyo3(signature = (scene, resolution=None))]
fn build_graph(py: Python<'_>, scene: &PyScene, resolution: Option<f64>) -> PyResult<PyGraph> {
    let res = resolution.unwrap_or_else(|| homospline_optim::default_resolution(&scene.inner));
    if !(res.is_finite() && res > 0.0) {
        return Err(bad(format!("resolution={res}: must be positive")));
    }
    let s = &scene.inner;
    check_memory(
        || format!("scene {} at resolution={res}", s.name),
        homospline_front::memory::scene_cells(s, res),
    )?;
    py.detach(|| homospline_voronoi::build(s, res))
        .map(|(_, _, inner)| PyGraph { inner })
        .map_err(|e| bad(format!("{}: {e}", s.name)))
}

/// One optimised homotopy class.
#[pyclass(name = "ClassPlan", module = "homospline", frozen)]
struct PyClassPlan {
    inner: ClassPlan,
}

#[pymethods]
impl PyClassPlan {
    /// 1 = best.
    #[getter]
    fn rank(&self) -> usize {
        self.inner.rank
    }
    /// Homotopy signature.
    #[getter]
    fn signature(&self) -> String {
        self.inner.signature.clone()
    }
    /// The curve, sampled: an `(n, 2)` float64 array.
    #[getter]
    fn path<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points(py, &self.inner.path)
    }
    /// Start, optimised via-points, goal: `(k, 2)` float64.
    #[getter]
    fn via_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points(py, &self.inner.via_points)
    }
    /// Length.
    #[getter]
    fn length(&self) -> f64 {
        self.inner.length
    }
    /// Minimum clearance of the sampled path.
    #[getter]
    fn min_clearance(&self) -> f64 {
        self.inner.min_clearance
    }
    /// Certified lower bound of the curve's clearance.
    #[getter]
    fn certified_clearance(&self) -> f64 {
        self.inner.certified_clearance
    }
    /// Collision-free.
    #[getter]
    fn collision_free(&self) -> bool {
        self.inner.collision_free
    }
    /// Certified clearance at least `dm`.
    #[getter]
    fn safe(&self) -> bool {
        self.inner.safe
    }
    /// Total cost.
    #[getter]
    fn cost(&self) -> f64 {
        self.inner.cost.total
    }
    fn __repr__(&self) -> String {
        format!(
            "ClassPlan(rank {}, {:?}, length {:.2}, clearance {:.3}, collision_free {})",
            self.inner.rank,
            self.inner.signature,
            self.inner.length,
            self.inner.min_clearance,
            if self.inner.collision_free {
                "True"
            } else {
                "False"
            }
        )
    }
}

/// A plan: every class, ranked, and the chosen one.
#[pyclass(name = "Plan", module = "homospline", frozen)]
struct PyPlan {
    inner: Plan,
}

#[pymethods]
impl PyPlan {
    /// Rank of the chosen class, or `None` when no class is collision-free.
    #[getter]
    fn best(&self) -> Option<usize> {
        self.inner.best
    }
    /// The classes in rank order.
    #[getter]
    fn classes(&self) -> Vec<PyClassPlan> {
        self.inner
            .classes
            .iter()
            .map(|c| PyClassPlan { inner: c.clone() })
            .collect()
    }
    /// The chosen class, or `None`.
    #[getter]
    fn chosen(&self) -> Option<PyClassPlan> {
        self.inner.best.map(|b| PyClassPlan {
            inner: self.inner.classes[b - 1].clone(),
        })
    }
    /// The chosen path as an `(n, 2)` float64 array, or `None`.
    #[getter]
    fn path<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.inner
            .best
            .map(|b| points(py, &self.inner.classes[b - 1].path))
            .transpose()
    }
    /// The plan result of `docs/formats.md` (what `homospline plan --json` writes), as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_loads(py, &report::plan_json(&self.inner))
    }
    fn __repr__(&self) -> String {
        format!(
            "Plan({:?}, {} classes, best {}, {:.1} ms)",
            self.inner.scene,
            self.inner.classes.len(),
            self.inner.best.map_or("None".to_owned(), |b| b.to_string()),
            self.inner.timing.total
        )
    }
}

/// Weights as `(name, value)` pairs from a dict.
fn weights_of(weights: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, f64)>> {
    let mut out = Vec::new();
    if let Some(d) = weights {
        for (k, v) in d.iter() {
            let name: String = k.extract()?;
            let value: f64 = v
                .extract()
                .map_err(|_| bad(format!("weights[{name:?}]: not a number")))?;
            out.push((name, value));
        }
    }
    Ok(out)
}

/// An option error as Python spells it: `classes=0: must be between 1 and 64`.
fn bad_option(e: OptionError) -> PyErr {
    bad(e.spelled(Spelling::Keyword))
}

/// A keyword argument given as text, read as its type (`seed="voronoi"`); `None` when absent.
fn named<T: std::str::FromStr>(opt: Opt, text: Option<&str>) -> PyResult<Option<T>>
where
    T::Err: std::fmt::Display,
{
    text.map(|t| {
        t.parse()
            .map_err(|e: T::Err| bad_option(OptionError::new(opt, format!("'{t}'"), e.to_string())))
    })
    .transpose()
}

/// `"off"` or a number (an `OrOff`), as the command line's `--prune` and `--finish-within`;
/// anything else is a `TypeError` that names the keyword.
fn off_or<'py, T: std::str::FromStr + FromPyObjectOwned<'py>>(
    opt: Opt,
    value: Option<&Bound<'py, PyAny>>,
    expected: &str,
) -> PyResult<Option<OrOff<T>>> {
    let Some(v) = value else {
        return Ok(None);
    };
    if let Ok(text) = v.extract::<String>() {
        return text.parse::<OrOff<T>>().map(Some).map_err(|_| {
            bad_option(OptionError::new(
                opt,
                format!("'{text}'"),
                format!("expected {expected}"),
            ))
        });
    }
    let keyword = opt.keyword().replace('-', "_");
    v.extract::<T>().map(|x| Some(OrOff::On(x))).map_err(|_| {
        if v.is_instance_of::<pyo3::types::PyInt>() && !v.is_instance_of::<pyo3::types::PyBool>() {
            // A number of the wrong range (-1): the value is wrong, not its type.
            bad(format!("{keyword}={v}: expected {expected}"))
        } else {
            PyTypeError::new_err(format!("{keyword}: expected {expected}"))
        }
    })
}

/// Plans a scene: the k best homotopy classes, each optimised and checked (the `plan`
/// command). `weights` maps names (`safety`, `dm`, ...) to values.
#[pyfunction]
#[pyo3(signature = (scene, classes=None, preset="paper-voronoi", weights=None, optimizer=None, seed="voronoi", roughness=None, clearance_floor=0.0, graph=None, soft_dm=false, prune=None, clearance_search=None, polish=None, finish_within=None, time_limit=None))]
#[allow(clippy::too_many_arguments)]
fn plan(
    py: Python<'_>,
    scene: &PyScene,
    classes: Option<&Bound<'_, PyAny>>,
    preset: &str,
    weights: Option<&Bound<'_, PyDict>>,
    optimizer: Option<String>,
    seed: &str,
    roughness: Option<String>,
    clearance_floor: f64,
    graph: Option<&PyGraph>,
    soft_dm: bool,
    prune: Option<&Bound<'_, PyAny>>,
    clearance_search: Option<String>,
    polish: Option<&Bound<'_, PyAny>>,
    finish_within: Option<&Bound<'_, PyAny>>,
    time_limit: Option<f64>,
) -> PyResult<PyPlan> {
    let limit = deadline_of(time_limit)?;
    let classes = count("classes", classes)?;
    let polish = count("polish", polish)?.unwrap_or(0);
    let options = PlanOptions {
        seed: named(Opt::Seed, Some(seed))?.unwrap_or_default(),
        classes,
        preset: named(Opt::Preset, Some(preset))?.unwrap_or_default(),
        weights: weights_of(weights)?,
        optimizer: named(Opt::Optimizer, optimizer.as_deref())?,
        roughness: named(Opt::Roughness, roughness.as_deref())?,
        clearance_floor,
        soft_dm,
        prune: off_or(Opt::Prune, prune, "\"off\" or a ratio of at least 1")?,
        clearance_search: named(Opt::ClearanceSearch, clearance_search.as_deref())?,
        polish,
        finish_within: off_or(
            Opt::FinishWithin,
            finish_within,
            "\"off\" or a number of evaluations",
        )?,
        graph: graph.is_some(),
        ..PlanOptions::default()
    };
    let cfg = options.validate(Some(&scene.inner)).map_err(bad_option)?;
    let s = &scene.inner;
    let saved = graph.map(|g| g.inner.clone());
    if saved.is_none() && cfg.seed == homospline_optim::Seed::Voronoi {
        let res = cfg
            .resolution
            .unwrap_or_else(|| homospline_optim::default_resolution(s));
        check_memory(
            || format!("scene {} at resolution={res}", s.name),
            homospline_front::memory::scene_cells(s, res),
        )?;
    }
    let _deadline = limit.map(|d| cfg.interrupt.raise_after(d));
    interruptible(py, &cfg.interrupt, || {
        homospline_optim::plan_with_graph(s, saved, &cfg)
    })?
    .map(|inner| PyPlan { inner })
    .map_err(|e| {
        let msg = format!("{}: {e}", s.name);
        if matches!(e, homospline_optim::PlanError::Interrupted) {
            timed_out(&s.name, time_limit)
        } else if e.is_no_route() {
            // Start and goal walled apart: an answer, as on maps.
            NoRoute::new_err(msg)
        } else {
            bad(msg)
        }
    })
}

/// The occupancy of a NumPy array, checked: 2-D, bool, not empty.
fn occupancy_of(a: &Bound<'_, PyAny>) -> PyResult<(usize, usize, Vec<bool>)> {
    let Ok(dtype) = a.getattr("dtype") else {
        return Err(PyTypeError::new_err(format!(
            "occupancy: expected a NumPy array of bool (True = occupied), got {}",
            a.get_type().name()?
        )));
    };
    let ndim: usize = a.getattr("ndim")?.extract()?;
    if ndim != 2 {
        return Err(bad(format!(
            "occupancy: expected a 2-D array (rows, columns), got {ndim} dimension(s)"
        )));
    }
    let kind: String = dtype.getattr("name")?.extract()?;
    if kind != "bool" {
        return Err(PyTypeError::new_err(format!(
            "occupancy: expected dtype bool (True = occupied), got {kind}; convert with `grid > threshold` or `.astype(bool)`"
        )));
    }
    let arr: PyReadonlyArray2<'_, bool> = a.extract()?;
    let [rows, cols] = [arr.shape()[0], arr.shape()[1]];
    if rows == 0 || cols == 0 {
        return Err(bad(format!(
            "occupancy: the array is empty ({rows} x {cols})"
        )));
    }
    let view = arr.as_array();
    let cells: Vec<bool> = view.iter().copied().collect();
    Ok((rows, cols, cells))
}

/// Plans on an occupancy grid given as a 2-D NumPy bool array (`True` = occupied), the shape a
/// ROS OccupancyGrid or an image gives: row `j`, column `i` is the cell
/// `[origin + i * resolution, origin + (i + 1) * resolution]` in x and likewise in y, with
/// y up from `origin` (ROS) or, with `y_down=True`, rows down the page (images, MovingAI).
#[pyfunction]
#[pyo3(signature = (occupancy, start, goal, resolution=1.0, origin=(0.0, 0.0), y_down=false, classes=None, robot_radius=0.0, time_limit=None))]
#[allow(clippy::too_many_arguments)]
fn plan_map(
    py: Python<'_>,
    occupancy: &Bound<'_, PyAny>,
    start: (f64, f64),
    goal: (f64, f64),
    resolution: f64,
    origin: (f64, f64),
    y_down: bool,
    classes: Option<&Bound<'_, PyAny>>,
    robot_radius: f64,
    time_limit: Option<f64>,
) -> PyResult<PyPlan> {
    let limit = deadline_of(time_limit)?;
    let classes = count("classes", classes)?.unwrap_or(PlanConfig::maps().classes);
    let (rows, cols, cells) = occupancy_of(occupancy)?;
    // The checks a ROS map's YAML gets, named by keyword.
    homospline_maps::check_geometry(resolution, [origin.0, origin.1], cols, rows).map_err(
        |(field, problem)| match field {
            "origin" => bad(format!(
                "origin=({}, {}): {problem}",
                Num(origin.0),
                Num(origin.1)
            )),
            _ => bad(format!("resolution={}: {problem}", Num(resolution))),
        },
    )?;
    let map = OccupancyMap {
        name: "array".into(),
        width: cols,
        height: rows,
        cell: resolution,
        origin: Point::new(origin.0, origin.1),
        occupied: cells,
        y_down,
    };
    let cfg = PlanOptions {
        classes: Some(classes),
        ..PlanOptions::default()
    }
    .validate(None)
    .map_err(bad_option)?;
    let (s, g) = (Point::new(start.0, start.1), Point::new(goal.0, goal.1));
    if !homospline_geom::is_robot_radius(robot_radius) {
        return Err(bad(format!(
            "robot_radius={robot_radius}: {} (map units)",
            homospline_geom::ROBOT_RADIUS_RULE
        )));
    }
    check_memory(
        || format!("occupancy ({rows} x {cols} cells)"),
        homospline_front::memory::map_cells(&map, robot_radius),
    )?;
    let _deadline = limit.map(|d| cfg.interrupt.raise_after(d));
    interruptible(py, &cfg.interrupt, || {
        homospline_maps::plan_map_for_robot(&map, robot_radius, s, g, &cfg)
    })?
    .map(|(inner, _)| PyPlan { inner })
    .map_err(|e| {
        if matches!(
            e,
            homospline_maps::MapError::Plan(homospline_optim::PlanError::Interrupted)
        ) {
            timed_out("array", time_limit)
        } else if e.is_no_route() {
            // An answer, not bad input: its own exception (a `ValueError` still).
            NoRoute::new_err(e.to_string())
        } else {
            bad(e.to_string())
        }
    })
}

pyo3::create_exception!(
    homospline,
    NoRoute,
    PyValueError,
    "No route joins start and goal for the robot at its radius (`plan` exits 1): on a map \
     the message names the widest route's least clearance and where it is; in a scene, the \
     obstacles that wall start and goal apart."
);

/// Runs the mission of a world file, on a scene or an occupancy map (`homospline simulate`),
/// and returns its JSON as a dict.
#[pyfunction]
#[pyo3(signature = (world, policy=None, scouts=None))]
fn simulate<'py>(
    py: Python<'py>,
    world: PathBuf,
    policy: Option<&str>,
    scouts: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let scouts = count("scouts", scouts)?;
    let w = homospline_mission::world::load_any(&world, |p| std::fs::read(p)).map_err(bad)?;
    let policy = match policy {
        None => Policy::default(),
        Some(policy) => Policy::named(policy).ok_or_else(|| {
            bad(format!(
                "policy='{policy}': expected one of {}",
                Policy::names()
            ))
        })?,
    };
    let cfg = MissionConfig {
        policy,
        scouts,
        ..match &w {
            AnyWorld::Scene(_) => MissionConfig::default(),
            AnyWorld::Map(_) => MissionConfig::for_maps(),
        }
    };
    cfg.check().map_err(|e| bad_option(e.into()))?;
    let text = py
        .detach(|| match &w {
            AnyWorld::Scene(w) => {
                homospline_mission::simulate(w, &cfg).map(|r| mission::mission_json(w, &r))
            }
            AnyWorld::Map(w) => {
                homospline_mission::simulate_map(w, &cfg).map(|r| mission::map_mission_json(w, &r))
            }
        })
        .map_err(|e| bad(e.to_string()))?;
    json_loads(py, &text)
}

/// Plans MovingAI scenarios (`homospline bench-scen`): every `.scen` file (or directory of
/// them) in `files`, `sample` scenarios of each spread over every bucket (or the first
/// `limit`, or all), and only slice `shard = (k, n)` of them. Returns the CSV text of
/// `docs/formats.md`; `bench_summary` merges the CSVs of several shards.
#[pyfunction]
#[pyo3(signature = (files, sample=None, limit=None, shard=None, classes=None, time_limit=None, robot_radius=0.0))]
#[allow(clippy::too_many_arguments)]
fn bench_scen(
    py: Python<'_>,
    files: Vec<PathBuf>,
    sample: Option<&Bound<'_, PyAny>>,
    limit: Option<&Bound<'_, PyAny>>,
    shard: Option<(Bound<'_, PyAny>, Bound<'_, PyAny>)>,
    classes: Option<&Bound<'_, PyAny>>,
    time_limit: Option<f64>,
    robot_radius: f64,
) -> PyResult<String> {
    let sample = count("sample", sample)?;
    let limit = count("limit", limit)?;
    let classes = count("classes", classes)?.unwrap_or(PlanConfig::maps().classes);
    let shard = match &shard {
        Some((k, n)) => (
            count("shard[0]", Some(k))?.unwrap_or(1),
            count("shard[1]", Some(n))?.unwrap_or(1),
        ),
        None => (1, 1),
    };
    let shard = homospline_maps::sweep::Shard::parse(&format!("{}/{}", shard.0, shard.1))
        .map_err(|e| bad(format!("shard {e}")))?;
    let job = homospline_front::bench::BenchJob {
        files,
        sample,
        limit,
        shard,
        classes,
        time_limit,
        weights: Vec::new(),
        robot_radius,
    };
    let (rows, _) = py
        .detach(|| homospline_front::bench::run_files(&job, |_, _| {}))
        .map_err(|e| match e {
            homospline_front::bench::BenchError::Option(e) => bad_option(e),
            input => bad(input.to_string()),
        })?;
    Ok(homospline_front::bench::csv_text(&rows))
}

/// The summary of the rows of one or more `bench_scen` CSVs (shards of one sweep), as
/// `homospline bench-merge` prints it.
#[pyfunction]
fn bench_summary(csvs: Vec<String>) -> PyResult<String> {
    let rows = homospline_front::bench::rows_of(&csvs).map_err(bad)?;
    Ok(homospline_maps::sweep::summary(&rows))
}

/// The Python module.
#[pymodule]
fn homospline(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyScene>()?;
    m.add_class::<PyGraph>()?;
    m.add_class::<PyPlan>()?;
    m.add_class::<PyClassPlan>()?;
    m.add_function(wrap_pyfunction!(plan, m)?)?;
    m.add_function(wrap_pyfunction!(plan_map, m)?)?;
    m.add_function(wrap_pyfunction!(build_graph, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(bench_scen, m)?)?;
    m.add_function(wrap_pyfunction!(bench_summary, m)?)?;
    m.add("NoRoute", m.py().get_type::<NoRoute>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
