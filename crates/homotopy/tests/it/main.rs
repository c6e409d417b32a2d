//! The integration tests of `homospline-homotopy` in one binary, one module per former
//! `tests/NAME.rs` (one link instead of one per file: most of a cold `cargo test` was
//! linking). Run one with `cargo test -p homospline-homotopy --test it NAME::`.

mod search;
mod shortest;
mod signature;
