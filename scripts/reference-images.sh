#!/usr/bin/env bash
# Regenerates the reference renderings in docs/images/ and their statistics
# (docs/images/*.json): the three built-in scenes at 240x240 with `unlimited`,
# `split-bands` (the default) and `shared` (1 main slot, 2 pool addresses, default
# pool) and `zbuffer`.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p host-sim
mkdir -p docs/images
for scene in teapot spheres starfighter; do
  for method in unlimited split-bands shared zbuffer; do
    ./target/release/host-sim render --scene "$scene" --method "$method" \
      --out "docs/images/$scene-$method.png" --stats-json "docs/images/$scene-$method.json" >/dev/null
  done
done
echo "wrote docs/images/"
