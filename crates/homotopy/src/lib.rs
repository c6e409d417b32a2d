//! Homotopy signatures and the k best homotopy-distinct paths (method.md section 5.2).
//!
//! - [`signature`]: [`Rays`] and [`Signature`], the exact reduced-word invariant; the
//!   H-signature of Bhattacharya et al. as [`h_signature`].
//! - [`search`]: [`k_best_classes`] on a [`homospline_voronoi::VoronoiGraph`], with blocked
//!   edges and regions ([`k_best_classes_on`] on one query of a prepared map's graph,
//!   [`homospline_voronoi::QueryGraph`]), and [`classes_through_edge`] / [`in_class`] for re-planning and for
//!   keeping an optimised curve in its class.
//! - [`id`]: [`class_id`], a short id for a class, for tables, legends and `--avoid`.
//! - [`shortest`]: [`shortest_in_class`], the exact shortest path of one class that keeps a
//!   clearance from circles (the oracle that checks an optimised curve's length).

pub mod id;
pub mod search;
pub mod shortest;
pub mod signature;

pub use id::{class_id, class_letter, is_hashed_id};
pub use search::{
    ClassPath, EdgeCost, SearchConfig, SearchError, SearchResult, classes_through_edge, in_class,
    k_best_classes, k_best_classes_each, k_best_classes_each_on, k_best_classes_on,
};
pub use shortest::{
    MAX_LETTERS, MAX_STATES, TooManyStates, shortest_in_class, shortest_in_class_within,
};
pub use signature::{Rays, Signature, h_distance, h_signature};
