#!/usr/bin/env bash
# Regenerates the tables and images of the section "Z-buffer with midpoint
# subdivision" in docs/results.md: depth comparisons, time per frame and
# pixels differing from the plain z-buffer for zbuffer, zbuffer-hiz and
# zbuffer-midpoint (K = 0..3, as published and with per-pixel tests kept), at
# 800x600 on the built-in scene `overdraw` (one band for the whole frame, and
# bands of 16 rows) and on the teapot. Times are the host's processor time per
# frame, the fastest of REPEAT timings of 5 renders each, configurations taking
# turns (default 9); the counters are exact and the same on every run. Takes
# about two minutes on a 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p host-sim
HS="${CARGO_TARGET_DIR:-target}/release/host-sim"
OUT=docs/results
REPEAT="${REPEAT:-9}"
mkdir -p "$OUT"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

"$HS" zbuffer-table --scene overdraw --repeat "$REPEAT" --out "$OUT/zbuffer-overdraw.md"
"$HS" zbuffer-table --scene overdraw --band 16 --repeat "$REPEAT" --out "$OUT/zbuffer-overdraw-band16.md"
"$HS" zbuffer-table --scene teapot --repeat "$REPEAT" --out "$OUT/zbuffer-teapot.md"

# Where the published setting (K = 2, visible pieces untested) goes wrong.
SIZE=(--scene overdraw --width 800 --height 600 --band 600)
"$HS" render "${SIZE[@]}" --method zbuffer --out "$OUT/zbuffer-overdraw.png" >/dev/null
"$HS" render "${SIZE[@]}" --method zbuffer-midpoint --out "$TMP/midpoint.png" >/dev/null
"$HS" render "${SIZE[@]}" --method zbuffer-midpoint --midpoint-safe --out "$TMP/safe.png" >/dev/null
"$HS" compare "$TMP/midpoint.png" "$OUT/zbuffer-overdraw.png" \
  --diff "$OUT/zbuffer-midpoint-k2-diff.png" --diff-scale 64
"$HS" compare "$TMP/safe.png" "$OUT/zbuffer-overdraw.png" \
  --diff "$OUT/zbuffer-midpoint-k2-safe-diff.png" --diff-scale 64
