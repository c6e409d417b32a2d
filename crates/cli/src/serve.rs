//! `homospline serve`: a local web page to plan on. It opens a scene, a map or a world of
//! the folder it serves, plans where the user clicks the start and the goal, re-plans round
//! the passages the user blocks, and plays missions. Every answer comes from the same code
//! as the command line's (`plan::outcome`, `simulate::run`, with arguments parsed by the
//! same parser), so the page shows the command line's plans and its error messages.

use std::net::SocketAddr;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use anyhow::Context;
use axum::extract::{Json, State};
use axum::http::{StatusCode, header};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use clap::Parser;
use homospline_maps::input::Input;
use serde::{Deserialize, Serialize};
use serde_json::json;
use serde_json::value::RawValue;

use crate::args::{PlanArgs, SimulateArgs};
use crate::input::Reads;
use crate::out::bad;
use crate::{Cli, Command, picture};

/// The largest request the server reads, bytes.
const MAX_REQUEST_BYTES: usize = 64 << 20;

/// The page: plain HTML, CSS and JavaScript, no build step.
const PAGE: &str = include_str!("serve/page.html");

/// The folder served, and where uploads go.
struct Served {
    /// The served folder, canonical.
    root: PathBuf,
    /// Uploaded files (`uploads/NAME` on the page), a folder of the system's temporary
    /// directory removed when the server stops.
    uploads: PathBuf,
}

/// `serve DIR`: binds to `bind:port` and serves until interrupted.
pub fn serve(
    dir: &Path,
    bind: &str,
    port: u16,
    memory_limit_mb: Option<u64>,
) -> anyhow::Result<u8> {
    let root = dir
        .canonicalize()
        .map_err(|e| bad(format!("{}: cannot serve: {e}", dir.display())))?;
    if !root.is_dir() {
        return Err(bad(format!(
            "{}: cannot serve: not a folder",
            dir.display()
        )));
    }
    if let Some(mb) = memory_limit_mb {
        set_memory_limit(mb)?;
    }
    let uploads = std::env::temp_dir().join(format!("homospline-serve-{}", std::process::id()));
    std::fs::create_dir_all(&uploads)
        .with_context(|| format!("{}: cannot make the uploads folder", uploads.display()))?;
    // Ctrl-C, SIGTERM and SIGHUP end the process (`out::remove_temporaries_on_signals`):
    // the uploads go with it.
    crate::out::remove_dir_on_signals(&uploads);
    let served = Arc::new(Served {
        root,
        uploads: uploads.clone(),
    });
    let addr: SocketAddr = format!("{bind}:{port}")
        .parse()
        .map_err(|_| bad(format!("--bind {bind}: not an IP address")))?;
    let app = axum::Router::new()
        .route("/", get(|| async { Html(PAGE) }))
        .route("/api/files", get(files))
        .route("/api/open", post(open))
        .route("/api/plan", post(plan))
        .route("/api/simulate", post(simulate))
        .route("/api/upload", post(upload))
        .route("/favicon.ico", get(no_icon))
        // Uploads and requests up to 64 MB (axum's default is 2 MB): a scene of a million
        // circles is about 40 MB of YAML.
        .layer(axum::extract::DefaultBodyLimit::max(MAX_REQUEST_BYTES))
        .with_state(served.clone());
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_io()
        .build()
        .context("starting the server's runtime")?;
    let result = runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .map_err(|e| anyhow::anyhow!("{addr}: cannot listen: {e}"))?;
        let local = listener.local_addr()?;
        say!(
            "serving {} on http://{local}/ (Ctrl-C stops)",
            served.root.display()
        );
        axum::serve(listener, app)
            .with_graceful_shutdown(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .map_err(anyhow::Error::from)
    });
    let _ = std::fs::remove_dir_all(&uploads);
    result.map(|()| 0)
}

/// Sets the process's soft address-space limit (`ulimit -v`), so that a request for a map
/// too large for it is refused with the command line's message, not by the allocator.
fn set_memory_limit(mb: u64) -> anyhow::Result<()> {
    #[cfg(unix)]
    {
        let bytes = mb.saturating_mul(1 << 20);
        let (_, hard) = rlimit::getrlimit(rlimit::Resource::AS).context("reading ulimit -v")?;
        rlimit::setrlimit(rlimit::Resource::AS, bytes.min(hard), hard)
            .context("setting the memory limit")?;
    }
    #[cfg(not(unix))]
    let _ = mb;
    Ok(())
}

impl Served {
    /// The file `path` names: relative to the served folder (or `uploads/NAME`), inside it
    /// once links are followed.
    fn resolve(&self, path: &str) -> anyhow::Result<PathBuf> {
        let outside = || {
            bad(format!(
                "{path}: outside the folder this server serves ({})",
                self.root.display()
            ))
        };
        let rel = Path::new(path);
        if path.is_empty()
            || path.contains('\0')
            || rel
                .components()
                .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir))
        {
            return Err(outside());
        }
        let (base, rel) = match rel.strip_prefix("uploads") {
            Ok(r) => (&self.uploads, r),
            Err(_) => (&self.root, rel),
        };
        let full = base
            .join(rel)
            .canonicalize()
            .map_err(|e| bad(format!("{path}: cannot read: {e}")))?;
        if !full.starts_with(base) {
            return Err(outside());
        }
        Ok(full)
    }

    /// `text` with the served folder's path left out, as the page names files.
    fn relative(&self, text: &str) -> String {
        let root = format!("{}/", self.root.display());
        let uploads = format!("{}/", self.uploads.display());
        text.replace(&uploads, "uploads/").replace(&root, "")
    }

    /// The scenes, maps and worlds under the served folder (and the uploads), by path.
    fn files(&self) -> Vec<String> {
        let mut out = Vec::new();
        walk(&self.root, &self.root, 0, &mut out);
        let mut up = Vec::new();
        walk(&self.uploads, &self.uploads, 0, &mut up);
        out.extend(up.into_iter().map(|p| format!("uploads/{p}")));
        out
    }
}

/// Input files under `dir` (at most 6 folders deep, hidden ones left out), sorted.
fn walk(root: &Path, dir: &Path, depth: usize, out: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = entries.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        let hidden = p
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with('.'));
        if hidden {
            continue;
        }
        if p.is_dir() && depth < 6 {
            walk(root, &p, depth + 1, out);
        } else if p
            .extension()
            .is_some_and(|e| matches!(e.to_str(), Some("yaml" | "yml" | "json" | "map")))
            && let Ok(rel) = p.strip_prefix(root)
        {
            out.push(rel.display().to_string());
        }
    }
}

/// Whether the file at `path` is a world (a `team` in its first megabyte).
fn is_world(path: &Path) -> bool {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path).is_ok_and(|f| {
        f.take(1 << 20).read_to_end(&mut head).is_ok()
            && String::from_utf8_lossy(&head)
                .lines()
                .any(|l| l.starts_with("team:") || l.trim_start().starts_with("\"team\""))
    })
}

/// An answer: the JSON text, or the error's message (as the command line prints it) with
/// 400. Answers are JSON text, not values: the plan JSON goes out as the command line
/// writes it, its numbers never parsed and printed again (a parse may move a number by an
/// ulp).
fn answer(result: anyhow::Result<String>, served: &Served) -> Response {
    match result {
        Ok(text) => ([(header::CONTENT_TYPE, "application/json")], text).into_response(),
        Err(e) => (
            StatusCode::BAD_REQUEST,
            Json(json!({ "error": served.relative(&format!("{e:#}")) })),
        )
            .into_response(),
    }
}

/// Runs `work` off the server's threads; a panic is an error, and the server goes on.
async fn blocking(
    served: Arc<Served>,
    work: impl FnOnce(&Served) -> anyhow::Result<String> + Send + 'static,
) -> Response {
    let s = served.clone();
    let result = tokio::task::spawn_blocking(move || work(&s))
        .await
        .unwrap_or_else(|e| Err(anyhow::anyhow!("the request failed: {e}")));
    answer(result, &served)
}

async fn files(State(served): State<Arc<Served>>) -> Response {
    let files = served.files();
    Json(json!({ "files": files })).into_response()
}

/// What the page asks to open or plan.
#[derive(Deserialize)]
struct PlanRequest {
    path: String,
    #[serde(default)]
    start: Option<[f64; 2]>,
    #[serde(default)]
    goal: Option<[f64; 2]>,
    #[serde(default)]
    robot_radius: Option<f64>,
    #[serde(default)]
    classes: Option<usize>,
    /// Discs `[x, y, r]` the user blocked.
    #[serde(default)]
    blocks: Vec<[f64; 3]>,
}

/// The arguments of `plan` for a request, parsed by the command line's parser.
fn plan_args(file: &Path, r: &PlanRequest) -> anyhow::Result<PlanArgs> {
    let mut argv = vec!["homospline".to_owned(), "plan".to_owned()];
    argv.push(file.display().to_string());
    let point = |p: [f64; 2]| format!("{},{}", p[0], p[1]);
    if let Some(s) = r.start {
        argv.extend(["--start".to_owned(), point(s)]);
    }
    if let Some(g) = r.goal {
        argv.extend(["--goal".to_owned(), point(g)]);
    }
    if let Some(rr) = r.robot_radius {
        argv.extend(["--robot-radius".to_owned(), rr.to_string()]);
    }
    if let Some(k) = r.classes {
        argv.extend(["--classes".to_owned(), k.to_string()]);
    }
    for b in &r.blocks {
        argv.extend(["--block".to_owned(), format!("{},{},{}", b[0], b[1], b[2])]);
    }
    match parse(&argv)? {
        Command::Plan(a) => Ok(*a),
        _ => Err(bad("not a plan")),
    }
}

/// The command `argv` asks for, parsed as the command line parses it; a refusal is clap's
/// message.
fn parse(argv: &[String]) -> anyhow::Result<Command> {
    Cli::try_parse_from(argv)
        .map(|cli| cli.command)
        .map_err(|e| bad(e.render().to_string().trim().to_owned()))
}

async fn open(State(served): State<Arc<Served>>, Json(r): Json<PlanRequest>) -> Response {
    blocking(served, move |s| {
        let file = s.resolve(&r.path)?;
        if is_world(&file) {
            return Ok(json!({ "kind": "world", "path": r.path }).to_string());
        }
        let a = plan_args(&file, &r)?;
        // Read once: a map is shown before its start and goal are clicked, a scene planned.
        match crate::input::load_input(&file, &Reads::default())? {
            Input::Map(map) => {
                crate::plan::check_map_memory(&map, 0.0)?;
                let bg = picture::Background::Map(&map);
                Ok(json!({
                    "kind": "map",
                    "path": r.path,
                    "svg": picture::background_svg(&bg, None),
                    "transform": picture::transform(&bg),
                    "size": [map.width, map.height],
                })
                .to_string())
            }
            scene @ Input::Scene(_) => planned(s, &a, crate::plan::edit_input(&a, scene)?, &r.path),
        }
    })
    .await
}

async fn plan(State(served): State<Arc<Served>>, Json(r): Json<PlanRequest>) -> Response {
    blocking(served, move |s| {
        let file = s.resolve(&r.path)?;
        let a = plan_args(&file, &r)?;
        let edited = crate::plan::edited_input(&a, &Reads::default())?;
        planned(s, &a, edited, &r.path)
    })
    .await
}

/// The plan of `plan` with arguments `a` on the edited input: the picture, the click transform, the
/// table and the plan JSON (`docs/formats.md`), as the command line makes them.
fn planned(
    s: &Served,
    a: &PlanArgs,
    (input, ends): (
        Input,
        Option<(homospline_geom::Point, homospline_geom::Point)>,
    ),
    path: &str,
) -> anyhow::Result<String> {
    let done = crate::plan::outcome(a, input, ends, true)?;
    let (kind, transform, start, goal) = match &done.input {
        Input::Scene(sc) => (
            "scene",
            picture::transform(&picture::Background::Scene(sc, 0.0)),
            sc.start,
            sc.goal,
        ),
        Input::Map(m) => (
            "map",
            picture::transform(&picture::Background::Map(m)),
            done.result.start,
            done.result.goal,
        ),
    };
    let plan = RawValue::from_string(homospline_front::report::plan_json_with(&done.result, &[]))?;
    Ok(serde_json::to_string(&Planned {
        kind,
        path,
        svg: done.picture.unwrap_or_default(),
        transform,
        table: s.relative(&homospline_front::report::plan_table(
            &done.result,
            a.class_names,
        )),
        plan: &plan,
        start: [start.x, start.y],
        goal: [goal.x, goal.y],
    })?)
}

/// The answer to a plan.
#[derive(Serialize)]
struct Planned<'a> {
    kind: &'a str,
    path: &'a str,
    svg: String,
    transform: [f64; 4],
    table: String,
    /// The plan JSON of `plan --json`, as written.
    plan: &'a RawValue,
    start: [f64; 2],
    goal: [f64; 2],
}

/// A mission the page asks for.
#[derive(Deserialize)]
struct SimulateRequest {
    path: String,
    #[serde(default)]
    policy: Option<String>,
    #[serde(default)]
    scouts: Option<usize>,
}

async fn simulate(State(served): State<Arc<Served>>, Json(r): Json<SimulateRequest>) -> Response {
    blocking(served, move |s| {
        let file = s.resolve(&r.path)?;
        let mut argv = vec![
            "homospline".to_owned(),
            "simulate".to_owned(),
            file.display().to_string(),
        ];
        if let Some(p) = &r.policy {
            argv.extend(["--policy".to_owned(), p.clone()]);
        }
        if let Some(k) = r.scouts {
            argv.extend(["--scouts".to_owned(), k.to_string()]);
        }
        let a: SimulateArgs = match parse(&argv)? {
            Command::Simulate(a) => a,
            _ => return Err(bad("not a mission")),
        };
        let world = homospline_mission::world::load_any(&file, |p| Reads::default().read(p))
            .map_err(bad)?;
        let done = crate::simulate::run(&a, &world, (true, false))?;
        let mission = RawValue::from_string(done.json)?;
        Ok(serde_json::to_string(&Simulated {
            kind: "world",
            path: &r.path,
            svg: done.svg.unwrap_or_default(),
            text: s.relative(&done.text),
            time: done.result.time,
            animation_seconds: crate::mission_svg::ANIMATION_SECONDS,
            mission: &mission,
        })?)
    })
    .await
}

/// The answer to a mission.
#[derive(Serialize)]
struct Simulated<'a> {
    kind: &'a str,
    path: &'a str,
    svg: String,
    text: String,
    time: f64,
    animation_seconds: f64,
    /// The mission JSON of `simulate --json`, as written.
    mission: &'a RawValue,
}

/// A file the user uploads: its name and text.
#[derive(Deserialize)]
struct UploadRequest {
    name: String,
    content: String,
}

/// Keeps an uploaded scene, map or world if it reads as the command line reads it; else
/// the command line's message, and nothing kept.
async fn upload(State(served): State<Arc<Served>>, Json(r): Json<UploadRequest>) -> Response {
    blocking(served, move |s| {
        let name = Path::new(&r.name)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .filter(|n| !n.starts_with('.') && !n.is_empty())
            .ok_or_else(|| bad(format!("{}: not a file name", r.name)))?;
        let file = s.uploads.join(&name);
        std::fs::write(&file, r.content.as_bytes())
            .with_context(|| format!("{name}: cannot keep the upload"))?;
        let checked = if is_world(&file) {
            homospline_mission::world::load_any(&file, |p| Reads::default().read(p))
                .map(|_| ())
                .map_err(bad)
        } else {
            crate::input::load_input(&file, &Reads::default()).map(|_| ())
        };
        if let Err(e) = checked {
            let _ = std::fs::remove_file(&file);
            return Err(e);
        }
        Ok(json!({ "path": format!("uploads/{name}") }).to_string())
    })
    .await
}

/// The page's favicon request gets nothing (no 404 noise in the browser's console).
async fn no_icon() -> impl IntoResponse {
    (
        StatusCode::NO_CONTENT,
        [(header::CACHE_CONTROL, "max-age=86400")],
    )
}
