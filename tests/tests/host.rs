//! The system tests that run on the host, one module per file beside this one,
//! built as one binary (see `tests/Cargo.toml`). One file's tests run with, for
//! example, `cargo test -p system-tests --test host oracle::`.

#[path = "board_display.rs"]
mod board_display;
#[path = "coverage_bound.rs"]
mod coverage_bound;
#[path = "extreme.rs"]
mod extreme;
#[path = "fuzz_regressions.rs"]
mod fuzz_regressions;
#[path = "memory.rs"]
mod memory;
#[path = "merge_insert.rs"]
mod merge_insert;
#[path = "oracle.rs"]
mod oracle;
#[path = "ranges.rs"]
mod ranges;
#[path = "top_left.rs"]
mod top_left;
