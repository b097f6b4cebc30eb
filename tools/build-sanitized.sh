#!/usr/bin/env bash
# Builds the sanitized tree, build-asan/: the test suite and the fuzz targets, with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer, in one configuration, so that the sanitizer pass of tools/run-tests.sh and
# tools/fuzz.sh compile the project once between them. Installs clang if it is missing.
# Usage: tools/build-sanitized.sh [TARGET ...; default all]
# -O1 -g1 (line tables, enough for the sanitizers' stack traces): on 2 cores the build took 395 s and the tests
# 452 s, against 692 s and 394 s at RelWithDebInfo's -O2 -g. No benchmarks. (The tests' own code at -O0 took 15 s
# instead of 2 s for each brute-force sum of Region/RegionEveryKernel.) Built with clang, which compiles
# instrumented code in 60-68% of GCC's time (bake_cli_test.cpp 19.6 s against 32.6 s, report.cpp 10.4 s against
# 15.3 s); the plain build stays GCC's, so both compilers see the code. (Unity batches of the libraries,
# CMAKE_UNITY_BUILD, were tried: 334 s against 285 s on 2 cores, the batches' long compiles leaving a core idle.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-clang.sh
bash tools/install-deps.sh
cmake -S . -B build-asan -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DPB_SANITIZE=ON -DPB_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DPB_BENCHMARKS=OFF >/dev/null
if [ $# -gt 0 ]; then cmake --build build-asan --target "$@"; else cmake --build build-asan; fi
