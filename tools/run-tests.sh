#!/usr/bin/env bash
# Quick start 2 (and CI): install what is missing (the Khronos glTF Validator from npm included), build, and run
# the whole test suite: the statistical tests (tests/sanitizers/left-out.txt) and bake-mpi's in the plain tree, then
# every other test in a build with AddressSanitizer and UndefinedBehaviorSanitizer (into build-asan/,
# tools/build-sanitized.sh), after fuzzing every file reader briefly there. With SANITIZE=0, the whole suite in the
# plain tree.
#   FUZZ_SECONDS  the fuzzing pass (tools/fuzz.sh), per reader: default 15; 0 skips it. Any crash, leak or sanitizer
#                 finding fails the run.
#   SANITIZE=0    skips the sanitizer pass (the larger part of the run) and runs every test in the plain tree.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
# Each phase's wall time, printed as it ends and together at the end.
phases=""
phase() { phases+=$(printf '  %-24s %5d s\n' "$1" "$((SECONDS - phase_start))")$'\n'; echo "run-tests: $1 took $((SECONDS - phase_start)) s"; phase_start=$SECONDS; }
trap 'printf "run-tests: wall time by phase\n%s" "$phases"' EXIT
# ctest starts the longest tests first when it knows their times; a clean clone does not, so a tree without
# timings starts from a recent run's (tests/ctest-costs/, tools/update-test-costs.sh), which ctest then updates.
seed_test_costs() {
  local data="$1/Testing/Temporary/CTestCostData.txt"
  [ -f "$data" ] || { mkdir -p "$(dirname "$data")" && cp "tests/ctest-costs/$2.txt" "$data"; }
}
phase_start=$SECONDS
# With the sanitizer pass, the plain tree builds and runs only the tests that pass leaves out or cannot run
# (tools/plain-only-tests.sh): every test runs once, in the tree that checks the most. No benchmark there: no test
# runs one (22 s of compiling; tools/build.sh builds them again).
if [ "${SANITIZE:-1}" != 0 ]; then
  bash tools/build.sh "-DPB_TEST_SOURCES_ONLY=$(bash tools/plain-only-tests.sh)" -DPB_BENCHMARKS=OFF
else
  bash tools/build.sh
fi
phase "install and build"
bash tools/install-gltf-validator.sh  # the Khronos glTF Validator, which gltf_output_test.cpp runs
export PB_REQUIRE_GLTF_VALIDATOR=1    # so that test fails, rather than skips, if it is missing
# bake-mpi's tests too (the sanitizer build below has no bake-mpi: Open MPI's allocations would read as leaks)
seed_test_costs build plain
# The statistical or repeated tests that the sanitizer pass leaves out (tests/sanitizers/left-out.txt says which).
left_out=$(sed -e 's/#.*//' -e 's/[[:space:]]*$//' -e '/^$/d' tests/sanitizers/left-out.txt | paste -sd '|')
# With the sanitizer pass, only those, bake-mpi's and the memory limit's: the other tests of the sources that hold
# them run under the sanitizers (42 s of tests run twice before).
only=()
[ "${SANITIZE:-1}" != 0 ] && only=(-R "^($left_out|BakeMpi\..*|MemoryLimit\..*)( |$)")
(cd build && PB_REQUIRE_MPI=1 ctest --output-on-failure --timeout 900 -j "$(nproc)" "${only[@]}")
phase "tests"
bash tools/corpus-stages.sh build  # the corpus's real assets: no stage's time per triangle jumps (skipped without it)
phase "corpus stages"
# The sanitized tree (build-asan/): the suite and the fuzz targets, one compile between them.
if [ "${SANITIZE:-1}" != 0 ]; then
  bash tools/build-sanitized.sh
  phase "sanitizer build"
fi
if [ "${FUZZ_SECONDS:-15}" != 0 ]; then
  bash tools/fuzz.sh "${FUZZ_SECONDS:-15}"
  phase "fuzzing"
fi
if [ "${SANITIZE:-1}" != 0 ]; then
  # Less the statistical or repeated tests whose code smaller tests also run (left_out, above).
  seed_test_costs build-asan sanitized
  cd build-asan
  # Two frames of each allocation's and free's stack, not 30: every allocation unwinds its stack, and the deep
  # unwinds cost a tenth of the pass; a finding still shows the full stack of the bad access (run its test again
  # with ASAN_OPTIONS=malloc_context_size=30 for where the memory came from).
  ASAN_OPTIONS=malloc_context_size=2 LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp" \
    UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure --timeout 900 -j "$(nproc)" -E "^($left_out)( |$)"
  phase "sanitizer tests"
fi
