//! Seeding the classes: the straight seed (`S`, the midpoint, `T`), or the Voronoi graph's k
//! best classes (avoided ones left out, optionally limited in overlap), each class path made
//! into a seed ([`class_seed`]); on a map each class is optimised as soon as the search has
//! it, while the search goes on.

use std::sync::Mutex;
use std::time::Instant;

use homospline_geom::{Point, Real};
use homospline_homotopy::{
    ClassPath, Rays, SearchConfig, SearchError, SearchResult, Signature, k_best_classes,
    k_best_classes_each, k_best_classes_each_on, k_best_classes_on,
};
use homospline_spline::ClearanceModel;
use homospline_voronoi::{BuildError, QueryGraph, VoronoiGraph};

use super::class::start_class;
use super::clearance::{clear_at_least, clearances_of};
use super::config::{DIVERSE_CANDIDATES, PlanConfig, PlanError, Seed};
use super::pool::in_pool;
use super::rank::{EdgeLengths, limited_overlap};
use super::report::{ClassPlan, Timing, ms};
use super::via::resample;
use super::world::World;

/// A seed: the polyline, its class (none for the straight seed), its graph cost.
pub(super) type SeedPath = (Vec<Point>, Option<Signature>, Real);

/// A plan's seeds, and what the seeding did on the way.
pub(super) struct Seeds {
    /// Seeds: (seed polyline, class signature, graph cost).
    pub seeds: Vec<SeedPath>,
    /// The graph (Voronoi seeds on a graph of its own; not a prepared map's query).
    pub graph: Option<VoronoiGraph>,
    /// The graph's cell (Voronoi seeds).
    pub cell: Option<Real>,
    /// The seeds are class paths still to be made into seeds ([`class_seed`]), on the
    /// graph's cell.
    pub raw: Option<Real>,
    /// Each seed's graph path by edge (for overlaps), in seed order.
    pub edges: Vec<EdgeLengths>,
    /// The classes optimised while the search ran (a map's: [`stream_classes`]), by seed
    /// index, and the time spent after the search ended, ms.
    pub streamed: Option<(Vec<(usize, ClassPlan)>, Real)>,
    /// The avoided classes ([`PlanConfig::avoid`]) that the search found, in their order.
    pub avoided: Vec<String>,
}

impl Seeds {
    /// Each seed's class as text, in seed order (empty for the straight seed).
    pub(super) fn signatures(&self) -> Vec<String> {
        self.seeds
            .iter()
            .map(|(_, s, _)| s.as_ref().map(|s| s.to_string()).unwrap_or_default())
            .collect()
    }
}

/// The graph a plan searches: a graph of its own (a scene's, or a saved one), or one query on
/// a prepared map's complete graph (no copy of it).
pub enum PlanGraph<'g> {
    /// A graph of its own, start and goal attached; the plan keeps it ([`Plan::graph`]).
    ///
    /// [`Plan::graph`]: super::Plan::graph
    Whole(VoronoiGraph),
    /// A query on a prepared map ([`homospline_voronoi::MapGraph::query`]).
    Query(QueryGraph<'g>),
}

impl PlanGraph<'_> {
    /// Cells per map unit.
    fn resolution(&self) -> Real {
        match self {
            PlanGraph::Whole(g) => g.resolution,
            PlanGraph::Query(q) => q.resolution(),
        }
    }

    /// Edge `e`'s length.
    fn edge_length(&self, e: usize) -> Real {
        match self {
            PlanGraph::Whole(g) => g.edges[e].length,
            PlanGraph::Query(q) => q.edge(e).length,
        }
    }

    /// The k best classes ([`k_best_classes`]).
    fn classes(&self, rays: &Rays, search: &SearchConfig) -> Result<SearchResult, SearchError> {
        match self {
            PlanGraph::Whole(g) => k_best_classes(g, rays, search),
            PlanGraph::Query(q) => k_best_classes_on(q, rays, search),
        }
    }

    /// The k best classes, each handed to `found` as soon as it is found.
    fn classes_each(
        &self,
        rays: &Rays,
        search: &SearchConfig,
        found: impl FnMut(&ClassPath),
    ) -> Result<SearchResult, SearchError> {
        match self {
            PlanGraph::Whole(g) => k_best_classes_each(g, rays, search, found),
            PlanGraph::Query(q) => k_best_classes_each_on(q, rays, search, found),
        }
    }
}

/// The seeds `cfg.seed` asks for; `graph` gives the Voronoi graph. The Voronoi stage's and
/// the class search's times go to `timing`.
pub(super) fn seed_classes<'g>(
    world: &World<'_>,
    graph: impl FnOnce() -> Result<PlanGraph<'g>, BuildError>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    timing: &mut Timing,
) -> Result<Seeds, PlanError> {
    match cfg.seed {
        Seed::Straight => {
            timing.voronoi = 0.0;
            let mid = Point::from((world.start.coords + world.goal.coords) * 0.5);
            Ok(Seeds {
                seeds: vec![(vec![world.start, mid, world.goal], None, 0.0)],
                graph: None,
                cell: None,
                raw: None,
                edges: Vec::new(),
                streamed: None,
                avoided: Vec::new(),
            })
        }
        Seed::Voronoi => {
            let tv = Instant::now();
            let graph = graph()?;
            timing.voronoi = ms(tv);
            voronoi_seeds(world, graph, cfg, pool, timing)
        }
    }
}

/// The Voronoi seed's classes of `graph`: searched, the avoided ones left out, selected
/// ([`select`]), and made into seeds; on a map, optimised as the search finds them.
fn voronoi_seeds(
    world: &World<'_>,
    graph: PlanGraph<'_>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    timing: &mut Timing,
) -> Result<Seeds, PlanError> {
    let tc = Instant::now();
    let cell = 1.0 / graph.resolution();
    let (search, min_clearance) = search_config(world, cfg, cell);
    let (result, streamed) = match cfg.diverse {
        // On a map, without the limited-overlap selection, the classes to optimise are the
        // first found: each is optimised as soon as the search has it, on another thread,
        // while the search goes on (a map's search takes a tenth of a plan). Each class is
        // independent of the others and of when it ran, so this changes no result. A scene's
        // search takes microseconds: there the classes are better run longest first (the
        // board's order).
        None if world.grid_is_exact => {
            let (r, streamed, end) = stream_classes(world, cfg, pool, &graph, &search, cell);
            timing.classes = end.duration_since(tc).as_secs_f64() * 1e3;
            (r, Some(streamed))
        }
        _ => (
            search_classes(&graph, &world.rays, &search, min_clearance, cfg),
            None,
        ),
    };
    let mut found = result?.classes;
    let avoided = cfg
        .avoid
        .iter()
        .filter(|a| found.iter().any(|c| !taken(&[a.to_string()], c)))
        .cloned()
        .collect();
    found.retain(|c| taken(&cfg.avoid, c));
    let (kept, edges) = select(&found, &graph, cfg);
    let (seeds, raw, streamed) = match streamed {
        Some((optimised, made, after_search)) => (made, None, Some((optimised, after_search))),
        None => {
            timing.classes = ms(tc);
            // A scene's seeds are the class paths as found: each is made (its ends
            // shortcut, centred: a tenth of a millisecond or two) in its class's first
            // job, while the other classes run ([`class_seed`]).
            let seeds = kept
                .iter()
                .map(|c| (c.polyline.clone(), Some(c.signature.clone()), c.cost))
                .collect();
            (seeds, Some(cell), None)
        }
    };
    Ok(Seeds {
        seeds,
        graph: match graph {
            PlanGraph::Whole(g) => Some(g),
            PlanGraph::Query(_) => None,
        },
        cell: Some(cell),
        raw,
        edges,
        streamed,
        avoided,
    })
}

/// The class search's settings on a graph of cell `cell`, and the least clearance it asks
/// of a class's path.
fn search_config(world: &World<'_>, cfg: &PlanConfig, cell: Real) -> (SearchConfig, Real) {
    // A passage narrower than one grid cell of a rasterised scene is below what the grid
    // can tell apart from a wall: it is not offered, unless there is no other way
    // ([`search_classes`]). On a map the cells are the truth, and a one-cell door is a door.
    let floor = if world.grid_is_exact { 0.0 } else { cell };
    let min_clearance = cfg.search.min_clearance.max(floor);
    // Avoided classes and the limited-overlap selection need more candidates.
    let extra = cfg.avoid.len();
    let k = match cfg.diverse {
        Some(_) => (cfg.classes + extra) * DIVERSE_CANDIDATES,
        None => cfg.classes + extra,
    };
    let search = SearchConfig {
        k,
        min_clearance,
        ..cfg.search.clone()
    };
    (search, min_clearance)
}

/// Whether the class is not one of `avoid` ([`PlanConfig::avoid`]), by its signature or its
/// short id.
fn taken(avoid: &[String], c: &ClassPath) -> bool {
    if avoid.is_empty() {
        // No text to compare with (a long map path's word is hundreds of thousands of
        // letters: writing it out took milliseconds on the search's thread).
        return true;
    }
    let signature = c.signature.to_string();
    let id = homospline_homotopy::class_id(&signature);
    !avoid.iter().any(|a| *a == signature || *a == id)
}

/// The classes of `graph` by `search`. When every way is narrower than a cell (a robot that
/// has driven into a tight spot), those ways are offered after all: the certification of
/// each curve decides whether it is clear.
fn search_classes(
    graph: &PlanGraph<'_>,
    rays: &Rays,
    search: &SearchConfig,
    min_clearance: Real,
    cfg: &PlanConfig,
) -> Result<SearchResult, SearchError> {
    graph.classes(rays, search).and_then(|r| {
        if r.classes.is_empty() && min_clearance > cfg.search.min_clearance {
            let below = SearchConfig {
                min_clearance: cfg.search.min_clearance,
                ..search.clone()
            };
            graph.classes(rays, &below)
        } else {
            Ok(r)
        }
    })
}

/// A map's classes searched and each optimised, on `pool`, as soon as the search has it
/// (the first `cfg.classes` not avoided): the search's result, the classes optimised (by
/// seed index), their seeds, and the time after the search ended, ms; with the instant
/// the search ended.
#[allow(clippy::type_complexity)]
fn stream_classes(
    world: &World<'_>,
    cfg: &PlanConfig,
    pool: Option<&rayon::ThreadPool>,
    graph: &PlanGraph<'_>,
    search: &SearchConfig,
    cell: Real,
) -> (
    Result<SearchResult, SearchError>,
    (Vec<(usize, ClassPlan)>, Vec<SeedPath>, Real),
    Instant,
) {
    let done = Mutex::new(Vec::new());
    let seeds = Mutex::new(Vec::new());
    // The search's result, how many classes it handed out, and when it ended. Each class's
    // seed is made in its own job (a map's class path is thousands of points, and checking
    // its class as its ends are shortcut took a tenth of the search's time on its thread).
    let (r, end) = in_pool(pool, || {
        rayon::scope(|s| {
            let mut handed = 0;
            let r = graph.classes_each(&world.rays, search, |c| {
                if handed >= cfg.classes || !taken(&cfg.avoid, c) {
                    return;
                }
                let (i, c, done, seeds) = (handed, c.clone(), &done, &seeds);
                handed += 1;
                s.spawn(move |_| {
                    let seed = made_seed(world, cell, &c);
                    seeds
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push((i, seed.clone()));
                    if cfg.interrupt.is_raised() {
                        return;
                    }
                    let (poly, sig, gcost) = &seed;
                    let mut task = start_class(world, cfg, poly, sig.as_ref(), *gcost, Some(cell));
                    let interrupted = || cfg.interrupt.is_raised();
                    while task.step_unless(world.model, &interrupted) == Some(true) {}
                    if cfg.interrupt.is_raised() {
                        return;
                    }
                    let (plan, _) = task.report(world, cfg);
                    done.lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push((i, plan));
                });
            });
            (r, Instant::now())
        })
    });
    let optimised = done.into_inner().unwrap_or_else(|e| e.into_inner());
    let mut made = seeds.into_inner().unwrap_or_else(|e| e.into_inner());
    made.sort_by_key(|m| m.0);
    let made = made.into_iter().map(|m| m.1).collect();
    (r, (optimised, made, ms(end)), end)
}

/// The seed of a class the search found: its class path made into a seed ([`class_seed`]).
fn made_seed(world: &World<'_>, cell: Real, c: &ClassPath) -> SeedPath {
    (
        class_seed(world, cell, &c.polyline, &c.signature),
        Some(c.signature.clone()),
        c.cost,
    )
}

/// The classes of `found` to optimise, in order, and each one's graph path by edge: with
/// [`PlanConfig::diverse`], the limited-overlap selection ([`limited_overlap`]); else the
/// first `cfg.classes`.
fn select<'f>(
    found: &'f [ClassPath],
    graph: &PlanGraph<'_>,
    cfg: &PlanConfig,
) -> (Vec<&'f ClassPath>, Vec<EdgeLengths>) {
    let edge_lengths: Vec<EdgeLengths> = found
        .iter()
        .map(|c| {
            c.edges
                .iter()
                .map(|&(e, _)| (e, graph.edge_length(e)))
                .collect()
        })
        .collect();
    let keep = match cfg.diverse {
        Some(limit) => {
            let lengths: Vec<Real> = found.iter().map(|c| c.length).collect();
            limited_overlap(&edge_lengths, &lengths, limit, cfg.classes)
        }
        None => (0..found.len().min(cfg.classes)).collect(),
    };
    let kept: Vec<&ClassPath> = found
        .iter()
        .enumerate()
        .filter(|(i, _)| keep.contains(i))
        .map(|(_, c)| c)
        .collect();
    let edges = (0..found.len())
        .filter(|i| keep.contains(i))
        .map(|i| edge_lengths[i].clone())
        .collect();
    (kept, edges)
}

/// A class path made into a seed: its ends at the start and the goal (the class path runs
/// from the start node to the goal node, which sit there), shortcut where the attach route
/// meets the ridge behind them ([`shortcut_ends`]), and on a scene centred ([`centre`]:
/// a rasterised scene's class path runs along cell sides; a map's already runs along the
/// ridge through free cells, and is pulled taut in its class's own task), each change kept
/// only if the class stays.
pub(super) fn class_seed(
    world: &World<'_>,
    cell: Real,
    polyline: &[Point],
    signature: &Signature,
) -> Vec<Point> {
    let rays = &world.rays;
    let mut poly = polyline.to_vec();
    poly[0] = world.start;
    let last = poly.len() - 1;
    poly[last] = world.goal;
    let poly = shortcut_ends(&poly, world.model, cell, rays);
    if world.grid_is_exact {
        return poly;
    }
    let centred = centre(&poly, world.model, cell);
    if rays.signature(&centred) == *signature {
        centred
    } else {
        poly
    }
}

/// Start and goal join the graph along their maximum-clearance route, which may meet the
/// ridge behind them: the class path then runs away from its start and turns back (or passes
/// its goal and curls into it), and the curve through it does too. This replaces each end's
/// stretch, up to `4 clearance + 8 cells` of arc length from the start (goal), by the
/// straight segment to the farthest point of it that the segment reaches with at least the
/// stretch's least vertex clearance less half a cell (and at least half of it: a start next
/// to a wall keeps its margin), as long as the class stays the same.
fn shortcut_ends(
    poly: &[Point],
    model: &dyn ClearanceModel,
    cell: Real,
    rays: &Rays,
) -> Vec<Point> {
    // The indices `k > 1` (within the window) of the points `poly[k]` that `poly[0]` joins.
    let reachable = |poly: &[Point]| -> Vec<usize> {
        let mut stretch = model.clearance_value(&poly[0]);
        let window = 4.0 * stretch.max(cell) + 8.0 * cell;
        let mut arc = 0.0;
        let mut out = Vec::new();
        for k in 1..poly.len() - 1 {
            arc += (poly[k] - poly[k - 1]).norm();
            if arc > window {
                break;
            }
            stretch = stretch.min(model.clearance_value(&poly[k]));
            let target = (stretch - 0.5 * cell).max(0.5 * stretch);
            if k > 1 && clear_at_least(model, poly[0], poly[k], target, cell) {
                out.push(k);
            }
        }
        out
    };
    if poly.len() < 3 {
        return poly.to_vec();
    }
    let mut out = poly.to_vec();
    for _ in 0..2 {
        // The farthest point whose shortcut keeps the class (a few tries; each costs the
        // stretch's word, not the whole path's: a map's class path has thousands of points).
        // The second pass works on the reversed path.
        for &k in reachable(&out).iter().rev().take(SHORTCUT_TRIES) {
            if rays.chord_keeps_class(&out[..=k]) {
                let mut cut = vec![out[0]];
                cut.extend_from_slice(&out[k..]);
                out = cut;
                break;
            }
        }
        out.reverse();
    }
    out
}

/// Shortcuts tried at each end of a seed, farthest first.
const SHORTCUT_TRIES: usize = 32;

/// The graph's edges run along cell sides, so in a passage one cell wide a class path can lie
/// on an obstacle's boundary. This resamples the path every half cell and moves each inner
/// point up the clearance gradient, a quarter cell at a time, until it is two cells clear or
/// stops gaining: the seed runs down the middle of passages.
fn centre(poly: &[Point], model: &dyn ClearanceModel, cell: Real) -> Vec<Point> {
    let len = super::polyline_length(poly);
    let n = ((len / (0.5 * cell)).ceil() as usize).clamp(2, 20_000);
    let mut pts = resample(poly, n - 1);
    if pts.len() < 3 {
        // No inner point (a path of one point, start and goal at one node).
        return pts;
    }
    let last = pts.len() - 1;
    // Most points are already two cells clear: their clearances come in one batch.
    let clear = clearances_of(model, &pts);
    for (p, &c) in pts[1..last].iter_mut().zip(&clear[1..last]) {
        if c >= 2.0 * cell {
            continue;
        }
        for _ in 0..8 {
            let (d, g) = model.clearance(p);
            if d >= 2.0 * cell || g.norm() < 1e-9 {
                break;
            }
            let q = *p + g.normalize() * (0.25 * cell);
            if model.clearance_value(&q) <= d {
                break;
            }
            *p = q;
        }
    }
    pts
}
