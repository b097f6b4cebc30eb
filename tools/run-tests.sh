#!/usr/bin/env bash
# Quick start 2 (and CI): install what is missing, build, and run the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
cd build
ctest --output-on-failure --timeout 900 -j "$(nproc)"
