#!/usr/bin/env bash
# Bakes the Cornell box at h = 0.02 m and 4M photons, seeds 1 and 2, with and without covered parts (--no-cover),
# and prints the light under and beside its blocks (tools/box_contact.py). Usage: tools/box-contact.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=$(mktemp -d)
for cover in "" --no-cover; do
  for seed in 1 2; do
    "$build/bake" data/box/box.obj -q -o "$out/box-seed$seed$cover.ply" --h 0.02 --photons 4000000 --seed "$seed" --direct photons $cover
  done
done
python3 tools/box_contact.py "$out"/*.ply
rm -rf "$out"
