//! The integration tests of `homospline-geom` in one binary, one module per former
//! `tests/NAME.rs` (one link instead of one per file: most of a cold `cargo test` was
//! linking). Run one with `cargo test -p homospline-geom --test it NAME::`.

mod invalid_scenes;
mod properties;
mod shortest;
mod yaml_limits;
