//! The integration tests of `homospline-voronoi` in one binary, one module per former
//! `tests/NAME.rs` (one link instead of one per file: most of a cold `cargo test` was
//! linking). Run one with `cargo test -p homospline-voronoi --test it NAME::`.

mod apart;
mod complete;
mod fixtures;
mod properties;
