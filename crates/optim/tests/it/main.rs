//! The integration tests of `homospline-optim` in one binary, one module per former
//! `tests/NAME.rs` (one link instead of one per file: most of a cold `cargo test` was
//! linking). Run one with `cargo test -p homospline-optim --test it NAME::`.

mod barrier;
mod budget;
mod config;
mod dm_gap;
mod interrupt;
mod nelder_mead;
mod optimum;
mod planner;
mod prune;
mod quadrature;
