//! The system tests that build firmware (the QEMU machines' and the board's), one
//! module per file beside this one, built as one binary (see `tests/Cargo.toml`).
//! Their time is the firmware builds (a QEMU run takes a fraction of a second
//! to a few seconds); in one binary the board's builds run beside the QEMU
//! firmware's, each in its own target folder (`xtask::firmware`).
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
