//! The integration tests of `homospline-mission` in one binary, one module per former
//! `tests/NAME.rs` (one link instead of one per file: most of a cold `cargo test` was
//! linking). Run one with `cargo test -p homospline-mission --test it NAME::`.

mod maps;
mod mission;
mod oscillation;
mod policies;
mod tracks;
