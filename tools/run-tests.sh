#!/usr/bin/env bash
# Quick start 2 (and CI): install what is missing (the Khronos glTF Validator from npm included), build, and run
# the whole test suite; fuzz every file reader briefly; then build the suite again with AddressSanitizer and UndefinedBehaviorSanitizer (into build-asan/) and
# run it there too.
#   FUZZ_SECONDS  the fuzzing pass (tools/fuzz.sh), per reader: default 15; 0 skips it. Any crash, leak or sanitizer
#                 finding fails the run.
#   SANITIZE=0    skips the sanitizer pass (the larger part of the run).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
# Each phase's wall time, printed as it ends and together at the end.
phases=""
phase() { phases+=$(printf '  %-24s %5d s\n' "$1" "$((SECONDS - phase_start))")$'\n'; echo "run-tests: $1 took $((SECONDS - phase_start)) s"; phase_start=$SECONDS; }
trap 'printf "run-tests: wall time by phase\n%s" "$phases"' EXIT
phase_start=$SECONDS
bash tools/build.sh
phase "install and build"
bash tools/install-gltf-validator.sh  # the Khronos glTF Validator, which gltf_output_test.cpp runs
export PB_REQUIRE_GLTF_VALIDATOR=1    # so that test fails, rather than skips, if it is missing
# bake-mpi's tests too (the sanitizer build below has no bake-mpi: Open MPI's allocations would read as leaks)
(cd build && PB_REQUIRE_MPI=1 ctest --output-on-failure --timeout 900 -j "$(nproc)")
phase "tests"
bash tools/corpus-stages.sh build  # the corpus's real assets: no stage's time per triangle jumps (skipped without it)
phase "corpus stages"
if [ "${FUZZ_SECONDS:-30}" != 0 ]; then
  bash tools/fuzz.sh "${FUZZ_SECONDS:-15}"
  phase "fuzzing (build and runs)"
fi
if [ "${SANITIZE:-1}" != 0 ]; then
  # -O1 -g1 (line tables, enough for the sanitizers' stack traces): on 2 cores the build took 395 s and the tests
  # 452 s, against 692 s and 394 s at RelWithDebInfo's -O2 -g. No benchmarks. (The tests' own code at -O0 took 15 s
  # instead of 2 s for each brute-force sum of Region/RegionEveryKernel.) Built with clang, which compiles
  # instrumented code in 60-68% of GCC's time (bake_cli_test.cpp 19.6 s against 32.6 s, report.cpp 10.4 s against
  # 15.3 s); the plain build stays GCC's, so both compilers see the code.
  bash tools/install-clang.sh
  BUILD_DIR=build-asan bash tools/build.sh -DCMAKE_CXX_COMPILER=clang++ -DPB_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DPB_BENCHMARKS=OFF
  phase "sanitizer build"
  # Less the statistical tests whose code smaller tests also run (tests/sanitizers/statistical-only.txt says which).
  statistical=$(sed -e 's/#.*//' -e 's/[[:space:]]*$//' -e '/^$/d' tests/sanitizers/statistical-only.txt | paste -sd '|')
  cd build-asan
  LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp" UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure --timeout 900 -j "$(nproc)" -E "^($statistical)( |$)"
  phase "sanitizer tests"
fi
