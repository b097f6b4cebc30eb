#!/usr/bin/env bash
# Installs missing Debian packages, then configures and builds photonbake (Release) into ./build.
# Usage: tools/build.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build
