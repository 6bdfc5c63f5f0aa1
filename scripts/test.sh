#!/usr/bin/env bash
# Runs every test on a fresh machine: installs what is missing (the toolchain of
# rust-toolchain.toml with its targets, QEMU, flip-link (the firmwares' linker),
# the toolchain of the workspace's
# minimum Rust version), then checks formatting and lints,
# checks the workspace with its minimum Rust version, builds the library for
# bare-metal targets, and runs the whole suite: host unit and system tests, the QEMU
# firmware parity and instruction-count tests (Cortex-M4) and the SPI display
# screendump test (Cortex-M3), the STM32F411 board firmware's link check and the
# host test of its display path, checks the board's chip name and memory against
# probe-rs's target description (probe-rs itself when installed, else the copy in
# firmware/blackpill/probe-rs-target; it does not install probe-rs), then runs
# every fuzz target for a short time.
set -euo pipefail
cd "$(dirname "$0")/.."

# Every step's heading with the minutes and seconds since the start.
started=$SECONDS
step() { printf '== [%d:%02d] %s\n' $(((SECONDS - started) / 60)) $(((SECONDS - started) % 60)) "$*"; }

step "setup"
# The toolchain rust-toolchain.toml names, with its components and targets
# (older rustup installs it on first use instead).
rustup toolchain install 2>/dev/null || true
rustup component add rustfmt clippy >/dev/null 2>&1 || true
rustup target add thumbv7em-none-eabihf thumbv7m-none-eabi thumbv6m-none-eabi
if ! command -v qemu-system-arm >/dev/null 2>&1; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "qemu-system-arm is missing and installing it needs root: apt-get install -y qemu-system-arm" >&2
    exit 1
  fi
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y qemu-system-arm
fi
qemu-system-arm --version | head -n 1
# The firmwares link through flip-link (the stack below the statics).
if ! command -v flip-link >/dev/null 2>&1; then
  cargo install flip-link --locked --version 0.1.12
fi

step "format"
cargo fmt --all -- --check
cargo fmt --manifest-path firmware/qemu/Cargo.toml -- --check
cargo fmt --manifest-path firmware/blackpill/Cargo.toml -- --check

step "clippy"
cargo clippy --workspace --all-targets -- -D warnings
cargo clippy --manifest-path firmware/qemu/Cargo.toml --release --target thumbv7em-none-eabihf -- -D warnings
cargo clippy --manifest-path firmware/qemu/Cargo.toml --release --no-default-features --features oled --target thumbv7m-none-eabi -- -D warnings
cargo clippy --manifest-path firmware/blackpill/Cargo.toml --release --target thumbv7em-none-eabihf --all-targets -- -D warnings
# The minimal example firmware (README, "Add it to your firmware") links for the board.
cargo build --manifest-path firmware/blackpill/Cargo.toml --release --target thumbv7em-none-eabihf --example minimal

step "the library's documentation builds without warnings (broken links included)"
RUSTDOCFLAGS="-D warnings" cargo doc -p mcu-abuffer --no-deps

step "the library and the scene crate package for crates.io (dry run)"
cargo publish --dry-run --allow-dirty -p mcu-abuffer -p abuffer-scenes

step "the declared minimum Rust version (workspace rust-version) builds everything"
msrv=$(sed -n 's/^rust-version = "\(.*\)"/\1/p' Cargo.toml)
rustup toolchain install "$msrv" --profile minimal >/dev/null
CARGO_TARGET_DIR=target/msrv cargo +"$msrv" check --workspace --all-targets

step "library for Cortex-M4F and Cortex-M0+"
cargo build -p mcu-abuffer --release --target thumbv7em-none-eabihf
cargo build -p mcu-abuffer --release --target thumbv6m-none-eabi

step "tests (host, QEMU Cortex-M4 parity and counts, QEMU Cortex-M3 OLED screendump, board link and display path)"
# The firmware tests skip themselves when QEMU or a Cortex-M target is missing;
# here both were installed above, so a missing one must fail instead.
export ABUFFER_REQUIRE_QEMU=1
cargo test --workspace

step "board: the runner's chip is one probe-rs knows, with memory.x's flash and RAM (probe-rs if installed, else the copy of its target description)"
bash scripts/check-board-chip.sh

step "fuzz: 10 s per target from the seed corpus with a fixed seed (installs nightly)"
# A fixed seed makes the run reproducible: the same inputs on every machine, in
# the same order. Exploring new inputs is `bash scripts/fuzz.sh SECONDS`.
FUZZ_SEED=1 bash scripts/fuzz.sh 10

step "main job: render a built-in scene"
# The README's first command, built with the test profile that the tests above
# compiled it with (the release build would add minutes of compiling here).
cargo run --profile test -p host-sim -- render --scene teapot --out target/teapot.png
step "done"
