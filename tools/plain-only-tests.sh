#!/usr/bin/env bash
# Prints, as a CMake list (';' between), the test sources whose tests only the plain tree runs when tools/run-tests.sh
# runs the sanitizer pass too: those holding a test that the sanitizer pass leaves out (tests/sanitizers/
# left-out.txt; each line's suite and the start of its name, found in a TEST, TEST_P or TEST_F), bake-mpi's, which
# the sanitized tree does not build, and the memory limit's, which AddressSanitizer's shadow memory makes it skip.
# Every other test then runs once, under the sanitizers, and the plain tree compiles and runs only these
# (docs/testing.md).
set -euo pipefail
cd "$(dirname "$0")/.."
sources=$'tests/tools/bake_mpi_test.cpp\ntests/tools/memory_limit_test.cpp'
while read -r pattern; do
  left=${pattern%%.*}
  suite=${left##*/}
  rest=${pattern#*.}
  name=$(sed -E 's/[/(.*].*//' <<<"$rest")
  found=$(grep -rlE "TEST(_P|_F)?\($suite, $name" tests --include='*_test.cpp' || true)
  [ -n "$found" ] || { echo "plain-only-tests: no source holds $pattern (tests/sanitizers/left-out.txt)" >&2; exit 1; }
  sources+=$'\n'"$found"
done < <(sed -e 's/#.*//' -e 's/[[:space:]]*$//' -e '/^$/d' tests/sanitizers/left-out.txt)
sort -u <<<"$sources" | paste -sd ';'
