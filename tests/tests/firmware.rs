//! The system tests that build firmware (the QEMU machines' and the board's), one
//! module per file beside this one, built as one binary (see `tests/Cargo.toml`).
//! In one binary the test threads overlap one file's firmware builds with
//! another's QEMU runs, which were one after another as binaries of their own.
//! One file's tests run with, for example,
//! `cargo test -p system-tests --test firmware qemu_m4::`.

#[path = "board_link.rs"]
mod board_link;
#[path = "qemu_m4.rs"]
mod qemu_m4;
#[path = "qemu_oled.rs"]
mod qemu_oled;
#[path = "qemu_stack.rs"]
mod qemu_stack;
