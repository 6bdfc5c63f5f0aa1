//! The project's tooling behind `cargo xtask` (see `cargo xtask --help`): the
//! test command, building and running the QEMU and board firmware, the Cortex-M4
//! benchmarks and profiles, fuzzing, and the reference images and results in
//! `docs/`. The system tests use [`firmware`] to build and run the QEMU
//! firmware; `host-sim` stays a simulator and test program.
#![warn(missing_docs)]

pub mod bench;
pub mod board_chip;
pub mod firmware;
pub mod fuzz;
pub mod results;
pub mod run;
pub mod sizing;
pub mod test_command;
