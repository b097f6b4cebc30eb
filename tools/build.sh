#!/usr/bin/env bash
# Installs missing Debian packages, then configures and builds photonbake (Release) into ./build.
# Usage: tools/build.sh [extra cmake arguments]; BUILD_DIR=dir to build elsewhere (tools/run-tests.sh builds the
# sanitizer suite into build-asan).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPB_TEST_SOURCES_ONLY= -DPB_BENCHMARKS=ON "$@" >/dev/null  # all tests and benchmarks unless "$@" says
cmake --build "$build"
