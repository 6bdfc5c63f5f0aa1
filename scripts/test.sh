#!/usr/bin/env bash
# Runs every test on a fresh machine: installs what is missing, then checks
# formatting, lints, the bare-metal library builds and the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== setup"
rustup component add rustfmt clippy >/dev/null 2>&1 || true
rustup target add thumbv7em-none-eabihf thumbv6m-none-eabi

echo "== format"
cargo fmt --all -- --check

echo "== clippy"
cargo clippy --workspace --all-targets -- -D warnings

echo "== library for Cortex-M4F and Cortex-M0+"
cargo build -p mcu-abuffer --release --target thumbv7em-none-eabihf
cargo build -p mcu-abuffer --release --target thumbv6m-none-eabi

echo "== tests"
cargo test --workspace

echo "== main job: render a built-in scene"
cargo run --release -p host-sim -- render --scene teapot --out target/teapot.png
