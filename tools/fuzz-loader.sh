#!/usr/bin/env bash
# Fuzzes the OBJ/MTL loader with libFuzzer (clang, from Debian) for a bounded time, starting from the seed corpus in
# tests/fuzz/corpus. Usage: tools/fuzz-loader.sh [SECONDS, default 60]. Installs clang if it is missing. Crashes
# and the inputs that caused them land in build-fuzz/findings; new interesting inputs in build-fuzz/corpus.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
if ! command -v clang++ >/dev/null; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq && $sudo apt-get install -y -qq --no-install-recommends clang >/dev/null
fi
bash tools/install-deps.sh
cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPB_FUZZ=ON >/dev/null
cmake --build build-fuzz --target fuzz_obj_loader
mkdir -p build-fuzz/corpus build-fuzz/findings
build-fuzz/fuzz_obj_loader build-fuzz/corpus tests/fuzz/corpus -max_total_time="$seconds" -max_len=4096 \
  -artifact_prefix=build-fuzz/findings/ -print_final_stats=1
