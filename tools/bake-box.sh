#!/usr/bin/env bash
# Quick start 1: install what is missing, build, and bake the bundled Cornell box.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
mkdir -p out
./build/bake data/box/box.obj -o out/box.ply --kernel epanechnikov --h 0.05 --photons 2000000 --seed 1 \
  --report out/box.json
cat <<MSG

The baked box is $(pwd)/out/box.ply (figures in $(pwd)/out/box.json).
Open it in MeshLab:  meshlab $(pwd)/out/box.ply
  (Render > Color > Per Vertex shows the baked light; Filters > Quality Measure > Colorize by vertex
   quality shows irradiance H. Turn lighting off with the light-bulb button: the colours already hold it.)
MSG
