#!/usr/bin/env bash
# Regenerates everything in docs/results/ that docs/results.md reports:
#   sweeps (CSV, Markdown summary, NMSE plots) of the three test objects and a
#   synthetic scene, the supersampling comparison table, depth-complexity
#   statistics and heat maps, difference heat maps, and a turntable animation.
# Takes about three minutes on a 2-core machine. Section numbers refer to
# docs/results.md.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p host-sim
HS="${CARGO_TARGET_DIR:-target}/release/host-sim"
OUT=docs/results
mkdir -p "$OUT"
SIZE=(--width 240 --height 240)
# The tables in docs/results.md were measured with 16-row bands (the library's
# default is 8): the band is given explicitly wherever it changes a figure.
BAND=(--band 16)
OBJECTS=(starfighter teapot:24 knot)
FRAMES=12
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

nmse() { "$HS" compare "$1" "$2" | awk '/^NMSE / { printf "%.2e", $2 }'; }
tag() { echo "$1" | tr ':' '-'; }

# Sections 1, 2 and 4: every policy at 1..8 fragments per pixel over a
# 12-frame turntable; the pool of shared and merge-closest is the worst peak
# over the frames.
for s in "${OBJECTS[@]}"; do
  "$HS" sweep --scene "$s" "${SIZE[@]}" "${BAND[@]}" --frames "$FRAMES" --quiet --out-dir "$OUT" >/dev/null
done
# Section 2: the same with one band as tall as the image (a pool for the whole frame).
for s in "${OBJECTS[@]}"; do
  "$HS" sweep --scene "$s" "${SIZE[@]}" --frames "$FRAMES" --band 240 --policies fixed-merge,shared \
    --splits 1 --name "$(tag "$s")-frame" --quiet --out-dir "$OUT" >/dev/null
done
# Synthetic layers of depth complexity 6 (section 1, controlled complexity).
"$HS" sweep --scene layers:1000:6:1 "${SIZE[@]}" "${BAND[@]}" --frames "$FRAMES" --quiet --out-dir "$OUT" >/dev/null

# Performance: one frame of the heaviest object, all policies and budgets.
"$HS" sweep --scene knot "${SIZE[@]}" "${BAND[@]}" --quiet --out-dir "$TMP" 2>&1 >/dev/null |
  grep '^sweep:' >"$OUT/sweep-timing.txt"

# Section 3: the unlimited A-buffer against supersampled ground truth.
{
  echo "| scene | zbuffer vs ssaa 16x16 | unlimited 4x4 vs ssaa 16x16 | ssaa 4x4 vs ssaa 16x16 | unlimited 4x4 vs ssaa 4x4 | unlimited 8x8 vs ssaa 16x16 | ssaa 8x8 vs ssaa 16x16 | unlimited 8x8 vs ssaa 8x8 |"
  echo "|---|---|---|---|---|---|---|---|"
  for s in "${OBJECTS[@]}" spheres teapot layers:1000:6:1; do
    t=$(tag "$s")
    "$HS" render --scene "$s" "${SIZE[@]}" --method zbuffer --out "$TMP/$t-z.png" >/dev/null
    "$HS" render --scene "$s" "${SIZE[@]}" --method unlimited --out "$TMP/$t-u4.png" >/dev/null
    "$HS" render --scene "$s" "${SIZE[@]}" --method unlimited --grid 8x8 --out "$TMP/$t-u8.png" >/dev/null
    for n in 4 8 16; do
      "$HS" render --scene "$s" "${SIZE[@]}" --method ssaa --ssaa "$n" --out "$TMP/$t-s$n.png" >/dev/null
    done
    echo "| $s | $(nmse "$TMP/$t-z.png" "$TMP/$t-s16.png") | $(nmse "$TMP/$t-u4.png" "$TMP/$t-s16.png") | $(nmse "$TMP/$t-s4.png" "$TMP/$t-s16.png") | $(nmse "$TMP/$t-u4.png" "$TMP/$t-s4.png") | $(nmse "$TMP/$t-u8.png" "$TMP/$t-s16.png") | $(nmse "$TMP/$t-s8.png" "$TMP/$t-s16.png") | $(nmse "$TMP/$t-u8.png" "$TMP/$t-s8.png") |"
  done
} >"$OUT/ssaa.md"
# Where the A-buffer's shading at pixel centers differs from shading per sample.
"$HS" compare "$TMP/starfighter-u4.png" "$TMP/starfighter-s4.png" --diff "$OUT/starfighter-unlimited-vs-ssaa4.png" >/dev/null
cp "$TMP/starfighter-s16.png" "$OUT/starfighter-ssaa16.png"

# Section 1: where 3 fragments per pixel lose quality (shared, 1 + 2, pool per band
# sized to the worst peak of the sweep).
for s in starfighter teapot:24; do
  t=$(tag "$s")
  peak=$(awk -F, '$7 == "shared" && $8 == 3 && $10 == 1 { print $13 }' "$OUT/$t-sweep.csv")
  "$HS" render --scene "$s" "${SIZE[@]}" --method shared "${BAND[@]}" --main 1 --extra 2 --pool "$peak" \
    --out "$TMP/$t-shared3.png" >/dev/null
  "$HS" compare "$TMP/$t-shared3.png" "$TMP/$t-u4.png" --diff "$OUT/$t-shared3-vs-unlimited.png" \
    --diff-scale 64 >/dev/null
done

# Depth complexity: histograms, heat maps, memory.
for s in "${OBJECTS[@]}" layers:1000:6:1; do
  "$HS" stats --scene "$s" "${SIZE[@]}" "${BAND[@]}" --pool 1920 --out-dir "$OUT" >"$OUT/$(tag "$s")-stats.txt"
done

# Bounded memory against unlimited over an 8-frame turntable: the default M4
# memory (band 8, pool 512) and the host defaults (band 16, pool 1,920).
"$HS" bounded --row-plot "$OUT/bounded-rows-teapot.svg" >"$OUT/bounded-m4.md"
"$HS" bounded --band 16 --pool 1920 >"$OUT/bounded-host.md"
# The fastest configuration within 112 KiB and 96 KiB (host times decide).
for s in teapot spheres; do
  for ram in 112K 96K; do
    "$HS" tune --scene "$s" --ram "$ram" --show 3
  done
done >"$OUT/tune.md"

# The dynamic mode: a turntable with per-frame statistics.
"$HS" render --scene starfighter --width 160 --height 160 "${BAND[@]}" --pool 1280 --turntable --frames 24 \
  --out "$OUT/starfighter-turntable.gif" >"$OUT/starfighter-turntable.txt"

echo "wrote $OUT/"
