#!/usr/bin/env bash
# Regenerates the shading comparisons in docs/images/shading-*.png and their
# numbers (docs/images/shading-*.json): gouraud | quadratic | phong | error of
# gouraud | error of quadratic, for one lit sphere and for the teapot.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p host-sim
target="${CARGO_TARGET_DIR:-target}"
mkdir -p docs/images
for scene in docs/scenes/sphere.toml teapot; do
  name=$(basename "$scene" .toml)
  "$target/release/host-sim" shading --scene "$scene" \
    --out "docs/images/shading-$name.png" --stats-json "docs/images/shading-$name.json"
done
