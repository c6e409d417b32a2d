//! The k cheapest simple start-goal paths of a Voronoi graph in pairwise distinct homotopy
//! classes, with blocked edges and regions, and which classes use an edge.
//!
//! Best-first search over partial simple paths, ordered by cost so far plus the exact
//! distance to the goal ignoring simplicity (an admissible, consistent bound): complete paths
//! leave the queue in order of cost, so the first path of each signature to reach the goal is
//! the cheapest simple path of that class, and the first `k` signatures are the `k` best
//! classes. Exact; checked against brute-force enumeration of all simple paths. A budget on
//! expansions bounds pathological graphs, and the result says whether it was reached.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};

use homospline_geom::{Point, Real};
use homospline_voronoi::{Adjacency, Edge, QueryGraph, VoronoiGraph};
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};
use thiserror::Error;

use crate::signature::{Rays, Signature};

/// The cost of an edge in the search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EdgeCost {
    /// Its length.
    Length,
    /// `length * (1 + weight / max(mean clearance, 1e-6))`: prefers wide passages.
    ClearancePenalty {
        /// How much narrowness costs.
        weight: Real,
    },
}

/// What to search for.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchConfig {
    /// How many classes (the paper uses 5 to 7).
    pub k: usize,
    /// Edge cost.
    pub cost: EdgeCost,
    /// Edges whose minimum clearance is below this are not used (start and goal connectors
    /// excepted: the robot is where it is).
    pub min_clearance: Real,
    /// Edges not to use (what a scout found blocked).
    pub blocked_edges: Vec<usize>,
    /// Discs `(centre, radius)` no edge may enter.
    pub blocked_regions: Vec<(Point, Real)>,
    /// Budget of partial paths taken from the queue.
    pub max_expansions: usize,
    /// Expand only the first (cheapest) partial path to reach a node with a given word. The
    /// exact search enumerates every simple path, which explodes on a map's graph with
    /// thousands of cycles (seconds for the second class); with this, each (node, word) state
    /// is expanded once, so the work grows with the classes found times the graph. It can
    /// miss a class whose cheapest simple path needs a prefix that the first one to reach a
    /// state blocks (by simplicity); the maps' default.
    pub one_path_per_state: bool,
}

impl Default for SearchConfig {
    fn default() -> Self {
        Self {
            k: 5,
            cost: EdgeCost::Length,
            min_clearance: 0.0,
            blocked_edges: Vec::new(),
            blocked_regions: Vec::new(),
            max_expansions: 1_000_000,
            one_path_per_state: false,
        }
    }
}

/// Why a search could not run.
#[derive(Debug, Error, PartialEq)]
pub enum SearchError {
    /// The graph has no start or goal attached.
    #[error("the graph has no {0} attached")]
    NotAttached(&'static str),
    /// A parameter is out of range.
    #[error("{0}")]
    Config(String),
}

/// One class: its cheapest simple path.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassPath {
    /// Node sequence from start to goal.
    pub nodes: Vec<usize>,
    /// Edges used, with `true` when walked from `from` to `to`.
    pub edges: Vec<(usize, bool)>,
    /// Search cost.
    pub cost: Real,
    /// Length in map units.
    pub length: Real,
    /// Smallest edge clearance on it.
    pub min_clearance: Real,
    /// The path as a polyline.
    pub polyline: Vec<Point>,
    /// Its homotopy class.
    pub signature: Signature,
}

/// What a search found.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchResult {
    /// The classes, cheapest first.
    pub classes: Vec<ClassPath>,
    /// `true` when every class that exists is listed or `k` were found; `false` when the
    /// expansion budget ran out first.
    pub complete: bool,
    /// Partial paths expanded.
    pub expansions: usize,
}

#[derive(Clone, Copy)]
struct Entry {
    /// The order key of `f`: `f` in units of a quantum (see the search).
    key: i64,
    g: Real,
    order: usize,
    id: usize,
}

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    // A max-heap: smaller f first; among equal f the deeper partial path (larger g), so
    // that lattices of equally short paths (warehouses, offices) are walked depth first
    // rather than breadth first; then earlier insertion.
    fn cmp(&self, o: &Self) -> Ordering {
        o.key
            .cmp(&self.key)
            .then(self.g.total_cmp(&o.g))
            .then(o.order.cmp(&self.order))
    }
}

struct Partial {
    parent: usize,
    /// Edges from the start.
    depth: usize,
    node: usize,
    edge: (usize, bool),
    g: Real,
    /// Its reduced word, as an id of [`Words`].
    word: WordId,
}

/// An interned reduced word ([`Words`]).
type WordId = usize;

/// The reduced words of the search's partial paths, interned as the nodes of a trie: a word
/// is its last letter below the word before it, and equal words have equal ids. A partial
/// path holds one id, and the states `(node, word)` compare in constant time. (Each partial
/// path had held its word whole: on a map of 4096 x 4096 cells the words of long paths run to
/// thousands of letters, and copying them at every step filled the memory.)
struct Words {
    /// `(parent, letter)` of each word; word 0 is the empty word.
    nodes: Vec<(WordId, i32)>,
    /// The word `parent` followed by `letter`, for each `(parent, letter)` made so far.
    children: FxHashMap<(WordId, i32), WordId>,
}

impl Words {
    /// The empty word, alone.
    fn new() -> Self {
        Self {
            nodes: vec![(EMPTY_WORD, 0)],
            children: FxHashMap::default(),
        }
    }

    /// Word `w` followed by `letter`, reduced: a letter that undoes `w`'s last one cancels it.
    fn push(&mut self, w: WordId, letter: i32) -> WordId {
        let (parent, last) = self.nodes[w];
        if w != EMPTY_WORD && last == -letter {
            return parent;
        }
        let next = self.nodes.len();
        let nodes = &mut self.nodes;
        *self.children.entry((w, letter)).or_insert_with(|| {
            nodes.push((w, letter));
            next
        })
    }

    /// Word `w` followed by `edge`'s word, walked forward or backward (its inverse).
    fn concat(&mut self, mut w: WordId, edge: &Signature, forward: bool) -> WordId {
        if forward {
            for &l in &edge.0 {
                w = self.push(w, l);
            }
        } else {
            for &l in edge.0.iter().rev() {
                w = self.push(w, -l);
            }
        }
        w
    }

    /// Word `w` written out.
    fn signature(&self, mut w: WordId) -> Signature {
        let mut letters = Vec::new();
        while w != EMPTY_WORD {
            let (parent, letter) = self.nodes[w];
            letters.push(letter);
            w = parent;
        }
        letters.reverse();
        Signature(letters)
    }
}

/// The id of the empty word in [`Words`].
const EMPTY_WORD: WordId = 0;

/// What the search walks: a graph's nodes and edges, the links it may take and their costs.
trait Walk {
    /// How many nodes.
    fn node_count(&self) -> usize;
    /// Edge `e`.
    fn edge(&self, e: usize) -> &Edge;
    /// Edge `e`'s cost.
    fn cost(&self, e: usize) -> Real;
    /// Hands node `k`'s allowed links to `f`, `(other end, edge, walked from -> to)`, in
    /// edge order.
    fn for_each_link(&self, k: usize, f: impl FnMut(usize, usize, bool));
}

/// A graph of its own, with the adjacency of its allowed edges and their costs.
struct Whole<'a> {
    graph: &'a VoronoiGraph,
    adjacency: Adjacency,
    cost: Vec<Real>,
}

impl Walk for Whole<'_> {
    fn node_count(&self) -> usize {
        self.graph.nodes.len()
    }
    fn edge(&self, e: usize) -> &Edge {
        &self.graph.edges[e]
    }
    fn cost(&self, e: usize) -> Real {
        self.cost[e]
    }
    fn for_each_link(&self, k: usize, mut f: impl FnMut(usize, usize, bool)) {
        for (m, e, fwd) in self.adjacency.of(k) {
            f(m, e, fwd);
        }
    }
}

/// A query on a prepared map ([`QueryGraph`]), with each edge's cost: infinite where the
/// edge is not the query's or the search's settings close it. Worked out for an edge when
/// the search first walks it, or for every edge at once, in one parallel pass in order, when
/// the query spans a good part of the map ([`EAGER_REACH`]): then the search's Dijkstra
/// walks nearly every edge, and reading each one where it lies (scattered over the whole
/// graph) took longer than the pass.
struct Query<'a> {
    graph: &'a QueryGraph<'a>,
    cost: Costs,
    cfg: &'a SearchConfig,
    blocked: FxHashSet<usize>,
}

/// A query's edge costs ([`Query`]).
enum Costs {
    /// Every edge's, worked out at once.
    All(Vec<Real>),
    /// Per edge, its cost's bits with [`KNOWN`] set once worked out (0: not yet).
    AsWalked(Vec<AtomicU64>),
}

/// In [`Costs::AsWalked`]: the bit that marks a cost worked out (a cost is never negative,
/// so its own sign bit is clear).
const KNOWN: u64 = 1 << 63;

/// Queries whose straight distance is at least this share of the map's diagonal have
/// their edges' costs worked out all at once (`Query`).
pub const EAGER_REACH: Real = 0.25;

impl Query<'_> {
    /// Edge `e`'s cost, worked out from the edge.
    fn work_out(&self, e: usize) -> Real {
        let (graph, cfg) = (self.graph, self.cfg);
        if !graph.in_query(e) {
            return Real::INFINITY;
        }
        let edge = graph.edge(e);
        match allowed(e, edge, cfg, &self.blocked, (graph.start(), graph.goal())) {
            true => edge_cost(edge, cfg.cost),
            false => Real::INFINITY,
        }
    }
}

impl Walk for Query<'_> {
    fn node_count(&self) -> usize {
        self.graph.node_count()
    }
    fn edge(&self, e: usize) -> &Edge {
        self.graph.edge(e)
    }
    #[inline]
    fn cost(&self, e: usize) -> Real {
        let known = match &self.cost {
            Costs::All(all) => return all[e],
            Costs::AsWalked(known) => &known[e],
        };
        let bits = known.load(AtomicOrdering::Relaxed);
        if bits != 0 {
            return Real::from_bits(bits & !KNOWN);
        }
        let c = self.work_out(e);
        known.store(c.to_bits() | KNOWN, AtomicOrdering::Relaxed);
        c
    }
    #[inline]
    fn for_each_link(&self, k: usize, mut f: impl FnMut(usize, usize, bool)) {
        self.graph.for_each_link(k, |m, e, fwd| {
            if self.cost(e) < Real::INFINITY {
                f(m, e, fwd);
            }
        });
    }
}

fn edge_polyline<W: Walk + ?Sized>(g: &W, e: usize, forward: bool) -> Vec<Point> {
    let mut pts: Vec<Point> = g
        .edge(e)
        .polyline
        .iter()
        .map(|p| Point::new(p[0], p[1]))
        .collect();
    if !forward {
        pts.reverse();
    }
    pts
}

/// The k best classes of `graph` (start and goal attached) relative to `rays`: the cheapest
/// path of each of the `cfg.k` cheapest homotopy classes, by a best-first search over
/// (node, signature) states; classes are told apart by their h-signatures on `rays`.
///
/// # Examples
///
/// Between two discs on the line from start to goal, three ways: above both, below both,
/// and between them (which crosses the line twice):
///
/// ```
/// use homospline_geom::Scene;
/// use homospline_homotopy::{Rays, SearchConfig, k_best_classes};
///
/// let scene = Scene::from_str(
///     "name: two\nbounds: {min: [0, 0], max: [40, 20]}\nstart: [2, 10]\ngoal: [38, 10]\n\
///      obstacles:\n  - name: a\n    circles: [[14, 10, 3]]\n  - name: b\n    circles: [[26, 10, 3]]\n",
///     "two.yaml",
/// )?;
/// let (_, _, graph) = homospline_voronoi::build(&scene, 4.0)?;
/// let rays = Rays::for_scene(&scene);
/// let cfg = SearchConfig { k: 3, ..SearchConfig::default() };
/// let found = k_best_classes(&graph, &rays, &cfg)?;
/// assert_eq!(found.classes.len(), 3);
/// assert!(found.classes[0].cost <= found.classes[1].cost);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn k_best_classes(
    graph: &VoronoiGraph,
    rays: &Rays,
    cfg: &SearchConfig,
) -> Result<SearchResult, SearchError> {
    k_best_classes_each(graph, rays, cfg, |_| {})
}

/// [`k_best_classes`], handing each class to `found` as soon as the search has it (best
/// first), so that a caller can start on it while the search goes on.
pub fn k_best_classes_each(
    graph: &VoronoiGraph,
    rays: &Rays,
    cfg: &SearchConfig,
    found: impl FnMut(&ClassPath),
) -> Result<SearchResult, SearchError> {
    let start = graph.start.ok_or(SearchError::NotAttached("start"))?;
    let goal = graph.goal.ok_or(SearchError::NotAttached("goal"))?;
    check_config(cfg)?;
    let allowed = allowed_edges(graph.edges.iter(), cfg, start, goal);
    let walk = Whole {
        graph,
        adjacency: graph.adjacency(|i| allowed[i]),
        cost: graph.edges.iter().map(|e| edge_cost(e, cfg.cost)).collect(),
    };
    Ok(search_walk(
        &walk,
        rays,
        cfg,
        (start, goal),
        found,
        false,
        true,
    ))
}

/// [`k_best_classes`] on one query of a prepared map ([`QueryGraph`]): the same classes as
/// on the graph [`homospline_voronoi::MapGraph::with_endpoints`] builds, without a copy of
/// the map's graph.
pub fn k_best_classes_on(
    graph: &QueryGraph<'_>,
    rays: &Rays,
    cfg: &SearchConfig,
) -> Result<SearchResult, SearchError> {
    k_best_classes_each_on(graph, rays, cfg, |_| {})
}

/// [`k_best_classes_on`], handing each class to `found` as soon as the search has it.
pub fn k_best_classes_each_on(
    graph: &QueryGraph<'_>,
    rays: &Rays,
    cfg: &SearchConfig,
    found: impl FnMut(&ClassPath),
) -> Result<SearchResult, SearchError> {
    check_config(cfg)?;
    let (start, goal) = (graph.start(), graph.goal());
    let eager = graph.reach() >= EAGER_REACH;
    let mut walk = Query {
        graph,
        cost: Costs::AsWalked(Vec::new()),
        cfg,
        blocked: cfg.blocked_edges.iter().copied().collect(),
    };
    walk.cost = match eager {
        true => Costs::All(
            (0..graph.edge_count())
                .into_par_iter()
                .with_min_len(1 << 14)
                .map(|e| walk.work_out(e))
                .collect(),
        ),
        false => Costs::AsWalked((0..graph.edge_count()).map(|_| AtomicU64::new(0)).collect()),
    };
    Ok(search_walk(
        &walk,
        rays,
        cfg,
        (start, goal),
        found,
        true,
        eager,
    ))
}

/// The search on `walk` from `start` to `goal`; `prefetch`: the words of the edges at the
/// shortest path's nodes are computed first, in parallel ([`shortest_path_words`]);
/// `settle_all`: every distance to the goal at once, else as the search asks
/// ([`Distances`]).
fn search_walk<W: Walk + Sync>(
    walk: &W,
    rays: &Rays,
    cfg: &SearchConfig,
    (start, goal): (usize, usize),
    found: impl FnMut(&ClassPath),
    prefetch: bool,
    settle_all: bool,
) -> SearchResult {
    let mut h = Distances::new(walk, goal);
    if settle_all {
        h.settle_all(walk);
    }
    let words = match prefetch {
        true => shortest_path_words(walk, rays, &mut h, start, goal),
        false => FxHashMap::default(),
    };
    let mut frontier = Frontier::new(walk, rays, h, start);
    frontier.words = words;
    frontier.search(cfg, goal, found)
}

/// Refuses a negative or non-finite minimum clearance or clearance penalty weight.
fn check_config(cfg: &SearchConfig) -> Result<(), SearchError> {
    if !(cfg.min_clearance.is_finite() && cfg.min_clearance >= 0.0) {
        return Err(SearchError::Config(format!(
            "min_clearance must be finite and >= 0, got {}",
            cfg.min_clearance
        )));
    }
    if let EdgeCost::ClearancePenalty { weight } = cfg.cost
        && !(weight.is_finite() && weight >= 0.0)
    {
        return Err(SearchError::Config(format!(
            "clearance penalty weight must be finite and >= 0, got {weight}"
        )));
    }
    Ok(())
}

/// Whether the search may use each edge: not blocked, wide enough (start and goal
/// connectors excepted) and entering no blocked region.
fn allowed_edges<'e>(
    edges: impl Iterator<Item = &'e Edge>,
    cfg: &SearchConfig,
    start: usize,
    goal: usize,
) -> Vec<bool> {
    let blocked: FxHashSet<usize> = cfg.blocked_edges.iter().copied().collect();
    edges
        .enumerate()
        .map(|(i, e)| allowed(i, e, cfg, &blocked, (start, goal)))
        .collect()
}

/// Whether the search may use edge `i`, `e`: not in `blocked`, wide enough (start and goal
/// connectors excepted) and entering no blocked region.
fn allowed(
    i: usize,
    e: &Edge,
    cfg: &SearchConfig,
    blocked: &FxHashSet<usize>,
    (start, goal): (usize, usize),
) -> bool {
    let connector = [e.from, e.to].iter().any(|&x| x == start || x == goal);
    !blocked.contains(&i)
        && (connector || e.min_clearance >= cfg.min_clearance)
        && !enters_blocked_region(e, &cfg.blocked_regions)
}

/// Whether edge `e` enters one of the discs `regions`; the polyline's box is tested first (a
/// map mission closes a disc round every blocked cell, against tens of thousands of edges).
fn enters_blocked_region(e: &Edge, regions: &[(Point, Real)]) -> bool {
    if regions.is_empty() {
        return false;
    }
    let (mut lo, mut hi) = ([Real::INFINITY; 2], [Real::NEG_INFINITY; 2]);
    for q in e.polyline.iter() {
        lo = [lo[0].min(q[0]), lo[1].min(q[1])];
        hi = [hi[0].max(q[0]), hi[1].max(q[1])];
    }
    regions.iter().any(|(c, r)| {
        let outside = c.x + r < lo[0] || c.x - r > hi[0] || c.y + r < lo[1] || c.y - r > hi[1];
        !outside
            && e.polyline.windows(2).any(|s| {
                homospline_geom::math::distance_point_segment(
                    c,
                    &Point::new(s[0][0], s[0][1]),
                    &Point::new(s[1][0], s[1][1]),
                ) <= *r
            })
    })
}

/// An edge's cost in the search ([`EdgeCost`]).
fn edge_cost(e: &Edge, cost: EdgeCost) -> Real {
    match cost {
        EdgeCost::Length => e.length,
        EdgeCost::ClearancePenalty { weight } => {
            e.length * (1.0 + weight / e.mean_clearance.max(1e-6))
        }
    }
}

/// The exact distance from each node of a walk to the goal along its links: Dijkstra
/// backwards from the goal (the graph is undirected), run only as far as asked. A node's
/// distance is settled when [`Distances::get`] first asks for it, by going on until it is
/// taken from the queue; so the work grows with the distance of the farthest node the search
/// looks at, not with the map (a short query on a large map settles a small disc round the
/// goal). Infinite where the goal is out of reach.
struct Distances {
    h: Vec<Real>,
    /// Every node settled ([`Distances::settle_all`]).
    complete: bool,
    settled: Vec<bool>,
    /// A radix heap over the distances' bits (non-negative floats order as their bits, and
    /// Dijkstra's keys never fall below the last taken): about half the time of a binary
    /// heap over a map's millions of nodes. The order in which equal keys leave does not
    /// change any distance.
    heap: radix_heap::RadixHeapMap<Reverse<u64>, usize>,
}

impl Distances {
    /// Nothing settled yet but the goal's queue entry.
    fn new<W: Walk>(walk: &W, goal: usize) -> Self {
        let n = walk.node_count();
        let mut d = Self {
            h: vec![Real::INFINITY; n],
            complete: false,
            settled: vec![false; n],
            heap: radix_heap::RadixHeapMap::new(),
        };
        d.h[goal] = 0.0;
        d.heap.push(Reverse(0u64), goal);
        d
    }

    /// Settles every node at once (a query across much of the map: its search asks for
    /// nearly all of them, and one loop without the bookkeeping of [`Distances::get`] is
    /// faster).
    fn settle_all<W: Walk>(&mut self, walk: &W) {
        while let Some((Reverse(bits), id)) = self.heap.pop() {
            let f = Real::from_bits(bits);
            if f <= self.h[id] {
                self.relax(walk, id, f);
            }
        }
        self.complete = true;
    }

    /// Relaxes the links of node `id`, settled at distance `f`.
    #[inline]
    fn relax<W: Walk>(&mut self, walk: &W, id: usize, f: Real) {
        let (h, heap) = (&mut self.h, &mut self.heap);
        walk.for_each_link(id, |m, e, _| {
            let d = f + walk.cost(e);
            if d < h[m] {
                h[m] = d;
                heap.push(Reverse(d.to_bits()), m);
            }
        });
    }

    /// Node `k`'s exact distance to the goal, settling nodes in order until it is.
    #[inline]
    fn get<W: Walk>(&mut self, walk: &W, k: usize) -> Real {
        if self.complete {
            return self.h[k];
        }
        while !self.settled[k] {
            let Some((Reverse(bits), id)) = self.heap.pop() else {
                // Everything the goal reaches is settled: `k` is out of reach.
                self.settled[k] = true;
                break;
            };
            if self.settled[id] {
                continue;
            }
            self.settled[id] = true;
            self.relax(walk, id, Real::from_bits(bits));
        }
        self.h[k]
    }
}

/// The words of every edge at a node of the shortest path from `start` to `goal` (each
/// step to the neighbour that `h` says is on it), computed in parallel: the search walks
/// every one of them before it has the first class, one at a time, and on a map's graph an
/// edge's word (tens to hundreds of crossings) is most of an expansion. The words are the
/// same whoever computes them, so the search is too.
fn shortest_path_words<W: Walk + Sync>(
    walk: &W,
    rays: &Rays,
    h: &mut Distances,
    start: usize,
    goal: usize,
) -> FxHashMap<usize, Signature> {
    let mut edges = Vec::new();
    let mut on_path = FxHashSet::default();
    let mut k = start;
    while h.get(walk, k).is_finite() && on_path.insert(k) {
        let mut next: Option<(Real, usize)> = None;
        let mut links = Vec::new();
        walk.for_each_link(k, |m, e, _| links.push((m, e)));
        for (m, e) in links {
            edges.push(e);
            let f = walk.cost(e) + h.get(walk, m);
            if !on_path.contains(&m) && next.is_none_or(|(b, _)| f < b) {
                next = Some((f, m));
            }
        }
        match next {
            Some((_, m)) if k != goal => k = m,
            _ => break,
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges
        .into_par_iter()
        .map(|e| (e, rays.signature(&edge_polyline(walk, e, true))))
        .collect()
}

/// The best-first search over partial paths: every partial path made so far (each with its
/// parent, in `arena`), the queue of those not yet expanded, and the edge words computed so
/// far; `h` is the exact distance to the goal.
struct Frontier<'a, W> {
    walk: &'a W,
    rays: &'a Rays,
    h: Distances,
    /// Edge words, forward, computed when the search first walks the edge: a map's graph
    /// has tens of thousands of edges, whose words all together take long to compute, and a
    /// search walks a few hundred of them (measured: docs/performance.md, "Measurements
    /// behind the defaults"). Keyed by edge, so that the cache is as large as the walk, not
    /// as the graph.
    words: FxHashMap<usize, Signature>,
    /// The partial paths' words, interned.
    path_words: Words,
    arena: Vec<Partial>,
    queue: BinaryHeap<Entry>,
    /// Entries pushed so far, the start's not counted.
    order: usize,
    /// The unit in which `f` is compared ([`Frontier::key`]).
    quantum: Real,
}

impl<'a, W: Walk> Frontier<'a, W> {
    /// The search with the empty path at `start` queued, if the goal can be reached.
    fn new(walk: &'a W, rays: &'a Rays, mut h: Distances, start: usize) -> Self {
        let h_start = h.get(walk, start);
        let arena = vec![Partial {
            parent: usize::MAX,
            depth: 0,
            node: start,
            edge: (usize::MAX, true),
            g: 0.0,
            word: EMPTY_WORD,
        }];
        // With the exact heuristic every partial path on a shortest path has f = h(start), up
        // to rounding: g sums forward, h backward. On a lattice of equally short paths (a
        // random field of one-cell obstacles) those rounding differences decide between
        // thousands of ties and send the search breadth first, past its budget before any
        // class is found (random512-20-0). f is therefore compared in units of 1e-9 of
        // h(start), and ties go to the deeper path.
        let quantum = 1e-9 * (1.0 + h_start.abs());
        let mut frontier = Self {
            walk,
            rays,
            h,
            words: FxHashMap::default(),
            path_words: Words::new(),
            arena,
            queue: BinaryHeap::new(),
            order: 0,
            quantum,
        };
        if h_start.is_finite() {
            let key = frontier.key(h_start);
            frontier.queue.push(Entry {
                key,
                g: 0.0,
                order: 0,
                id: 0,
            });
        }
        frontier
    }

    /// The order key of `f`: `f` in units of the quantum.
    fn key(&self, f: Real) -> i64 {
        (f / self.quantum).round() as i64
    }

    /// Expands partial paths best first until `cfg.k` classes are found, the queue is empty
    /// or the expansion budget is spent; hands each class to `found` as it is found.
    fn search(
        mut self,
        cfg: &SearchConfig,
        goal: usize,
        mut found: impl FnMut(&ClassPath),
    ) -> SearchResult {
        let mut seen: FxHashSet<WordId> = FxHashSet::default();
        let mut expanded: FxHashSet<(usize, WordId)> = FxHashSet::default();
        let mut classes = Vec::new();
        let mut expansions = 0;
        let mut complete = true;
        // The nodes on the partial path last expanded, marked (`marked` is that path).
        let mut on_path = vec![false; self.walk.node_count()];
        let mut marked = usize::MAX;
        while let Some(Entry { id, .. }) = self.queue.pop() {
            if classes.len() >= cfg.k {
                break;
            }
            if expansions >= cfg.max_expansions {
                complete = false;
                break;
            }
            let node = self.arena[id].node;
            if cfg.one_path_per_state
                && node != goal
                && !expanded.insert((node, self.arena[id].word))
            {
                continue;
            }
            expansions += 1;
            if node == goal {
                if seen.insert(self.arena[id].word) {
                    let signature = self.path_words.signature(self.arena[id].word);
                    classes.push(assemble(self.walk, &self.arena, id, signature));
                    found(&classes[classes.len() - 1]);
                }
                continue;
            }
            self.mark_path(marked, id, &mut on_path);
            marked = id;
            self.expand(id, &on_path);
        }
        SearchResult {
            classes,
            complete,
            expansions,
        }
    }

    /// Moves the marks in `on_path` from the nodes of partial path `from` (none:
    /// `usize::MAX`) to those of partial path `to`, through the two paths' common prefix:
    /// unmarks `from`'s nodes below it, marks `to`'s. Best first, the next path to expand is
    /// most often the last one's child, so this is a step or two, where marking the whole
    /// path at every expansion walked thousands of nodes on a map's long paths. Each path
    /// is simple, so a node is on it at most once.
    fn mark_path(&self, from: usize, to: usize, on_path: &mut [bool]) {
        let depth = |p: usize| {
            if p == usize::MAX {
                0
            } else {
                self.arena[p].depth + 1
            }
        };
        let (mut a, mut b) = (from, to);
        let mut marks = Vec::new();
        while a != b {
            if depth(a) >= depth(b) {
                on_path[self.arena[a].node] = false;
                a = self.arena[a].parent;
            } else {
                marks.push(self.arena[b].node);
                b = self.arena[b].parent;
            }
        }
        for k in marks {
            on_path[k] = true;
        }
    }

    /// Queues partial path `id` extended by each allowed edge to a node not marked in
    /// `on_path` (off the path) from which the goal can be reached.
    fn expand(&mut self, id: usize, on_path: &[bool]) {
        let (walk, rays) = (self.walk, self.rays);
        walk.for_each_link(self.arena[id].node, |m, e, fwd| {
            let hm = self.h.get(walk, m);
            if on_path[m] || !hm.is_finite() {
                return;
            }
            let g = self.arena[id].g + walk.cost(e);
            let edge_word = self
                .words
                .entry(e)
                .or_insert_with(|| rays.signature(&edge_polyline(walk, e, true)));
            let word = self.path_words.concat(self.arena[id].word, edge_word, fwd);
            self.arena.push(Partial {
                parent: id,
                depth: self.arena[id].depth + 1,
                node: m,
                edge: (e, fwd),
                g,
                word,
            });
            self.order += 1;
            let key = self.key(g + hm);
            self.queue.push(Entry {
                key,
                g,
                order: self.order,
                id: self.arena.len() - 1,
            });
        });
    }
}

/// The class of partial path `id`, which reached the goal with word `signature`.
fn assemble<W: Walk>(graph: &W, arena: &[Partial], id: usize, signature: Signature) -> ClassPath {
    let mut chain = Vec::new();
    let mut p = id;
    while p != usize::MAX {
        chain.push(p);
        p = arena[p].parent;
    }
    chain.reverse();
    let nodes: Vec<usize> = chain.iter().map(|&i| arena[i].node).collect();
    let edges: Vec<(usize, bool)> = chain[1..].iter().map(|&i| arena[i].edge).collect();
    let mut polyline: Vec<Point> = Vec::new();
    for &(e, fwd) in &edges {
        for p in edge_polyline(graph, e, fwd) {
            if polyline.last() != Some(&p) {
                polyline.push(p);
            }
        }
    }
    ClassPath {
        length: edges.iter().map(|&(e, _)| graph.edge(e).length).sum(),
        min_clearance: edges
            .iter()
            .map(|&(e, _)| graph.edge(e).min_clearance)
            .fold(Real::INFINITY, Real::min),
        cost: arena[id].g,
        signature,
        nodes,
        edges,
        polyline,
    }
}

/// Indices of the classes whose path uses `edge`: the ones a scout's report that `edge` is
/// blocked invalidates.
pub fn classes_through_edge(classes: &[ClassPath], edge: usize) -> Vec<usize> {
    classes
        .iter()
        .enumerate()
        .filter(|(_, c)| c.edges.iter().any(|&(e, _)| e == edge))
        .map(|(i, _)| i)
        .collect()
}

/// Whether a dense polyline with the same ends is in the class `signature`.
pub fn in_class(rays: &Rays, polyline: &[Point], signature: &Signature) -> bool {
    &rays.signature(polyline) == signature
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::{EMPTY_WORD, Signature, Words};

    /// Edge words over three rays, walked forward or backward.
    fn steps() -> impl Strategy<Value = Vec<(Vec<i32>, bool)>> {
        let letter = prop_oneof![-3..=-1i32, 1..=3i32];
        prop::collection::vec((prop::collection::vec(letter, 0..4), any::<bool>()), 0..12)
    }

    proptest! {
        /// The interned words are the reduced words `Signature::concat` makes, and two
        /// walks reach one id exactly when their words are equal.
        #[test]
        fn interned_words_are_the_reduced_words(a in steps(), b in steps()) {
            let mut words = Words::new();
            let mut walk = |steps: &[(Vec<i32>, bool)]| {
                let (mut id, mut word) = (EMPTY_WORD, Signature::identity());
                for (letters, forward) in steps {
                    let edge = Signature(letters.clone());
                    id = words.concat(id, &edge, *forward);
                    word = word.concat(&if *forward { edge } else { edge.inverse() });
                }
                (id, word)
            };
            let ((ia, wa), (ib, wb)) = (walk(&a), walk(&b));
            prop_assert_eq!(words.signature(ia), wa.clone());
            prop_assert_eq!(words.signature(ib), wb.clone());
            prop_assert_eq!(ia == ib, wa == wb);
        }
    }
}
