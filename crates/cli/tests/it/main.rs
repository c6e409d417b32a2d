//! The integration tests of `homospline-cli` in one binary, one module per former
//! `tests/NAME.rs` (one link instead of one per file: most of a cold `cargo test` was
//! linking). Run one with `cargo test -p homospline-cli --test it NAME::`.

mod answers;
mod bench_scen;
mod check;
mod common;
mod docs;
mod fuzz;
mod fuzz_cli;
mod hostile;
mod limits;
mod maps;
mod odd_inputs;
mod pictures;
mod plan;
mod simulate;
