//! The integration tests of `homospline-spline` in one binary, one module per former
//! `tests/NAME.rs` (one link instead of one per file: most of a cold `cargo test` was
//! linking). Run one with `cargo test -p homospline-spline --test it NAME::`.

mod accuracy;
mod gradient;
