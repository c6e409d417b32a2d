//! The shortest path of one homotopy class that keeps a clearance from circles: the tangent
//! graph of [`homospline_geom::shortest`] searched with each route's reduced word of ray
//! crossings, Dijkstra in the universal cover of free space, up to a length bound.
//!
//! The shortest path of a class is taut: tangent segments and arcs of the grown circles,
//! all of them edges of the tangent graph. A route's class is its reduced word, so a search
//! whose states are (node, word so far) finds the shortest route of every word it reaches;
//! a bound on the length keeps the words finite. It is A*: a state is taken in the order of
//! its distance plus its node's distance to the goal in the plane (any class; exact, so the
//! search takes in only routes that can come within the bound), and it gives up past
//! [`MAX_STATES`] states or [`MAX_LETTERS`] letters in their words rather than fill the
//! memory (dozens of obstacles each passed either way make that many words; a loose bound
//! lets routes wind round obstacles again and again, and their words grow long: unbounded,
//! a search can fill the memory before it reaches its budget of states; measured:
//! docs/performance.md, "Measurements behind the defaults"). An arc's word is
//! taken on chords whose lenses hold no ray origin (see `word`).

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use thiserror::Error;

use homospline_geom::Real;
use homospline_geom::shortest::{Piece, ShortestPath, TangentGraph};

use crate::signature::{Rays, Signature};

/// The word of one piece. An arc's is taken on chords: a ray can tell a chord from its arc
/// only through the lens between them, whose points lie within the chord's sagitta of the
/// circle. With no ray origin that near the circle, a ray's line meets the lens boundary
/// twice, and a line meets the circle at most twice: it crosses the chord and the arc once
/// each (the same letter; parallel lines keep their order along both), or the arc twice and
/// the chord not at all. Those two crossings enclose only other such pairs (the lines are
/// parallel, the cap beyond a line is convex), so they reduce away. The chords are chosen so
/// that the sagitta is at most half the least distance from an origin to the circle, and at
/// most 0.5 radians (1e-3 radians at least, where that distance is tiny).
fn word(rays: &Rays, piece: &Piece) -> Signature {
    let step = match *piece {
        Piece::Segment { .. } => Real::INFINITY,
        Piece::Arc { circle, .. } => {
            let gap = rays
                .origins()
                .iter()
                .map(|o| ((o - circle.center).norm() - circle.radius).abs())
                .fold(Real::INFINITY, Real::min);
            // Sagitta r (1 - cos(step / 2)) <= gap / 2.
            let cos_half = 1.0 - 0.5 * gap / circle.radius.max(Real::MIN_POSITIVE);
            if cos_half <= -1.0 {
                0.5
            } else {
                (2.0 * cos_half.acos()).clamp(1e-3, 0.5)
            }
        }
    };
    rays.signature(&piece.points(step))
}

/// The search gives up past this many (node, word) states.
pub const MAX_STATES: usize = 1 << 20;

/// The search gives up past this many letters in its states' words (each word is held
/// twice, 4 bytes a letter: 2^23 letters are 64 MB).
pub const MAX_LETTERS: usize = 1 << 23;

/// A search that gave up: the states it held.
#[derive(Debug, Error, PartialEq)]
#[error(
    "the class search gave up after {0} states (node and word) within the length bound: \
     its budget of states (at most {MAX_STATES}) or of {MAX_LETTERS} letters in their words"
)]
pub struct TooManyStates(pub usize);

/// A search state: its node, its word, its distance, and the state and edge it came by.
type State = (usize, Signature, Real, Option<(usize, usize)>);

/// The shortest route from the start to the goal of `graph` whose reduced word `accept`s
/// (a class's signature; the class is the word's), among those no longer than `bound`;
/// `None` when there is none. With `bound` the length of a curve of the class that keeps
/// the graph's clearance, `None` would mean that the curve beats the optimum.
pub fn shortest_in_class(
    graph: &TangentGraph,
    rays: &Rays,
    accept: impl Fn(&Signature) -> bool,
    bound: Real,
) -> Result<Option<ShortestPath>, TooManyStates> {
    shortest_in_class_within(graph, rays, accept, bound, MAX_STATES)
}

/// [`shortest_in_class`], giving up past `max_states` states (at most [`MAX_STATES`]) or
/// [`MAX_LETTERS`] letters: for a caller that needs an answer in microseconds (the planner's
/// dm rule) and can do without one.
pub fn shortest_in_class_within(
    graph: &TangentGraph,
    rays: &Rays,
    accept: impl Fn(&Signature) -> bool,
    bound: Real,
    max_states: usize,
) -> Result<Option<ShortestPath>, TooManyStates> {
    let max_states = max_states.min(MAX_STATES);
    // The heuristic: each node's distance to the goal, any class.
    let h = graph.distances_to(TangentGraph::GOAL);
    // Each edge's word, computed when the search first takes the edge.
    let mut words: Vec<Vec<Option<Signature>>> = (0..graph.nodes().len())
        .map(|u| vec![None; graph.edges(u).len()])
        .collect();
    // States: (node, word); per state its distance and the state and edge it came by.
    let mut ids: HashMap<(usize, Signature), usize> = HashMap::new();
    let mut states: Vec<State> = Vec::new();
    let mut letters = 0;
    let start = (TangentGraph::START, Signature::identity());
    ids.insert(start.clone(), 0);
    states.push((start.0, start.1, 0.0, None));
    // Entries (key's bits, state): non-negative floats order as their bits.
    let mut heap = BinaryHeap::from([Reverse((h[TangentGraph::START].to_bits(), 0))]);
    while let Some(Reverse((bits, id))) = heap.pop() {
        let key = Real::from_bits(bits);
        let d = states[id].2;
        if key > d + h[states[id].0] {
            continue;
        }
        let (u, w) = (states[id].0, states[id].1.clone());
        if u == TangentGraph::GOAL && accept(&w) {
            let mut pieces = Vec::new();
            let mut at = id;
            while let Some((from, k)) = states[at].3 {
                pieces.push(graph.edges(states[from].0)[k].piece);
                at = from;
            }
            pieces.reverse();
            return Ok(Some(ShortestPath { length: d, pieces }));
        }
        for (k, e) in graph.edges(u).iter().enumerate() {
            let dv = d + e.piece.length();
            if dv + h[e.to] > bound {
                continue;
            }
            let edge_word = words[u][k].get_or_insert_with(|| word(rays, &e.piece));
            let key = (e.to, w.concat(edge_word));
            let next = match ids.get(&key) {
                Some(&v) if states[v].2 <= dv => continue,
                Some(&v) => v,
                None if states.len() >= max_states || letters + key.1.0.len() > MAX_LETTERS => {
                    return Err(TooManyStates(states.len()));
                }
                None => {
                    let v = states.len();
                    letters += key.1.0.len();
                    ids.insert(key.clone(), v);
                    states.push((key.0, key.1, dv, None));
                    v
                }
            };
            states[next].2 = dv;
            states[next].3 = Some((id, k));
            heap.push(Reverse(((dv + h[e.to]).to_bits(), next)));
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use homospline_geom::{Circle, Point};

    #[test]
    fn the_two_ways_round_a_circle_are_two_classes() {
        // A circle below the line S-T, off centre: above it is the shorter way, below it the
        // longer; both are found, each in its class, and the straight segment is in the
        // class that passes above.
        let circles = [Circle::new(0.0, -0.5, 1.0)];
        let (s, t) = (Point::new(-5.0, 0.0), Point::new(5.0, 0.0));
        let rays = Rays::new(vec![circles[0].center]);
        let g = TangentGraph::build(&s, &t, &circles, 0.0).unwrap().unwrap();
        let above = rays.signature(&[s, Point::new(0.0, 3.0), t]);
        let below = rays.signature(&[s, Point::new(0.0, -3.0), t]);
        assert_ne!(above, below);
        let a = shortest_in_class(&g, &rays, |w| *w == above, 1e9)
            .unwrap()
            .unwrap();
        let b = shortest_in_class(&g, &rays, |w| *w == below, 1e9)
            .unwrap()
            .unwrap();
        let best = g.shortest().unwrap();
        assert!((a.length - best.length).abs() < 1e-12);
        assert!(b.length > a.length);
        // Tangents from (-5, 0) and (5, 0) to the circle and the arc between; the centre is
        // `base` below the line seen from either end.
        let d = (25.0f64 + 0.25).sqrt();
        let (base, half) = ((0.5f64 / 5.0).atan(), (1.0 / d).acos());
        let way =
            |arc_half: Real| 2.0 * (d * d - 1.0).sqrt() + std::f64::consts::PI - 2.0 * arc_half;
        let (exact_above, exact_below) = (way(half + base), way(half - base));
        assert!(
            (a.length - exact_above).abs() < 1e-9,
            "{} vs {exact_above}",
            a.length
        );
        assert!(
            (b.length - exact_below).abs() < 1e-9,
            "{} vs {exact_below}",
            b.length
        );
        // Bounded below its length, it is not found.
        assert_eq!(
            shortest_in_class(&g, &rays, |w| *w == below, b.length - 1e-6),
            Ok(None)
        );
        // The path's own word is its class's.
        let pts: Vec<Point> = b
            .pieces
            .iter()
            .flat_map(|p| (0..=64).map(move |k| p.point(k as Real / 64.0)))
            .collect();
        assert_eq!(rays.signature(&pts), below);
    }

    #[test]
    fn an_unbounded_search_for_a_word_never_found_gives_up_within_its_letters() {
        // A ring of twelve circles, S and T outside it, a word no route has
        // (every letter +1): without a bound the routes wind round the ring again and again,
        // and the search must give up by the letters its words hold, not fill the memory
        // (it filled the memory before it had MAX_STATES states; measured:
        // docs/performance.md, "Measurements behind the defaults").
        let circles: Vec<Circle> = (0..12)
            .map(|i| {
                let a = i as Real * std::f64::consts::TAU / 12.0;
                Circle::new(10.0 * a.cos(), 10.0 * a.sin(), 2.5)
            })
            .collect();
        let rays = Rays::new(circles.iter().map(|c| c.center).collect());
        let (s, t) = (Point::new(-20.0, 1.0), Point::new(20.0, -1.0));
        let g = TangentGraph::build(&s, &t, &circles, 0.5).unwrap().unwrap();
        let never = |w: &Signature| w.0.len() > 3 && w.0.iter().all(|&l| l == 1);
        match shortest_in_class(&g, &rays, never, Real::INFINITY) {
            Err(TooManyStates(n)) => assert!(n < MAX_STATES, "{n} states"),
            other => panic!("{other:?}"),
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]

        /// An arc's word on its coarse chords is its word on chords 1e-4 radians apart,
        /// whatever the ray origins (some near the circle, some inside it).
        #[test]
        fn an_arcs_word_on_coarse_chords_is_its_word_on_fine_ones(
            (cx, cy, r) in (-5.0..5.0f64, -5.0..5.0f64, 0.5..20.0f64),
            (a, span) in (-4.0..4.0f64, -6.3..6.3f64),
            origins in proptest::collection::vec((0.0..6.3f64, 0.0..1.6f64), 1..8),
        ) {
            let circle = Circle::new(cx, cy, r);
            // Origins at 0 to 1.6 radii from the centre: inside, near and outside the circle.
            let rays = Rays::new(
                origins
                    .iter()
                    .map(|&(t, f)| Point::new(cx + f * r * t.cos(), cy + f * r * t.sin()))
                    .collect(),
            );
            let arc = Piece::Arc { circle, from: a, to: a + span };
            proptest::prop_assert_eq!(word(&rays, &arc), rays.signature(&arc.points(1e-4)));
        }
    }
}
