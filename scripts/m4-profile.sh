#!/usr/bin/env bash
# Exact instructions per function and per source file of one frame (frame 0 of
# the turntable) on the Cortex-M4 under QEMU, for the teapot with `shared`,
# `zbuffer` and `split-bands` in the default M4 configuration: builds the QEMU
# firmware with FIRMWARE_FRAMES=1 and runs scripts/qemu-profile.py on it (by
# innermost inlined function, by source file, and by function symbol with its
# inlined callees). Writes docs/m4-profile/teapot-<method>.txt.
# Needs qemu-system-arm, python3 and llvm-symbolizer (Debian's llvm package);
# about a minute per method.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p docs/m4-profile
for method in shared zbuffer split-bands; do
  (cd firmware/qemu && FIRMWARE_FRAMES=1 FIRMWARE_SCENE=teapot FIRMWARE_METHOD="$method" \
    cargo build --release --quiet)
  python3 scripts/qemu-profile.py firmware/qemu/target/thumbv7em-none-eabihf/release/qemu-m4 \
    --top 40 --files --outer > "docs/m4-profile/teapot-$method.txt"
  echo "wrote docs/m4-profile/teapot-$method.txt"
done
